"""The Navigation system (learning-agent paper, section 3; notes, sections 1-4): agents that bid
among themselves for what the robot should do next, the Map Manager that answers their questions,
and the Communicator that forwards the winners to the Pilot and to Vision.

One tick, in order:

1. the Map Manager learns from the image taken last tick (:mod:`.map_manager`);
2. the original target is located: the least imprecise of the visual memory and the map;
3. the Rescuer (:mod:`.rescuer`) decides: sweep, scan when lost, or, when blocked, a diverting
   target from the Map Manager, which becomes the current target;
4. the bidding agents bid on the :class:`~.situation.Situation`: Target Tracker
   (:mod:`.target_tracker`), Risk Manager (:mod:`.risk_manager`), Distance Estimator
   (:mod:`.distance_estimator`), and the Rescuer's own bids;
5. the Communicator (:mod:`.communicator`) forwards the highest Move/Stop and Look bids.

The output carries the current target for the Pilot (the mission hands it over), the events, and
a reason to end the mission as ``blocked`` when the Rescuer gives up.
"""

from __future__ import annotations

import math
from dataclasses import replace
from types import MappingProxyType
from typing import Mapping, NamedTuple

import numpy as np

from ..beliefs import Beliefs
from ..bidding import Bid, Resource
from ..fuzzy import FuzzyPoint
from ..geometry import Point, midpoint
from ..params import NAVIGATION, PILOT, ROBOT, NavigationParams, PilotParams, RobotParams
from .communicator import Communicator
from .distance_estimator import DistanceEstimator
from .map_manager import TARGET, MapManager, MapSnapshot
from .rescuer import Rescuer
from .risk_manager import RiskManager
from .situation import Agent, AgentSetup, Situation
from .target_tracker import TargetTracker

__all__ = [
    "Agent",
    "AgentSetup",
    "Communicator",
    "DistanceEstimator",
    "MapManager",
    "NavigationOutput",
    "NavigationSystem",
    "Rescuer",
    "RiskManager",
    "Situation",
    "TargetTracker",
]


NO_INFO: Mapping[str, object] = MappingProxyType({})  # read-only: one empty explanation serves all


class NavigationOutput(NamedTuple):
    """The system's bids to the robot's arbiter, the agents' bids they were chosen from, the
    current target for the Pilot (egocentric point, or a line to cross), and what explains it.
    (A NamedTuple, made every tick: see :class:`~.situation.Situation`.)"""

    bids: tuple[Bid, ...]
    agent_bids: tuple[Bid, ...]
    target: Point | None = None
    target_line: tuple[Point, Point] | None = None
    diverting: bool = False
    events: tuple[tuple[str, str, str], ...] = ()  # (agent, level, message)
    give_up: str | None = None
    info: Mapping[str, object] = NO_INFO  # the scalar fields of ``/navigation``; none when nothing records them
    forwarded_by: Mapping[Resource, str] = MappingProxyType({})  # resource -> the agent whose bid was forwarded
    believed: FuzzyPoint | None = None  # the original target as the system believes it (egocentric), if at all


class NavigationSystem:
    """The agents, the Map Manager and the Communicator (see the module docstring).

    ``target_key`` is how the visual memory names the target (``target`` for a point, the
    landmark's id for a landmark); ``line_target`` for a mission whose target is a line.
    ``plugin_agents`` bid beside the bidding agents (after them), or instead of them without
    ``own_agents``; a ``policy_agent`` (the Learning Agent) replaces them all."""

    name = "navigation"

    def __init__(
        self,
        params: NavigationParams = NAVIGATION,
        robot: RobotParams = ROBOT,
        pilot: PilotParams = PILOT,
        target_key: str = TARGET,
        line_target: bool = False,
        rng: np.random.Generator | None = None,
        pan_limit: float = math.radians(100.0),
        policy_agent: Agent | None = None,
        plugin_agents: tuple[Agent, ...] = (),
        own_agents: bool = True,
    ):
        self.params = params
        self.target_key = target_key
        self.line_target = line_target
        self.map = MapManager(params, target_key, passable=2 * pilot.R_min)
        self.tracker = TargetTracker(params, robot.max_speed, pilot.corridor_margin)
        self.risk = RiskManager(params, pan_limit)
        self.estimator = DistanceEstimator(params, robot.max_speed)
        self.rescuer = Rescuer(params, rng, robot)
        self.agents: tuple[Agent, ...] = (
            (self.tracker, self.risk, self.estimator) if own_agents else ()
        ) + plugin_agents
        # the Learning Agent (or the hand-coded policy) replaces the three (learning-agent paper,
        # section 4); it waits for the Rescuer's initial sweep, so its actions are its own
        self.policy_agent = policy_agent
        if policy_agent is not None:
            self.agents = (policy_agent,)
        self.communicator = Communicator(self.name, params.communicator_window_s)
        self._ahead_lim = math.radians(params.ahead_deg)  # rad
        self.explains = True  # build the output's ``info``, which only a log or an observer reads (Mission sets it)

    @property
    def sweeping(self) -> bool:
        """The Rescuer is making its sweep (the initial one: a policy agent waits it out)."""
        return self.rescuer.state == "sweep"

    @property
    def diverting_targets(self) -> int:
        """Diverting targets set so far (the mission summary's)."""
        return self.rescuer.diverting_targets

    def situation(
        self, beliefs: Beliefs, line: tuple[Point, Point] | None = None, landmarks_of: Situation | None = None
    ) -> Situation:
        """What the agents see: the current target (``line``, a diverting target, replaces the
        original one), its imprecision, and the landmarks with the Map Manager's quality; those
        of ``landmarks_of``, a situation of the same tick, if given (they do not depend on the
        target)."""
        if line is not None or self.line_target:
            # a diverting line is held by the Rescuer and taken as given (our design); a line
            # target is as imprecise as the memory's worse end
            spread = 0.0 if line is not None else beliefs.target_spread
            line = line or beliefs.target_line
            assert line is not None  # a line target's line is in the beliefs
            target: FuzzyPoint | None = FuzzyPoint(*midpoint(*line), (0.0,) * 4)
            source = "line"
        else:
            found = self.map.locate(self.target_key, beliefs)
            target, source = found if found is not None else (None, "none")
            spread = target.heading_width() if target is not None else 2 * math.pi
        I_a = self.tracker.imprecision(spread)
        if landmarks_of is not None:
            s = landmarks_of
            return Situation(
                beliefs, target, line, source, I_a, s.landmarks, s.ahead, s.quality_ahead, s.quality_around
            )
        known = dict(self.map.memory_points(beliefs))
        known.pop(TARGET, None)
        known.pop(self.target_key, None)
        ahead_lim = self._ahead_lim
        ahead = {k: p for k, p in known.items() if abs(math.atan2(p.y, p.x)) <= ahead_lim}
        return Situation(
            beliefs, target, line, source, I_a, known, tuple(ahead), self.map.quality(ahead), self.map.quality(known)
        )

    def bid(self, beliefs: Beliefs) -> NavigationOutput:
        """One tick of the Navigation system (see the module docstring)."""
        self.map.observe(beliefs)
        original = self.situation(beliefs)
        rescue = self.rescuer.decide(original, lambda failed: self._ask(beliefs, original, failed))
        # while diverting, the agents weigh the diverting line, not the original target
        s = original if rescue.diverting is None else self.situation(beliefs, rescue.diverting, original)
        agents = () if self.policy_agent is not None and self.sweeping else self.agents
        offered = list(rescue.bids)  # the Rescuer first: it wins ties
        for agent in agents:
            offered += agent.bid(s)
        agent_bids = tuple(offered)
        bids = tuple(self.communicator.forward(agent_bids, beliefs.time))
        info = self._explanation(s) if self.explains else NO_INFO
        events = tuple([(self.rescuer.name, level, msg) for level, msg in rescue.events]) if rescue.events else ()
        return NavigationOutput(
            bids,
            agent_bids,
            s.aim,
            s.target_line,
            rescue.diverting is not None,
            events,
            rescue.give_up,
            info,
            self.communicator.forwarded_by,
            original.target,
        )

    def _explanation(self, s: Situation) -> Mapping[str, object]:
        """The scalar fields of ``/navigation`` for the situation ``s`` the agents bid on."""
        return {
            "I_a": s.I_a,
            "risk": self.risk.risk(s),
            "quality_ahead": s.quality_ahead,
            "quality_around": s.quality_around,
            "landmarks_known": len(s.landmarks),
            "landmarks_ahead": len(s.ahead),
            "target_source": s.target_source,
            "rescuer": self.rescuer.state,
            "diverting_targets": self.rescuer.diverting_targets,
            "failures": self.rescuer.failures,
            "beta_units": len(self.map.network),
        }

    def _ask(self, beliefs: Beliefs, original: Situation, failed):
        """The Rescuer's word to the Map Manager: the edge of a diverting target that failed (its
        arc becomes costly), and the question: a diverting target toward the original target."""
        if failed is not None:
            self.map.report_blocked(failed)
        aim = original.aim  # a line target's aim is its middle
        return None if aim is None else self.map.diverting_target(beliefs, aim)

    def snapshot(self, beliefs: Beliefs) -> MapSnapshot:
        """The map for the log, with every diverting line the Rescuer has ended, egocentric."""
        odo = beliefs.odometry
        tried = tuple((odo.to_local(a), odo.to_local(b), ending) for a, b, ending in self.rescuer.tried)
        return replace(self.map.snapshot(beliefs), tried=tried)
