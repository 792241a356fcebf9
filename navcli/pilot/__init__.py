"""The Pilot (pilot paper): what every pilot shares (:mod:`.base`), the potential-field pilot of
the paper (:mod:`.potential_field`) and the geometric baseline of its Table 1 (:mod:`.geometric`),
by the names scenarios and ``--pilot`` give them."""

from __future__ import annotations

from ..params import PILOT, PILOT_NAMES, ROBOT, PilotParams, RobotParams
from .base import Avoidance, Pilot, PilotOutput
from .geometric import GeometricPilot
from .potential_field import PotentialFieldPilot

PILOTS: dict[str, type[Pilot]] = {"potential-field": PotentialFieldPilot, "geometric": GeometricPilot}
assert tuple(PILOTS) == PILOT_NAMES

__all__ = ["PILOTS", "Avoidance", "GeometricPilot", "Pilot", "PilotOutput", "PotentialFieldPilot", "make_pilot"]


def make_pilot(name: str, params: PilotParams = PILOT, robot: RobotParams = ROBOT) -> Pilot:
    """A fresh pilot of the named kind (raises ``ValueError`` for an unknown name)."""
    if name not in PILOTS:
        raise ValueError(f"unknown pilot {name!r} (expected one of: {', '.join(PILOT_NAMES)})")
    return PILOTS[name](params, robot)
