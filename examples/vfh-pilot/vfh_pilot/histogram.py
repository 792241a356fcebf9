"""The Vector Field Histogram, VFH+ (Ulrich & Borenstein 1998, "VFH+: Reliable obstacle avoidance
for fast mobile robots", ICRA), built on VFH (Borenstein & Koren 1991, "The vector field
histogram: fast obstacle avoidance for mobile robots", IEEE Trans. Robotics and Automation 7(3)).

Its four stages, each a function here, on plain numpy arrays:

1. **the primary polar histogram** (:func:`primary_histogram`): every occupied cell of the active
   window around the robot, at distance ``d`` and direction ``beta``, adds its magnitude
   ``m = c*^2 (a - b d^2)`` to every sector within its *enlargement angle*
   ``gamma = arcsin(r_rs / d)`` of ``beta`` (``r_rs = r_robot + d_safety``: the cell grown by the
   robot's radius and a safety distance), ``a - b ((w_s - 1) / 2)^2 = 1``;
2. **the binary polar histogram** (:func:`binary_histogram`): a sector is blocked above
   ``tau_high``, free below ``tau_low``, and between them as it was the step before (hysteresis);
3. **the masked polar histogram** (:func:`masked_histogram`): the robot drives arcs no tighter
   than its minimum turning radius, so an occupied cell that the right (left) circle of that
   radius, grown by ``r_rs``, would meet blocks every direction to the right (left) beyond it;
4. **the selection** (:func:`candidates`, :func:`choose`): openings of consecutive free sectors;
   a wide one (more than ``s_max`` sectors) gives the candidates ``s_max / 2`` in from each of its
   borders, and the target's direction when it lies between them; a narrow one its middle; the
   candidate of least cost ``mu1 D(c, k_t) + mu2 D(c, k_heading) + mu3 D(c, k_previous)`` wins,
   ``D`` the distance in sectors around the circle.

Sectors are numbered counter-clockwise from the frame's x axis, sector ``k`` centred on
``k * alpha``. The speed rule is VFH's: the speed falls with the primary histogram's density in
the direction of travel, ``V = V_max (1 - min(h_c, h_m) / h_m)``.
"""

from __future__ import annotations

import math

import numpy as np


def window_cells(radius: float, cell: float) -> np.ndarray:
    """The centres (k x 2, egocentric) of the active window's cells: a square grid of ``cell`` m
    centred on the robot, cut to the disc of ``radius`` (the window's ``(w_s - 1) / 2`` cells)."""
    half = int(round(radius / cell))
    ticks = np.arange(-half, half + 1) * cell
    xs, ys = np.meshgrid(ticks, ticks, indexing="ij")
    pts = np.stack([xs.ravel(), ys.ravel()], axis=1)
    d = np.hypot(pts[:, 0], pts[:, 1])
    return pts[(d <= radius + 1e-9) & (d > 1e-9)]


def occupied(cells: np.ndarray, a: np.ndarray, b: np.ndarray, radius: np.ndarray, cell: float) -> np.ndarray:
    """The certainty grid of VFH, from obstacles known as geometry (the robot's visual memory): a
    cell is occupied (``c* = 1``) when its centre lies within half a cell of an obstacle's body,
    the segment ``a``-``b`` (m x 2 each; a point obstacle has ``a == b``) widened by its ``radius``.
    Returns the occupied cells' centres."""
    if len(a) == 0:
        return cells[:0]
    ab = b - a  # m x 2
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-12)
    rel = cells[None, :, :] - a[:, None, :]  # m x k x 2
    t = np.clip((rel * ab[:, None, :]).sum(axis=2) / length2[:, None], 0.0, 1.0)
    nearest = a[:, None, :] + t[:, :, None] * ab[:, None, :]
    dist = np.hypot(cells[None, :, 0] - nearest[:, :, 0], cells[None, :, 1] - nearest[:, :, 1])
    return cells[(dist <= radius[:, None] + cell / 2).any(axis=0)]


def sector_of(angle: float | np.ndarray, n: int) -> np.ndarray:
    """The sector (0 .. n-1) whose centre is nearest ``angle`` (rad).

    >>> int(sector_of(math.radians(7.0), 72)), int(sector_of(-math.radians(5.0), 72))
    (1, 71)
    """
    return np.rint(np.asarray(angle) / (2 * math.pi / n)).astype(int) % n


def primary_histogram(cells: np.ndarray, heading: float, n: int, a: float, b: float, r_rs: float) -> np.ndarray:
    """Stage 1: the obstacle density of each of ``n`` sectors, from the occupied ``cells``
    (egocentric) of a robot whose heading in the histogram's frame is ``heading`` (rad):
    ``H_k = sum m h'``, ``m = a - b d^2`` (``c* = 1``), ``h' = 1`` for the sectors within
    ``gamma = arcsin(r_rs / d)`` of the cell's direction (all within 90 degrees for a cell closer
    than ``r_rs``).

    >>> h = primary_histogram(np.array([[1.0, 0.0]]), 0.0, 72, 5.0, 1.0, 0.35)
    >>> float(h[0]), int((h > 0).sum())  # m = 5 - 1; gamma = asin(0.35) = 20.5 deg: sectors -4 .. 4
    (4.0, 9)
    """
    if len(cells) == 0:
        return np.zeros(n)
    d = np.hypot(cells[:, 0], cells[:, 1])
    beta = np.arctan2(cells[:, 1], cells[:, 0]) + heading
    gamma = np.arcsin(np.minimum(1.0, r_rs / d))
    m = np.maximum(a - b * d * d, 0.0)
    centres = np.arange(n) * (2 * math.pi / n)
    off = np.abs((centres[:, None] - beta[None, :] + math.pi) % (2 * math.pi) - math.pi)  # n x cells
    return ((off <= gamma[None, :] + 1e-12) * m[None, :]).sum(axis=1)


def binary_histogram(h: np.ndarray, previous: np.ndarray, tau_low: float, tau_high: float) -> np.ndarray:
    """Stage 2: True where a sector is blocked: above ``tau_high``; free below ``tau_low``; between
    them as in ``previous`` (the step before), so a sector near the threshold does not flicker.

    >>> binary_histogram(np.array([1.0, 5.0, 9.0, 5.0]), np.array([True, True, False, False]), 3.0, 7.0).tolist()
    [False, True, True, False]
    """
    return np.where(h > tau_high, True, np.where(h < tau_low, False, previous))


def masked_histogram(blocked: np.ndarray, cells: np.ndarray, heading: float, r_turn: float, r_rs: float) -> np.ndarray:
    """Stage 3: True where a sector is blocked for a robot that turns no tighter than ``r_turn``
    (m): blocked in ``blocked``, or beyond the nearest direction to the right (left) of the heading
    in which an occupied cell lies within ``r_turn + r_rs`` of the centre of the right (left)
    turning circle, at ``(0, -r_turn)`` (``(0, r_turn)``) egocentric. ``heading`` places the
    egocentric cells in the histogram's frame."""
    n = len(blocked)
    phi_r, phi_l = -math.pi, math.pi  # egocentric limits: at first, straight behind
    if len(cells):
        beta = np.arctan2(cells[:, 1], cells[:, 0])
        reach2 = (r_turn + r_rs) ** 2
        right = cells[:, 0] ** 2 + (cells[:, 1] + r_turn) ** 2 < reach2
        left = cells[:, 0] ** 2 + (cells[:, 1] - r_turn) ** 2 < reach2
        if (right & (beta <= 0)).any():
            phi_r = float(beta[right & (beta <= 0)].max())
        if (left & (beta >= 0)).any():
            phi_l = float(beta[left & (beta >= 0)].min())
    centres = (np.arange(n) * (2 * math.pi / n) - heading + math.pi) % (2 * math.pi) - math.pi  # egocentric
    return blocked | (centres < phi_r) | (centres > phi_l)


def openings(blocked: np.ndarray) -> list[tuple[int, int]]:
    """The runs of free sectors as ``(start, length)``: sectors ``start``, ``start + 1`` ... counter-
    clockwise (``start`` the right border), around the circle; one run of every sector when all
    are free, none when all are blocked.

    >>> openings(np.array([True, False, False, True, True, False]))
    [(1, 2), (5, 1)]
    >>> openings(np.array([False, True, False]))  # a run across sector 0
    [(2, 2)]
    """
    n = len(blocked)
    if not blocked.any():
        return [(0, n)]
    first = int(np.argmax(blocked))  # start scanning just after a blocked sector
    runs, start, length = [], None, 0
    for i in range(1, n + 1):
        k = (first + i) % n
        if not blocked[k]:
            if start is None:
                start, length = k, 0
            length += 1
        elif start is not None:
            runs.append((start, length))
            start = None
    if start is not None:
        runs.append((start, length))
    return sorted(runs)


def candidates(runs: list[tuple[int, int]], target: int, s_max: int, n: int) -> list[int]:
    """Stage 4's candidate directions (sectors): for a wide opening (more than ``s_max`` sectors)
    the sectors ``s_max / 2`` in from each border and ``target`` when it lies between them; for a
    narrow one its middle.

    >>> candidates([(10, 30)], 25, 16, 72), candidates([(10, 30)], 5, 16, 72), candidates([(10, 6)], 5, 16, 72)
    ([18, 31, 25], [18, 31], [12])
    """
    out = []
    for start, length in runs:
        if length == n:
            return [target]
        if length > s_max:
            out += [(start + s_max // 2) % n, (start + length - 1 - s_max // 2) % n]
            if s_max // 2 <= (target - start) % n <= length - 1 - s_max // 2:
                out.append(target)
        else:
            out.append((start + (length - 1) // 2) % n)
    return out


def sector_distance(c1: int, c2: int, n: int) -> int:
    """The distance between two sectors around the circle: ``min(|c1 - c2|, |c1 - c2 - n|, |c1 - c2 + n|)``.

    >>> sector_distance(1, 71, 72)
    2
    """
    d = abs(c1 - c2) % n
    return min(d, n - d)


def choose(
    cands: list[int], target: int, heading: int, previous: int | None, mu: tuple[float, float, float], n: int
) -> int:
    """The candidate of least cost ``mu1 D(c, target) + mu2 D(c, heading) + mu3 D(c, previous)``
    (the last term left out before a first choice); the first of equals.

    >>> choose([18, 31, 25], 25, 0, None, (5.0, 2.0, 2.0), 72)  # toward the target: 0 + 2 x 25
    25
    """

    def cost(c: int) -> float:
        g = mu[0] * sector_distance(c, target, n) + mu[1] * sector_distance(c, heading, n)
        return g + (mu[2] * sector_distance(c, previous, n) if previous is not None else 0.0)

    return min(cands, key=cost)


def speed_factor(h_c: float, h_m: float, least: float) -> float:
    """VFH's speed rule: ``1 - min(h_c, h_m) / h_m`` of full speed, ``h_c`` the density in the
    direction of travel, never below ``least``.

    >>> speed_factor(5.0, 20.0, 0.2), speed_factor(50.0, 20.0, 0.2)
    (0.75, 0.2)
    """
    return max(least, 1.0 - min(h_c, h_m) / h_m)
