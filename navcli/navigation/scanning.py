"""The Rescuer's scans and turns (see :mod:`.rescuer`): the looks of a scan, one pan an image,
and a turn by a random angle drawn from the Navigation system's generator."""

from __future__ import annotations

import math

import numpy as np

from ..bidding import Bid, Look, Move, looked_at
from ..geometry import Point, Pose, wrap_angle
from ..params import NavigationParams

STOP = Move(0.0, 0.0)  # a value: one serves every stop


class Scanning:
    """What the Rescuer's scans and turns need of it: its parameters, state, scan index, generator
    and the heading it turns to."""

    name: str
    params: NavigationParams
    state: str
    rng: np.random.Generator
    _scan: int
    _turn_to: float | None

    def _scan_look(self) -> Look:
        """The look of the scan's current pan: a scan for the lost target (the target and the
        known landmarks) when the target is lost; a search for new landmarks otherwise (the
        initial sweep, and looking around to explore)."""
        pan = math.radians(self.params.scan_pans_deg[self._scan])
        return Look(pan, "scan" if self.state == "lost" else "search")

    def _scan_bids(self) -> tuple[Bid, ...]:
        v = self.params.rescuer_bid
        return (Bid(self.name, "motion", STOP, v), Bid(self.name, "camera", self._scan_look(), v))

    def _scanned(self, looked: Look | None) -> bool:
        """Advance the scan when the camera reports the look asked for; True when all are done."""
        if self._scan < len(self.params.scan_pans_deg) and looked_at(looked, self._scan_look()):
            self._scan += 1
        return self._scan >= len(self.params.scan_pans_deg)

    def _start_turn(self, odo: Pose, events: list[tuple[str, str]], why: str, away: Point | None = None) -> None:
        """Turn by a random angle of up to ``random_turn_deg``; exploring (``away``: the target,
        egocentric), to a random heading within half that of the one away from the target."""
        lim = math.radians(self.params.random_turn_deg)
        if away is None:
            angle = float(self.rng.uniform(-lim, lim))
        else:
            angle = wrap_angle(math.atan2(away[1], away[0]) + math.pi + float(self.rng.uniform(-lim / 2, lim / 2)))
        self._turn_to = wrap_angle(odo.theta + angle)
        self.state = "turn"
        events.append(("warning", f"{why}: turning by {math.degrees(angle):.0f} deg"))
