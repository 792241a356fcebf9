"""The Learning Agent: Prioritized Sweeping and Q-learning against value iteration on small MDPs,
the belief-state features, the actions, the hand-coded policy, the run option and the model file."""

from __future__ import annotations

import copy
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from conftest import SCENARIOS
from navcli.beliefs import Beliefs
from navcli.fuzzy import FuzzyPoint
from navcli.geometry import Pose
from navcli.learning.actions import MB, MLL, MOT, MVL, MVT, action_bids
from navcli.learning.features import SHAPE, Features, discretise, features, state_index
from navcli.learning.hand_coded import hand_coded_action
from navcli.learning.prioritized_sweeping import PrioritizedSweeping
from navcli.learning.q_learning import QLearning
from navcli.navigation.situation import Situation

try:
    import gymnasium  # noqa: F401
except ModuleNotFoundError:
    HAVE_GYM = False
else:
    HAVE_GYM = True
requires_gym = pytest.mark.skipif(not HAVE_GYM, reason="needs gymnasium (pip install 'navcli[gym]')")
"""For the tests of the Gym env, of training (which runs it) and on Gymnasium's toy MDPs."""


# -- small MDPs from Gymnasium's toy_text tables, solved here by value iteration
def tables(name: str, **kw):
    """Transition probabilities T, expected rewards R, rewards by landing Rt and terminal flags D."""
    gym = pytest.importorskip("gymnasium")
    P = gym.make(name, **kw).unwrapped.P
    S, A = len(P), len(P[0])
    T, R, Rt, D = np.zeros((S, A, S)), np.zeros((S, A)), np.zeros((S, A, S)), np.zeros((S, A, S), bool)
    for s in range(S):
        for a in range(A):
            for p, s2, r, d in P[s][a]:
                T[s, a, s2] += p
                R[s, a] += p * r
                Rt[s, a, s2] = r
                D[s, a, s2] |= d
    return T, R, Rt, D


def value_iteration(T, R, D, gamma):
    V = np.zeros(T.shape[0])
    for _ in range(10000):
        Q = R + gamma * np.einsum("sat,t->sa", T * ~D, V)
        if np.abs(Q.max(1) - V).max() < 1e-12:
            break
        V = Q.max(1)
    return V, Q


def learn(learner, T, Rt, D, start, *, steps=None, episodes=None, goal=None, seed=0):
    """Let ``learner`` act in the MDP (sampled with its own generator) for ``steps`` steps, or
    ``episodes`` episodes (each ended at a terminal state or ``goal``); returns the steps taken."""
    rng, cum, s, n, done_eps = np.random.default_rng(seed), T.cumsum(-1), start, 0, 0
    while (steps is None or n < steps) and (episodes is None or done_eps < episodes):
        a = learner.act(s)
        s2 = min(int(np.searchsorted(cum[s, a], rng.random())), T.shape[0] - 1)
        learner.observe(s, a, float(Rt[s, a, s2]), s2, bool(D[s, a, s2]))
        n += 1
        end = bool(D[s, a, s2]) or s2 == goal
        done_eps += end
        s = start if end else s2
    return n


def rollout(choose, T, R, D, start=36):
    """The return of a deterministic MDP's episode under ``choose`` (at most 100 steps)."""
    s, ret = start, 0.0
    for _ in range(100):
        a = choose(s)
        s2 = int(np.argmax(T[s, a]))
        ret += R[s, a]
        if D[s, a, s2] or s2 == 47:
            return ret
        s = s2
    return ret


def policy_value(T, R, D, policy, gamma):
    """The exact value of a deterministic policy: its Bellman equation solved as a linear system."""
    s = np.arange(len(policy))
    return np.linalg.solve(np.eye(len(policy)) - gamma * T[s, policy] * ~D[s, policy], R[s, policy])


def model_value_sd(T, R, Rt, D, policy, tries, gamma, start):
    """The standard deviation of a learned model's value of ``start`` under ``policy`` when each
    state's transitions are estimated from ``tries[s, policy[s]]`` samples, to first order: an error
    e in the estimated P(.|s, a) moves the value by e . W (W the reward of each landing plus gamma
    times the value after it), weighted by the discounted visits of s from ``start``; states are
    sampled independently. Infinite if the policy reaches an action never tried."""
    s, n = np.arange(len(policy)), tries[np.arange(len(policy)), policy]
    P, V = T[s, policy], policy_value(T, R, D, policy, gamma)
    visits = np.linalg.solve((np.eye(len(policy)) - gamma * P * ~D[s, policy]).T, np.eye(len(policy))[start])
    W = Rt[s, policy] + gamma * np.where(D[s, policy], 0.0, V[None, :])
    var = (P * (W - (P * W).sum(1, keepdims=True)) ** 2).sum(1)
    if (n[visits > 1e-12] == 0).any():
        return math.inf
    return math.sqrt((visits**2 * var / np.maximum(n, 1)).sum())


def frozen_lake_check(seed: int, steps: int = 4000) -> None:
    """Prioritized Sweeping on slippery FrozenLake from ``seed`` (its generator and the MDP's), and
    what must hold whatever the seed; see the test."""
    T, R, Rt, D = tables("FrozenLake-v1", is_slippery=True)
    gamma = 0.99
    V, Q = value_iteration(T, R, D, gamma)
    best = Q.argmax(1)
    assert V == pytest.approx(policy_value(T, R, D, best, gamma), abs=1e-9)  # V* is its greedy policy's value
    ps = PrioritizedSweeping(
        16, 4, gamma=gamma, backups=5, threshold=1e-4, explore=10, optimistic=1.0, rng=np.random.default_rng(seed)
    )
    learn(ps, T, Rt, D, 0, steps=steps, seed=seed - 1)
    # its model: every probability it estimated from n tries within 5 binomial standard errors of the
    # truth (landing in a hole or on the goal ends the episode: its model's last column)
    n = ps.tried
    truth = np.concatenate([T * ~D, (T * D).sum(-1, keepdims=True)], axis=-1)
    est = ps.counts / np.maximum(n, 1)[..., None]
    assert (n[0] >= ps.explore).all()  # every action tried at the start
    within = np.abs(est - truth) <= 5 * np.sqrt(truth * (1 - truth) / np.maximum(n, 1)[..., None])
    assert within[n > 0].all()
    # its greedy policy, evaluated exactly, and its value of the start: off the optimum by at most
    # 4 standard deviations of the two models' values (the optimal policy's and its own, from its
    # tries); the greedy policy is the best of its model, so its loss is at most their two errors
    policy = ps.greedy_policy().astype(np.int64)
    tol = 4 * (model_value_sd(T, R, Rt, D, best, n, gamma, 0) + model_value_sd(T, R, Rt, D, policy, n, gamma, 0))
    assert V[0] - policy_value(T, R, D, policy, gamma)[0] <= tol
    assert abs(ps.values[0] - V[0]) <= tol


def test_prioritized_sweeping_learns_slippery_frozen_lake_within_its_sampling_error():
    """What Prioritized Sweeping guarantees from 4000 steps whatever the seed: its model is the
    MDP's within sampling error, and so are its greedy policy's and its own value of the start.
    Not that the greedy policy is exactly optimal: some states' best actions win by 0.01-0.04, and
    an action underrated in its ``explore`` tries is not tried again (exactly optimal for 11 of
    seeds 1-20, and still for only 38 of 40 with 20000 steps and ``explore`` 100)."""
    frozen_lake_check(1)


def test_prioritized_sweeping_walks_the_cliff_edge_in_13_steps():
    T, R, Rt, D = tables("CliffWalking-v1")
    V, _ = value_iteration(T, R, D | (np.arange(48) == 47)[None, None, :], 1.0)
    assert V[36] == pytest.approx(-13)
    ps = PrioritizedSweeping(48, 4, gamma=1.0, backups=10, threshold=1e-3, explore=1, rng=np.random.default_rng(2))
    learn(ps, T, Rt, D, 36, episodes=30, goal=47)
    assert rollout(ps.greedy, T, R, D) == -13


def test_the_sweeps_plain_python_gives_the_array_expressions_bits():
    """Prioritized Sweeping backs up in plain Python for speed; its Q-values and its sweeps must be
    the module docstring's array expressions to the last bit (so a trained model file stays the
    same byte for byte). Checked on slippery FrozenLake after 1500 steps: the Q-values of every
    state with and without optimism, and ten more backups against the same backups done with
    arrays on a copy of the learner."""
    T, R, Rt, D = tables("FrozenLake-v1", is_slippery=True)
    ps = PrioritizedSweeping(16, 4, gamma=0.9, backups=3, threshold=1e-4, explore=3, optimistic=1.0)
    learn(ps, T, Rt, D, 0, steps=1500, seed=4)

    def q_array(L: PrioritizedSweeping, s: int, optimism: bool) -> np.ndarray:
        n = L.tried[s]
        q = (L.reward_sum[s] + L.gamma * (L.counts[s] @ L.values)) / np.maximum(n, 1)
        q[n == 0] = -np.inf
        if optimism:
            q[n < L.explore] = L.optimistic
        return q

    for s in range(16):
        for optimism in (True, False):
            assert ps.q_values(s, optimism).tobytes() == q_array(ps, s, optimism).tobytes()
    ps.priority[[0, 4, 8, 14]] = np.inf  # four states to back up, and whatever they raise
    ref = copy.deepcopy(ps)
    raised = 0
    for _ in range(10):
        s = int(ref.priority.argmax())
        assert ref.priority[s] > ref.threshold  # ten backups to compare
        ref.priority[s] = 0.0
        old = ref.values[s]
        ref.values[s] = q_array(ref, s, True).max()
        preds = np.nonzero(ref.counts[:, :, s].sum(1))[0]
        p = (ref.counts[preds, :, s] / np.maximum(ref.tried[preds], 1)).max(axis=1) * abs(ref.values[s] - old)
        ref.priority[preds] = np.maximum(ref.priority[preds], np.where(p > ref.threshold, p, 0.0))
        raised += int((p > ref.threshold).sum())
    assert ps.sweep(10) == 10
    assert raised > 0  # some predecessor's priority was raised: the comparison covers it
    assert ps.values.tobytes() == ref.values.tobytes()
    assert ps.priority.tobytes() == ref.priority.tobytes()


def steps_to_the_cliff_path(learner, T, R, Rt, D, max_episodes):
    """Steps ``learner`` takes, an episode at a time, until its greedy policy walks the 13-step
    path (None: not within ``max_episodes``)."""
    total = 0
    for _ in range(max_episodes):
        total += learn(learner, T, Rt, D, 36, episodes=1, goal=47)
        if rollout(learner.greedy, T, R, D) == -13:
            return total
    return None


def test_q_learning_finds_the_cliff_path_too_but_needs_more_steps():
    T, R, Rt, D = tables("CliffWalking-v1")
    ps = PrioritizedSweeping(48, 4, gamma=1.0, backups=10, threshold=1e-3, explore=1, rng=np.random.default_rng(2))
    ql = QLearning(48, 4, alpha=0.5, gamma=1.0, epsilon=0.1, rng=np.random.default_rng(2))
    steps_ps = steps_to_the_cliff_path(ps, T, R, Rt, D, 30)
    steps_q = steps_to_the_cliff_path(ql, T, R, Rt, D, 300)
    assert steps_ps is not None and steps_q is not None  # both find it
    assert steps_q > 2 * steps_ps  # the model-based learner needs far fewer real steps (Moore & Atkeson)


# -- features, actions, the hand-coded policy
def situation(target=(3.0, 0.0), landmarks=None, target_radius=0.1):
    b = Beliefs(0.0, Pose(0.0, 0.0, 0.0), None, None, ())
    t = None if target is None else FuzzyPoint(*target, (target_radius, target_radius * 0.7, target_radius * 0.3, 0.0))
    return Situation(b, t, None, "memory", 0.0, landmarks or {})


def point(x, y, r=0.1):
    return FuzzyPoint(x, y, (r, r * 0.7, r * 0.3, 0.0))


def test_features_count_the_sectors_and_average_the_best_four():
    lms = {k: point(2.0, 0.1 * i, 0.05 * (i + 1)) for i, k in enumerate("ABCDE")}  # five ahead
    lms["F"] = point(-2.0, 0.0)  # one behind
    lms["T"] = point(3.0, 0.0)  # the target landmark: not one of them
    f = features(situation(landmarks=lms), target_key="T")
    assert f.count == pytest.approx((4 + 1) / 6)  # N(s) = min(4, |L(s)|)
    best4 = sorted(lms[k].imprecision() for k in "ABCDE")[:4]
    assert f.landmark_imprecision == pytest.approx((sum(best4) / 4 + lms["F"].imprecision() + 4 * 1.0) / 6)
    assert f.distance == pytest.approx(3.0)
    lost = features(situation(target=None))
    assert (lost.distance, lost.target_imprecision, lost.count, lost.landmark_imprecision) == (math.inf, 1.0, 0.0, 1.0)


def test_980_states_each_reached_once():
    seen = {
        state_index(Features(d, i, c, m))
        for d in (0.1, 1, 2, 4, 9)
        for i in (0, 0.03, 0.05, 0.08, 0.12, 0.2, 1)
        for c in (0, 0.5, 0.8, 2)
        for m in (0.1, 0.3, 0.4, 0.6, 0.7, 0.9, 1)
    }
    assert len(seen) == 980 == math.prod(SHAPE) and seen == set(range(980))
    assert discretise(Features(0.9, 0.0, 0.0, 0.0))[0] == 1  # on a bound: the interval above


def test_actions_move_and_look_as_section_5_3_says():
    lms = {"A": point(2.0, 0.0, 0.3), "B": point(2.0, 0.2, 0.3), "C": point(1.0, 1.7, 0.02)}  # 2 ahead, 1 at +60
    s = situation(target=(0.0, 3.0), landmarks=lms)  # the target 90 deg left
    kw = dict(bidder="la", value=0.5, speed=0.3, pan_limit=math.radians(100))
    mb = action_bids(MB, s, **kw)
    assert [b.resource for b in mb] == ["motion"] and mb[0].action.heading == pytest.approx(math.pi / 2)
    mot = {b.resource: b.action for b in action_bids(MOT, s, side=-1.0, **kw)}
    assert mot["motion"].heading == pytest.approx(0.0, abs=1e-9) and mot["camera"].pan == pytest.approx(math.pi / 2)
    assert action_bids(MVT, s, **kw)[1].action.pan == pytest.approx(math.pi / 2)
    assert action_bids(MLL, s, **kw)[1].action.pan == pytest.approx(math.radians(-60))  # empty, nearest ahead
    assert action_bids(MVL, s, **kw)[1].action.pan == pytest.approx(0.0)  # A and B blurred, C sharp
    lost = action_bids(MB, situation(target=None), **kw)
    assert abs(lost[0].action.heading) == pytest.approx(math.pi)  # the paper's pacing


def lost_at(theta):
    """A situation with the target lost, the robot's odometry heading ``theta``."""
    return situation(target=None)._replace(beliefs=Beliefs(0.0, Pose(0.0, 0.0, theta), None, None, ()))


def paced_moves(pace, headings, ticks=2):
    """The moves a LearningAgent bids, MB in every action, the robot's odometry heading
    ``headings[k]`` through action k (``ticks`` ticks an action)."""
    from navcli.learning.learning_agent import LearningAgent
    from navcli.params import LEARNING

    params = replace(LEARNING, pace=pace, action_s=ticks * 0.1)
    agent = LearningAgent(lambda state: MB, params, max_speed=0.3)
    return [[agent.bid(lost_at(h))[0].action for _ in range(ticks)] for h in headings]


def test_a_lost_target_is_paced_at_pi_fixed_in_the_odometry_frame():
    """Section 5.3's pacing: the first lost action aims at pi from the robot's heading and is driven
    backwards (the body keeps its heading); the next aims pi from that aim, forwards, whatever the
    robot's heading became; within an action the aim stays where it was set."""
    (a1, a1b), (a2, a2b), (a3, _) = paced_moves(True, [0.0, 0.0, 0.0])
    assert a1.speed == -0.3 and a1.heading == pytest.approx(0.0, abs=1e-9)  # back along the line
    assert a2.speed == 0.3 and a2.heading == pytest.approx(0.0, abs=1e-9)  # forward again
    assert a3.speed == -0.3  # and back: pacing
    # the robot turned 0.4 rad during the second action: its aim stays the first action's opposite
    (_, _), (b2, _) = paced_moves(True, [0.0, 0.4])
    assert b2.heading == pytest.approx(-0.4) and b2.speed == 0.3
    # off: pi in the robot's own frame at every tick, driven forward (the Pilot turns it)
    (c1, c1b), (c2, _) = paced_moves(False, [0.0, 0.4])
    assert abs(c1.heading) == pytest.approx(math.pi) and c1.speed == 0.3 and abs(c2.heading) == pytest.approx(math.pi)


@pytest.mark.parametrize(
    "intervals, action",
    [
        # "If the robot is far from the target and there are few landmarks, it executes an MLL"
        pytest.param((4, 0, 0, 0), MLL, id="far, few landmarks: MLL"),
        pytest.param((3, 0, 1, 6), MLL, id="far (3 m), few landmarks, blurred: still MLL"),
        # "if there are enough landmarks but they are highly imprecise, an MVL is executed"
        pytest.param((4, 0, 2, 3), MVL, id="far, enough landmarks, highly imprecise: MVL"),
        # "if the landmarks are good enough, an MOT is executed if the target's location has a high
        # imprecision, and an MB is executed otherwise"
        pytest.param((4, 4, 3, 0), MOT, id="far, landmarks good, target highly imprecise: MOT"),
        pytest.param((3, 3, 3, 2), MB, id="far, landmarks good, target precise: MB"),
        # "If the robot is not far from the target but its location is highly imprecise, then an MVL
        # or an MVT is executed, depending on whether the overall imprecision of landmarks is high or not"
        pytest.param((2, 5, 0, 5), MVL, id="not far, target highly imprecise, landmarks imprecise: MVL"),
        pytest.param((1, 6, 3, 2), MVT, id="not far, target highly imprecise, landmarks sharp: MVT"),
        # "if the target's location has low imprecision, then if the robot is really near the target it
        # executes an MVT, and an MB is executed if the distance is medium"
        pytest.param((0, 1, 0, 6), MVT, id="really near, target precise: MVT"),
        pytest.param((2, 0, 0, 6), MB, id="medium distance, target precise: MB"),
    ],
)
def test_the_hand_coded_policy_follows_section_6(intervals, action):
    """Section 6's hand-coded policy, sentence by sentence (the intervals: distance, I(t), count,
    I-bar; the bounds of each word in :mod:`navcli.learning.hand_coded`)."""
    assert hand_coded_action(int(np.ravel_multi_index(intervals, SHAPE))) == action


# -- the run option, the mission, the model file, the environment
def test_run_spec_carries_the_navigation_choice(make_scenario):
    from navcli import NavcliError
    from navcli.config import RunSpec

    sc = make_scenario()
    a, h = RunSpec.build(sc), RunSpec.build(sc, navigation="hand-coded")
    assert a.navigation == "agents" and a.to_json()["navigation"] == "agents" and a.run_id != h.run_id
    assert RunSpec.from_json(h.to_json(), sc.text) == h and h.metadata()["navigation"] == "hand-coded"
    with pytest.raises(NavcliError, match="unknown navigation policy 'hand-coded:x'"):
        RunSpec.build(sc, navigation="hand-coded:x")


def test_learning_parameters_are_a_fifth_group():
    from navcli.params import Params

    p = Params().override({"learning.backups": 5, "learning.gamma": 0.9})
    assert "learning" in Params.GROUPS and p.learning.backups == 5 and Params.from_json(p.to_json()) == p
    assert p.flat()["learning.max_actions"] == 500


def test_a_hand_coded_mission_counts_its_actions_and_their_reward():
    from navcli import RunSpec, load_scenario, run_mission
    from navcli.learning.actions import ACTIONS

    spec = RunSpec.build(load_scenario(SCENARIOS / "landmarks-12.yaml"), navigation="hand-coded", time_limit=12)
    s = run_mission(spec, record=False).summary
    la, n = s["learning"], s["learning"]["actions"]
    assert s["navigation"] == "hand-coded" and 5 <= n <= 12  # 12 s less the initial sweep, 1 s each
    assert sum(la["action_counts"].values()) == n and set(la["action_counts"]) == set(ACTIONS)
    assert -10 * n <= la["reward"] <= -1 * n < 0  # each action costs 1 (MB) to 10 (MLL), section 5.3


def test_the_model_file_round_trips_and_refuses_garbage(tmp_path):
    from navcli.learning import model_file

    ps = PrioritizedSweeping(980, 5, rng=np.random.default_rng(0))
    for s in list(range(10)) * 2:  # each action tried twice: past exploring, the values are the model's
        for a in range(5):
            ps.observe(s, a, -1.0, s + 1)
    path = model_file.save(tmp_path / "m.npz", ps, {"seed": 3})
    arrays, meta = model_file.load(path)
    again = PrioritizedSweeping(980, 5)
    again.load_arrays(arrays)
    assert (
        meta == {"seed": 3, "algorithm": "prioritized-sweeping"}
        and (again.counts == ps.counts).all()
        and (again.values == ps.values).all()
    )
    again.priority[:] = ps.priority[:] = 0.0
    for learner in (ps, again):  # the reloaded one sweeps as the original: its predecessors and tries came back
        learner.observe(9, 0, 5.0, 10)  # state 9 turns good: its predecessors change
    assert again.values.tobytes() == ps.values.tobytes() and again.priority.tobytes() == ps.priority.tobytes()
    assert ps.values[8] > -1.0  # the step's backups reached a predecessor (the check has a subject)
    (tmp_path / "bad.npz").write_text("no")
    with pytest.raises(model_file.ModelError, match="bad.npz"):
        model_file.load(tmp_path / "bad.npz")
    assert model_file.load_policy().shape == (980,)  # the bundled model loads


def test_an_evaluation_takes_over_only_the_trials_a_greedy_policy_would_repeat():
    """The trainer reuses a test trial when the new greedy policy chooses the same action in every
    state the trial visited. Run for real: a policy changed everywhere else runs the very same
    trials; a change in one visited state sends back exactly the trials that visited it."""
    from navcli import load_scenario
    from navcli.learning.features import N_STATES
    from navcli.training.task import random_starts, task_spec
    from navcli.training.trainer import EvaluationMemo, evaluate

    spec = task_spec(load_scenario(SCENARIOS / "landmarks-12.yaml"), {"learning.max_actions": 6})
    starts = random_starts(spec, 3, 5)
    policy = np.random.default_rng(0).integers(0, 5, N_STATES).astype(np.int8)
    first = evaluate(spec, policy, starts)
    memo = EvaluationMemo()
    for i, r in enumerate(first):
        memo.remember(i, policy, r)
    seen = set().union(*(r.visited for r in first))
    assert all(r.visited for r in first) and len(seen) < N_STATES
    elsewhere = policy.copy()
    unseen = [s for s in range(N_STATES) if s not in seen]
    elsewhere[unseen] = (elsewhere[unseen] + 1) % 5
    assert all(memo.reusable(i, elsewhere) is r for i, r in enumerate(first))
    again = evaluate(spec, elsewhere, starts)  # what the memo claims, run
    assert [(r.outcome, r.actions, r.counts, r.visited) for r in again] == [
        (r.outcome, r.actions, r.counts, r.visited) for r in first
    ]
    s0 = first[0].visited[0]
    changed = policy.copy()
    changed[s0] = (changed[s0] + 1) % 5
    assert [memo.reusable(i, changed) is None for i in range(3)] == [s0 in r.visited for r in first]


def test_run_refuses_a_bad_navigation(tmp_path):
    from typer.testing import CliRunner

    from navcli.cli import app

    r = CliRunner().invoke(app, ["run", str(SCENARIOS / "landmarks-12.yaml"), "--navigation", "bogus"])
    assert r.exit_code == 2 and "unknown navigation" in r.output
    r = CliRunner().invoke(
        app, ["run", str(SCENARIOS / "landmarks-12.yaml"), "--navigation", f"learned:{tmp_path / 'none.npz'}"]
    )
    assert r.exit_code == 2 and "no such model file" in r.output


@requires_gym
def test_the_gymnasium_environment_passes_the_checker():
    import gymnasium as gym
    from gymnasium.utils.env_checker import check_env

    import navcli.envs  # noqa: F401  (registers it)

    env = gym.make("navcli/LandmarkNavigation-v0", overrides={"learning.max_actions": 2})
    check_env(env.unwrapped, skip_render_check=True)
    assert env.observation_space.n == 980 and env.action_space.n == 5
    o1, _ = env.reset(seed=4)
    o2, _ = env.reset(seed=4)
    assert o1 == o2
    _, r, term, trunc, _ = env.step(MLL)
    assert r == -10.0 and not term
    _, r, term, trunc, _ = env.step(MB)
    assert r == -1.0 and trunc  # max_actions = 2


@requires_gym
@pytest.mark.parametrize(
    "outcome,reached,ended,want",
    [
        ("reached", True, False, (True, False)),  # an end state
        ("blocked", False, True, (True, False)),  # the Rescuer gave up: an end state too, in either task
        ("timeout", False, True, (False, True)),  # max_actions or the time limit: cut from outside
        (None, False, False, (False, False)),  # the trial goes on
    ],
)
@pytest.mark.parametrize("paper_task", [0, 1])
def test_the_environment_follows_gymnasiums_terminated_truncated_contract(outcome, reached, ended, want, paper_task):
    from navcli.envs import LandmarkNavigationEnv

    env = LandmarkNavigationEnv(overrides={"learning.paper_task": paper_task})

    class Ending:  # the task's answer to one step, as NavigationTask gives it
        terminal = reached  # the learner's view (the simpler task does not count blocked as terminal)

        def step(self, action):
            self.outcome = outcome
            return 7, -1.0, reached, ended

    env.task = Ending()
    _, _, terminated, truncated, info = env.step(MB)
    assert (terminated, truncated) == want and info["outcome"] == outcome


@requires_gym
def test_the_environment_finds_its_room_inside_the_package():
    from navcli.envs.landmark_navigation import DEFAULT_SCENARIO

    import navcli

    assert DEFAULT_SCENARIO.is_file() and Path(navcli.__file__).parent in DEFAULT_SCENARIO.parents


def test_training_records_each_trial_and_resumes_where_the_model_was_saved(tmp_path):
    import csv

    from navcli.analysis import read_log
    from navcli import load_scenario
    from navcli.learning.actions import ACTIONS, reward_of
    from navcli.training.task import random_starts, task_spec
    from navcli.training.trainer import train, trials_paths

    sc = load_scenario(SCENARIOS / "landmarks-12.yaml")
    spec = task_spec(sc, {"learning.max_actions": 4})  # short trials: most end at 4 actions
    out = tmp_path / "m.npz"
    first = train(spec, trials=3, eval_every=2, eval_starts=2, seed=7, out=out, workers=1, log="full")
    csv_path, logs = trials_paths(out)
    rows = list(csv.DictReader(csv_path.open()))
    assert [int(r["trial"]) for r in rows] == [0, 1, 2] and [p.trials for p in first.curve] == [0, 2, 3]
    curve = list(csv.DictReader(open(f"{out.with_suffix('')}-curve.csv")))
    assert [int(c["trials"]) for c in curve] == [0, 2, 3] and first.hand_coded_reward < 0  # every action costs
    assert {float(c["hand_coded_reward_per_trial"]) for c in curve} == {round(first.hand_coded_reward, 2)}
    assert {o: sum(r["outcome"] == o for r in rows) for o in first.outcomes} == first.outcomes
    for r in rows:
        counts = [int(r[a]) for a in ACTIONS]
        assert sum(counts) == int(r["actions"]) <= 4 and float(r["reward"]) == reward_of(counts)
        log = read_log(logs / f"trial-{int(r['trial']):05d}.mcap")  # every tick of the trial, closed properly
        s = log.summary
        assert (
            s["outcome"] == r["outcome"] and s["navigation"] == "learned" and s["learning.actions"] == int(r["actions"])
        )
        assert len(log["/robot/pose"]) == s["ticks"] + 1
    start = random_starts(spec, 1, np.random.SeedSequence([7, 1]).generate_state(1)[0])[0]
    assert (float(rows[1]["x"]), float(rows[1]["y"]), int(rows[1]["seed"])) == (
        round(start.x, 3),
        round(start.y, 3),
        start.seed,
    )
    again = train(spec, trials=5, eval_every=2, eval_starts=2, out=out, resume=out, workers=1)  # 5 in all
    rows2 = list(csv.DictReader(csv_path.open()))
    assert again.trials == 5 and [int(r["trial"]) for r in rows2] == [0, 1, 2, 3, 4] and rows2[:3] == rows
    assert len(list(logs.glob("*.mcap"))) == 3  # summary only, the second time
    from navcli.learning.model_file import ModelError

    with pytest.raises(ModelError, match="already holds 5 trials"):  # --trials is a total, and it has them
        train(spec, trials=5, eval_every=2, eval_starts=2, out=out, resume=out, workers=1)


def test_too_few_tries_lock_the_learner_into_the_cheapest_loop():
    """A state left only by one action (cost 10), one try in ten, every other action looping back
    (MB's cost 1, the rest 5): the undiscounted model that has seen no way out sinks, and the
    cheapest loop wins for good. An action is judged on too few tries when all its ``explore``
    tries loop, chance 0.9 ** explore: 0.81 at 2, 0.047 at 29 (LearningParams.explore)."""

    def locked(explore: int, seed: int) -> bool:
        ps = PrioritizedSweeping(
            1, 5, gamma=1.0, backups=5, threshold=1e-3, explore=explore, rng=np.random.default_rng(seed)
        )
        world = np.random.default_rng([seed, 9])
        for _ in range(500):
            a = ps.act(0)
            out = a == 1 and world.random() < 0.1
            ps.observe(0, a, (-1.0, -10.0, -5.0, -5.0, -5.0)[a], 0, terminal=out)
            if out:
                return False
        return True

    assert sum(locked(2, seed) for seed in range(40)) >= 24  # 0.81 of 40: 32 expected
    assert sum(locked(29, seed) for seed in range(40)) <= 6  # 0.047 of 40: 2 expected
