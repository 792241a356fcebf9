"""One mission: the world, the robot's systems and the arbiter, ticked at a fixed control rate.

Shaped like Gymnasium's ``Env``: build it from a scenario and a seed, call :meth:`Mission.step`
until :attr:`Mission.outcome` is set; every step returns a :class:`Tick`, the complete record of
that control period (poses, every bid, the winners, the pilot's explanation, events), which the
recorder writes and tests inspect. One seeded ``numpy`` generator is made here and handed down.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import __version__
from .bidding import Bid, Resource, arbitrate
from .geometry import Pose, segments_intersect
from .navigation import NavigationSystem
from .params import CONTROL_DT, PHYSICS_DT
from .perception import make_perception
from .pilot import PilotOutput
from .pilots import make_pilot
from .scenario import Scenario
from .vision import Detection
from .world import World

OUTCOMES = ("reached", "timeout", "blocked", "interrupted", "error")


@dataclass(frozen=True)
class Event:
    """Something worth a line in ``/events``: ``source`` is the system or agent that reports it."""

    time: float
    source: str
    level: str  # "info" | "warning" | "error"
    message: str


@dataclass(frozen=True)
class Tick:
    """The record of one control period, stamped with the simulation time at its end."""

    index: int
    time_ns: int
    pose: Pose  # ground truth
    odometry: Pose  # the robot's belief
    command: tuple[float, float]  # (v m/s, omega rad/s) sent to the wheels
    bids: tuple[Bid, ...]  # every bid offered to the arbiter, in consultation order
    agent_bids: tuple[Bid, ...]  # the Navigation agents' bids to their Communicator
    winners: dict[Resource, Bid | None]
    pilot: PilotOutput
    events: tuple[Event, ...]
    camera: tuple[float, str]  # pan (rad, relative to the heading) and state: idle | panning | processing
    detections: tuple[Detection, ...] | None  # what the image taken this tick showed, if one was


class Mission:
    """A scenario being run with one seed and one pilot."""

    def __init__(self, scenario: Scenario, seed: int | None = None, pilot: str | None = None,
                 time_limit: float | None = None, perception: str | None = None):
        self.scenario = scenario
        self.seed = scenario.mission.seed if seed is None else seed
        self.pilot_name = pilot or scenario.mission.pilot
        self.time_limit = scenario.mission.time_limit if time_limit is None else time_limit
        self.rng = np.random.default_rng(self.seed)
        self.world = World(scenario, self.rng)
        self.perception_name = perception or scenario.mission.perception
        self.perception = make_perception(self.perception_name, scenario, self.rng)
        self.pilot = make_pilot(self.pilot_name, scenario.pilot, scenario.robot.max_speed)
        self.navigation = NavigationSystem(scenario.robot.max_speed)
        self.ticks = 0
        self.outcome: str | None = None
        self.reason = ""
        self.camera_looks = 0
        self._pending: list[Event] = [Event(0.0, "mission", "info", self._start_message())]

    def _start_message(self) -> str:
        s, t = self.scenario.robot.start, self.scenario.target
        goal = {"point": f"the point [{t.point[0]:g}, {t.point[1]:g}]",
                "landmark": f"landmark {t.landmark}",
                "line": f"crossing the line {t.line}"}[t.kind]
        return f"mission {self.scenario.name} started at [{s[0]:g}, {s[1]:g}] with the {self.pilot_name} pilot; target: {goal}"

    @property
    def time(self) -> float:
        return self.world.time

    def run_metadata(self) -> dict[str, str]:
        """The ``run`` metadata record: enough to reproduce this run."""
        sc = self.scenario
        return {
            "scenario": sc.name,
            "scenario_file": sc.source,
            "scenario_sha256": sc.sha256,
            "seed": str(self.seed),
            "pilot": self.pilot_name,
            "perception": self.perception_name,
            "navcli_version": __version__,
            "time_limit_s": repr(self.time_limit),
            "control_dt_s": repr(CONTROL_DT),
            "physics_dt_s": repr(PHYSICS_DT),
            "pilot_params": repr(sc.pilot),
            "noise": repr(sc.noise),
            "camera": repr(sc.camera),
        }

    def step(self) -> Tick:
        """Run one control period: perceive, bid, arbitrate, act, step the physics."""
        if self.outcome is not None:
            raise RuntimeError(f"the mission has ended ({self.outcome})")
        world = self.world
        before = world.pose
        beliefs = self.perception.observe(world.time, before, world.odometry.pose)
        nav_bids = self.navigation.bid(beliefs)
        request = next((b.action for b in nav_bids if b.resource == "motion"), None)
        pilot_out = self.pilot.decide(beliefs, request)
        bids = tuple(pilot_out.bids) + tuple(nav_bids)  # the Pilot is consulted first (ties)
        winners = arbitrate(bids)
        v, omega = self.pilot.execute(winners["motion"])
        look = winners["camera"].action if winners["camera"] is not None else None
        detections = self.perception.look(world.time, before, look)
        if detections is not None:  # an image was taken
            self.camera_looks += 1
            self.pilot.on_look(self.perception.camera.pan)
        odom_before = world.odometry.pose
        bumps = world.step(v, omega)
        slip = abs(v) * CONTROL_DT if world.touching else 0.0  # sliding along a contact is unmeasured
        self.perception.moved(odom_before, world.odometry.pose, bumps, slip)
        self.ticks += 1
        events = self.drain_events()
        events += [Event(world.time, "pilot", "info", m) for m in pilot_out.events]
        for b in bumps:
            events.append(Event(b.time, "pilot", "warning",
                                f"bumper contact with {b.what} at bearing {math.degrees(b.bearing):.0f} deg"))
        self.pilot.on_bumps(bumps)
        after = world.pose
        if self._reached(before, after):
            self._end("reached", f"target reached after {world.time:.1f} s")
        elif world.time >= self.time_limit - 1e-9:
            self._end("timeout", f"time limit of {self.time_limit:g} s reached")
        if self.outcome is not None:
            events.append(Event(world.time, "mission", "info" if self.outcome == "reached" else "warning", self.reason))
        cam = self.perception.camera
        return Tick(self.ticks, world.time_ns, after, world.odometry.pose, (v, omega),
                    bids, tuple(self.navigation.last_agent_bids), winners, pilot_out, tuple(events),
                    (cam.pan, cam.state), tuple(detections) if detections is not None else None)

    def drain_events(self) -> list[Event]:
        """Events raised outside a step (the mission's start) and not yet handed out."""
        events, self._pending = self._pending, []
        return events

    def _reached(self, before: Pose, after: Pose) -> bool:
        t = self.scenario.target
        p = (after.x, after.y)
        if t.kind == "point":
            return math.dist(p, t.point) <= t.tolerance
        if t.kind == "landmark":
            lm = next(lm for lm in self.scenario.landmarks if lm.id == t.landmark)
            return math.dist(p, t.point) <= t.tolerance + lm.radius + self.scenario.robot.radius
        return segments_intersect((before.x, before.y), p, *t.line)

    def _end(self, outcome: str, reason: str) -> None:
        self.outcome, self.reason = outcome, reason
        self.world.stop()

    def abort(self, outcome: str, reason: str) -> None:
        """End the mission from outside (Ctrl-C, an error)."""
        assert outcome in OUTCOMES
        self._end(outcome, reason)

    def summary(self) -> dict:
        """The ``/mission/summary`` record (shared/spec/log-format.md)."""
        w = self.world
        return {
            "scenario": self.scenario.name,
            "seed": self.seed,
            "pilot": self.pilot_name,
            "outcome": self.outcome or "interrupted",
            "reason": self.reason,
            "time_s": w.time,
            "path_length_m": w.path_length,
            "collisions": w.bumps,
            "camera_looks": self.camera_looks,
            "ticks": self.ticks,
            "navcli_version": __version__,
        }

