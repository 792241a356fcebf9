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

from .bidding import Bid, Move, arbitrate
from .geometry import corridor_aim
from .params import NAVIGATION, PILOT, NavigationParams
from .perception import Beliefs


@dataclass(frozen=True)
class TargetTracker:
    """Keeps the target located and heads for it (notes, section 2).

    Move bid ``kappa1 * (1 - I_a) ** alpha`` (the notes' substitute for the thesis' cut-off
    equations 7-8): highest when the target's heading is precisely known (``I_a = 0``). Until
    Vision lands the target's position comes from the mission and odometry, so ``I_a = 0``.
    """

    params: NavigationParams = NAVIGATION
    name: str = "target-tracker"

    def bid(self, beliefs: Beliefs, max_speed: float, imprecision: float = 0.0) -> list[Bid]:
        if beliefs.target is None:
            return []
        x, y = beliefs.target
        if beliefs.target_line is not None:  # a line to cross: through the safe corridor
            (x, y), _ = corridor_aim(*beliefs.target_line, PILOT.corridor_margin)
        value = self.params.kappa1 * (1.0 - imprecision) ** self.params.alpha
        return [Bid(self.name, "motion", Move(math.atan2(y, x), max_speed), value)]


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
