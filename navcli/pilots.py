"""The pilots a run can use, by the names scenarios and ``--pilot`` give them."""

from __future__ import annotations

from .geometric import GeometricPilot
from .params import PILOT, PILOT_NAMES, ROBOT, PilotParams
from .pilot import Pilot
from .potential_field import PotentialFieldPilot

PILOTS: dict[str, type[Pilot]] = {"potential-field": PotentialFieldPilot, "geometric": GeometricPilot}
assert tuple(PILOTS) == PILOT_NAMES


def make_pilot(name: str, params: PilotParams = PILOT, max_speed: float = ROBOT.max_speed) -> Pilot:
    """A fresh pilot of the named kind (raises ``ValueError`` for an unknown name)."""
    if name not in PILOTS:
        raise ValueError(f"unknown pilot {name!r} (expected one of: {', '.join(PILOT_NAMES)})")
    return PILOTS[name](params, max_speed)
