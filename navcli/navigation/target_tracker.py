"""The Target Tracker: keeps the target located with maximum precision and reaches it (notes,
section 2)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..bidding import Bid, Look, Move
from ..fuzzy import TWO_PI
from ..geometry import corridor_aim
from ..params import NAVIGATION, PILOT, ROBOT, NavigationParams
from .situation import Situation


@dataclass(frozen=True)
class TargetTracker:
    """Bids to move toward the target and to look at it, from how precisely it is known.

    The target's heading imprecision is ``I_a = (eps / 2 pi) ** beta`` (thesis eq. 6), ``eps`` the
    width of the 70 % cut of its fuzzy heading. The bidding functions are the notes' substitutes
    for the thesis' cut-off equations 7-8:

    - move toward the target: ``kappa1 * (1 - I_a) ** alpha``, falling as the target blurs;
    - look at the target: ``kappa2 * I_a / I_a_bar`` up to ``I_a_bar``, then
      ``kappa2 * (1 - I_a) / (1 - I_a_bar)``: low while the target is precise, highest when it
      becomes imprecise, and low again once it is lost (so the Rescuer can take over).

    A line target is headed for through the Pilot's safe corridor (``corridor_margin``, m, the
    pilot's parameter, so both aim at the same point); ``max_speed`` (m/s) is the speed asked for.
    A bid of 0 is not offered: once the target is lost (its heading unknown, I_a = 1) the tracker
    asks for no motion at all, so a silent Pilot leaves the wheels still instead of driving toward
    a heading nobody knows (finding the target again is the Rescuer's job). The target's estimate
    is the least imprecise of the visual memory's and the Map Manager's (the system asks the map
    whenever the target is out of sight); I_a is computed from it (:meth:`imprecision`).
    """

    params: NavigationParams = NAVIGATION
    max_speed: float = ROBOT.max_speed
    corridor_margin: float = PILOT.corridor_margin
    name: str = "target-tracker"

    def imprecision(self, spread: float) -> float:
        """I_a in [0, 1] from the width ``spread`` (rad) of the heading's 70 % cut (thesis eq. 6)."""
        return float(min(1.0, spread / TWO_PI) ** self.params.beta)

    def bid(self, s: Situation) -> list[Bid]:
        aim = s.aim
        if aim is None:
            return []
        p = self.params
        x, y = aim
        if s.target_line is not None:  # a line to cross: through the safe corridor
            (x, y), _ = corridor_aim(*s.target_line, self.corridor_margin)
        i_a = s.I_a
        move = p.kappa1 * (1.0 - i_a) ** p.alpha
        look = p.kappa2 * (i_a / p.I_a_bar if i_a <= p.I_a_bar else (1.0 - i_a) / (1.0 - p.I_a_bar))
        heading = math.atan2(y, x)
        bids = []
        if move > 0.0:
            bids.append(Bid(self.name, "motion", Move(heading, self.max_speed), move))
        if look > 0.0:
            bids.append(Bid(self.name, "camera", Look(heading, "target"), look))
        return bids
