"""The Learning Agent's task as trials, action by action (learning-agent paper, section 6): the
robot starts at a random place of the scenario's room and must reach the target; a trial ends
when it has, after ``max_actions`` actions, or when the robot is blocked.

:class:`NavigationTask` runs a :class:`~navcli.mission.Mission` without a log, its Navigation
system's Learning Agent told each action by the caller (:meth:`NavigationTask.step`), and
reports the belief state after it, the action's reward and whether the trial ended: what both
learners and the Gymnasium environment (:mod:`navcli.envs`) step through.

**The paper's task** (``learning.paper_task`` on, the default; :data:`PAPER_TASK`), its conditions
as the paper states them:

- "The target is visible from the robot's initial location" (introduction): a trial starts where
  the target lies within the camera's range with nothing in the way (:func:`random_starts`); its
  heading is random, so the target may be behind, where the pan unit cannot look;
- the robot "knows nothing" at the start (section 5.1: "a starting belief state in which it
  knows nothing"): the target is one of the landmarks, visible, but its position is not given
  (``vision.told_target`` off), nor is a first image of it (``learning.first_sighting`` off; on,
  the robot starts with the sighting a look from its start would give); it knows the target once
  a look finds it (a search, or a look for the target: :mod:`navcli.vision.routines`);
- the camera is shared as the papers share it: the Learning Agent bids for it with every action
  but MB, and the Pilot bids for it as the pilot paper's Pilot does (``pilot.looks`` on, as
  everywhere: eq. 1's look-ahead, a reflex's looks around), so an action that leaves the camera
  free lets the Pilot look (the learning paper's aim: a policy "that freed the camera for use by
  the low-level obstacle avoidance routines"); the Rescuer neither sweeps nor scans
  (``navigation.rescuer_looks`` off: a lost target is the Learning Agent's). ``--param
  pilot.looks=0`` keeps the camera the Learning Agent's alone;
- with the target's heading unknown, the robot paces (``learning.pace``,
  :mod:`navcli.learning.learning_agent`);
- a trial succeeds when the robot "reaches the target (and is confident that it has reached the
  target)": the body within reach of the landmark (as a mission's), and the robot sure of it,
  every place its belief of the target allows at the papers' 70 % cut within that reach
  (``navigation.reach_confident`` on; our reading of "confident", in the papers' own terms, the
  cut that defines I(l)); ``navigation.reach_imprecision`` adds a bound on I(t) itself;
- it terminates "if the robot is blocked" (``navigation.blocked_ends`` on: the Rescuer's first
  blocked situation ends it): "the robot can be blocked by the landmarks or by the wall", so
  ``navigation.blocked_bumps`` bumps within the blocked window, or the Pilot's report of an
  obstacle it cannot easily avoid, end it whether or not the target is known
  (:class:`~navcli.navigation.rescuer.Rescuer`). No progress toward a known target within the
  window is not "blocked" here (``navigation.blocked_no_progress`` off): nothing stopped the
  robot, so the trial goes on; after 500 actions (``max_actions``) it is cut, its outcome
  ``timeout``, counted apart from ``blocked``;
- the objective is the total reward of the actions taken, undiscounted (``learning.gamma`` 1),
  "to minimize the total cost of the actions taken to reach the target". **What a blocked ending
  is worth to the learner** (the paper does not say; ours): not 0. Reaching the target is the
  only end state of value 0; a blocked trial has not reached it, and what reaching it would still
  have cost is unknown, so the learner takes the blocked ending as it takes the 500-action cut:
  the trial stops, and the value of the state it stopped in stands for the rest
  (``learning.blocked_terminal`` off). On, blocked is an end state of value 0, and
  a learner is paid for getting blocked cheaply.

**Presets lie under the user's word**: the task's conditions are a preset applied under the
scenario's own values and the command line's (:func:`task_spec`, ``RunSpec.build(preset=...)``),
so any ``--param`` given is heard, whatever its value (``--param vision.told_target=1`` gives a
told target). ``learning.paper_task=0`` gives a simpler task: the target told at the start
(+-2 cm, never forgotten), the camera free to all, starts anywhere 1.5 m from the target,
success by the body alone, blocked not terminal. The initial sweep, where the Rescuer makes one,
comes before the first action and is not counted.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..config import RunSpec
from ..geometry import Point, Pose, distance_to_segment
from ..mission import Mission
from ..runner import Observer, advance, close_log, open_log, recording
from ..scenario import Scenario
from ..learning.actions import REWARDS

PAPER_TASK = {
    "vision.told_target": False,
    "navigation.rescuer_looks": False,
    "navigation.blocked_ends": True,
    "navigation.blocked_no_progress": False,
    "navigation.reach_confident": True,
}
"""The conditions of the paper's task (module docstring), by parameter: a preset, under the
scenario's and the command line's values (:func:`task_spec`)."""
START_CLEARANCE = 0.3  # m between the robot's body and any wall, landmark or obstacle at a start
START_MIN_DISTANCE = 1.5  # m from the target at least: a trial that starts at the target teaches nothing


@dataclass(frozen=True)
class Start:
    """Where a trial starts: position (m), heading (rad), and the mission's seed (sensor noise)."""

    x: float
    y: float
    heading: float
    seed: int


def random_starts(spec: RunSpec, n: int, seed: int) -> list[Start]:
    """``n`` starts drawn uniformly over the free floor of ``spec``'s room (clear of walls,
    landmarks and obstacles by :data:`START_CLEARANCE`, at least :data:`START_MIN_DISTANCE` from
    the target), with headings uniform and seeds, all from ``seed``. Under the paper's task the
    target is also visible from each (:func:`target_in_view`)."""
    scenario = spec.scenario
    rng = np.random.default_rng(seed)
    a, r = scenario.arena, spec.params.robot.radius + START_CLEARANCE
    in_view = spec.params.learning.paper_task
    out: list[Start] = []
    while len(out) < n:
        x, y = rng.uniform(r, a.width - r), rng.uniform(r, a.height - r)
        if math.dist((x, y), scenario.target.point) < START_MIN_DISTANCE or not _clear(scenario, (x, y), r):
            continue
        heading, trial_seed = float(rng.uniform(-math.pi, math.pi)), int(rng.integers(2**31))
        if in_view and not target_in_view(scenario, (float(x), float(y))):
            continue
        out.append(Start(float(x), float(y), heading, trial_seed))
    return out


def target_in_view(scenario: Scenario, p: Point) -> bool:
    """Is the target visible from ``p`` (the paper's "the target is visible from the robot's
    initial location"): within the camera's range, and no landmark, obstacle or wall in the line
    of sight (the camera's own test, :meth:`~navcli.vision.camera.Camera.sight`, for a look
    straight at it; whether the pan unit can turn that way depends on the heading)?"""
    from ..vision.camera import Camera

    t = scenario.target
    key = t.landmark or "target"
    facing = Pose(p[0], p[1], math.atan2(t.point[1] - p[1], t.point[0] - p[0]))
    return Camera(scenario, np.random.default_rng(0)).sight(facing)(t.point[0], t.point[1], key)


def _clear(scenario: Scenario, p: Point, r: float) -> bool:
    for o in scenario.objects:
        if o.kind in ("wall", "target"):
            continue
        if distance_to_segment(p, o.a, o.b) < r + o.radius:
            return False
    return True


def task_spec(scenario: Scenario, overrides: Mapping[str, Any] | None = None, **choices: Any) -> RunSpec:
    """The run configuration of a learning-task run in ``scenario``: with ``learning.paper_task``
    on (the scenario's or ``overrides``'), the paper's conditions (:data:`PAPER_TASK`) as a preset
    under the scenario's and ``overrides``' values, so every value the user gives is heard; off,
    the simpler task (module docstring). ``choices`` as :meth:`RunSpec.build`'s."""
    paper = scenario.params.override(overrides or {}).learning.paper_task
    return RunSpec.build(scenario, overrides=overrides, preset=PAPER_TASK if paper else None, **choices)


def spec_at(base: RunSpec, start: Start) -> RunSpec:
    """``base`` with the robot at ``start`` and its seed."""
    sc = base.scenario
    robot = dataclasses.replace(sc.robot, start=(start.x, start.y), heading=start.heading)
    return base.replace(scenario=dataclasses.replace(sc, robot=robot), seed=start.seed)


class NavigationTask:
    """Trials of ``base`` (a :class:`RunSpec`; its navigation is set to the trainer's) from
    starts given to :meth:`reset`."""

    def __init__(self, base: RunSpec):
        self.base = base  # (built by task_spec for the paper's task: its conditions lie under the user's values)
        self.params = base.params.learning
        self.mission: Mission | None = None
        self.recorder = None  # the trial's log, when reset was given one
        self.observers: list[Observer] = []  # told of every tick of every trial, after the log (the env's drawing)
        self.actions = 0
        self.outcome: str | None = None
        self.terminal = (
            False  # the last step ended the trial in an end state (the target, or blocked in the paper's task)
        )

    def reset(self, start: Start, log: Path | None = None) -> int:
        """Start a trial at ``start``; runs the initial sweep; returns the first belief state.
        With ``log``, every tick of the trial is recorded there (an MCAP log like ``navcli run``'s),
        closed when the trial ends or :meth:`close` is called."""
        from ..learning import LearningAgent

        self.close("interrupted", "a new trial began")
        spec = spec_at(self.base, start)
        p = spec.params
        agent = LearningAgent(
            None,
            p.learning,
            max_speed=p.robot.max_speed,
            pan_limit=spec.scenario.camera.pan_limit,
            target_key=spec.scenario.target.landmark,
        )
        m = Mission(
            spec, policy_agent=agent, snapshots=log is not None, explain=log is not None or bool(self.observers)
        )
        if p.learning.first_sighting and p.learning.paper_task:
            m.perception.glimpse_target(m.world.pose)
        self.mission, self.agent, self.actions, self.outcome = m, agent, 0, None
        if log is not None:
            self.recorder = open_log(spec, m, log, overwrite=True)  # the training's own folder
        advance(m, self._observers(), until=lambda m: agent.state is not None and not m.navigation.sweeping)
        return agent.state if agent.state is not None else 0

    def _observers(self) -> tuple[Observer, ...]:
        return ((recording(self.recorder),) if self.recorder is not None else ()) + tuple(self.observers)

    def close(self, outcome: str = "interrupted", reason: str = "stopped") -> None:
        """Close the trial's log, if one is open, ending its mission as ``outcome`` if it runs on."""
        if self.recorder is None:
            return
        m, rec, self.recorder = self.mission, self.recorder, None
        if m.outcome is None:
            m.abort(outcome, reason)
        close_log(rec, m)

    def step(self, action: int) -> tuple[int, float, bool, bool]:
        """Carry out ``action`` for one action's length: (state, reward, reached, ended otherwise)."""
        m, agent = self.mission, self.agent
        if m is None or self.outcome is not None:
            raise RuntimeError("the trial has ended: reset it")
        if m.outcome is None:
            agent.take(action)
            taken = agent.actions_taken
            advance(m, self._observers(), until=lambda m: agent.actions_taken > taken and agent.between_actions)
        self.actions += 1
        reward = REWARDS[action]  # the action is paid for; reaching the target adds AT_TARGET (0)
        reached = m.outcome == "reached"
        ended = not reached and (m.outcome is not None or self.actions >= self.params.max_actions)
        blocked = m.outcome == "blocked" and self.base.params.navigation.blocked_ends
        self.terminal = reached or (
            blocked and self.params.blocked_terminal
        )  # a blocked ending is a cut (module docstring)
        if reached or ended:
            self.outcome = m.outcome or "timeout"
            self.close("timeout", f"{self.actions} actions without reaching the target")
        return (agent.state if agent.state is not None else 0), reward, reached, ended  # 0 as reset's
