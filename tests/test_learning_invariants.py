"""Prioritized Sweeping held to Moore & Atkeson's definition (navcli/learning/prioritized_sweeping.py):
a real step queues the state just left at the top; a sweep pops the states in priority order, only
those above the threshold; a backup is the Bellman backup over the model learned from the counts;
after it every predecessor ``p`` of the state backed up has its priority raised to ``delta P(s|p, a)``
(the largest over a) when that is above the threshold, each state queued once with its largest
priority. A property test replays random experience one backup at a time against a reference
written from those equations; the worked examples give the numbers by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from navcli.learning.prioritized_sweeping import PrioritizedSweeping


def bellman(ps: PrioritizedSweeping, s: int) -> float:
    """``max_a [R(s, a) + gamma sum_s' P(s'|s, a) V(s')]`` from the counts, an action tried fewer
    than ``explore`` times worth ``optimistic``, one never tried (with ``explore`` 0) nothing."""
    q = []
    for a in range(ps.n_actions):
        n = ps.tried[s, a]
        if n < ps.explore:
            q.append(ps.optimistic)
        elif n > 0:
            P = ps.counts[s, a] / n  # over the states and, last, the goal
            q.append(ps.reward_sum[s, a] / n + ps.gamma * float(P @ ps.values))
    return max(q, default=-math.inf)


def raised(ps: PrioritizedSweeping, priority: np.ndarray, s: int, delta: float) -> np.ndarray:
    """The queue after ``s`` changed by ``delta``: each predecessor at ``max_a delta P(s|pred, a)``
    if above the threshold and above what it holds."""
    out = priority.copy()
    if delta <= ps.threshold:
        return out
    for pred in range(ps.n_states):
        tried = ps.tried[pred] > 0
        if not (ps.counts[pred, :, s] > 0).any():
            continue  # not a predecessor of s
        p = delta * max(ps.counts[pred, a, s] / ps.tried[pred, a] for a in np.flatnonzero(tried))
        if p > ps.threshold:
            out[pred] = max(out[pred], p)
    return out


def check_one_backup(ps: PrioritizedSweeping) -> bool:
    """Make one backup (``sweep(1)``) and check it against the definition; False if none was due."""
    priority, values = ps.priority.copy(), ps.values.copy()
    top = priority.max()
    due = top > ps.threshold
    done = ps.sweep(1)
    assert done == (1 if due else 0)
    if not due:  # nothing above the threshold: nothing popped, nothing changed
        assert np.array_equal(ps.priority, priority) and np.array_equal(ps.values, values)
        return False
    changed = np.flatnonzero(ps.values != values)
    popped = [s for s in np.flatnonzero(priority == top) if ps.priority[s] < priority[s] or s in changed]
    assert len(popped) == 1, "one state of the highest priority is backed up"
    s = popped[0]
    assert set(changed) <= {s} and ps.values[-1] == 0.0  # the goal's value stays 0
    values_then = ps.values.copy()
    ps.values[:] = values  # the backup reads the values before it
    want = bellman(ps, s)
    ps.values[:] = values_then
    assert ps.values[s] == pytest.approx(want, rel=1e-12, abs=1e-12)
    after = priority.copy()
    after[s] = 0.0  # popped
    after = raised(ps, after, s, abs(ps.values[s] - values[s]))
    np.testing.assert_allclose(ps.priority, after, rtol=1e-12, atol=0)
    return True


@st.composite
def experiences(draw):
    n = draw(st.integers(2, 5))
    A = draw(st.integers(1, 3))
    ps = PrioritizedSweeping(
        n,
        A,
        gamma=draw(st.sampled_from([0.5, 0.9, 1.0])),
        backups=0,  # a real step only queues; the test makes the backups one by one
        threshold=draw(st.sampled_from([0.0, 1e-3, 0.05, 0.25, 0.5])),
        explore=draw(st.sampled_from([0, 0, 1, 2])),  # 0 (twice as likely): no optimism
        optimistic=0.0,
    )
    step = st.tuples(st.integers(0, n - 1), st.integers(0, A - 1), st.sampled_from([-2.0, -1.0, -0.5]))
    steps = draw(st.lists(st.tuples(step, st.integers(0, n), st.integers(0, 4)), min_size=1, max_size=20))
    return ps, steps


@given(experiences())
def test_every_backup_and_every_queue_change_is_moore_and_atkesons(case):
    ps, steps = case
    for (s, a, r), to, backups in steps:
        terminal = to == ps.n_states  # the goal
        before = ps.priority.copy()
        ps.observe(s, a, r, None if terminal else to, terminal=terminal)
        assert ps.priority[s] == math.inf  # the state just left goes to the top ...
        others = np.arange(ps.n_states) != s
        assert np.array_equal(ps.priority[others], before[others])  # ... and nothing else moves
        for _ in range(backups):
            if not check_one_backup(ps):
                break
    assert ps.steps == len(steps) and ps.tried.sum() == len(steps)


@given(experiences(), st.integers(1, 6))
def test_a_loaded_learner_backs_up_as_the_definition_says(case, backups):
    """What :meth:`to_arrays` saves is the whole model: a learner loaded from it makes the
    backups of the definition (its predecessors rebuilt from the counts alone)."""
    ps, steps = case
    for (s, a, r), to, _ in steps:
        ps.observe(s, a, r, None if to == ps.n_states else to, terminal=to == ps.n_states)
    loaded = PrioritizedSweeping(
        ps.n_states, ps.n_actions, gamma=ps.gamma, backups=0, threshold=ps.threshold, explore=ps.explore
    )
    loaded.load_arrays(ps.to_arrays())
    for _ in range(backups):
        if not check_one_backup(loaded):
            break


def test_a_real_step_backs_up_the_state_just_left_not_its_successor():
    ps = PrioritizedSweeping(3, 1, gamma=0.9, backups=1, threshold=0.1, explore=0)
    ps.observe(0, 0, -1.0, 1)
    assert ps.values.tolist() == [-1.0, 0.0, 0.0, 0.0]  # V(0) = -1 + 0.9 V(1) = -1; V(1) untouched


def test_predecessors_are_queued_at_delta_times_their_transition_probability():
    """State 0 leads to 1 or 2 (half each, reward -1); then 1 is seen to reach the goal for -2."""
    ps = PrioritizedSweeping(3, 1, gamma=0.9, backups=0, threshold=0.1, explore=0)
    ps.observe(0, 0, -1.0, 1)
    ps.observe(0, 0, -1.0, 2)
    assert ps.sweep() == 0 and ps.priority.tolist() == [math.inf, 0.0, 0.0]  # queued once, however often left
    assert ps.sweep(5) == 1 and ps.values[0] == -1.0  # -1 + 0.9 (0.5 V(1) + 0.5 V(2)), nothing else due
    ps.observe(1, 0, -2.0, None, terminal=True)
    assert ps.sweep(1) == 1 and ps.values[1] == -2.0  # -2 + 0.9 V(goal)
    assert ps.priority.tolist() == [1.0, 0.0, 0.0]  # delta 2 x P(1|0) 1/2
    assert ps.sweep(1) == 1 and ps.values[0] == pytest.approx(-1.9)  # -1 + 0.9 (0.5 (-2) + 0.5 (0))
    assert ps.priority.tolist() == [0.0, 0.0, 0.0] and ps.sweep() == 0


def test_a_priority_must_be_above_the_threshold_and_the_largest_over_actions_wins():
    # threshold 1: the predecessor's delta P = 2 x 1/2 = 1 is not above it, so not queued
    ps = PrioritizedSweeping(3, 1, gamma=0.9, backups=0, threshold=1.0, explore=0)
    for step in ((0, 0, -1.0, 1), (0, 0, -1.0, 2)):
        ps.observe(*step)
    ps.sweep(9)
    ps.observe(1, 0, -2.0, None, terminal=True)
    assert ps.sweep(1) == 1 and ps.priority.tolist() == [0.0, 0.0, 0.0]
    # two actions from 0 reach 1: a0 once in two tries (P 1/2), a1 in its only try (P 1): delta x 1
    ps = PrioritizedSweeping(3, 2, gamma=0.9, backups=0, threshold=0.1, explore=0)
    for step in ((0, 0, -1.0, 1), (0, 0, -1.0, 2), (0, 1, -1.0, 1), (2, 0, -1.0, 1)):
        ps.observe(*step)
    ps.sweep(9)
    ps.observe(1, 0, -3.0, None, terminal=True)
    assert ps.sweep(1) == 1 and ps.values[1] == -3.0
    assert ps.priority.tolist() == [3.0, 0.0, 3.0]  # 0: 3 x max(1/2, 1); 2: 3 x 1
    ps.priority[2] = 5.0  # a higher priority is kept
    ps.values[1] = 0.0
    ps.priority[1] = math.inf
    assert ps.sweep(1) == 1 and ps.priority.tolist() == [3.0, 0.0, 5.0]  # V(1) 0 -> -3 again: delta 3


def test_an_action_is_judged_on_the_model_from_its_explore_th_try():
    ps = PrioritizedSweeping(2, 2, gamma=1.0, backups=0, explore=2, optimistic=0.0)
    ps.observe(0, 0, -1.0, 1)
    assert ps.q_values(0).tolist() == [0.0, 0.0]  # tried once, fewer than 2: optimistic
    ps.observe(0, 0, -1.0, 1)
    assert ps.q_values(0).tolist() == [-1.0, 0.0]  # tried twice: its model, -1 + V(1)
    assert ps.greedy(0) == 0  # greedy: an action never tried ranks last, however optimistic
    assert ps.q_values(0, optimism=False)[1] == -math.inf


def test_a_tie_is_broken_by_the_given_generator_and_only_a_tie():
    ps = PrioritizedSweeping(2, 5, rng=np.random.default_rng(7))
    picks = [ps.act(0) for _ in range(40)]  # five equally unknown actions: tried alike
    twin = np.random.default_rng(7)
    assert picks == [int(twin.choice(np.arange(5))) for _ in range(40)] and len(set(picks)) == 5
    ps = PrioritizedSweeping(2, 2, explore=0, rng=np.random.default_rng(7))
    assert len({ps.act(1) for _ in range(30)}) == 2  # never visited, explore 0: a tie of two unknowns
    ps.observe(0, 0, -1.0, 1)
    ps.observe(0, 1, -2.0, 1)
    state = ps.rng.bit_generator.state
    assert [ps.act(0) for _ in range(5)] == [0] * 5 and ps.rng.bit_generator.state == state  # no tie, no draw


def test_a_learner_without_a_generator_is_deterministic():
    a, b = PrioritizedSweeping(1, 4), PrioritizedSweeping(1, 4)
    assert [a.act(0) for _ in range(20)] == [b.act(0) for _ in range(20)]


def test_a_saved_learner_goes_on_as_the_one_it_was_saved_from():
    steps = [(0, 0, -1.0, 1), (1, 1, -1.0, 2), (2, 0, -1.0, None), (0, 1, -2.0, 2), (2, 1, -1.0, 0), (1, 0, -1.0, 1)]
    a = PrioritizedSweeping(3, 2, gamma=0.9, backups=2, threshold=0.01, explore=1)
    for s, act, r, to in steps:
        a.observe(s, act, r, to, terminal=to is None)
    b = PrioritizedSweeping(3, 2, gamma=0.9, backups=2, threshold=0.01, explore=1)
    b.load_arrays(a.to_arrays())
    for s, act, r, to in [(1, 1, -1.0, 2), (0, 0, -1.0, 1), (2, 0, -1.0, None)] * 3:
        for ps in (a, b):
            ps.observe(s, act, r, to, terminal=to is None)
        assert np.array_equal(a.values, b.values) and np.array_equal(a.priority, b.priority)
    assert b.steps == a.steps == 15 and a.to_arrays()["policy"].dtype == np.int8
