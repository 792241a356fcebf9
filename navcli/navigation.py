"""The Navigation system: agents that bid among themselves, and the Communicator.

Learning-agent paper, section 2, and notes section 1-2: each Navigation agent bids for the action
it wants; the Communicator takes the highest Move/Stop bid and the highest Look bid and sends
each, with its value, as the Navigation system's bid to the Pilot and to Vision. This module
holds the Target Tracker so far; the Risk Manager, Rescuer, Distance Estimator and Map Manager
join it with the navigation issue.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .bidding import Bid, Look, Move, arbitrate
from .fuzzy import TWO_PI
from .geometry import corridor_aim
from .params import NAVIGATION, PILOT, NavigationParams
from .perception import Beliefs


@dataclass(frozen=True)
class TargetTracker:
    """Keeps the target located with maximum precision and reaches it (notes, section 2).

    The target's heading imprecision is ``I_a = (eps / 2 pi) ** beta`` (thesis eq. 6), ``eps`` the
    width of the 70 % cut of its fuzzy heading. The bidding functions are the notes' substitutes
    for the thesis' cut-off equations 7-8:

    - move toward the target: ``kappa1 * (1 - I_a) ** alpha``, falling as the target blurs;
    - look at the target: ``kappa2 * I_a / I_a_bar`` up to ``I_a_bar``, then
      ``kappa2 * (1 - I_a) / (1 - I_a_bar)``: low while the target is precise, highest when it
      becomes imprecise, and low again once it is lost (so the Rescuer can take over).
    """

    params: NavigationParams = NAVIGATION
    name: str = "target-tracker"

    def imprecision(self, beliefs: Beliefs) -> float:
        """I_a in [0, 1]."""
        return min(1.0, beliefs.target_spread / TWO_PI) ** self.params.beta

    def bid(self, beliefs: Beliefs, max_speed: float) -> list[Bid]:
        if beliefs.target is None:
            return []
        p = self.params
        x, y = beliefs.target
        if beliefs.target_line is not None:  # a line to cross: through the safe corridor
            (x, y), _ = corridor_aim(*beliefs.target_line, PILOT.corridor_margin)
        i_a = self.imprecision(beliefs)
        move = p.kappa1 * (1.0 - i_a) ** p.alpha
        look = p.kappa2 * (i_a / p.I_a_bar if i_a <= p.I_a_bar else (1.0 - i_a) / (1.0 - p.I_a_bar))
        heading = math.atan2(y, x)
        bids = [Bid(self.name, "motion", Move(heading, max_speed), move)]
        if look > 0.0:
            bids.append(Bid(self.name, "camera", Look(heading), look))
        return bids


class NavigationSystem:
    """The agents plus the Communicator; ``bid`` returns the system's bids per resource."""

    name = "navigation"

    def __init__(self, max_speed: float, params: NavigationParams = NAVIGATION):
        self.max_speed = max_speed
        self.tracker = TargetTracker(params)
        self.last_agent_bids: list[Bid] = []

    def bid(self, beliefs: Beliefs) -> list[Bid]:
        """Run the agents' auction (the Communicator) and forward each resource's winner."""
        agent_bids = self.tracker.bid(beliefs, self.max_speed)
        self.last_agent_bids = agent_bids
        winners = arbitrate(agent_bids)
        return [Bid(self.name, r, b.action, b.value) for r, b in winners.items() if b is not None]
