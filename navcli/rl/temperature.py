"""``navcli tune-softmax``: the temperature of the ``softmax`` policy (:mod:`navcli.learning.softmax`)
chosen on training rooms alone.

Each temperature of a grid runs the same trials: in each room given, ``starts`` starts drawn from
``seed`` (:func:`~navcli.training.task.random_starts`; by default not the evaluation's starts,
whose seed is :data:`~navcli.training.trainer.EVAL_SEED`), each trial's draws seeded by its start
(:func:`~navcli.learning.sampled.trial_sampler`). The temperature of the highest mean reward per
trial over every room's trials wins (the lowest temperature on a tie: the one nearest the greedy
policy). The choice and the grid's numbers are written as JSON; written to
``navcli/learning/models/softmax.json`` it is the bundled choice (``softmax.temperature``'s
default).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..config import RunSpec
from ..training.task import Start, random_starts

GRID = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
"""The temperatures tried by default (reward units: the bundled model's gap between its best and
second-best action values is 0.4 to 8.5 in nine states of ten, median 2)."""
TUNE_SEED = 1
"""The starts' seed by default (the evaluation's are another: comparisons never run the starts a
temperature was chosen on)."""


@dataclass(frozen=True)
class Job:
    spec: RunSpec
    temperature: float
    starts: tuple[Start, ...]


def run_job(job: Job) -> list[dict[str, Any]]:
    """The trials of one temperature in one room: outcome and reward per start."""
    from ..learning.sampled import trial_sampler
    from ..learning.softmax import SoftmaxParams, SoftmaxPolicy
    from ..training.task import NavigationTask
    from ..training.trainer import run_trial

    probabilities = SoftmaxPolicy.probabilities(SoftmaxParams(temperature=job.temperature))
    task = NavigationTask(job.spec)
    out = []
    for st in job.starts:
        r = run_trial(task, st, trial_sampler(probabilities, st.seed))
        out.append({"outcome": r.outcome, "reward": r.reward, "actions": r.actions})
    return out


def plan(specs: list[RunSpec], grid: tuple[float, ...], starts: int, seed: int) -> list[Job]:
    """A job per (room, temperature)."""
    jobs = []
    for spec in specs:
        st = tuple(random_starts(spec, starts, seed))
        jobs += [Job(spec, t, st) for t in grid]
    return jobs


def choose(
    specs: list[RunSpec],
    grid: tuple[float, ...] = GRID,
    starts: int = 50,
    seed: int = TUNE_SEED,
    ex: Any = None,
    on_done: Callable[[], None] | None = None,
) -> dict[str, Any]:
    """Run the grid (on the executor ``ex``; None: in this process) and return the choice with
    every temperature's numbers (module docstring)."""
    from ..experiments.executor import SerialExecutor, run_each
    from ..learning import model_file
    from ..learning.softmax import bundled_values

    jobs = plan(specs, grid, starts, seed)
    results: dict[int, list[dict[str, Any]]] = {}

    def keep(i: int, f: Any) -> None:
        results[i] = f.result()
        if on_done:
            on_done()

    run_each(run_job, jobs, ex or SerialExecutor(), keep)
    rows = []
    for t in grid:
        trials = [tr for i, j in enumerate(jobs) if j.temperature == t for tr in results[i]]
        rewards = np.array([tr["reward"] for tr in trials])
        rows.append(
            {
                "temperature": t,
                "trials": len(trials),
                "successes": sum(tr["outcome"] == "reached" for tr in trials),
                "reward": float(rewards.mean()),
                "reward_sem": float(rewards.std(ddof=1) / math.sqrt(len(rewards))) if len(rewards) > 1 else None,
                "per_room": {
                    j.spec.scenario.name: {
                        "successes": sum(tr["outcome"] == "reached" for tr in results[i]),
                        "reward": float(np.mean([tr["reward"] for tr in results[i]])),
                    }
                    for i, j in enumerate(jobs)
                    if j.temperature == t
                },
            }
        )
    best = max(rows, key=lambda r: (r["reward"], -r["temperature"]))
    return {
        "temperature": best["temperature"],
        "grid": rows,
        "rooms": [s.scenario.name for s in specs],
        "rooms_sha256": [s.scenario.sha256 for s in specs],
        "starts_per_room": starts,
        "seed": seed,
        "model": bundled_values()[1],
        "model_sha256": hashlib.sha256(model_file.BUNDLED.read_bytes()).hexdigest(),
        "rule": "the highest mean reward per trial over every room's trials; the lowest temperature on a tie",
    }
