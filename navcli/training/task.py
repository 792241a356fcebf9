"""The Learning Agent's task as trials, action by action (learning-agent paper, section 6): the
robot starts at a random place of the scenario's room and must reach the target; a trial ends
when it has, after ``max_actions`` actions, or when the robot is blocked.

:class:`NavigationTask` runs a :class:`~navcli.mission.Mission` without a log, its Navigation
system's Learning Agent told each action by the caller (:meth:`NavigationTask.step`), and
reports the belief state after it, the action's reward and whether the trial ended: what both
learners and the Gymnasium environment (:mod:`navcli.envs`) step through.

**The paper's task** (``learning.paper_task`` 1, the default; :data:`PAPER_TASK`), its conditions
as the paper states them:

- the robot "knows nothing" at the start: the target is one of the landmarks, visible, but its
  position is not given (``vision.told_target`` 0); the robot knows it when it sees it;
- the camera is the Learning Agent's: the Pilot still avoids what the memory holds, but bids for
  no look (``pilot.looks`` 0: neither eq. 1's look-ahead nor a reflex's looks), and the Rescuer
  neither sweeps nor scans (``navigation.rescuer_looks`` 0);
- a trial succeeds when the robot "reaches the target (and is confident that it has reached the
  target)": the body within reach of the landmark (as a mission's), and the robot sure of it,
  every place its belief of the target allows at the papers' 70 % cut within that reach
  (``navigation.reach_confident`` 1; our reading of "confident", in the papers' own terms, the
  cut that defines I(l)); ``navigation.reach_imprecision`` adds a bound on I(t) itself, for the
  README's sensitivity;
- it terminates when the robot is blocked (``navigation.blocked_ends`` 1: the Rescuer's first
  blocked situation ends it, no diverting target), a terminal state of value 0 for the learner,
  as reaching the target is; after 500 actions (``max_actions``) it is cut, not terminal;
- the objective is the total reward, undiscounted (``learning.gamma`` 1).

Each condition is set by the task unless the configuration gives it a value of its own (so
``--param navigation.reach_imprecision=0.07`` is heard); ``learning.paper_task=0`` gives navcli's
first task: the target told at the start (+-2 cm, never forgotten), the camera free to all,
success by the body alone, blocked not terminal, with ``--param learning.gamma=0.99`` as it was.
The initial sweep, where the Rescuer makes one, comes before the first action and is not counted.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import RunSpec
from ..geometry import Point, distance_to_segment
from ..mission import Mission
from ..params import Params
from ..runner import Observer, advance, close_log, open_log, recording
from ..scenario import Scenario
from ..learning.actions import REWARDS

PAPER_TASK = {"vision.told_target": 0, "pilot.looks": 0, "navigation.rescuer_looks": 0,
              "navigation.blocked_ends": 1, "navigation.reach_confident": 1}
"""The conditions of the paper's task (module docstring), by parameter."""
START_CLEARANCE = 0.3  # m between the robot's body and any wall, landmark or obstacle at a start
START_MIN_DISTANCE = 1.5  # m from the target at least: a trial that starts at the target teaches nothing


@dataclass(frozen=True)
class Start:
    """Where a trial starts: position (m), heading (rad), and the mission's seed (sensor noise)."""

    x: float
    y: float
    heading: float
    seed: int


def random_starts(scenario: Scenario, n: int, seed: int, robot_radius: float) -> list[Start]:
    """``n`` starts drawn uniformly over the free floor of ``scenario`` (clear of walls, landmarks
    and obstacles by :data:`START_CLEARANCE`, at least :data:`START_MIN_DISTANCE` from the
    target), with headings uniform and seeds, all from ``seed``."""
    rng = np.random.default_rng(seed)
    a, r = scenario.arena, robot_radius + START_CLEARANCE
    out: list[Start] = []
    while len(out) < n:
        x, y = rng.uniform(r, a.width - r), rng.uniform(r, a.height - r)
        if math.dist((x, y), scenario.target.point) < START_MIN_DISTANCE or not _clear(scenario, (x, y), r):
            continue
        out.append(Start(float(x), float(y), float(rng.uniform(-math.pi, math.pi)), int(rng.integers(2 ** 31))))
    return out


def _clear(scenario: Scenario, p: Point, r: float) -> bool:
    for o in scenario.objects:
        if o.kind in ("wall", "target"):
            continue
        if distance_to_segment(p, o.a, o.b) < r + o.radius:
            return False
    return True


def task_spec(spec: RunSpec) -> RunSpec:
    """``spec`` under the paper's task (:data:`PAPER_TASK`) when ``learning.paper_task`` is 1: each
    condition set unless the configuration gives that parameter a value other than navcli's default."""
    if not spec.params.learning.paper_task:
        return spec
    mine, defaults = spec.params.flat(), Params().flat()
    changes = {k: v for k, v in PAPER_TASK.items() if mine[k] == defaults[k]}
    return spec.replace(params=spec.params.override(changes)) if changes else spec


def spec_at(base: RunSpec, start: Start) -> RunSpec:
    """``base`` with the robot at ``start`` and its seed."""
    sc = base.scenario
    robot = dataclasses.replace(sc.robot, start=(start.x, start.y), heading=start.heading)
    return base.replace(scenario=dataclasses.replace(sc, robot=robot), seed=start.seed)


class NavigationTask:
    """Trials of ``base`` (a :class:`RunSpec`; its navigation is set to the trainer's) from
    starts given to :meth:`reset`."""

    def __init__(self, base: RunSpec):
        self.base = base = task_spec(base)
        self.params = base.params.learning
        self.mission: Mission | None = None
        self.recorder = None  # the trial's log, when reset was given one
        self.observers: list[Observer] = []  # told of every tick of every trial, after the log (the env's drawing)
        self.actions = 0
        self.outcome: str | None = None
        self.terminal = False  # the last step ended the trial in an end state (the target, or blocked in the paper's task)

    def reset(self, start: Start, log: Path | None = None) -> int:
        """Start a trial at ``start``; runs the initial sweep; returns the first belief state.
        With ``log``, every tick of the trial is recorded there (an MCAP log like ``navcli run``'s),
        closed when the trial ends or :meth:`close` is called."""
        from ..learning import LearningAgent

        self.close("interrupted", "a new trial began")
        spec = spec_at(self.base, start)
        p = spec.params
        agent = LearningAgent(None, p.learning, max_speed=p.robot.max_speed, pan_limit=spec.scenario.camera.pan_limit,
                              target_key=spec.scenario.target.landmark)
        m = Mission(spec, policy_agent=agent, snapshots=log is not None)
        self.mission, self.agent, self.actions, self.outcome = m, agent, 0, None
        if log is not None:
            self.recorder = open_log(spec, m, log)
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
        self.terminal = reached or (m.outcome == "blocked" and bool(self.base.params.navigation.blocked_ends))
        if reached or ended:
            self.outcome = m.outcome or "timeout"
            self.close("timeout", f"{self.actions} actions without reaching the target")
        return (agent.state if agent.state is not None else 0), reward, reached, ended  # 0 as reset's
