"""``navcli compare pilots``: rerun missions with many seeds, in parallel, each as its own log.

Every (scenario, pilot, rerun) is one run, a whole :class:`~navcli.config.RunSpec`, with one log,
``<out>/<scenario>/<pilot>-seed<N>-<run id>.mcap``. Seeds come from the scenario's seed and the
rerun index (the same seeds for every pilot, so the comparison is paired). A job carries its
configuration whole to the worker, so whatever was planned (parameters, time limit) is what
runs. A run whose complete log of the same configuration (same run id) already exists is not run
again, so an interrupted comparison resumes, and a comparison with other parameters never reuses
its logs; a run that fails keeps its log (marked ``error``) and is reported. The table itself is
built from the logs by ``analysis`` (see :mod:`analysis.tables`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping

import numpy as np

from ..config import RunSpec


def rerun_seed(base: int, index: int) -> int:
    """The seed of rerun ``index`` of a scenario whose seed is ``base`` (a 31-bit integer)."""
    return int(np.random.SeedSequence([base, index]).generate_state(1)[0] >> 1)


def reruns(base: RunSpec, overrides: Mapping[str, Any], n: int) -> Iterator[RunSpec]:
    """``base`` with the parameter ``overrides`` at its first ``n`` rerun seeds: the same seeds
    whatever the overrides, so ``sweep``'s points and ``tune``'s trials are paired."""
    spec = base.replace(params=base.params.override(overrides))
    for i in range(n):
        yield spec.replace(seed=rerun_seed(base.seed, i))


@dataclass(frozen=True)
class Job:
    spec: RunSpec
    log: str


@dataclass(frozen=True)
class Outcome:
    job: Job
    outcome: str  # the summary's outcome, or "error"
    message: str = ""
    ran: bool = True  # False: a complete log was already there


def plan(specs: list[RunSpec], pilots: list[str], n: int, out: Path) -> list[Job]:
    """All runs of a comparison: each base configuration (one per scenario) with every pilot at
    its first ``n`` rerun seeds (:func:`reruns`)."""
    jobs = []
    for base in specs:
        for seeded in reruns(base, {}, n):
            for pilot in pilots:
                spec = seeded.replace(pilot=pilot)
                jobs.append(Job(spec, str(spec.default_log_path(out))))
    return jobs


def complete(log: str, run_id: str) -> str | None:
    """The outcome of an existing, complete log of the run ``run_id`` (not interrupted, not an
    error), else None."""
    p = Path(log)
    if not p.exists():
        return None
    from ..analysis import LogError, read_log

    try:
        done = read_log(p, topics=[])
    except LogError:
        return None
    outcome = done.summary.get("outcome")
    if done.metadata.get("run", {}).get("run_id") != run_id:
        return None
    return outcome if outcome in ("reached", "timeout", "blocked") else None


def run_job(job: Job) -> Outcome:
    """Run one job (in a worker process, or in this one); never raises."""
    done = complete(job.log, job.spec.run_id)
    if done is not None:
        return Outcome(job, done, ran=False)
    from ..runner import run_mission

    try:
        res = run_mission(job.spec, out=Path(job.log), overwrite=True)  # not complete: rerun
    except Exception as e:  # the runner has closed the log, marked error
        return Outcome(job, "error", f"{type(e).__name__}: {e}")
    return Outcome(job, res.summary["outcome"], res.summary.get("reason", ""))


def run_all(jobs: list[Job], workers: int, on_done: Callable[[Outcome], None] | None = None) -> list[Outcome]:
    """Run ``jobs`` on ``workers`` local processes (1: in this process); see :func:`run_on`."""
    from .executor import executor

    with executor(workers) as ex:
        return run_on(jobs, ex, on_done)


def run_on(jobs: list[Job], ex, on_done: Callable[[Outcome], None] | None = None) -> list[Outcome]:
    """Run ``jobs`` on the executor ``ex`` of :mod:`.executor` (a local pool, or a Dask cluster whose
    workers can all write the logs' folder); results in the order they finish. Ctrl-C or SIGTERM
    stops every local worker (their logs closed, marked ``interrupted``) and is re-raised."""
    from .executor import run_each

    results: list[Outcome] = []

    def done(i: int, f) -> None:
        r = f.result()
        results.append(r)
        if on_done:
            on_done(r)

    run_each(run_job, jobs, ex, done)
    return results
