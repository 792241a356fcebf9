"""The Risk Manager: keeps the risk of losing the target low (notes, section 2; thesis node 42),
by keeping "a reasonable amount of known landmarks, as non collinear as possible" around the
robot, so that the target can always be located through the beta-coefficient map."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..bidding import Bid, Look
from ..fuzzy import TWO_PI
from ..params import NAVIGATION, NavigationParams
from .situation import Situation

SECTORS = tuple(math.radians(a) for a in (0.0, 60.0, -60.0, 120.0, -120.0, 180.0))
"""The centres of the six 60-degree sectors around the robot (learning-agent paper, section 5.2)."""


def sector_of(x: float, y: float) -> int:
    """The index into :data:`SECTORS` of the sector holding the egocentric point (x, y): the
    nearest centre, the first of equals.

    >>> sector_of(1.0, 0.0), sector_of(-1.0, 0.0), sector_of(1.0, 1.0)
    (0, 5, 1)
    """
    h = math.atan2(y, x)
    best, nearest = math.inf, 0
    for i, c in enumerate(SECTORS):
        off = abs(math.remainder(h - c, TWO_PI))
        if off < best:  # strictly: the first of equals
            best, nearest = off, i
    return nearest


@dataclass(frozen=True)
class RiskManager:
    """Risk (thesis eq. 9; the operator our copy elides read as ``+``, as the notes propose)::

        R = 1 - min(1, q_A (|A| / 6) ** gamma_A + q_B (|B| / 6) ** gamma_B)

    ``A`` the landmarks ahead (within ``ahead_deg`` of the heading), ``B`` all known ones,
    ``q`` the Map Manager's non-collinearity quality of each set: R = 0 with six well-spread
    landmarks ahead, 1 with none. Our substitute bid (the thesis' is cut off): look with
    ``R ** gamma_R`` toward the sector, among those the camera can pan to, where the fewest
    landmarks are known, when ``R > R_bar``."""

    params: NavigationParams = NAVIGATION
    pan_limit: float = math.radians(100.0)
    name: str = "risk-manager"

    def risk(self, s: Situation) -> float:
        p = self.params
        a, b = len(s.ahead), len(s.landmarks)
        return 1.0 - min(1.0, float(s.quality_ahead * (a / 6) ** p.gamma_A + s.quality_around * (b / 6) ** p.gamma_B))

    def least_known_sector(self, s: Situation) -> float:
        """The centre (rad) of the reachable sector holding the fewest known landmarks (nearest
        ahead on a tie)."""
        counts = [0] * len(SECTORS)
        for lm in s.landmarks.values():
            counts[sector_of(lm.x, lm.y)] += 1
        reachable = [i for i, c in enumerate(SECTORS) if abs(c) <= self.pan_limit + 1e-9]
        return SECTORS[min(reachable, key=lambda i: (counts[i], abs(SECTORS[i])))]

    def bid(self, s: Situation) -> list[Bid]:
        r = self.risk(s)
        if r <= self.params.R_bar:
            return []
        return [Bid(self.name, "camera", Look(self.least_known_sector(s), "search"), min(1.0, r**self.params.gamma_R))]
