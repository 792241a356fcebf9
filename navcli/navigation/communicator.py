"""The Communicator: the Navigation system's voice to the Pilot and to Vision (notes, section 1;
thesis node 44).

It collects the agents' bids over a time window; a later bid from the same agent for the same
action type (Move/Stop or Look) replaces the earlier one; it then forwards the highest Move/Stop
bid to the Pilot and the highest Look bid to Vision, with their values, as the Navigation
system's bids, and says whose they were (:attr:`Communicator.forwarded_by`: a bid held from an
earlier tick may win, so this tick's bids alone do not tell).
"""

from __future__ import annotations

from typing import Iterable

from ..bidding import Bid, Resource, arbitrate


class Communicator:
    """See the module docstring. ``window`` is in simulated seconds; 0 keeps only this tick's bids."""

    def __init__(self, name: str = "navigation", window: float = 0.0):
        self.name = name
        self.window = window
        self._held: dict[tuple[str, Resource], tuple[float, Bid]] = {}
        self.forwarded_by: dict[Resource, str] = {}  # the agent whose bid each forwarded bid is, last call

    def forward(self, agent_bids: Iterable[Bid], time: float = 0.0) -> list[Bid]:
        """Take this tick's bids (at ``time``, s) and return each resource's winning bid among
        those held within the window, re-signed as the Navigation system's.

        >>> from navcli.bidding import Look, Move
        >>> c = Communicator(window=0.2)
        >>> bids = [Bid("a", "motion", Move(0.0, 0.3), 0.2), Bid("b", "motion", Move(1.0, 0.3), 0.4),
        ...         Bid("a", "camera", Look(0.5, "search"), 0.1)]
        >>> [(b.bidder, b.resource, b.value) for b in c.forward(bids, 0.0)]
        [('navigation', 'motion', 0.4), ('navigation', 'camera', 0.1)]
        >>> c.forwarded_by
        {'motion': 'b', 'camera': 'a'}
        >>> [(b.resource, b.value) for b in c.forward([Bid("b", "motion", Move(1.0, 0.3), 0.1)], 0.1)]
        [('motion', 0.2), ('camera', 0.1)]
        >>> c.forwarded_by  # a's earlier motion bid, held in the window, beats b's fresh one
        {'motion': 'a', 'camera': 'a'}
        >>> [(b.resource, b.value) for b in c.forward([], 0.35)]  # all older than the window
        []
        """
        held = {(b.bidder, b.resource): (time, b) for b in agent_bids}  # a later bid replaces the earlier
        # this tick's bids first, in the order offered, so ties go as the caller ordered them
        since = time - self.window - 1e-9
        for k, tb in self._held.items():
            if k not in held and tb[0] >= since:
                held[k] = tb
        self._held = held
        self.forwarded_by, out = {}, []
        for r, b in arbitrate([b for _, b in held.values()]).items():
            if b is not None:
                self.forwarded_by[r] = b.bidder
                out.append(Bid(self.name, r, b.action, b.value))
        return out
