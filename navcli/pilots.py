"""The pilots a run can use, by the names scenarios and ``--pilot`` give them."""

from __future__ import annotations

from .params import PILOT, PILOT_NAMES, PilotParams
from .pilot import Pilot


def make_pilot(name: str, params: PilotParams = PILOT) -> Pilot:
    """A fresh pilot of the named kind (raises ``ValueError`` for an unknown name)."""
    if name not in PILOT_NAMES:
        raise ValueError(f"unknown pilot {name!r} (expected one of: {', '.join(PILOT_NAMES)})")
    return Pilot(params)
