"""What the bumpers tell the visual memory (:meth:`navcli.vision.visual_memory.VisualMemory.add_bump`):
whether a bump lies on a remembered line, whether two bumps may be on one object, and a line
moved, whole, to touch the robot where it was felt. A bumper knows where on the body it was
pressed and odometry where the robot stood; not what it touched."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Iterable

from ..fuzzy import CUT
from ..geometry import distance_to_segment

if TYPE_CHECKING:
    from .visual_memory import Memory, Spot


def line_under(items: Iterable[Memory], spot: Spot) -> Memory | None:
    """The remembered linear obstacle (not the target) that the bump ``spot`` may lie on: its
    centre no farther from the line's crisp segment than the line's half-width, the bump's
    support and the 70 % cut of the line there (its ends' cuts, linear in between: how far the
    line may be off)."""
    best, best_d = None, math.inf
    for m in items:
        if len(m.spots) != 2 or m.kind == "target":
            continue
        a, b = m.spots
        t = along(spot.x, spot.y, a.x, a.y, b.x, b.y)
        d = math.hypot(a.x + t * (b.x - a.x) - spot.x, a.y + t * (b.y - a.y) - spot.y)
        cut = (1.0 - t) * a.radius(CUT) + t * b.radius(CUT)
        if d <= m.radius + spot.r0 + cut and d < best_d:
            best, best_d = m, d
    return best


def one_object(bump: Memory, spot: Spot, body: float) -> bool:
    """May the remembered lone ``bump`` and the bump ``spot`` felt now be on one object: the
    line between them passes no nearer than the robot's radius to where the robot stood at
    either bump (now: the origin), and both times the robot stood on the same side of it?"""
    p, was = bump.spots[0], bump.felt_from
    if was is None:
        return False
    if not (clears(was, p, spot, body) and clears((0.0, 0.0), p, spot, body)):
        return False
    ux, uy = spot.x - p.x, spot.y - p.y
    then = ux * (was[1] - p.y) - uy * (was[0] - p.x)
    now = ux * (0.0 - p.y) - uy * (0.0 - p.x)
    return then * now > 0.0


def carried(s: Spot, dx: float, dy: float) -> Spot:
    """The end ``s`` of a linear obstacle moved by ``(dx, dy)`` with its other end, which a
    sighting corrected by that much: its support grown by the move, so that it still holds the
    whole of the support it had (honest whatever the correction; the move is what odometry shifted
    both ends by, bar the turn's share between them)."""
    grow = math.hypot(dx, dy)
    return type(s)(s.x + dx, s.y + dy, s.base + grow, s.r1, s.drift, s.r0 + grow)


def gap(a: Spot, b: Spot) -> float:
    """The distance between two spots' centres (m)."""
    return math.hypot(a.x - b.x, a.y - b.y)


def lone(m: Memory) -> bool:
    """Is ``m`` an unidentified point: a plain obstacle point or a bump?"""
    return m.kind in ("obstacle", "bump") and len(m.spots) == 1


def along(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    """Where along the segment from ``(ax, ay)`` (0) to ``(bx, by)`` (1) the point nearest
    ``(px, py)`` lies."""
    ux, uy = bx - ax, by - ay
    l2 = ux * ux + uy * uy
    return 0.0 if l2 == 0.0 else max(0.0, min(1.0, ((px - ax) * ux + (py - ay) * uy) / l2))


def onto(m: Memory, spot: Spot, body: float) -> None:
    """Move the remembered line ``m`` across, rigidly, so that it touches the robot, on the side
    where the bump ``spot`` was felt: in contact, the line's middle lies ``body`` plus its
    half-width from the robot's centre. Only where the robot's centre faces the line between its
    ends (beyond an end the contact is with the end, or with another thing); each end's support
    grows by the move, so it still holds all it held."""
    a, b = m.spots
    ux, uy = b.x - a.x, b.y - a.y
    length = math.hypot(ux, uy)
    if length == 0.0 or not 0.0 <= -(a.x * ux + a.y * uy) / (length * length) <= 1.0:
        return
    nx, ny = -uy / length, ux / length
    side = spot.x * nx + spot.y * ny
    if side == 0.0:
        return
    off = math.copysign(body + m.radius, side) - (a.x * nx + a.y * ny)  # the line's move across
    m.spots = [carried(e, off * nx, off * ny) for e in (a, b)]


def clears(at: tuple[float, float], a: Spot, b: Spot, body: float) -> bool:
    """Does the segment between the centres of ``a`` and ``b`` stay at least ``body`` (m) from
    ``at``, so that a robot standing there is not on it?"""
    return distance_to_segment(at, (a.x, a.y), (b.x, b.y)) >= body
