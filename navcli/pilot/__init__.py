"""The Pilot (pilot paper): what every pilot shares (:mod:`.base`), the potential-field pilot of
the paper (:mod:`.potential_field`) and the geometric baseline of its Table 1 (:mod:`.geometric`).
Scenarios and ``--pilot`` name them ``potential-field`` and ``geometric``; a pilot of one's own
subclasses :class:`Pilot` and is found by name like them (:mod:`navcli.plugins`)."""

from __future__ import annotations

from .base import MODES, PHASES, Avoidance, Pilot, PilotOutput
from .geometric import RULES, SIDES, GeometricPilot
from .potential_field import PotentialFieldPilot

ENUMERATIONS: dict[str, tuple[str, ...]] = {
    "pilot.mode": MODES,
    "pilot.phase": PHASES,
    "geometric.rule": RULES,
    "geometric.side": SIDES,
}
"""The enumerations of the pilots' ``/pilot`` fields, by the name the log format gives each
(:func:`~navcli.log.format.enumerated`)."""

__all__ = ["ENUMERATIONS", "Avoidance", "GeometricPilot", "Pilot", "PilotOutput", "PotentialFieldPilot"]
