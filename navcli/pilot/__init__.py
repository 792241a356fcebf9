"""The Pilot (pilot paper): what every pilot shares (:mod:`.base`), the potential-field pilot of
the paper (:mod:`.potential_field`) and the geometric baseline of its Table 1 (:mod:`.geometric`).
Scenarios and ``--pilot`` name them ``potential-field`` and ``geometric``; a pilot of one's own
subclasses :class:`Pilot` and is found by name like them (:mod:`navcli.plugins`)."""

from __future__ import annotations

from .base import Avoidance, Pilot, PilotOutput
from .geometric import GeometricPilot
from .potential_field import PotentialFieldPilot

__all__ = ["Avoidance", "GeometricPilot", "Pilot", "PilotOutput", "PotentialFieldPilot"]
