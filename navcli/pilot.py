"""The Pilot: the only system that moves the robot (pilot paper, sections 2-4).

Every tick the Pilot (1) proposes its own motion, with a bid, when it sees a reason to (obstacle
avoidance, reflexes), and (2) executes whichever motion bid won the arbiter: its own or the
Navigation system's. This module holds what every pilot shares: turning a winning :class:`Move`
into wheel commands. The avoidance strategies (potential field, geometric) subclass
:class:`Pilot` and fill in :meth:`Pilot.decide`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .bidding import Bid, Move
from .params import PILOT, ROBOT, PilotParams, RobotDefaults
from .perception import Beliefs


@dataclass(frozen=True)
class PilotOutput:
    """What a pilot decided this tick, and why.

    ``bids`` go to the arbiter; ``info`` is the JSON-ready explanation logged on ``/pilot``
    (forces, turn angle, IN_DISTRESS, mode); ``arrows`` are egocentric force vectors
    ``(name, fx, fy)`` drawn in ``/robot/scene``.
    """

    bids: list[Bid]
    info: dict
    arrows: list[tuple[str, float, float]] = field(default_factory=list)


class Pilot:
    """Executes the winning motion bid; proposes nothing of its own.

    Execution is a heading servo: turn at ``heading_gain * error`` (clipped to the turn-rate
    limit), drive at the requested speed scaled by ``cos(error)``, and stop to turn in place when
    the error exceeds ``turn_in_place``, so the robot never sweeps wide arcs into obstacles.
    """

    name = "pilot"

    def __init__(self, params: PilotParams = PILOT, robot: RobotDefaults = ROBOT):
        self.params = params
        self.robot = robot

    def decide(self, beliefs: Beliefs) -> PilotOutput:
        return PilotOutput([], {"mode": "execute"})

    def on_bumps(self, bumps: list) -> None:
        """Bumper contacts that began this tick (:class:`navcli.world.Bump`); reflexes start here."""

    def execute(self, winner: Bid | None) -> tuple[float, float]:
        """Wheel command (v m/s, omega rad/s) that carries out the winning motion bid."""
        if winner is None or not isinstance(winner.action, Move):
            return 0.0, 0.0
        return self.drive(winner.action)

    def drive(self, move: Move) -> tuple[float, float]:
        err = move.heading
        omega = max(-self.robot.max_turn_rate, min(self.robot.max_turn_rate, self.params.heading_gain * err))
        if abs(err) > self.params.turn_in_place:
            return 0.0, omega
        return move.speed * math.cos(err), omega
