"""The market of the papers: bids for the robot's two resources, and the arbiter.

Both papers coordinate the robot's systems by bidding (pilot paper, section 2; learning-agent
paper, section 2): each system (and, inside Navigation, each agent) bids in [0, 1] for what it
wants a resource to do, and each resource carries out its highest bid. The same rule serves the
Communicator (the Navigation agents' internal auction) and the robot-level arbiter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Literal, Protocol

from .geometry import wrap_angle

if TYPE_CHECKING:
    from .beliefs import Beliefs

Resource = Literal["motion", "camera"]
RESOURCES: tuple[Resource, ...] = ("motion", "camera")


@dataclass(frozen=True)
class Move:
    """A motion action: head for ``heading`` (rad, egocentric: 0 = straight ahead, + = left) at
    ``speed`` (m/s, negative = backwards). ``Move(0, 0)`` is a stop."""

    heading: float
    speed: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.heading) and math.isfinite(self.speed)):
            raise ValueError(f"a move needs a finite heading and speed, got {self.heading}, {self.speed}")

    def as_json(self) -> dict:
        return {"type": "move", "heading_deg": math.degrees(self.heading), "speed": self.speed}


@dataclass(frozen=True)
class Look:
    """A camera action: pan to ``pan`` (rad, relative to the robot's heading) and take a look."""

    pan: float

    def __post_init__(self) -> None:
        if not math.isfinite(self.pan):
            raise ValueError(f"a look needs a finite pan, got {self.pan}")

    def as_json(self) -> dict:
        return {"type": "look", "pan_deg": math.degrees(self.pan)}


LOOK_MATCH = math.radians(5.0)  # our design: a reported look within this of the pan asked for is that look


def looked_at(looked: float | None, pan: float) -> bool:
    """Did the camera's report of a look at ``looked`` (rad, None: no look) carry out a request for
    ``pan``? An agent counts only the images it asked for, not a look another agent won."""
    if looked is None:
        return False
    return abs(wrap_angle(looked - pan)) < LOOK_MATCH


Action = Move | Look


@dataclass(frozen=True)
class Bid:
    """One bidder's offer for one resource: the action it wants and its urgency in [0, 1].

    >>> Bid("pilot", "motion", Move(0.0, 0.3), 0.9).value
    0.9
    >>> Bid("pilot", "motion", Move(0.0, 0.3), float("nan"))
    Traceback (most recent call last):
    ...
    ValueError: bid of pilot for motion is nan, outside [0, 1]
    """

    bidder: str
    resource: Resource
    action: Action
    value: float

    def __post_init__(self) -> None:
        if not (0.0 <= self.value <= 1.0):
            raise ValueError(f"bid of {self.bidder} for {self.resource} is {self.value}, outside [0, 1]")
        if self.resource not in RESOURCES:
            raise ValueError(f"unknown resource {self.resource!r}")


def arbitrate(bids: Iterable[Bid]) -> dict[Resource, Bid | None]:
    """Give each resource to its highest bid.

    >>> stop, go = Move(0.0, 0.0), Move(0.0, 0.3)
    >>> arbitrate([Bid("pilot", "motion", stop, 0.5), Bid("navigation", "motion", go, 0.5)])["motion"].bidder
    'pilot'

    Tie rule: between equal bids the one offered first wins, so the caller's fixed order of
    consultation (the Pilot before the Navigation system: safety first) decides, and the outcome
    never depends on hashing or timing. A resource nobody bid for maps to ``None``.
    """
    best: dict[Resource, Bid | None] = {r: None for r in RESOURCES}
    for b in bids:
        cur = best[b.resource]
        if cur is None or b.value > cur.value:
            best[b.resource] = b
    return best


class Agent(Protocol):
    """What a bidding agent is (the Navigation system's agents, and anything that replaces them):
    a name for the logs, and beliefs in, bids out. Agents keep their own state between ticks but
    learn of the world only through :class:`~navcli.beliefs.Beliefs`."""

    name: str

    def bid(self, beliefs: Beliefs) -> list[Bid]:
        ...
