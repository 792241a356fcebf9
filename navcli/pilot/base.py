"""The Pilot: the only system that moves the robot (pilot paper, sections 2-4).

Every tick the Pilot (1) proposes its own motion with a bid (obstacle avoidance, reflexes) and
its look-ahead camera bid, and (2) executes whichever motion bid won the arbiter: its own or the
Navigation system's. This module holds what every pilot shares:

- **execution** of a winning :class:`Move` as a heading servo, with the section 3.5 rule that a
  turn larger than 160 degrees is driven backwards (turning the complement) while the distance
  driven backwards stays under ``max_backward``;
- **reflexes** (section 3.5): on a bumper hit, stop, look around, back up ``backup_distance``,
  then recompute with the obstacle that was hit (which the visual memory now holds);
- the **look-ahead camera bid** (eq. 1): ``(d_l / d_m) ** s``, capped at 0.9 like every Pilot bid.

The avoidance strategies subclass :class:`Pilot` and implement :meth:`Pilot.avoid`:
:mod:`navcli.pilot.potential_field` (the paper's pilot) and :mod:`navcli.pilot.geometric` (the
baseline). Everything the Pilot learns comes in its :class:`~navcli.beliefs.Beliefs` (the memory's
obstacles, odometry, the image taken last tick, the bumps of last tick) and the Navigation
system's request; everything it decides goes out in its :class:`PilotOutput` and wheel command.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..beliefs import Beliefs, Bump, KnownObstacle
from ..bidding import Bid, Look, Move
from ..geometry import Pose, motion_between, wrap_angle
from ..params import CONTROL_DT, PILOT, ROBOT, PilotParams, RobotParams


@dataclass(frozen=True)
class Avoidance:
    """An avoidance strategy's proposal: the move, its bid, and the quantities that explain it."""

    move: Move | None
    bid: float
    info: dict
    arrows: list[tuple[str, float, float]] = field(default_factory=list)


@dataclass(frozen=True)
class PilotOutput:
    """What the pilot decided this tick, and why.

    ``bids`` go to the arbiter; ``info`` is the JSON-ready explanation logged on ``/pilot``
    (forces, turn angle, IN_DISTRESS, mode); ``arrows`` are egocentric force vectors
    ``(name, fx, fy)`` drawn in ``/robot/scene``; ``events`` are reports to the Navigation system.
    """

    bids: list[Bid]
    info: dict
    arrows: list[tuple[str, float, float]] = field(default_factory=list)
    events: list[str] = field(default_factory=list)
    obstacles: tuple[KnownObstacle, ...] = ()  # what the pilot avoided this tick, egocentric


class Pilot:
    """Shared pilot machinery (see the module docstring); ``avoid`` proposes nothing here."""

    name = "pilot"

    def __init__(self, params: PilotParams = PILOT, robot: RobotParams = ROBOT):
        self.params = params
        self.max_speed = robot.max_speed
        self.robot = robot
        self.backward = 0.0  # m driven backwards since the robot last drove forwards max_backward
        self.forward = 0.0
        self.since_look = 0.0  # d_l of eq. 1, metres
        self._reflex: list[tuple[str, float]] = []  # pending reflex phases (name, amount)
        self._reflex_progress = 0.0
        self._phase_ticks = 0  # ticks spent in the current reflex phase
        self._events: list[str] = []
        self._last_odom: Pose | None = None

    # -- to be provided by the strategies
    def avoid(self, beliefs: Beliefs, obstacles: list[KnownObstacle], request: Move | None) -> Avoidance:
        return Avoidance(None, 0.0, {})

    # -- per tick
    def decide(self, beliefs: Beliefs, request: Move | None = None) -> PilotOutput:
        """The pilot's bids for this tick; ``request`` is the Navigation system's motion request."""
        if beliefs.looked is not None:
            self._looked(beliefs.looked)
        self._bumped(beliefs.bumps)
        self._track(beliefs.odometry)
        events, self._events = self._events, []
        obstacles = list(beliefs.obstacles)  # the visual memory, bumped obstacles included
        look = self.look_bid()
        if self._reflex:
            return self._reflex_output(look, events, obstacles)
        a = self.avoid(beliefs, obstacles, request)
        bids = [Bid(self.name, "camera", Look(0.0), look)] if look > 0 else []
        info = {"mode": "avoid" if a.move is not None else "idle", "bid": a.bid, "look_bid": look} | a.info
        if a.move is not None:
            bids.insert(0, Bid(self.name, "motion", a.move, a.bid))
        return PilotOutput(bids, info, a.arrows, events, tuple(obstacles))

    def look_bid(self) -> float:
        """Eq. 1: ``(d_l / d_m) ** s``, never above the Pilot's cap of 0.9."""
        p = self.params
        return min(p.bid_cap, (self.since_look / p.look_d_max) ** p.look_exponent)

    def _looked(self, pan: float) -> None:
        """Vision carried out a look at ``pan`` (rad); a look ahead resets d_l of eq. 1."""
        if abs(pan) < self.params.look_ahead_cone:
            self.since_look = 0.0
        if self._reflex and self._reflex[0][0] == "look":
            self._reflex_progress += 1

    def _track(self, odom: Pose) -> None:
        """Distances the pilot keeps from its odometry: since the last look, and backwards."""
        last, self._last_odom = self._last_odom, odom
        if last is None:
            return
        ds, _ = motion_between(last, odom)
        self.since_look += abs(ds)
        if ds < 0:
            self.backward += -ds
            self.forward = 0.0
        else:
            self.forward += ds
            if self.forward >= self.params.max_backward:
                self.backward = 0.0  # a good stretch forwards: backing up is allowed again
        if self._reflex:
            phase = self._reflex[0][0]
            if phase == "backup":
                self._reflex_progress += -ds

    # -- reflexes (section 3.5)
    def _bumped(self, bumps: tuple[Bump, ...]) -> None:
        """Bumper contacts that began last tick: start the reflex.

        The obstacle that was hit goes to the visual memory (perception hears of the bumps too),
        so the recomputed forces include it."""
        if not bumps:
            return
        p = self.params
        self._reflex = [("stop", p.reflex_stop_s), ("look", float(len(p.reflex_look_pans_deg))),
                        ("backup", p.backup_distance)]
        self._reflex_progress = 0.0
        self._phase_ticks = 0
        self._events.append(f"reflex: bumper hit at bearing {math.degrees(bumps[0].bearing):.0f} deg; "
                            "stopping, looking around, backing up")

    def _reflex_output(self, look: float, events: list[str], obstacles: list[KnownObstacle]) -> PilotOutput:
        p = self.params
        while self._reflex and (self._reflex_progress >= self._reflex[0][1] - 1e-9
                                or self._phase_ticks * CONTROL_DT >= p.reflex_phase_limit_s):
            self._reflex.pop(0)  # done, or given up (backing into something, the camera kept busy)
            self._reflex_progress = 0.0
            self._phase_ticks = 0
        self._phase_ticks += 1
        if not self._reflex:
            events.append("reflex done: recomputing with the obstacle that was hit")
            return PilotOutput([], {"mode": "reflex", "phase": "done", "bid": 0.0, "look_bid": look}, [], events,
                               tuple(obstacles))
        phase = self._reflex[0][0]
        if phase == "stop":
            self._reflex_progress += CONTROL_DT  # this tick is spent standing still
        bids = [Bid(self.name, "motion", Move(0.0, -p.backup_speed if phase == "backup" else 0.0), p.bid_cap)]
        if phase == "look":
            pan = math.radians(p.reflex_look_pans_deg[int(self._reflex_progress)])
            bids.append(Bid(self.name, "camera", Look(pan), p.bid_cap))
        elif look > 0:
            bids.append(Bid(self.name, "camera", Look(0.0), look))
        return PilotOutput(bids, {"mode": "reflex", "phase": phase, "bid": p.bid_cap, "look_bid": look}, [], events,
                           tuple(obstacles))

    # -- execution
    def execute(self, winner: Bid | None) -> tuple[float, float]:
        """Wheel command (v m/s, omega rad/s) that carries out the winning motion bid."""
        if winner is None or not isinstance(winner.action, Move):
            return 0.0, 0.0
        move = winner.action
        if abs(move.heading) > self.params.backward_turn and move.speed > 0 and self.backward < self.params.max_backward:
            move = Move(wrap_angle(move.heading - math.pi), -move.speed)  # section 3.5: back up, turn the complement
        return self.drive(move)

    def drive(self, move: Move) -> tuple[float, float]:
        """Heading servo: turn toward ``move.heading``; drive only when roughly facing it."""
        err = move.heading
        omega = max(-self.robot.max_turn_rate, min(self.robot.max_turn_rate, self.params.heading_gain * err))
        if abs(err) > self.params.turn_in_place:
            return 0.0, omega
        return move.speed * math.cos(err), omega
