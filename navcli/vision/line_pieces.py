"""The memory of linear obstacles as pieces, behind ``vision.line_objects`` 0 for the
sensitivity table: the camera reports a fence or wall, unidentified, as the pieces its view cuts
(the ends of each stretch in view, a point for a sliver), and the memory re-joins them by
geometry. A stretch joins the remembered line it lies along (:func:`same_line`), a sliver the
line it lies on (:func:`near_line`), and :func:`extend` moves the line's ends to the farthest
spots. Lines built so can cross open floor (a sample of one wall taken into the next wall's
line round a corner, a U's base and arm joined into one diagonal): the reason the default is one
identified object per fence (:meth:`navcli.vision.visual_memory.VisualMemory._observe_line`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..fuzzy import CUT

if TYPE_CHECKING:
    from .visual_memory import Memory, Spot, VisualMemory

END_TIE = 0.10  # m: ends this close along a linear obstacle count as the same extent; the sharper is kept
JOIN_ANGLE = math.radians(30.0)
"""Stretches whose crisp directions differ by more than this are never one line (ours: a far
sighting's supports let a piece of the next wall, round a corner, lie "on" a wall)."""


def join(memory: VisualMemory, spots: list[Spot], radius: float, time: float, kind: str) -> bool:
    """With ``vision.line_objects`` 0, join an unidentified sighting of a linear obstacle (a
    stretch, or a sliver: one spot) with the remembered line of its ``kind`` (a fence or a wall)
    it lies along, which then spans both; a lone sample of a wall on no wall known is dropped.
    True when the sighting was taken in (or dropped); False to remember it as new (the caller's
    point fusion and new objects). With ``line_objects`` 1, nothing is joined: False."""
    if memory.params.line_objects:
        return False
    gap = memory.params.line_join_gap
    lines = [m for m in memory.items.values() if len(m.spots) == 2 and m.kind == kind]
    if len(spots) == 1:
        for m in lines:
            if near_line(spots[0], m.spots, gap):  # a sliver of a linear obstacle already known
                extend(m, spots)
                m.radius, m.seen = radius, time
                return True
        return kind == "wall"  # a lone sample of a wall on no wall known: too little to remember
    same = [m for m in lines if same_line(m.spots, spots, gap)]
    if not same:
        return False
    keep = same[0]  # the stretch seen extends what is known, and may join two known stretches
    extend(keep, spots)
    for other in same[1:]:  # (not two fences that a stretch at their corner meets)
        if len(keep.spots) != 2:
            break  # it shrank to a point: nothing to join
        if same_line(keep.spots, other.spots, gap):
            extend(keep, other.spots)
            del memory.items[other.key]
    keep.radius, keep.seen = radius, time
    return True


def same_line(ends: list[Spot], spots: list[Spot], gap: float) -> bool:
    """Is the sighted stretch ``spots`` part of the remembered line ``ends`` (a fence or wall)?
    It runs along it (:data:`JOIN_ANGLE`), its ends lie on its line (:func:`plausible`), and the
    two overlap or leave at most ``gap`` m between their crisp ends (``vision.line_join_gap``; ours:
    views of one fence meet where a view was cut; joins across wider gaps drew walls through open
    rooms)."""
    a, b = ends
    ux, uy = b.x - a.x, b.y - a.y
    L = math.hypot(ux, uy)
    if L < 1e-9:
        return False
    ux, uy = ux / L, uy / L
    p, q = spots
    vx, vy = q.x - p.x, q.y - p.y
    lv = math.hypot(vx, vy)
    if lv > p.radius(CUT) + q.radius(CUT) and abs(ux * vy - uy * vx) > math.sin(JOIN_ANGLE) * lv:
        return False  # across the line, not along it (a stretch shorter than its 70 % cuts has no direction)
    along = []
    for s in spots:
        rx, ry = s.x - a.x, s.y - a.y
        if abs(rx * uy - ry * ux) > plausible(s, ends, L, gap):  # off the line
            return False
        along.append(rx * ux + ry * uy)
    return min(along) <= L + gap and max(along) >= -gap


def near_line(s: Spot, ends: list[Spot], gap: float) -> bool:
    """Does spot ``s`` lie on the segment between ``ends``: off its line by no more than their 70 %
    cuts (``gap`` if it has no direction), and along it between the ends or at most ``gap`` beyond
    one (see :func:`same_line`)?"""
    a, b = ends
    ux, uy = b.x - a.x, b.y - a.y
    L = math.hypot(ux, uy)
    if L < 1e-9:  # a point: as near as its cuts
        return math.hypot(s.x - a.x, s.y - a.y) <= plausible(s, ends, L, math.inf)
    tol = plausible(s, ends, L, gap)
    rx, ry = s.x - a.x, s.y - a.y
    t = (rx * ux + ry * uy) / L
    return -gap <= t <= L + gap and abs(rx * uy - ry * ux) / L <= tol


def plausible(s: Spot, ends: list[Spot], length: float, gap: float) -> float:
    """How far off a remembered line's ``ends`` (``length`` m apart) the spot ``s`` may lie and
    plausibly be on it: their 70 % cuts, not their supports, which at the camera's range are a
    metre wide; at most ``gap`` for a line too blurred to have a direction, its ends' cuts together
    wider than ``tan(JOIN_ANGLE)`` of its length (ours: such cuts let a wall take in the next wall
    round a corner, a U's base its arm)."""
    a, b = (e.radius(CUT) for e in ends)
    tol = s.radius(CUT) + max(a, b)
    return min(tol, gap) if a + b > length * math.tan(JOIN_ANGLE) else tol


def extend(m: Memory, spots: list[Spot]) -> None:
    """Grow the remembered linear obstacle ``m`` to span the sighted ``spots`` too.

    A linear sighting sharper than the memory and longer than its supports re-anchors the line:
    the remembered ends are moved onto the sighted line (their supports grown by the move, so they
    stay honest); a shorter one has no direction to give (ours: a U's arm seen by its corner
    turned the base onto it). The two spots farthest apart along the obstacle become its ends
    (of nearly equal extent, the sharper)."""
    a, b = m.spots
    if len(spots) == 2 and spots[0].r0 + spots[1].r0 < a.r0 + b.r0:
        p, q = spots
        ux, uy = q.x - p.x, q.y - p.y
        L = math.hypot(ux, uy)
        if L > p.r0 + q.r0:
            ux, uy = ux / L, uy / L
            moved = []
            for e in (a, b):
                t = (e.x - p.x) * ux + (e.y - p.y) * uy
                nx, ny = p.x + t * ux, p.y + t * uy
                moved.append(type(e)(nx, ny, e.r0 + math.hypot(e.x - nx, e.y - ny), e.r1))
            a, b = moved
    ux, uy = b.x - a.x, b.y - a.y
    L = math.hypot(ux, uy) or 1.0
    ux, uy = ux / L, uy / L
    # The ends of a stretch are wherever it left the view, not fixed points of the obstacle, so
    # they are never fused (that would mix two points); each kept end is one honest spot.
    along = [((s.x - a.x) * ux + (s.y - a.y) * uy, s) for s in (a, b, *spots)]
    lo, hi = min(t for t, _ in along), max(t for t, _ in along)
    first = min((s for t, s in along if t <= lo + END_TIE), key=lambda s: s.r0)
    last = min((s for t, s in along if t >= hi - END_TIE), key=lambda s: s.r0)
    m.spots = [first, last] if first is not last else [first]  # all at one extent: a point now
