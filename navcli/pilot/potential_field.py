"""The potential-field Pilot of Mohan, Busquets, López de Màntaras and Sierra (2004).

Everything is egocentric, as in the paper (section 3.4): the robot is at the origin, x ahead,
y to the left; obstacles and the target are positions relative to it, in metres. Forces are in
the paper's units (K = 18, A_t = 50: a force of 50 is the target's pull).

Section by section:
- 3.1 point obstacles: ``point_force`` (equations 2-4), the target: ``target_force`` (eq. 5);
- 3.2 linear obstacles: ``linear_force`` (magnitude from the nearest point, direction from the centre,
  and, our design, from the nearest point when IN_DISTRESS),
  and the room's walls, and linear obstacles longer than the paper's, as a bounded stretch of
  them (``wall_window``, our design);
- 3.3 diverting targets: ``line_target_force`` (the safe corridor);
- 3.4 net force and turn angle: ``field`` (eq. 6, 7);
- 4 the bid: ``pilot_bid`` (eq. 9);
- 5 the fixes: occlusion (``facing``; an obstacle in distress is never hidden), IN_DISTRESS (each
  offending obstacle x1.5, target ignored), passed obstacles (repulsion dropped when it points
  within 90 degrees of the attraction), and the averaging of the turn angle with the previous one
  (in :class:`PotentialFieldPilot`).

**Prohibited areas are grown from the obstacle's surface** (our reading of section 3.1, where
obstacles are grown "slightly larger than the diameter of the robot"): ``d`` in eq. 2-4 is the
distance from the robot's centre to the obstacle's surface (its centre or nearest point less its
physical half-width), so with R_min = 0.40 m and a 0.25 m robot IN_DISTRESS begins 0.15 m before
contact, whatever the obstacle's size. The paper's obstacles are points and lines of no width,
for which this is the paper's formula unchanged; the direction of each force stays the paper's
(from the point, or from the linear obstacle's centre).

**Eq. 8** (the analysis the paper omits): the robot heads for a gap between two point obstacles
``2 d_min`` wide along its bisector; at ``x`` before the gap their repulsions push it back with
``2 K x / (x^2 + d_min^2)^(3/2)``, largest at ``x = d_min / sqrt(2)``, where it is
``(2 / sqrt 2) / (3/2)^(3/2) K / d_min^2 = 0.7698 K / d_min^2``. The robot passes when the target's
constant pull A_t exceeds that: ``A_t > 0.770 K / d_min^2`` (the paper rounds the constant to 0.76).
With K = 18 and A_t = 50, ``d_min = 0.526 m``: the gap must be wider than **1.053 m** between
centres (the paper says "1 meter"). :func:`passable_gap` computes it, also for obstacles with a
radius; ``tests/test_pilots.py`` checks in simulation that the pilot passes just above it and
stops just below.

The loops are plain Python on purpose: with the dozen obstacles of the paper's rooms a per-obstacle
loop costs less than numpy's call overhead.
"""

from __future__ import annotations

import math
from typing import Any, Final, NamedTuple, cast

from ..beliefs import Beliefs, KnownObstacle
from ..bidding import Move
from ..geometry import ORIGIN, Point, closest_on_segment, corridor_aim, wrap_angle
from ..params import PilotParams, RobotParams
from .base import Avoidance, Pilot

NUMPY_FROM = 32  # obstacles: where numpy's occlusion test overtakes the loop (navcli bench --occlusion)


def point_force(o: Point, K: float, R_min: float, radius: float = 0.0) -> tuple[float, float, float, bool]:
    """Force of a point obstacle at ``o`` (of physical ``radius``) on the robot at the origin:
    (fx, fy, |F|, in_distress).

    Eq. 2 with Q = q_o = 1: ``F = K / d**2 * u``, ``u`` the unit vector from the obstacle to the
    robot, ``d`` measured from the obstacle's surface; eq. 3-4: inside the prohibited area
    (``d <= R_min``) the constant ``F_max = K / R_min**2``.
    """
    c = math.hypot(o[0], o[1])
    if c < 1e-12:
        return 0.0, 0.0, K / (R_min * R_min), True  # on top of it: no direction to flee in
    d = c - radius
    distress = d <= R_min
    mag = K / (R_min * R_min) if distress else K / (d * d)  # eq. 3 / eq. 2
    return -o[0] / c * mag, -o[1] / c * mag, mag, distress


def linear_force(
    a: Point, b: Point, K: float, R_min: float, radius: float = 0.0, distress_from_nearest: bool = False
) -> tuple[float, float, float, bool]:
    """Force of a linear obstacle ``ab`` of half-width ``radius`` (section 3.2): the magnitude of
    eq. 4 taken at the segment's nearest point (less the half-width), the direction from the
    segment's centre (Figure 6).

    ``distress_from_nearest``: inside the prohibited area the direction is from the nearest point
    instead (our design, ``pilot.distress_from_nearest``). There the push from the centre can
    point along the obstacle or into its neighbour: in the corner of two fences each one's
    centre pushes the robot toward the other, and the corner is a sink the robot spun in for
    minutes, touching both. Only the normal from the nearest point takes the body off what it
    is about to touch.

    >>> fx, fy, _, _ = linear_force((0.3, 0.0), (0.3, 3.0), 18.0, 0.4, distress_from_nearest=True)
    >>> round(fx, 6), round(fy, 6) + 0.0  # 18 / 0.4**2 straight back from the nearest point (0.3, 0)
    (-112.5, 0.0)
    >>> fx, fy, _, _ = linear_force((0.3, 0.0), (0.3, 3.0), 18.0, 0.4)  # section 3.2: from the centre (0.3, 1.5)
    >>> round(math.degrees(math.atan2(fy, fx)), 1)  # atan2(-1.5, -0.3)
    -101.3
    """
    q = closest_on_segment(ORIGIN, a, b)
    dq = math.hypot(q[0], q[1])
    d = dq - radius
    distress = d <= R_min
    mag = K / (R_min * R_min) if distress else K / (d * d)
    if distress and distress_from_nearest and dq > 1e-12:
        return -q[0] / dq * mag, -q[1] / dq * mag, mag, distress
    cx, cy = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
    dc = math.hypot(cx, cy)
    if dc < 1e-12:  # the robot sits on the centre: flee along the segment's normal, away from q
        nx, ny = -(b[1] - a[1]), b[0] - a[0]
        n = math.hypot(nx, ny)
        ux, uy = nx / n, ny / n
        if ux * q[0] + uy * q[1] > 0:
            ux, uy = -ux, -uy
        return ux * mag, uy * mag, mag, distress
    return -cx / dc * mag, -cy / dc * mag, mag, distress


def wall_window(o: KnownObstacle, length: float) -> KnownObstacle:
    """A wall as the stretch of it, at most ``length`` long, centred on its point nearest the
    robot and clipped to its ends (our design).

    Section 3.2 takes a linear obstacle's direction from its centre, which is right for the paper's
    obstacles (a few metres long, met from the side) but not for a room's walls: near a long wall
    the force would point along it, and a corner would become a sink where both walls push the
    robot further in. A bounded stretch around the nearest point keeps section 3.2's rule (its
    centre gives the direction) while the direction stays away from the wall, and turns away from
    a corner near a wall's end."""
    (ax, ay), (bx, by) = o.a, o.b
    L = math.hypot(bx - ax, by - ay)
    if L <= length:
        return o
    q = closest_on_segment(ORIGIN, o.a, o.b)
    t = math.hypot(q[0] - ax, q[1] - ay)
    lo = min(max(t - length / 2, 0.0), L - length)
    ux, uy = (bx - ax) / L, (by - ay) / L
    return KnownObstacle(
        o.key, (ax + lo * ux, ay + lo * uy), (ax + (lo + length) * ux, ay + (lo + length) * uy), o.radius, o.wall
    )


def passable_gap(K: float, A_t: float, radius: float = 0.0) -> float:
    """The narrowest gap (m, between the two obstacles' centres) the robot passes heading
    straight for the gap between two point obstacles of ``radius`` (eq. 8, derived in the module
    docstring): the half-gap ``d`` at which the largest push-back of the pair along the bisector,
    ``max_x 2 K x / (s (s - radius)^2)`` with ``s = hypot(x, d)``, equals A_t.

    >>> round(passable_gap(18.0, 50.0), 3)  # 2 sqrt(0.7698 K / A_t)
    1.053
    """

    def push(d: float) -> float:
        best, x = 0.0, 0.0
        while x < 4.0 * d + 1.0:  # the maximum lies near x = d / sqrt(2)
            s = math.hypot(x, d)
            best = max(best, 2.0 * K * x / (s * (s - radius) ** 2))
            x += d / 2000.0
        return best

    lo, hi = radius + 1e-6, 100.0
    for _ in range(60):  # bisection: push() falls as the gap widens
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if push(mid) > A_t else (lo, mid)
    return 2.0 * hi


def target_force(t: Point, A_t: float) -> tuple[float, float]:
    """Eq. 5: a constant pull of ``A_t`` toward the target (attractive, whatever the distance)."""
    d = math.hypot(t[0], t[1])
    if d < 1e-12:
        return 0.0, 0.0
    return t[0] / d * A_t, t[1] / d * A_t


def line_target_force(a: Point, b: Point, A_t: float, margin: float) -> tuple[float, float, bool]:
    """Section 3.3, a diverting target line ``ab`` to cross: (fx, fy, in_corridor).

    Inside the safe corridor the pull (eq. 5) is perpendicular to the line, toward it; outside,
    toward the line's centre (Figure 8; the corridor is :func:`navcli.geometry.corridor_aim`).
    """
    aim, inside = corridor_aim(a, b, margin)
    fx, fy = target_force(aim, A_t)
    return fx, fy, inside


def facing(obstacles: tuple[KnownObstacle, ...] | list[KnownObstacle]) -> list[bool]:
    """Section 5, occlusion: which obstacles contribute (see :func:`facing_loop`).

    Dispatches by size, as measured by ``navcli bench --occlusion``: plain Python for the
    dozen-odd obstacles of the paper's rooms, numpy from ``NUMPY_FROM`` obstacles on.
    """
    if len(obstacles) >= NUMPY_FROM:
        return facing_numpy(obstacles)
    return facing_loop(obstacles)


def facing_numpy(obstacles: tuple[KnownObstacle, ...] | list[KnownObstacle]) -> list[bool]:
    """:func:`facing_loop` as n x m array operations (the same tests, the same answers)."""
    import numpy as np

    n = len(obstacles)
    if n == 0:
        return []
    A = np.array([o.a for o in obstacles], dtype=float)
    B = np.array([o.b for o in obstacles], dtype=float)
    C = (A + B) / 2  # reference points: the centre of each obstacle (a point's centre is itself)
    cx, cy = C[:, 0:1], C[:, 1:2]  # (n, 1): one sight line 0 -> c per row
    L2 = cx * cx + cy * cy
    is_pt = np.all(A == B, axis=1)
    blocked = np.zeros((n, n), dtype=bool)
    if is_pt.any():
        P = A[is_pt]
        r2 = np.array([o.radius**2 for o, q in zip(obstacles, is_pt) if q])
        dot = cx * P[:, 0] + cy * P[:, 1]  # (n, m)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = dot / L2
            dx, dy = P[:, 0] - t * cx, P[:, 1] - t * cy  # as the loop computes it, to the last bit
            d2 = dx * dx + dy * dy
        blocked[:, is_pt] = (t > 0.0) & (t < 1.0) & (d2 < r2)
    if (~is_pt).any():
        SA, SB = A[~is_pt], B[~is_pt]
        d3 = cx * SA[:, 1] - cy * SA[:, 0]
        d4 = cx * SB[:, 1] - cy * SB[:, 0]
        ex, ey = SB[:, 0] - SA[:, 0], SB[:, 1] - SA[:, 1]
        d1 = ex * -SA[:, 1] - ey * -SA[:, 0]  # (k,)
        d2 = ex * (cy - SA[:, 1]) - ey * (cx - SA[:, 0])  # (n, k)
        # signs, not products: products of tiny coordinates underflow to zero
        blocked[:, ~is_pt] = (np.sign(d3) * np.sign(d4) < 0.0) & (np.sign(d1) * np.sign(d2) < 0.0)
    np.fill_diagonal(blocked, False)
    blocked[L2[:, 0] == 0.0] = False
    return cast(list[bool], (~blocked.any(axis=1)).tolist())  # numpy's tolist() gives Python bools


def facing_loop(obstacles: tuple[KnownObstacle, ...] | list[KnownObstacle]) -> list[bool]:
    """Section 5, 'more than one obstacle in the same direction': an obstacle contributes only
    if the line from its centre to the robot crosses no other obstacle (a point obstacle by its
    body, a linear one by its segment).

    The hot spot of a tick (n x n tests), so :func:`navcli.geometry.blocks_sight` (a point
    obstacle's body cuts the sight line ``0 -> c``) and :func:`navcli.geometry.crosses_sight`
    (a linear one crosses it properly) are inlined here, with the robot at the origin, and what
    does not depend on the sight line (the robot's side of each segment) is computed once.
    A point obstacle needs no test against itself: its own sight line ends on its centre, at
    ``t == 1`` exactly (the same products over the same sum), which the test excludes.
    """
    points = []  # x, y, radius^2
    lines = []  # index, a, b - a, the robot's side of ab
    for j, o in enumerate(obstacles):
        (ax, ay), (bx, by) = o.a, o.b
        if ax == bx and ay == by:
            points.append((ax, ay, o.radius * o.radius))
            continue
        ex, ey = bx - ax, by - ay
        d1 = ex * -ay - ey * -ax
        if d1 != 0.0:  # (the robot on the segment's line: no sight line crosses it properly)
            lines.append((j, ax, ay, bx, by, ex, ey, d1 > 0.0))
    out = []
    for i, o in enumerate(obstacles):
        cx, cy = o.centre
        L2 = cx * cx + cy * cy
        free = True
        if L2 > 0.0:
            for px, py, r2 in points:
                t = (px * cx + py * cy) / L2
                if t <= 0.0 or t >= 1.0:
                    continue  # beside the sight line's ends: the robot or the obstacle itself is nearer
                dx, dy = px - t * cx, py - t * cy
                if dx * dx + dy * dy < r2:
                    free = False
                    break
            if free:
                for j, ax, ay, bx, by, ex, ey, left in lines:
                    d3 = cx * ay - cy * ax  # sides of a and b relative to the sight line
                    d4 = cx * by - cy * bx
                    if (d3 > 0.0) == (d4 > 0.0) or d3 == 0.0 or d4 == 0.0 or j == i:
                        continue
                    d2 = ex * (cy - ay) - ey * (cx - ax)  # the side of c relative to ab
                    if left != (d2 > 0.0) and d2 != 0.0:
                        free = False
                        break
        out.append(free)
    return out


def pilot_bid(g_max: float, p: PilotParams) -> float:
    """Eq. 9: ``0.9 * G_max / |F_max|``, G_max the strongest single repulsion; in [0, 0.9].
    With K = 0 nothing repels, and the pilot bids nothing."""
    f_max = p.K / (p.R_min * p.R_min)  # eq. 3
    return p.bid_cap * min(g_max / f_max, 1.0) if f_max > 0.0 else 0.0


class ObstacleForce:
    """One obstacle's force (eq. 4 / section 3.2) and whether it counts (section 5); one per
    obstacle per tick (a plain class the compiled build makes native, as
    :class:`~navcli.beliefs.KnownObstacle`: docs/design.md, "Values made every tick")."""

    def __init__(self, key: str, fx: float, fy: float, magnitude: float, facing: bool, in_distress: bool) -> None:
        self.key: Final = key
        self.fx: Final = fx
        self.fy: Final = fy
        self.magnitude: Final = magnitude
        self.facing: Final = facing
        self.in_distress: Final = in_distress

    def _values(self) -> tuple[str, float, float, float, bool, bool]:
        return (self.key, self.fx, self.fy, self.magnitude, self.facing, self.in_distress)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ObstacleForce) and self._values() == other._values()

    def __hash__(self) -> int:
        return hash(self._values())

    def __repr__(self) -> str:
        return "ObstacleForce" + repr(self._values())


class Field(NamedTuple):
    """The net-force computation at one spot (section 3.4 with the section 5 fixes); one per tick
    (a NamedTuple: docs/design.md, "Values made every tick")."""

    forces: tuple[ObstacleForce, ...]
    target: tuple[float, float]
    repulsion: tuple[float, float]
    net: tuple[float, float]
    turn: float  # rad, eq. 7 (egocentric heading of the net force)
    in_distress: bool
    passed: bool  # repulsion dropped: obstacles already passed
    in_corridor: bool | None  # for a line target: inside the safe corridor
    g_max: float
    bid: float


def field(
    beliefs_target: Point | None,
    target_line: tuple[Point, Point] | None,
    obstacles: tuple[KnownObstacle, ...] | list[KnownObstacle],
    p: PilotParams,
) -> Field:
    """Net force, turn angle and bid for the robot at the origin (eq. 4-7 and 9, section 5)."""
    obstacles = [wall_window(o, p.wall_window if o.wall else p.line_window) for o in obstacles]
    face = facing(obstacles)
    K, R_min, nearest = p.K, p.R_min, bool(p.distress_from_nearest)
    forces = []
    rx = ry = 0.0
    g_max = 0.0
    in_distress = False
    for o, f in zip(obstacles, face):
        a, b = o.a, o.b
        fx, fy, mag, distress = (
            point_force(a, K, R_min, o.radius) if a == b else linear_force(a, b, K, R_min, o.radius, nearest)
        )
        f = f or distress  # our design: the occlusion test never hides what the robot is about to touch
        forces.append(ObstacleForce(o.key, fx, fy, mag, f, distress))
        in_distress = in_distress or distress
        if not f:
            continue
        rx += fx
        ry += fy
        if mag > g_max:
            g_max = mag
    in_corridor = None
    if target_line is not None:
        tx, ty, in_corridor = line_target_force(*target_line, p.A_t, p.corridor_margin)
    elif beliefs_target is not None:
        tx, ty = target_force(beliefs_target, p.A_t)
    else:
        tx = ty = 0.0
    passed = False
    if in_distress:
        # Section 5: each obstacle that caused IN_DISTRESS weighs 1.5 times; the target is ignored.
        k = p.distress_gain - 1.0
        for of in forces:
            if of.in_distress:
                rx += k * of.fx
                ry += k * of.fy
        nx, ny = rx, ry
    else:
        if rx * tx + ry * ty > 0.0 and (rx or ry):
            # Section 5: repulsion within 90 degrees of the attraction comes from obstacles behind.
            passed = True
            rx = ry = 0.0
        nx, ny = rx + tx, ry + ty  # eq. 6
    turn = math.atan2(ny, nx) if (nx or ny) else 0.0  # eq. 7
    return Field(
        tuple(forces), (tx, ty), (rx, ry), (nx, ny), turn, in_distress, passed, in_corridor, g_max, pilot_bid(g_max, p)
    )


class PotentialFieldPilot(Pilot):
    """``--pilot potential-field``: steers along the net virtual force and bids eq. 9.

    Section 5, 'abrupt turns': the turn angle is the mean of the angle computed now and the one
    computed in the previous step (not a running filter: raw angles 0, 90, 90, 90 degrees give
    0, 45, 90, 90), except when IN_DISTRESS. The previous angle is carried into the present frame
    through odometry, so the mean is taken between two headings of the same frame.
    """

    def __init__(self, params: PilotParams, robot: RobotParams):
        super().__init__(params, robot)
        self._prev_heading: float | None = None  # the previous step's computed turn, as an odometry-frame heading

    def avoid(self, beliefs: Beliefs, obstacles: tuple[KnownObstacle, ...], request: Move | None) -> Avoidance:
        f = field(beliefs.target, beliefs.target_line, obstacles, self.params)
        theta = beliefs.odometry.theta
        turn = f.turn
        if self._prev_heading is not None and not f.in_distress:
            prev = wrap_angle(self._prev_heading - theta)
            turn = wrap_angle(prev + wrap_angle(turn - prev) / 2)  # section 5: the mean with the previous
        self._prev_heading = theta + f.turn
        blocked = blocking(f, obstacles)  # read by decisions (Pilot._report): found whether explained or not
        if not self.explains:
            return Avoidance(Move(turn, self.max_speed), f.bid, {} if blocked is None else {"blocked_by": blocked})
        info, arrows = explanation(f, turn, blocked)
        return Avoidance(Move(turn, self.max_speed), f.bid, info, arrows)


def explanation(f: Field, turn: float, blocked: str | None) -> tuple[dict[str, Any], list[tuple[str, float, float]]]:
    """What ``/pilot`` says of the field ``f`` (``turn``: the turn angle after the averaging, rad;
    ``blocked``: :func:`blocking`'s answer) and the force arrows drawn in ``/robot/scene``."""
    per_obstacle = {}
    arrows = [("net", *f.net), ("target", *f.target)]
    for of in f.forces:
        # explained to 1e-4 force units (the drawn arrows start at 2): written with all 17 digits, these
        # per-obstacle forces were 38 % of a log's bytes, 2.2 kB a tick on paper-8x8 (benchmarks/log_size.py)
        per_obstacle[of.key] = {
            "x": round(of.fx, 4),
            "y": round(of.fy, 4),
            "mag": round(of.magnitude, 4),
            "facing": of.facing,
        }
        if of.facing:
            arrows.append((of.key, of.fx, of.fy))
    info: dict[str, Any] = {
        "turn_deg": math.degrees(turn),
        "raw_turn_deg": math.degrees(f.turn),
        "in_distress": f.in_distress,
        "passed": f.passed,
        "g_max": f.g_max,
        "net": {"x": f.net[0], "y": f.net[1]},
        "target": {"x": f.target[0], "y": f.target[1]},
        "repulsive": {"x": f.repulsion[0], "y": f.repulsion[1]},
        "obstacles": per_obstacle,
    }
    if f.in_corridor is not None:
        info["in_corridor"] = f.in_corridor
    if blocked is not None:
        info["blocked_by"] = blocked
    return info, arrows


def blocking(f: Field, obstacles: tuple[KnownObstacle, ...]) -> str | None:
    """The long obstacle the field cannot lead round, or None (our reading of the thesis' "the
    Pilot reports a long obstacle ahead that cannot be easily avoided"): the net force leads
    away from the target (more than 90 degrees off the attraction) and the strongest push comes
    from a linear obstacle that is no wall of the room. In front of a fence seen square on, the
    potential field's minimum: the robot would only go back and forth there."""
    (nx, ny), (tx, ty) = f.net, f.target
    if nx * tx + ny * ty >= 0.0 or f.passed:
        return None
    strongest = max((of for of in f.forces if of.facing), key=lambda of: of.magnitude, default=None)
    if strongest is None:
        return None
    o = next(o for o in obstacles if o.key == strongest.key)
    return o.key if not o.is_point and not o.wall else None
