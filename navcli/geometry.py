"""Plane geometry on plain float pairs: small, exact, and fast enough for a 10 Hz loop.

Points are ``(x, y)`` tuples in metres. These helpers are shared by the scenario checks, the
world's mission bookkeeping and the agents; none of them knows about pymunk.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

Point = tuple[float, float]
ORIGIN: Point = (0.0, 0.0)  # the robot, in egocentric coordinates


@dataclass(frozen=True)
class Pose:
    """A planar pose: position in metres, heading in radians counter-clockwise from +x.

    Attributes:
        x: position along the frame's x axis (m).
        y: position along the frame's y axis (m).
        theta: heading, counter-clockwise from the frame's +x (rad).
    """

    x: float
    y: float
    theta: float

    def to_local(self, p: Point) -> Point:
        """Express the world point ``p`` in this pose's frame (egocentric: x ahead, y left).

        Args:
            p: a point ``(x, y)`` in the pose's parent frame (m).

        Returns:
            The point in the pose's frame (m).

        >>> x, y = Pose(1.0, 1.0, math.pi / 2).to_local((1.0, 3.0))  # 2 m north of a robot facing north
        >>> round(x, 9), round(y, 9)
        (2.0, 0.0)
        """
        dx, dy = p[0] - self.x, p[1] - self.y
        c, s = math.cos(self.theta), math.sin(self.theta)
        return (c * dx + s * dy, -s * dx + c * dy)

    def to_world(self, q: Point) -> Point:
        """The inverse of :meth:`to_local`: an egocentric point back in this pose's parent frame.

        Args:
            q: a point ``(x, y)`` in the pose's frame (m).

        Returns:
            The point in the pose's parent frame (m).
        """
        c, s = math.cos(self.theta), math.sin(self.theta)
        return (self.x + c * q[0] - s * q[1], self.y + s * q[0] + c * q[1])


def motion_between(before: Pose, after: Pose) -> tuple[float, float]:
    """What wheel odometry reports for going from ``before`` to ``after``: the distance driven
    along the mid-way heading (m, negative backwards) and the turn (rad)."""
    dtheta = wrap_angle(after.theta - before.theta)
    mid = before.theta + dtheta / 2
    return (after.x - before.x) * math.cos(mid) + (after.y - before.y) * math.sin(mid), dtheta


def orthogonal(bearing: float) -> tuple[float, float]:
    """The heading (rad) square to ``bearing`` that needs the smaller turn from straight ahead, and
    its side (+1: left of the bearing, -1: right; left on a tie).

    >>> orthogonal(0.5)
    (-1.0707963267948966, -1.0)
    """
    left, right = math.remainder(bearing + math.pi / 2, 2 * math.pi), math.remainder(bearing - math.pi / 2, 2 * math.pi)
    return (left, 1.0) if abs(left) <= abs(right) else (right, -1.0)


def midpoint(a: Point, b: Point) -> Point:
    """The point halfway between ``a`` and ``b``."""
    return (a[0] + b[0]) / 2, (a[1] + b[1]) / 2


def wrap_angle(a: float) -> float:
    """Wrap an angle to (-pi, pi].

    Args:
        a: the angle (rad).

    Returns:
        The same direction in (-pi, pi] (rad).

    >>> wrap_angle(3 * math.pi) == math.pi, wrap_angle(-math.pi) == math.pi, round(wrap_angle(7.0), 6)
    (True, True, 0.716815)
    """
    a = math.fmod(a + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


def closest_on_segment(p: Point, a: Point, b: Point) -> Point:
    """The point of a segment nearest to a point (a point obstacle's segment is one point).

    Args:
        p: the point (m).
        a: the segment's one end (m).
        b: its other end (m; ``a`` again for a point).

    Returns:
        The segment's point nearest to ``p`` (m).
    """
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    L2 = dx * dx + dy * dy
    if L2 == 0.0:
        return a
    t = ((p[0] - ax) * dx + (p[1] - ay) * dy) / L2
    t = 0.0 if t < 0.0 else 1.0 if t > 1.0 else t
    return (ax + t * dx, ay + t * dy)


def distance_to_segment(p: Point, a: Point, b: Point) -> float:
    """The distance from a point to a segment.

    Args:
        p: the point (m).
        a: the segment's one end (m).
        b: its other end (m; ``a`` again for a point).

    Returns:
        The Euclidean distance (m).
    """
    q = closest_on_segment(p, a, b)
    return math.hypot(p[0] - q[0], p[1] - q[1])


def _cross(ox: float, oy: float, ax: float, ay: float, bx: float, by: float) -> float:
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


def segments_intersect(p1: Point, p2: Point, q1: Point, q2: Point) -> bool:
    """True when the closed segments ``p1p2`` and ``q1q2`` share a point (proper or touching).

    >>> segments_intersect((0, 0), (2, 2), (0, 2), (2, 0)), segments_intersect((0, 0), (1, 0), (1, 0), (1, 5))
    (True, True)
    >>> segments_intersect((0, 0), (1, 0), (0, 1), (1, 1))
    False
    """
    d1 = _cross(*q1, *q2, *p1)
    d2 = _cross(*q1, *q2, *p2)
    d3 = _cross(*p1, *p2, *q1)
    d4 = _cross(*p1, *p2, *q2)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True

    def on(a: Point, b: Point, c: Point, d: float) -> bool:
        return d == 0 and min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    return on(q1, q2, p1, d1) or on(q1, q2, p2, d2) or on(p1, p2, q1, d3) or on(p1, p2, q2, d4)


def segment_distance(p1: Point, p2: Point, q1: Point, q2: Point) -> float:
    """Shortest distance between the closed segments ``p1p2`` and ``q1q2`` (0 if they cross)."""
    if segments_intersect(p1, p2, q1, q2):
        return 0.0
    return min(
        distance_to_segment(p1, q1, q2),
        distance_to_segment(p2, q1, q2),
        distance_to_segment(q1, p1, p2),
        distance_to_segment(q2, p1, p2),
    )


def corridor_aim(a: Point, b: Point, margin: float, p: Point = (0.0, 0.0)) -> tuple[Point, bool]:
    """Where to head to cross the line ``ab`` from ``p`` (pilot paper, section 3.3, Figure 8).

    The safe corridor is the band perpendicular to the line over its middle part, ``margin``
    away from both ends. Inside it: the foot of the perpendicular (cross straight over);
    outside it: the line's centre. Returns (aim point, inside the corridor).

    >>> corridor_aim((1.0, -2.0), (1.0, 2.0), 0.4)  # in front of the middle: straight across
    ((1.0, 0.0), True)
    >>> corridor_aim((1.0, 0.2), (1.0, 4.0), 0.4)  # beside the end: head for the centre
    ((1.0, 2.1), False)
    """
    dx, dy = b[0] - a[0], b[1] - a[1]
    L = math.hypot(dx, dy)
    t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (L * L)
    if margin / L <= t <= 1.0 - margin / L:
        return (a[0] + t * dx, a[1] + t * dy), True
    return ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), False


def blocks_sight(eye: Point, p: Point, c: Point, r: float) -> bool:
    """Does a disc (c, r) cut the line of sight ``eye -> p``? Only strictly between the two: a
    disc beside either end is the looker's own neighbourhood or the looked-at thing's."""
    vx, vy = p[0] - eye[0], p[1] - eye[1]
    L2 = vx * vx + vy * vy
    if L2 == 0.0:
        return False
    t = ((c[0] - eye[0]) * vx + (c[1] - eye[1]) * vy) / L2
    if t <= 0.0 or t >= 1.0:
        return False
    qx, qy = eye[0] + t * vx - c[0], eye[1] + t * vy - c[1]
    return qx * qx + qy * qy < r * r


def crosses_sight(eye: Point, p: Point, a: Point, b: Point) -> bool:
    """Does segment ``ab`` properly cross the line of sight ``eye -> p`` (touching does not count)?"""
    d1 = (b[0] - a[0]) * (eye[1] - a[1]) - (b[1] - a[1]) * (eye[0] - a[0])
    d2 = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    if (d1 > 0) == (d2 > 0) or d1 == 0 or d2 == 0:
        return False
    vx, vy = p[0] - eye[0], p[1] - eye[1]
    d3 = vx * (a[1] - eye[1]) - vy * (a[0] - eye[0])
    d4 = vx * (b[1] - eye[1]) - vy * (b[0] - eye[0])
    return (d3 > 0) != (d4 > 0) and d3 != 0 and d4 != 0
