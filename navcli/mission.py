"""One mission: the world, the robot's systems and the arbiter, ticked at a fixed control rate.

Shaped like Gymnasium's ``Env``: build it from a :class:`~navcli.config.RunSpec`, call
:meth:`Mission.step` until :attr:`Mission.outcome` is set; every step returns a :class:`Tick`, the
complete record of that control period (poses, every bid, the winners, the pilot's explanation,
the camera, what the memory holds, events), which the recorder writes and tests inspect. The
run's seed is spawned here into one generator per component that draws (:data:`COMPONENTS`).

A step runs the phases of the papers' market in order, each a method: perceive (beliefs from the
camera and memory, or the oracle), bid (the Navigation system, then the Pilot with the
Navigation system's request), arbitrate (the highest bid per resource), act (the wheel command
and the look), step the world (physics, odometry, bumps), and record (the :class:`Tick`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from . import __version__
from .beliefs import Beliefs, Bump
from .bidding import Bid, Look, Move, Resource, arbitrate
from .config import RunSpec
from .fuzzy import CUT, FuzzyPoint
from .geometry import Pose, segments_intersect
from .navigation import AgentSetup, MapSnapshot, NavigationOutput, NavigationSystem
from .params import CONTROL_DT
from .pilot import PilotOutput
from .plugins import boundary, registry
from .vision.camera import Detection
from .vision.perception import make_perception
from .vision.visual_memory import Remembered
from .world import World

if TYPE_CHECKING:
    from .learning.learning_agent import LearningAgent

OUTCOMES = ("reached", "timeout", "blocked", "interrupted", "error")
COMPONENTS = ("odometry", "camera", "rescuer", "plugins", "motion")
"""The components that draw random numbers: the world's odometry errors, the camera's measurement
errors, the Rescuer's random turns, the plugins (a plugin pilot's or policy's ``rng``) and the
wheels' slip (``robot.slip_noise``; with it 0 nothing is drawn from its generator). Each
draws from a generator of its own, spawned from the run's seed (docs/design.md, "Random numbers");
a new component is added at the end, so the others keep their streams."""


def component_generators(seed: int) -> dict[str, np.random.Generator]:
    """One generator per :data:`COMPONENTS`, from ``numpy.random.SeedSequence(seed).spawn``: a
    change in how one component draws leaves every other's draws alone.

    >>> g = component_generators(1)
    >>> a = g["camera"].standard_normal()
    >>> g2 = component_generators(1)
    >>> _ = g2["odometry"].standard_normal(1000)  # the odometry draws more: the camera's stream is unmoved
    >>> g2["camera"].standard_normal() == a
    True
    """
    children = np.random.SeedSequence(seed).spawn(len(COMPONENTS))
    return {name: np.random.default_rng(child) for name, child in zip(COMPONENTS, children)}


@dataclass(frozen=True)
class Event:
    """Something worth a line in ``/events``: ``source`` is the system or agent that reports it."""

    time: float
    source: str
    level: str  # "info" | "warning" | "error"
    message: str


class Tick:
    """The record of one control period, stamped with the simulation time at its end: its
    ``index``, ``time_ns``, the true ``pose`` and the robot's belief (``odometry``), the ``command``
    (v m/s, omega rad/s) sent to the wheels, every bid offered to the arbiter in consultation
    order (``bids``), the Navigation agents' bids to their Communicator (``agent_bids``), the
    ``winners``, the ``pilot``'s output, the ``events``, the ``camera`` (pan, rad from the heading;
    state, idle | panning | processing; purpose), the ``detections`` of an image taken this tick
    (if one was), the visual ``memory`` (every ``vision.draw_every`` ticks and at the end), what the
    ``navigation`` system decided and why, and the Map Manager's ``map`` (every
    ``navigation.map_draw_every`` ticks and at the end). Built only when something reads it, then
    every tick: a plain class with its own ``__init__``, which the compiled build makes native
    (docs/design.md, "Values made every tick"); its fields are not reassigned."""

    def __init__(  # noqa: PLR0913 (a record: one argument per field, each named where a Tick is made)
        self,
        index: int,
        time_ns: int,
        pose: Pose,
        odometry: Pose,
        command: tuple[float, float],
        bids: tuple[Bid, ...],
        agent_bids: tuple[Bid, ...],
        winners: dict[Resource, Bid | None],
        pilot: PilotOutput,
        events: tuple[Event, ...],
        camera: tuple[float, str, str | None],
        detections: tuple[Detection, ...] | None,
        memory: tuple[Remembered, ...] | None = None,
        navigation: NavigationOutput | None = None,
        map: MapSnapshot | None = None,
    ) -> None:
        self.index: Final = index
        self.time_ns: Final = time_ns
        self.pose: Final = pose
        self.odometry: Final = odometry
        self.command: Final = command
        self.bids: Final = bids
        self.agent_bids: Final = agent_bids
        self.winners: Final = winners
        self.pilot: Final = pilot
        self.events: Final = events
        self.camera: Final = camera
        self.detections: Final = detections
        self.memory: Final = memory
        self.navigation: Final = navigation
        self.map: Final = map

    def __repr__(self) -> str:
        return f"Tick(index={self.index}, time_ns={self.time_ns}, pose={self.pose!r}, command={self.command!r})"


class Mission:
    """A scenario being run with one configuration."""

    def __init__(
        self,
        spec: RunSpec,
        policy_agent: LearningAgent | None = None,
        snapshots: bool = True,
        explain: bool = True,
    ):
        """``policy_agent`` replaces the agent of ``spec.navigation`` (a trainer's Learning Agent).
        ``snapshots=False`` leaves out the visual memory and map snapshots that only a log draws
        (``Tick.memory``/``Tick.map`` stay None): runs without a log skip the map's triangulations.
        ``explain=False`` leaves out the explanations that only a log or an observer reads: the
        Pilot's ``/pilot`` fields and force arrows (its ``info`` keeps what decisions read,
        ``blocked_by``) and the Navigation system's ``info``. Neither changes what the robot does."""
        self.spec = spec
        self.snapshots = snapshots
        self.scenario = spec.scenario
        p = spec.params
        rngs = component_generators(spec.seed)
        self.world = World(spec.scenario, rngs["odometry"], p.robot, rngs["motion"])
        self.perception = make_perception(spec.perception, spec.scenario, rngs["camera"], p)
        pilot = registry.pilot(spec.pilot)
        policies = registry.navigation(spec.navigation)
        self.plugins = tuple(c for c in (pilot,) + policies if not c.builtin)  # whose exceptions are theirs
        limit = p.robot.decision_limit_s  # a plugin's calls are guarded and checked (navcli.plugins.boundary)
        self.pilot = (
            pilot.cls(p.pilot, p.robot)
            if pilot.builtin
            else boundary.make_pilot(
                pilot, limit, p.pilot, p.robot, own_params=p.plugin(pilot.group), rng=rngs["plugins"]
            )
        )
        self._pilot_fields = boundary.pilot_fields(pilot)  # what a plugin pilot's /pilot may hold
        t = spec.scenario.target
        pan_limit = spec.scenario.camera.pan_limit
        self.policy_agent = policy_agent
        if policy_agent is None and policies[0].builtin and policies[0].name != "agents":
            from .learning import policy_agent as make_policy_agent  # the Learning Agent or the hand-coded policy

            self.policy_agent = make_policy_agent(
                policies[0].name.partition(":")[0],
                policies[0].argument,
                p.learning,
                max_speed=p.robot.max_speed,
                pan_limit=pan_limit,
                target_key=t.landmark,
            )
        setup = AgentSetup(p, None, pan_limit, t.landmark or "target", rngs["plugins"])
        agents = boundary.make_agents(tuple(c for c in policies if not c.builtin), setup, limit)
        self.navigation = NavigationSystem(
            p.navigation,
            p.robot,
            p.pilot,
            target_key=t.landmark or "target",
            line_target=t.kind == "line",
            rng=rngs["rescuer"],
            pan_limit=pan_limit,
            policy_agent=self.policy_agent,
            plugin_agents=agents,
            own_agents=any(c.name == "agents" for c in policies),
        )
        self.pilot.explains = self.navigation.explains = explain
        self._reach = t.tolerance  # how near the target's point counts as there (m)
        if t.kind == "landmark":
            lm = next(lm for lm in self.scenario.landmarks if lm.id == t.landmark)
            self._reach += lm.radius + p.robot.radius
        self.ticks = 0
        self.outcome: str | None = None
        self.reason = ""
        self.camera_looks = 0
        self._pilot_blocked: str | None = None  # what the Pilot reported last tick as not easily avoided
        self._pending: list[Event] = [Event(0.0, "mission", "info", self._start_message())]

    def _start_message(self) -> str:
        s, t = self.scenario.robot.start, self.scenario.target
        goal = {
            "point": f"the point [{t.point[0]:g}, {t.point[1]:g}]",
            "landmark": f"landmark {t.landmark}",
            "line": f"crossing the line {t.line}",
        }[t.kind]
        return f"mission {self.scenario.name} started at [{s[0]:g}, {s[1]:g}] with the {self.spec.pilot_name} pilot; target: {goal}"

    @property
    def time(self) -> float:
        return self.world.time

    # -- the phases of one tick
    def perceive(self) -> Beliefs:
        w = self.world
        beliefs = self.perception.observe(w.time, w.pose, w.odometry.pose)
        return beliefs if self._pilot_blocked is None else replace(beliefs, pilot_blocked=self._pilot_blocked)

    def bid(self, beliefs: Beliefs) -> tuple[NavigationOutput, PilotOutput]:
        """The Navigation system bids first; the Pilot hears its motion request (to carry it out
        when it is safe) and its current target (a diverting target replaces the original one),
        and bids."""
        nav = self.navigation.bid(beliefs)
        request = next((b.action for b in nav.bids if isinstance(b.action, Move)), None)  # the motion bid's
        same = nav.target == beliefs.target and nav.target_line == beliefs.target_line
        for_pilot = beliefs if same else replace(beliefs, target=nav.target, target_line=nav.target_line)
        out = self.pilot.decide(for_pilot, request)
        if self._pilot_fields is not None and not out.info.keys() <= self._pilot_fields:
            raise boundary.undeclared(registry.pilot(self.spec.pilot), out.info)
        self._pilot_blocked = out.blocked_by
        return nav, out

    def act(
        self, winners: dict[Resource, Bid | None], before: Pose
    ) -> tuple[tuple[float, float], list[Detection] | None]:
        """The Pilot turns the winning motion bid into a wheel command; Vision carries out the
        winning look (an image may be taken)."""
        command = self.pilot.execute(winners["motion"])
        camera = winners["camera"]
        look = camera.action if camera is not None and isinstance(camera.action, Look) else None
        detections = self.perception.look(self.world.time, before, look)
        if detections is not None:
            self.camera_looks += 1
        return command, detections

    def step_world(self, command: tuple[float, float]) -> list[Bump]:
        """Physics and odometry for one control period; perception hears of the motion and bumps."""
        w = self.world
        odom_before = w.odometry.pose
        bumps = w.step(*command)
        slip = abs(command[0]) * CONTROL_DT if w.touching else 0.0  # sliding along a contact is unmeasured
        self.perception.moved(odom_before, w.odometry.pose, tuple(bumps), w.touching, slip)
        return bumps

    def step(self) -> Tick:
        """Run one control period: perceive, bid, arbitrate, act, step the world, record. An
        exception raised in a plugin's code (or passing through it) is raised as the plugin's
        :class:`~navcli.plugins.PluginError`, the original as its cause."""
        tick = self._step(True)
        assert tick is not None  # recorded
        return tick

    def step_unrecorded(self) -> None:
        """:meth:`step` without its :class:`Tick`, for a loop that nobody observes: the same
        control period, its record (the events, the snapshots) never built."""
        self._step(False)

    def _step(self, record: bool) -> Tick | None:
        if self.outcome is not None:
            raise RuntimeError(f"the mission has ended ({self.outcome})")
        world = self.world
        before = world.pose
        try:
            beliefs = self.perceive()
            nav, pilot_out = self.bid(beliefs)
            bids = tuple(pilot_out.bids) + nav.bids  # the Pilot is consulted first (ties)
            winners = arbitrate(bids)
            command, detections = self.act(winners, before)
        except Exception as e:
            culprit = registry.blame(e, self.plugins) if self.plugins else None
            if culprit is None:
                raise
            raise registry.failed(culprit, e) from e
        bumps = self.step_world(command)
        self.ticks += 1
        after = world.pose
        self._check_end(before, after, nav.give_up, nav.believed)
        if not record:
            return None
        return self._record(command, bids, nav, winners, pilot_out, bumps, detections, beliefs)

    def _record(
        self,
        command: tuple[float, float],
        bids: tuple[Bid, ...],
        nav: NavigationOutput,
        winners: dict[Resource, Bid | None],
        pilot_out: PilotOutput,
        bumps: list[Bump],
        detections: list[Detection] | None,
        beliefs: Beliefs,
    ) -> Tick:
        world = self.world
        events = self.drain_events()
        events += [Event(world.time, agent, level, m) for agent, level, m in nav.events]
        events += [Event(world.time, "pilot", "info", m) for m in pilot_out.events]
        for b in bumps:
            events.append(
                Event(
                    b.time,
                    "pilot",
                    "warning",
                    f"bumper contact with {b.what} at bearing {math.degrees(b.bearing):.0f} deg",
                )
            )
        if self.outcome is not None:
            events.append(Event(world.time, "mission", "info" if self.outcome == "reached" else "warning", self.reason))
        p = self.spec.params
        last = self.outcome is not None  # the log ends with the final memory and map, whatever their rates
        memory = (
            self.perception.snapshot() if self.snapshots and (last or self.ticks % p.vision.draw_every == 0) else None
        )
        map_ = (
            self.navigation.snapshot(beliefs)
            if self.snapshots and (last or self.ticks % p.navigation.map_draw_every == 0)
            else None
        )
        return Tick(
            self.ticks,
            world.time_ns,
            world.pose,
            world.odometry.pose,
            command,
            bids,
            nav.agent_bids,
            winners,
            pilot_out,
            tuple(events),
            self.perception.camera_state,
            tuple(detections) if detections is not None else None,
            memory,
            nav,
            map_,
        )

    def _check_end(
        self, before: Pose, after: Pose, give_up: str | None = None, believed: FuzzyPoint | None = None
    ) -> None:
        if self._reached(before, after) and self._confident(believed):
            self._end("reached", f"target reached after {self.world.time:.1f} s")
        elif give_up is not None:
            self._end("blocked", f"blocked after {self.world.time:.1f} s: {give_up}")
        elif self.world.time >= self.spec.time_limit - 1e-9:
            self._end("timeout", f"time limit of {self.spec.time_limit:g} s reached")

    def _confident(self, believed: FuzzyPoint | None) -> bool:
        """With ``navigation.reach_confident`` (the learning paper's trials: the robot "reaches the
        target (and is confident that it has reached the target)"), is the robot also sure of it:
        every place its belief of the target allows, at the papers' 70 % cut, within reach (and,
        with ``navigation.reach_imprecision``, its I(t) below that)? Always, without it."""
        nav = self.spec.params.navigation
        if not nav.reach_confident:
            return True
        if believed is None or math.hypot(believed.x, believed.y) + believed.radius(CUT) > self._reach:
            return False
        return not nav.reach_imprecision or believed.imprecision() < nav.reach_imprecision

    @property
    def pending(self) -> tuple[Event, ...]:
        """Events raised outside a step (the mission's start) and not yet handed out, left in place."""
        return tuple(self._pending)

    def drain_events(self) -> list[Event]:
        """Events raised outside a step (the mission's start) and not yet handed out."""
        events, self._pending = self._pending, []
        return events

    def _reached(self, before: Pose, after: Pose) -> bool:
        t = self.scenario.target
        p = (after.x, after.y)
        if t.kind != "line":
            return math.dist(p, t.point) <= self._reach
        assert t.line is not None  # a line target has its line
        return segments_intersect((before.x, before.y), p, *t.line)

    def _end(self, outcome: str, reason: str) -> None:
        self.outcome, self.reason = outcome, reason
        self.world.stop()

    def abort(self, outcome: str, reason: str, say: bool = False) -> None:
        """End the mission from outside (Ctrl-C, an error, an observer); with ``say``, the reason is
        an event of the mission's too (handed out by :meth:`drain_events`)."""
        assert outcome in OUTCOMES
        self._end(outcome, reason)
        if say:
            self._pending.append(Event(self.world.time, "mission", "warning", reason))

    def summary(self) -> dict[str, Any]:
        """The ``/mission/summary`` record (the log format in the README)."""
        w = self.world
        learning = {"learning": self.policy_agent.info()} if self.policy_agent is not None else {}
        return {
            "scenario": self.scenario.name,
            "seed": self.spec.seed,
            "pilot": self.spec.pilot_name,
            "navigation": self.spec.navigation,
            "outcome": self.outcome or "interrupted",
            "reason": self.reason,
            "time_s": w.time,
            "path_length_m": w.path_length,
            "collisions": w.bumps,
            "camera_looks": self.camera_looks,
            "ticks": self.ticks,
            "diverting_targets": self.navigation.diverting_targets,
            "navcli_version": __version__,
            "run_id": self.spec.run_id,
        } | learning
