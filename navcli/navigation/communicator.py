"""The Communicator: the Navigation system's voice to the Pilot and to Vision (notes, section 1).

It holds the Navigation agents' own auction: of the bids the agents made, the highest Move/Stop
bid and the highest Look bid are forwarded, with their values, as the Navigation system's bids
for the motion and camera resources.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

from ..bidding import Bid, arbitrate


@dataclass(frozen=True)
class Communicator:
    name: str = "navigation"

    def forward(self, agent_bids: Iterable[Bid]) -> list[Bid]:
        """Each resource's winning agent bid, re-signed as the Navigation system's.

        >>> from navcli.bidding import Look, Move
        >>> bids = [Bid("a", "motion", Move(0.0, 0.3), 0.2), Bid("b", "motion", Move(1.0, 0.3), 0.4),
        ...         Bid("a", "camera", Look(0.5), 0.1)]
        >>> [(b.bidder, b.resource, b.value) for b in Communicator().forward(bids)]
        [('navigation', 'motion', 0.4), ('navigation', 'camera', 0.1)]
        """
        winners = arbitrate(agent_bids)
        return [Bid(self.name, r, b.action, b.value) for r, b in winners.items() if b is not None]
