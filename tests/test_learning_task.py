"""The learning paper's task (issue 23): each of its conditions, the preset that sets them, and
the trials that end on them. Every test has its control: the same thing without the condition."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENARIOS
from navcli.beliefs import Beliefs, Bump
from navcli.config import ConfigError, RunSpec
from navcli.fuzzy import ALPHAS, FuzzyPoint
from navcli.geometry import Pose
from navcli.training.comparison import PolicyError, parse_policy
from navcli.learning.features import N_STATES
from navcli.training.task import PAPER_TASK, NavigationTask, Start, task_spec
from navcli.mission import Mission
from navcli.navigation.rescuer import Rescuer
from navcli.navigation.situation import Situation
from navcli.params import NAVIGATION, PILOT, ROBOT, Params
from navcli.pilot.base import Pilot
from navcli.scenario import load_scenario

ROOM = SCENARIOS / "landmarks-12.yaml"
CRISP = (0.0,) * len(ALPHAS)


def landmark_room(make_scenario, **over):
    """A 6 m x 4 m room, the target landmark T 2 m ahead of the robot, in view from the start."""
    return make_scenario(target={"landmark": "T", "tolerance": 0.3},
                         landmarks=[{"id": "T", "at": [3.0, 2.0]}, {"id": "A", "at": [4.0, 3.2]}], **over)


# -- the preset --------------------------------------------------------------------------------
def test_the_paper_task_sets_its_conditions_unless_given_others():
    spec = RunSpec.build(load_scenario(ROOM))
    task = task_spec(spec)
    flat = task.params.flat()
    assert all(flat[k] == v for k, v in PAPER_TASK.items())
    assert spec.params.flat()["vision.told_target"] == 1  # the spec itself is left alone
    mine = task_spec(RunSpec.build(load_scenario(ROOM), overrides={"pilot.looks": 1, "vision.told_target": 1}))
    assert mine.params.vision.told_target == 0  # 1 is the default: the task sets it all the same
    strict = task_spec(RunSpec.build(load_scenario(ROOM), overrides={"navigation.reach_imprecision": 0.04}))
    assert strict.params.navigation.reach_imprecision == 0.04 and strict.params.navigation.reach_confident == 1
    first = RunSpec.build(load_scenario(ROOM), overrides={"learning.paper_task": 0})
    assert task_spec(first) is first  # navcli's first task: nothing set
    assert Params().learning.gamma == 1.0  # the paper's objective: the total reward


def test_a_line_target_cannot_be_left_untold(make_scenario):
    sc = make_scenario(target={"line": [[5.0, 0.5], [5.0, 3.5]]})
    with pytest.raises(ConfigError, match="told_target"):
        RunSpec.build(sc, overrides={"vision.told_target": 0})


# -- the robot knows nothing at the start -------------------------------------------------------
def test_a_target_not_told_is_unknown_until_the_camera_sees_it(make_scenario):
    sc = landmark_room(make_scenario)
    told = Mission(RunSpec.build(sc))
    assert told.perceive().target is not None  # told at the start: known before any image
    m = Mission(RunSpec.build(sc, overrides={"vision.told_target": 0, "navigation.rescuer_looks": 0}))
    b = m.perceive()
    assert b.target is None and b.target_at is None and b.target_spread == pytest.approx(2 * math.pi)
    for _ in range(40):  # facing T: the Pilot's look-ahead (eq. 1) takes an image once it has driven a little
        m.step()
        if m.perceive().target is not None:
            break
    b = m.perceive()
    assert b.target is not None and math.dist(m.world.pose.to_world(b.target), (3.0, 2.0)) < 0.3


# -- the camera is the Learning Agent's ----------------------------------------------------------
def test_without_looks_the_pilot_bids_for_no_camera_and_its_reflex_does_not_look():
    quiet = Pilot(replace(PILOT, looks=0), ROBOT)
    quiet.since_look = 5.0  # eq. 1 would bid its cap of 0.9
    assert quiet.look_bid() == 0.0
    bump = Bump(0.0, "wall", (0.3, 0.0), 0.0)  # ahead
    out = quiet.decide(Beliefs(0.0, Pose(0, 0, 0), (5.0, 0.0), None, (), 0.0, None, (bump,)))
    assert quiet._reflex and all(phase != "look" for phase, _ in quiet._reflex)
    assert not any(b.resource == "camera" for b in out.bids)
    looking = Pilot(PILOT, ROBOT)  # the control: the reflex stops, looks around, backs up
    looking.decide(Beliefs(0.0, Pose(0, 0, 0), (5.0, 0.0), None, (), 0.0, None, (bump,)))
    assert [phase for phase, _ in looking._reflex] == ["stop", "look", "backup"]


def situation(t=0.0, I_a=0.0, aim=(3.0, 4.0)):
    b = Beliefs(t, Pose(0, 0, 0), aim, None, (), 0.0)
    return Situation(b, None if aim is None else FuzzyPoint(*aim, CRISP), None, "memory", I_a)


def test_without_looks_the_rescuer_neither_sweeps_nor_scans_a_lost_target():
    quiet = Rescuer(replace(NAVIGATION, rescuer_looks=0), np.random.default_rng(0))
    assert quiet.state == "normal"  # no initial sweep
    out = quiet.decide(situation(I_a=1.0), lambda f: None)  # lost
    assert quiet.state == "normal" and not out.bids
    scanning = Rescuer(replace(NAVIGATION, initial_sweep=0), np.random.default_rng(0))  # the control
    out = scanning.decide(situation(I_a=1.0), lambda f: None)
    assert scanning.state == "lost" and any(b.resource == "camera" for b in out.bids)


# -- blocked ends the trial ----------------------------------------------------------------------
def test_with_blocked_ends_the_first_blocked_situation_ends_the_mission():
    """No progress toward the target for the blocked window: the paper's trial terminates there;
    the control asks the map for a diverting target instead."""
    def blocked(params):
        r, asked, t = Rescuer(params, np.random.default_rng(0)), [], 0.0
        while t < r.window_s + 5.0:
            t += 0.1
            out = r.decide(situation(t), lambda f: asked.append(f))
            if out.give_up or asked:
                return out, asked
        raise AssertionError("never blocked")

    out, asked = blocked(replace(NAVIGATION, initial_sweep=0, blocked_ends=1))
    assert out.give_up == "no progress toward the target" and not asked
    out, asked = blocked(replace(NAVIGATION, initial_sweep=0))
    assert out.give_up is None and asked == [None]


# -- success only when confident -----------------------------------------------------------------
def test_reached_only_when_the_belief_too_is_within_reach(make_scenario):
    """Landmark T's reach is 0.3 + 0.15 + 0.25 = 0.7 m. The body at 0.6 m: a belief 0.5 m away
    whose 70 % cut reaches 0.1 m further is confident (0.6 <= 0.7); one 0.3 m wide is not
    (0.8); with reach_imprecision the belief's I(t) must also be below that bound."""
    sc = landmark_room(make_scenario)
    m = Mission(RunSpec.build(sc, overrides={"navigation.reach_confident": 1}))
    near = FuzzyPoint(0.5, 0.0, (0.2, 0.15, 0.1, 0.05))
    wide = FuzzyPoint(0.5, 0.0, (0.5, 0.4, 0.3, 0.2))
    far = FuzzyPoint(0.9, 0.0, (0.0, 0.0, 0.0, 0.0))
    assert m._confident(near) and not m._confident(wide) and not m._confident(far) and not m._confident(None)
    body_only = Mission(RunSpec.build(sc))
    assert body_only._confident(None) and body_only._confident(wide)  # the control: the body alone
    strict = Mission(RunSpec.build(sc, overrides={"navigation.reach_confident": 1,
                                                  "navigation.reach_imprecision": near.imprecision() / 2}))
    assert not strict._confident(near)


def test_a_trial_that_ends_blocked_is_terminal_in_the_paper_task_only(make_scenario):
    """The paper's trial "terminates ... if the robot is blocked": the learner hears a terminal
    step (value 0, as the target's); in navcli's first task the same ending is a cut, not
    terminal. (The mission is ended blocked by hand here; the Rescuer's own ending is tested
    above.)"""
    sc = landmark_room(make_scenario)
    for paper in (1, 0):
        task = NavigationTask(RunSpec.build(sc, overrides={"learning.paper_task": paper}))
        task.reset(Start(1.0, 1.0, 0.0, 3))
        task.step(0)
        assert task.outcome is None and task.terminal is False
        task.mission._end("blocked", "blocked after 2.0 s: no progress toward the target")
        _, _, reached, ended = task.step(0)
        assert not reached and ended and task.outcome == "blocked" and task.terminal is bool(paper)


# -- baselines -----------------------------------------------------------------------------------
def test_constant_policies_are_baselines():
    p = parse_policy("all-MLL")
    assert p.kind == "all-MLL" and (p.actions() == 1).all() and len(p.actions()) == N_STATES
    with pytest.raises(PolicyError, match="all-MB"):
        parse_policy("all-XY")
