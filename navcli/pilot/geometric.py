"""The geometric pilot: the nearest-obstacle avoidance the potential-field pilot replaced.

The pilot paper (section 6) names it only as "simple ... a nearest obstacle avoidance (using
geometric principles) algorithm"; the thesis (notes, section 2, Pilot) adds that obstacles are
grown (points to circles, lines to rounded rectangles) and that "if about to enter a forbidden
area, [it] bid[s] to move tangentially to the grown obstacle". Our rules, in full:

1. Grow every known obstacle by ``R_min`` from its surface, into the same prohibited areas the
   potential-field pilot uses: a circle around a point obstacle, a rounded rectangle (capsule)
   around a linear one. Take the **nearest** prohibited area (smallest clearance to its edge).
2. If the robot is inside it, move straight away from it (from its nearest point), bid 0.9.
3. Otherwise, if the motion the Navigation system asks for (its requested heading) would enter
   that prohibited area within ``geometric_lookahead`` metres, steer along the tangent of it
   (grown by a further ``geometric_clearance``, so the path passes beside the area's edge rather
   than grazing it) on the side nearer the requested heading, and bid 0.9 (the Pilot's cap, which
   beats any Navigation bid) while that holds. The side is chosen when avoidance starts and kept,
   whichever obstacle is nearest, until the way has been clear for ``geometric_side_memory``
   metres of driving: without this the robot dithers in front of a long obstacle seen square on,
   where both sides are equally near, and spins in place where the memory holds a long obstacle
   as several pieces and the nearest one keeps changing (each turn in place costs heading
   precision, and a few dozen lose the target). The memory is measured in distance, not in
   ticks: the visual memory re-cuts a long obstacle into pieces at each image, and it holds no
   piece at all for a tick now and then; a side forgotten at such a tick was chosen afresh for
   the next piece, often the other one, and a robot at 5 cm/s (which takes six times the images
   per metre of one at 30 cm/s) zigzagged along the fence, its path growing by half.
4. Otherwise propose nothing: the Navigation system's request is safe.

Reflexes, backward turns and the look-ahead bid are the shared ones of :class:`navcli.pilot.base.Pilot`.
"""

from __future__ import annotations

import math

from ..beliefs import Beliefs, KnownObstacle
from ..bidding import Move
from ..geometry import ORIGIN, Point, closest_on_segment, segment_distance, wrap_angle
from .base import Avoidance, Pilot


RULES = ("escape", "clear", "tangent")
"""The geometric pilot's rules (the module docstring's 2, 4 and 3), as ``/pilot.rule`` says."""
SIDES = ("right", "left")
"""The sides it passes a prohibited area on, as ``/pilot.side`` says."""


def ray_enters(h: float, o: KnownObstacle, R: float, reach: float) -> bool:
    """Does driving ``reach`` metres from the origin along heading ``h`` enter ``o`` grown by ``R``
    from its surface?"""
    end = (math.cos(h) * reach, math.sin(h) * reach)
    return segment_distance(ORIGIN, end, o.a, o.b) < R + o.radius


def _tangents(c: Point, R: float) -> tuple[float, float]:
    """The two headings tangent to the circle (c, R) seen from the origin (outside it)."""
    d = math.hypot(c[0], c[1])
    bearing = math.atan2(c[1], c[0])
    half = math.asin(min(1.0, R / d))
    return wrap_angle(bearing - half), wrap_angle(bearing + half)


def blocked_interval(o: KnownObstacle, R: float) -> tuple[float, float]:
    """The headings (right edge, left edge) that lead into obstacle ``o`` grown by ``R`` from its
    surface.

    For a capsule, the union of the tangent cones of its two end circles (the straight sides lie
    between them)."""
    g = R + o.radius
    r1, l1 = _tangents(o.a, g)
    if o.is_point:
        return r1, l1
    r2, l2 = _tangents(o.b, g)
    cx, cy = o.centre
    mid = math.atan2(cy, cx)
    # measure the edges relative to the direction of the capsule's middle, to take min and max
    rights = [wrap_angle(r - mid) for r in (r1, r2)]
    lefts = [wrap_angle(left - mid) for left in (l1, l2)]
    return wrap_angle(mid + min(rights)), wrap_angle(mid + max(lefts))


class GeometricPilot(Pilot):
    """``--pilot geometric``: the baseline of Table 1 (rules in the module docstring; the side is
    kept until the way has been clear for ``geometric_side_memory`` m of driving)."""

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self._side: str | None = None  # the side chosen to pass what is being avoided, until the way is clear
        self._clear_run = 0.0  # m driven with the way clear since the side was chosen (or last needed)
        self._at = 0.0  # self.travelled at the last call

    def avoid(self, beliefs: Beliefs, obstacles: tuple[KnownObstacle, ...], request: Move | None) -> Avoidance:
        p = self.params
        R = p.R_min
        driven, self._at = self.travelled - self._at, self.travelled  # since the last call (not in a reflex)
        best, clearance = None, math.inf
        for o in obstacles:
            q = closest_on_segment(ORIGIN, o.a, o.b)  # a point obstacle's own centre
            c = math.hypot(q[0], q[1]) - o.radius - R  # from the prohibited area's edge
            if c < clearance:
                best, clearance, nearest = o, c, q
        info: dict = {
            "nearest": best.key if best else None,
            "clearance": clearance if best else None,
            "in_distress": clearance <= 0.0,
        }
        if best is None:
            self._clear(driven, p.geometric_side_memory)
            return Avoidance(None, 0.0, info)
        cap = p.bid_cap
        if clearance <= 0.0:  # rule 2: inside the prohibited area (escaping it is not a clear way)
            self._clear_run = 0.0
            away = math.atan2(-nearest[1], -nearest[0])
            return Avoidance(Move(away, self.max_speed), cap, info | {"rule": "escape", "turn_deg": math.degrees(away)})
        h = request.heading if request is not None else 0.0
        if (
            request is None
            or clearance > p.geometric_lookahead
            or not ray_enters(h, best, R, clearance + R + best.radius + p.geometric_lookahead)
        ):
            self._clear(driven, p.geometric_side_memory)
            return Avoidance(None, 0.0, info | {"rule": "clear"})
        self._clear_run = 0.0
        right, left = blocked_interval(best, R + p.geometric_clearance)  # rule 3: steer along the nearer tangent...
        if self._side is None:  # ...chosen once, so the robot does not dither between sides
            self._side = "right" if abs(wrap_angle(h - right)) <= abs(wrap_angle(h - left)) else "left"
        turn = right if self._side == "right" else left
        return Avoidance(
            Move(turn, self.max_speed),
            cap,
            info | {"rule": "tangent", "side": self._side, "turn_deg": math.degrees(turn)},
        )

    def _clear(self, driven: float, memory: float) -> None:
        """The way is clear this tick, ``driven`` m after the last: forget the side once it has
        stayed clear for ``memory`` m of driving (a reflex's backing up, which calls no avoidance,
        is not counted)."""
        if self._side is None:
            return
        self._clear_run += driven
        if self._clear_run >= memory:
            self._side, self._clear_run = None, 0.0
