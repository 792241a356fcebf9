"""``navcli compare pilots``: rerun missions with many seeds, in parallel, each as its own log.

Every (scenario, pilot, rerun) is one run with one log, ``<out>/<scenario>/<pilot>-seed<N>.mcap``.
Seeds come from the scenario's seed and the rerun index (the same seeds for every pilot, so the
comparison is paired). A run whose complete log already exists is not run again, so an
interrupted comparison resumes; a run that fails keeps its log (marked ``error``) and is reported.
The table itself is built from the logs by ``analysis`` (see :mod:`analysis.compare`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np


def rerun_seed(base: int, index: int) -> int:
    """The seed of rerun ``index`` of a scenario whose seed is ``base`` (a 31-bit integer)."""
    return int(np.random.SeedSequence([base, index]).generate_state(1)[0] >> 1)


@dataclass(frozen=True)
class Job:
    scenario: str  # path of the scenario file
    name: str  # the scenario's name
    pilot: str
    seed: int
    log: str
    time_limit: float | None = None


@dataclass(frozen=True)
class Outcome:
    job: Job
    outcome: str  # the summary's outcome, or "error"
    message: str = ""
    ran: bool = True  # False: a complete log was already there


def plan(scenarios: list, pilots: list[str], reruns: int, out: Path, time_limit: float | None = None) -> list[Job]:
    """All runs of a comparison (``scenarios``: loaded :class:`navcli.scenario.Scenario` s)."""
    jobs = []
    for sc in scenarios:
        for i in range(reruns):
            seed = rerun_seed(sc.mission.seed, i)
            for pilot in pilots:
                jobs.append(Job(sc.source, sc.name, pilot, seed,
                                str(out / sc.name / f"{pilot}-seed{seed}.mcap"), time_limit))
    return jobs


def complete(log: str) -> str | None:
    """The outcome of an existing, complete log (not interrupted, not an error), else None."""
    p = Path(log)
    if not p.exists():
        return None
    from analysis import LogError, read_log

    try:
        outcome = read_log(p, topics=[]).summary.get("outcome")
    except LogError:
        return None
    return outcome if outcome in ("reached", "timeout", "blocked") else None


@functools.lru_cache(maxsize=None)
def _scenario(path: str):
    """Each worker parses each scenario once."""
    from .scenario import load_scenario

    return load_scenario(path)


def run_job(job: Job) -> Outcome:
    """Run one job (in a worker process, or in this one); never raises."""
    done = complete(job.log)
    if done is not None:
        return Outcome(job, done, ran=False)
    from .runner import run_mission

    try:
        res = run_mission(_scenario(job.scenario), seed=job.seed, pilot=job.pilot, out=Path(job.log),
                          time_limit=job.time_limit)
    except Exception as e:  # the runner has closed the log, marked error
        return Outcome(job, "error", f"{type(e).__name__}: {e}")
    return Outcome(job, res.summary["outcome"], res.summary.get("reason", ""))


def run_all(jobs: list[Job], workers: int, on_done: Callable[[Outcome], None] | None = None) -> list[Outcome]:
    """Run ``jobs`` on ``workers`` processes (1: in this process), in the order they finish."""
    results = []
    if workers <= 1:
        for j in jobs:
            r = run_job(j)
            results.append(r)
            if on_done:
                on_done(r)
        return results
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from . import recorder, runner  # noqa: F401  (imported once here, inherited by the forked workers)

    # fork: workers start with navcli already imported; nothing is re-imported per run
    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else None
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
        futures = [pool.submit(run_job, j) for j in jobs]
        for f in as_completed(futures):
            r = f.result()
            results.append(r)
            if on_done:
                on_done(r)
    return results
