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

    Attributes:
        time: when it began (simulated s).
        what: the thing hit (``wall``, ``obstacle 3``, ``landmark A``).
        point: the contact point in the world (arena frame, m).
        bearing: its direction in the robot's frame (rad, 0 = ahead, + = left).
    """

    time: float
    what: str
    point: Point
    bearing: float


class KnownObstacle:
    """An obstacle as the robot knows it, egocentric: in metres, x ahead and y to the left of the
    robot, as it believes the obstacle lies (its memory's estimate, not the truth).

    A point obstacle has ``a == b`` (its centre); a linear one (a fence, a wall's stretch) runs
    from ``a`` to ``b``. The body's edge is ``radius`` from that point or segment: the clearance to
    an obstacle is ``distance_to_segment((0, 0), o.a, o.b) - o.radius``
    (:func:`navcli.geometry.distance_to_segment`), the robot's own radius not taken off.

    One is made per remembered object every tick and read many times over by the Pilot's field
    and swept-arc checks: a plain class with its own ``__init__``, which the compiled build makes
    native (docs/design.md, "Values made every tick"). A value: its fields are not reassigned
    (mypy holds them ``Final``), and it compares and hashes by them.

    Attributes:
        key: names it, the same every tick (``obstacle-3``; ``LA``: landmark A, which is an
            obstacle too), for logs and for keeping track of one obstacle across ticks.
        a: a point obstacle's centre, or one end of a linear one, ``(x, y)`` in m, egocentric.
        b: the other end of a linear one (``a`` again for a point obstacle), ``(x, y)`` in m.
        radius: its physical half-width (m): a post's radius, half a fence's or a wall's thickness.
        wall: it is (a known stretch of) one of the room's walls.
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
    """A landmark as the visual memory holds it (a NamedTuple: one is made per remembered landmark
    every tick).

    Attributes:
        key: the landmark's id (``A``, ``B`` ...).
        where: its fuzzy egocentric position (:class:`~navcli.fuzzy.FuzzyPoint`: centre and
            radii in m).
        seen: when it was last seen (simulated s).
    """

    key: str
    where: FuzzyPoint
    seen: float


@dataclass(frozen=True)
class Beliefs:
    """Everything an agent may use at one tick: what the robot believes, never the world's truth.
    Positions are egocentric (m; x ahead, y to the left of the robot), angles in rad (0 = ahead,
    + = left), times in simulated seconds.

    Attributes:
        time: the tick's simulated time (s).
        odometry: where the robot believes it is, in the arena frame (:class:`~navcli.geometry.Pose`:
            x, y in m, theta in rad): its odometry, which drifts with the motion noise.
        target: the current target point ``(x, y)`` (m, egocentric; a line target's centre), or
            None when there is none. The Pilot is given the Navigation system's current target
            here: a diverting target while the Rescuer holds one.
        target_line: the line to cross, a diverting target's or a line target's (two egocentric
            points, m), or None.
        obstacles: the obstacles the robot knows (its visual memory, bumped ones included),
            each a :class:`KnownObstacle`.
        target_spread: the width (rad) of the 70 % cut of the target's fuzzy heading: 0 when it is
            known exactly, 2 pi when it is lost.
        looked: the look (:class:`~navcli.bidding.Look`: pan in rad from the heading, and purpose)
            of the image the camera took during the previous tick, None if it took none.
        bumps: the bumper contacts (:class:`Bump`) that began during the previous tick.
        touching: the bumper was pressed during the previous tick (a contact that lasts is no new
            bump).
        landmarks: the remembered landmarks (:class:`KnownLandmark`), with their fuzzy positions.
        target_at: the target's fuzzy position as remembered (a point or landmark target), or None.
        target_seen: when the target was last seen (simulated s; 0 when only told where it is).
        pilot_blocked: the key of the long obstacle the Pilot reported during the previous tick as
            ahead and not easily avoided (the thesis' blocked situation, which the Rescuer answers
            with a diverting target), None when it reported none.
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
