"""The market of the papers: bids for the robot's two resources, and the arbiter.

Both papers coordinate the robot's systems by bidding (pilot paper, section 2; learning-agent
paper, section 2): each system (and, inside Navigation, each agent) bids in [0, 1] for what it
wants a resource to do, and each resource carries out its highest bid. The same rule serves the
Communicator (the Navigation agents' internal auction) and the robot-level arbiter.
"""

from __future__ import annotations

import math
from typing import Iterable, Literal, NamedTuple

from .geometry import wrap_angle

Resource = Literal["motion", "camera"]
RESOURCES: tuple[Resource, ...] = ("motion", "camera")
SYSTEMS = ("pilot", "navigation")
"""The systems that bid at the robot's arbiter, by the names their bids go by: the Pilot's are
``pilot`` whatever a plugin pilot calls itself (its bids are keys of the log's ``/bids``)."""


class _MoveFields(NamedTuple):
    heading: float
    speed: float


class Move(_MoveFields):
    """A motion action: head for ``heading`` at ``speed``. ``Move(0, 0)`` is a stop.

    A dozen actions and bids are made every tick (a NamedTuple: docs/design.md, "Values made every tick"), like :class:`Look` and :class:`Bid`.
    Build them with the constructor, which checks them: ``_replace`` and ``_make`` would not.

    Attributes:
        heading (float): where to head, egocentric (rad: 0 = straight ahead, + = left).
        speed (float): how fast (m/s; negative = backwards). A pilot's own move is at most its
            ``max_speed``.

    Raises:
        ValueError: the heading or the speed is not a finite number.
    """

    __slots__ = ()

    def __new__(cls, heading: float, speed: float) -> Move:
        if not (math.isfinite(heading) and math.isfinite(speed)):
            raise ValueError(f"a move needs a finite heading and speed, got {heading}, {speed}")
        return tuple.__new__(cls, (heading, speed))

    def as_json(self) -> dict:
        """The move as ``/bids`` logs it.

        Returns:
            ``{"type": "move", "heading_deg": ..., "speed": ...}`` (deg, m/s).
        """
        return {"type": "move", "heading_deg": math.degrees(self.heading), "speed": self.speed}


LookPurpose = Literal["search", "landmarks", "target", "obstacles", "scan", "everything"]
PURPOSES: tuple[LookPurpose, ...] = ("search", "landmarks", "target", "obstacles", "scan", "everything")
"""What a look is for, said by whoever wins the camera. The learning paper (section 5.3): "The
vision system can either search for new landmarks or re-acquire already-detected landmarks, but
it is not able to do both things at the same time, because different image processing routines
are required for each." Each purpose is one routine (:mod:`navcli.vision.routines` says what
each registers):

- ``search``: search the view for new landmarks (MLL, the Risk Manager, the Rescuer's sweep and
  exploring looks);
- ``landmarks``: re-acquire the known landmarks in view (MVL);
- ``target``: re-acquire the target (the Target Tracker, the Distance Estimator, MVT, MOT);
- ``obstacles``: look for obstacles (the Pilot's look ahead, eq. 1, and its looks round a bump);
- ``scan``: scan for the lost target (the Rescuer's scans): the target and the known landmarks;
- ``everything``: the camera without routines (``vision.routines`` 0): every image registers
  everything in view, so it serves every purpose. No agent asks for it; the camera reports its
  images so, and :func:`looked_at` counts such an image for whoever asked for that pan.
"""


class _LookFields(NamedTuple):
    pan: float
    purpose: LookPurpose


class Look(_LookFields):
    """A camera action: pan to ``pan`` and take a look for ``purpose``. (A NamedTuple: see
    :class:`Move`.)

    Attributes:
        pan (float): where to point the camera, relative to the robot's heading (rad, + = left).
        purpose (str): what the look is for, one of :data:`PURPOSES`.

    >>> Look(0.5, "search")
    Look(pan=0.5, purpose='search')
    >>> Look(0.0, "anything")
    Traceback (most recent call last):
    ...
    ValueError: a look's purpose is one of search, landmarks, target, obstacles, scan, everything; got 'anything'
    """

    __slots__ = ()

    def __new__(cls, pan: float, purpose: LookPurpose) -> Look:
        if not math.isfinite(pan):
            raise ValueError(f"a look needs a finite pan, got {pan}")
        if purpose not in PURPOSES:
            raise ValueError(f"a look's purpose is one of {', '.join(PURPOSES)}; got {purpose!r}")
        return tuple.__new__(cls, (pan, purpose))

    def as_json(self) -> dict:
        """The look as ``/bids`` logs it.

        Returns:
            ``{"type": "look", "pan_deg": ..., "purpose": ...}`` (deg).
        """
        return {"type": "look", "pan_deg": math.degrees(self.pan), "purpose": self.purpose}


LOOK_MATCH = math.radians(5.0)  # our design: a reported look within this of the pan asked for is that look


def looked_at(looked: Look | None, want: Look) -> bool:
    """Did the camera's report of an image (``looked``: the look it carried out, None: no image)
    carry out the request ``want``: the same purpose, at a pan within :data:`LOOK_MATCH`? An
    agent counts only the images it asked for, not a look another agent won.

    >>> looked_at(Look(0.01, "scan"), Look(0.0, "scan")), looked_at(Look(0.0, "search"), Look(0.0, "scan"))
    (True, False)
    >>> looked_at(Look(0.0, "everything"), Look(0.0, "scan"))  # an image that registers all in view serves every purpose
    True
    """
    if looked is None or looked.purpose not in (want.purpose, "everything"):
        return False
    return abs(wrap_angle(looked.pan - want.pan)) < LOOK_MATCH


Action = Move | Look
ACTION_TYPES = ("move", "look")
"""The kinds of action, as a bid's action says in ``/bids`` (:meth:`Move.as_json`, :meth:`Look.as_json`)."""


class _BidFields(NamedTuple):
    bidder: str
    resource: Resource
    action: Action
    value: float


class Bid(_BidFields):
    """One bidder's offer for one resource: the action it wants and its urgency in [0, 1].
    (A NamedTuple: see :class:`Move`.)

    Attributes:
        bidder (str): who bids: ``pilot`` or ``navigation`` at the robot's arbiter, an agent's
            name inside the Navigation system.
        resource (str): ``motion`` (the wheels) or ``camera``.
        action (Move | Look): a :class:`Move` for the wheels, a :class:`Look` for the camera.
        value (float): the bid, in [0, 1]; each resource carries out its highest.

    >>> Bid("pilot", "motion", Move(0.0, 0.3), 0.9).value
    0.9
    >>> Bid("pilot", "motion", Move(0.0, 0.3), float("nan"))
    Traceback (most recent call last):
    ...
    ValueError: bid of pilot for motion is nan, outside [0, 1]
    """

    __slots__ = ()

    def __new__(cls, bidder: str, resource: Resource, action: Action, value: float) -> Bid:
        if not (0.0 <= value <= 1.0):
            raise ValueError(f"bid of {bidder} for {resource} is {value}, outside [0, 1]")
        if resource not in RESOURCES:
            raise ValueError(f"unknown resource {resource!r}")
        return tuple.__new__(cls, (bidder, resource, action, value))


def arbitrate(bids: Iterable[Bid]) -> dict[Resource, Bid | None]:
    """Give each resource to its highest bid.

    >>> stop, go = Move(0.0, 0.0), Move(0.0, 0.3)
    >>> arbitrate([Bid("pilot", "motion", stop, 0.5), Bid("navigation", "motion", go, 0.5)])["motion"].bidder
    'pilot'

    Tie rule: between equal bids the one offered first wins, so the caller's fixed order of
    consultation (the Pilot before the Navigation system: safety first) decides, and the outcome
    never depends on hashing or timing.

    Args:
        bids: the bids, in the order of consultation.

    Returns:
        The winning bid of each resource, None for a resource nobody bid for.
    """
    best: dict[Resource, Bid | None] = dict.fromkeys(RESOURCES)
    for b in bids:
        cur = best[b.resource]
        if cur is None or b.value > cur.value:
            best[b.resource] = b
    return best
