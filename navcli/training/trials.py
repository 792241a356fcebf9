"""Trials of the Learning Agent's task, one after another from given starts, with actions chosen
by a policy: what a training runs and learns from, and what its evaluations and ``navcli compare
policies`` run (:mod:`.trainer`, :mod:`.comparison`)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..config import RunSpec
from ..learning.actions import ACTIONS, reward_of
from ..learning.features import N_STATES
from ..learning.hand_coded import hand_coded_action
from ..learning.learning_agent import table_policy
from .task import NavigationTask, Start


@dataclass(frozen=True)
class TrialResult:
    """One trial: how it ended, its actions, its reward and the count of each action."""

    outcome: str
    actions: int
    counts: tuple[int, ...]
    visited: tuple[int, ...] = field(default=(), compare=False)  # the belief states it chose an action in, sorted

    @property
    def success(self) -> bool:
        return self.outcome == "reached"

    @property
    def reward(self) -> float:
        return reward_of(self.counts)


def run_trial(
    task: NavigationTask,
    start: Start,
    choose: Callable[[int], int],
    learn: Callable[[int, int, float, int, bool], None] | None = None,
    log: Path | None = None,
) -> TrialResult:
    """One trial from ``start``, actions chosen by ``choose(state)``; ``learn(s, a, r, s', terminal)``
    hears every step (terminal: the target reached, or blocked in the paper's task); with ``log``
    every tick is recorded there (MCAP)."""
    s = task.reset(start, log)
    m = task.mission
    assert m is not None  # reset made it
    counts = [0] * len(ACTIONS)
    visited = set()
    while task.outcome is None and m.outcome is None:
        a = choose(s)
        visited.add(s)
        s2, r, _, _ = task.step(a)
        counts[a] += 1
        if learn is not None:
            learn(s, a, r, s2, task.terminal)
        s = s2
    return TrialResult(task.outcome or m.outcome or "interrupted", task.actions, tuple(counts), tuple(sorted(visited)))


RANDOM_STREAM = 7  # the random policy's generator of a trial: [the start's seed, this]


def random_policy(start: Start) -> Callable[[int], int]:
    """The uniform random policy of a trial from ``start``: an action drawn uniformly at each
    choice, from a generator seeded by the start's seed (the same trial, the same draws)."""
    rng = np.random.default_rng([start.seed, RANDOM_STREAM])
    return lambda state: int(rng.integers(len(ACTIONS)))


def evaluate(spec: RunSpec, policy: np.ndarray | None, starts: list[Start]) -> list[TrialResult]:
    """The policy (an action per state; None: the uniform random policy) from each start, in this process."""
    task = NavigationTask(spec)
    if policy is None:
        return [run_trial(task, st, random_policy(st)) for st in starts]
    choose = table_policy(policy)
    return [run_trial(task, st, choose) for st in starts]


def hand_coded_table() -> np.ndarray:
    return np.array([hand_coded_action(s) for s in range(N_STATES)], dtype=np.int8)


def eval_job(spec: RunSpec, policy: np.ndarray | None, starts: list[Start]) -> tuple[list[TrialResult], float]:
    t0 = time.perf_counter()
    return evaluate(spec, policy, starts), time.perf_counter() - t0
