"""What the agents know at one tick: plain values, egocentric, with no link to how they were made.

Agents (the Pilot, the Navigation agents) take :class:`Beliefs` and return bids; they never see
the world, the camera or the memory. So this module imports only values and geometry, and an
agent that imports it pulls in nothing else.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, NamedTuple

from .bidding import Look
from .fuzzy import FuzzyPoint
from .geometry import Point, Pose, midpoint


@dataclass(frozen=True)
class Bump:
    """A bumper contact that began during a tick.

    ``what`` names the thing hit (``wall``, ``obstacle 3``, ``landmark A``); ``point`` is the
    contact point in the world; ``bearing`` is its direction in the robot frame (rad, 0 = ahead).
    """

    time: float
    what: str
    point: Point
    bearing: float


class KnownObstacle:
    """An obstacle as the robot knows it, egocentric (x ahead, y left, metres).

    A point obstacle has ``a == b`` (its centre); a linear one runs from ``a`` to ``b``.
    ``radius`` is its physical half-width, ``key`` names it stably across ticks for logs;
    ``wall`` marks (a known stretch of) one of the room's walls. A value: its fields are not
    reassigned (mypy holds them ``Final``), and it compares and hashes by them.

    One is made per remembered object every tick and read many times over by the Pilot's field
    and swept-arc checks: a plain class with its own ``__init__``, which the compiled build makes
    native (built by a C call, its fields read directly; docs/design.md, "Values made every tick").
    """

    def __init__(self, key: str, a: Point, b: Point, radius: float, wall: bool = False) -> None:
        self.key: Final = key
        self.a: Final = a
        self.b: Final = b
        self.radius: Final = radius
        self.wall: Final = wall

    def _values(self) -> tuple[str, Point, Point, float, bool]:
        return (self.key, self.a, self.b, self.radius, self.wall)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, KnownObstacle) and self._values() == other._values()

    def __hash__(self) -> int:
        return hash(self._values())

    def __repr__(self) -> str:
        return (
            f"KnownObstacle(key={self.key!r}, a={self.a!r}, b={self.b!r}, radius={self.radius!r}, wall={self.wall!r})"
        )

    @property
    def is_point(self) -> bool:
        return self.a == self.b

    @property
    def centre(self) -> Point:
        """Where the paper computes a force from: a point obstacle itself, a linear one's middle."""
        return self.a if self.is_point else midpoint(self.a, self.b)


class KnownLandmark(NamedTuple):
    """A landmark as the visual memory holds it: its id, its fuzzy egocentric position, and the
    simulated time it was last seen (s). A NamedTuple, as :class:`KnownObstacle` (one per
    remembered landmark every tick)."""

    key: str
    where: FuzzyPoint
    seen: float


@dataclass(frozen=True)
class Beliefs:
    """Everything an agent may use at one tick. Positions are egocentric, in metres.

    ``target_spread`` is the width (rad) of the 70 % cut of the target's fuzzy heading: 0 when
    it is known exactly, 2 pi when it is lost. ``looked`` is the look (pan, rad from the
    heading, and purpose) of the image the camera took during the previous tick, ``None`` if it
    took none;
    ``bumps`` are the bumper contacts that began during the previous tick; ``touching`` says the
    bumper was pressed during the previous tick (a contact that lasts is no new bump).
    ``landmarks`` are the remembered landmarks with their fuzzy positions; ``target_at`` is the
    target's fuzzy position as remembered (a point or landmark target), ``target_seen`` when it
    was last seen (s; 0 when only told). ``pilot_blocked`` names the long obstacle the Pilot
    reported during the previous tick as ahead and not easily avoided (the thesis' blocked
    situation, which the Rescuer answers with a diverting target), None when it reported none.
    """

    time: float
    odometry: Pose  # where the robot believes it is, in the arena frame
    target: Point | None  # egocentric target point (the line's centre for a line target)
    target_line: tuple[Point, Point] | None  # egocentric diverting-target line, if any
    obstacles: tuple[KnownObstacle, ...]
    target_spread: float = 0.0
    looked: Look | None = None
    bumps: tuple[Bump, ...] = ()
    touching: bool = False
    landmarks: tuple[KnownLandmark, ...] = ()
    target_at: FuzzyPoint | None = None
    target_seen: float = 0.0
    pilot_blocked: str | None = None  # the long obstacle the Pilot reported last tick as one it cannot easily avoid
