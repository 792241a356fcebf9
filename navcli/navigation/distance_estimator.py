"""The Distance Estimator: keeps the error in the distance to the target low (notes, section 2;
thesis nodes 48-49). In the thesis' simulation vision gave bearings only, and distance came from
the change of bearing across viewframes, so the agent bid "very high to move the robot
orthogonally to the line connecting it to the target and looking to the target"."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..bidding import Bid, Look, Move
from ..fuzzy import CUT
from ..geometry import orthogonal
from ..params import NAVIGATION, ROBOT, NavigationParams
from .situation import Situation


@dataclass(frozen=True)
class DistanceEstimator:
    """Our substitute bid (the thesis' formula was not available): ``kappa * tanh(I_d / d)``,
    ``I_d`` the width (m) of the 70 % cut of the target's fuzzy distance and ``d`` its distance,
    to move at right angles to the target's bearing (on the side needing the smaller turn) and to
    look at the target. Silent for a line target, whose crossing needs no distance.

    The notes propose ``kappa * tanh(I_d)``; we divide by the distance because our camera measures
    distances (the thesis' agent existed for a camera that gave bearings only): a target 8 m away
    known to within a metre needs no detour, one whose distance is as uncertain as the distance
    itself does. With ``kappa * tanh(I_d)`` the agent outbid the Target Tracker on paper-8x8 as
    soon as odometry drift blurred the target by a metre, and sent the robot sideways."""

    params: NavigationParams = NAVIGATION
    max_speed: float = ROBOT.max_speed
    name: str = "distance-estimator"

    def bid(self, s: Situation) -> list[Bid]:
        if s.target is None or s.target_line is not None:
            return []
        d = max(math.hypot(s.target.x, s.target.y), 1e-9)
        r = s.target.radius(CUT)
        i_d = min(d, r) + r  # the width of the distance's 70 % cut, (max(0, d - r), d + r)
        value = self.params.kappa * math.tanh(i_d / d)
        if value <= 0.0:
            return []
        bearing = math.atan2(s.target.y, s.target.x)
        heading, _ = orthogonal(bearing)  # the smaller turn; left on a tie
        return [
            Bid(self.name, "motion", Move(heading, self.max_speed), value),
            Bid(self.name, "camera", Look(bearing, "target"), value),
        ]
