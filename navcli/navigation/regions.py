"""Topological regions of the landmark map and the diverting target (notes, section 4).

The thesis builds regions from landmarks ("a landmark can be component of several regions"),
links them in a graph whose arcs cost 1 unless other systems report them blocked, finds the
shortest path from the robot's region to one holding the target, and hands the Pilot the first
step: an edge between two landmarks to cross, one landmark kept on the left and one on the right.
How regions are formed was not available to us; **our design**, as the notes propose after
Levitt and Lawton's qualitative navigation:

- regions are the triangles of a Delaunay triangulation of the mapped landmarks
  (``scipy.spatial.Delaunay``);
- beyond each edge of the convex hull a *virtual landmark* is placed ``virtual_distance`` metres
  out from the edge's middle, so the space around the landmarks belongs to outer regions too;
- **known long obstacles split what they cross**: each is put into the triangulation as a chain of
  *obstacle points* (ids ``#<key>:<i>``, its ends and points at most ``OBSTACLE_STEP`` apart
  along it), so the triangles lie on one side of it or the other and the edges of the chain run
  along it. An edge whose ends lie on the same obstacle (along it) is blocked, and so is every
  edge, to a virtual landmark too, that a known obstacle crosses, or that is too narrow for the
  robot, or that a wall crosses near its end (:func:`blocked_edges`): a robot in front of a fence
  and a target behind it are in different regions, and the way between them goes round the
  fence's ends, where an edge joins an end to a landmark. Obstacle points' ids follow the
  memory's keys and the obstacle's length, so they are not stable over a run as landmarks' are;
- two regions sharing an edge are joined by an arc whose cost is 1, or ``blocked_cost`` when the
  edge is known to be blocked (a long obstacle crosses it, or a diverting target through it
  failed), or ``seen_closed_cost`` when only a remembered obstacle the memory no longer holds
  was seen across it (the Map Manager's ``seen_blocked``: a way seen closed costs more and is
  tried again, never closed for good); the shortest path is ``scipy.sparse.csgraph.dijkstra``;
  :func:`way_out` takes as closed only what the obstacles the memory holds block;
- the robot's region (and the target's) is the triangle holding it, or the nearest one.

Everything is in one frame (the robot's, egocentric); landmark ids keep edges stable over time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from ..geometry import distance_to_segment, midpoint

Point = tuple[float, float]
Edge = frozenset[str]  # of two landmark ids
OBSTACLE_STEP = 1.0
"""m: the longest stretch of a known obstacle between two of its points in the triangulation (our
design: short enough that the triangulation's edges follow the obstacle between its points)."""
CROSS_MARGIN = 0.05
"""m: an obstacle that meets an edge this near one of the edge's ends touches it there (a bump
line drawn from a landmark, the end of a fence at its own point) and does not block it."""


def ends(edge: Edge) -> tuple[str, str]:
    """An edge's two landmark ids, in order (for messages and the log).

    >>> ends(frozenset(("B", "A")))
    ('A', 'B')
    """
    u, v = sorted(edge)
    return u, v


def is_real(key: str) -> bool:
    """A landmark, not a virtual landmark (``~``) or an obstacle's point (``#``)."""
    return not key.startswith(("~", "#"))


def obstacle_of(key: str) -> str | None:
    """The key of the obstacle an obstacle point (``#<key>:<i>``) lies on, else None."""
    return key[1:].rpartition(":")[0] if key.startswith("#") else None


@dataclass(frozen=True)
class Crossing:
    """A diverting target: cross the edge from ``left`` to ``right`` (ids, egocentric positions;
    ``left`` kept on the robot's left while crossing). A virtual landmark's id starts with ``~``."""

    left: str
    right: str
    left_at: Point
    right_at: Point
    cost: float  # of the whole path to the target's region

    @property
    def edge(self) -> Edge:
        return frozenset((self.left, self.right))

    @property
    def virtual(self) -> bool:
        """One end is no landmark: a virtual landmark or an obstacle's point (its position is
        carried by odometry from where it was set)."""
        return not (is_real(self.left) and is_real(self.right))


@dataclass(frozen=True)
class NoCrossing:
    """Why no diverting target could be given: ``why`` in words; ``trapped`` when every edge out
    of the robot's region is blocked (the map shows no way out), else the map does not yet know
    enough (too few landmarks, the target's region is the robot's, no path cheaper than a blocked
    arc) and looking around may tell it more; ``here`` when the target lies in the robot's own
    region (the map has no way to give but the straight one)."""

    why: str
    trapped: bool = False
    here: bool = False  # the target is in the robot's region: the map's way is straight to it


@dataclass(frozen=True)
class Regions:
    """A triangulation of landmarks (plus virtual ones) and its region graph."""

    ids: tuple[str, ...]
    points: np.ndarray  # (n, 2)
    triangles: np.ndarray  # (m, 3) indices into ids
    neighbours: np.ndarray  # (m, 3): the triangle across the edge opposite each vertex, -1 none

    def region_of(self, p: Point) -> int:
        """The triangle holding ``p``, or else the one whose centroid is nearest."""
        best, best_d = -1, math.inf
        for i, tri in enumerate(self.triangles):
            a, b, c = self.points[tri]
            if _inside(p, a, b, c):
                return i
            d = math.dist(p, tuple((a + b + c) / 3))
            if d < best_d:
                best, best_d = i, d
        return best

    def edges(self) -> list[tuple[int, int, Edge]]:
        """(region, neighbour, shared edge as a pair of ids) for every arc, each once."""
        out = []
        for i, tri in enumerate(self.triangles):
            for k in range(3):
                j = int(self.neighbours[i, k])
                if j > i:
                    shared = [self.ids[v] for m, v in enumerate(tri) if m != k]
                    out.append((i, j, frozenset(shared)))
        return out


def obstacle_points(obstacles: list[tuple[str, Point, Point]]) -> dict[str, Point]:
    """The points by which known linear obstacles (key, end, end) enter the triangulation: each
    end and points at most ``OBSTACLE_STEP`` apart between them."""
    out = {}
    for key, a, b in obstacles:
        n = max(1, math.ceil(math.dist(a, b) / OBSTACLE_STEP))
        for i in range(n + 1):
            out[f"#{key}:{i}"] = (a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n)
    return out


def blocked_edges(
    regions: Regions,
    lines: Sequence[tuple[str, Point, Point]],
    passable: float = 0.0,
    walls: Sequence[tuple[str, Point, Point]] = (),
) -> dict[Edge, str]:
    """The edges the known ``lines`` (key, end, end: the long obstacles) block, with what blocks
    each: the edges along an obstacle (both ends its points, or both within ``CROSS_MARGIN`` of
    it, as where two obstacles meet at a corner), the edges a line crosses farther than
    ``CROSS_MARGIN`` from both of the edge's ends, (``narrow``) the edges between two real
    things, landmarks or obstacle points, shorter than ``passable`` metres, and the edges a known
    stretch of the room's ``walls`` crosses nearer than ``passable`` to the edge's real end (no
    room for the robot between that end and the wall: a fence built up to the wall). A wall
    crossing an edge farther out only bounds the room the edge's region lies in."""
    out: dict[Edge, str] = {}
    pos = dict(zip(regions.ids, map(tuple, regions.points)))
    for _, _, e in regions.edges():
        u, v = sorted(e)
        ou, ov = obstacle_of(u), obstacle_of(v)
        if ou is not None and ou == ov:
            out[e] = ou
            continue
        a, b = pos[u], pos[v]
        if not (u.startswith("~") or v.startswith("~")) and math.dist(a, b) < passable:
            out[e] = "narrow"
            continue
        for key, p, q in lines:
            along = distance_to_segment(a, p, q) < CROSS_MARGIN and distance_to_segment(b, p, q) < CROSS_MARGIN
            if along or crossing_along(a, b, p, q, CROSS_MARGIN):  # along one (ends of two met at a corner), or across
                out[e] = key
                break
        else:
            real = b if v.startswith("~") else a
            for key, p, q in walls:
                if crossing_along(a, b, p, q, 0.0) and distance_to_segment(real, p, q) < passable:
                    out[e] = key
                    break
    return out


def crossing_along(a: Point, b: Point, p: Point, q: Point, margin: float) -> bool:
    """Does segment ``pq`` meet segment ``ab`` farther than ``margin`` from both ``a`` and ``b``?

    >>> crossing_along((0, 0), (2, 0), (1, -1), (1, 1), 0.05), crossing_along((0, 0), (2, 0), (0, 0), (0, 3), 0.05)
    (True, False)
    """
    rx, ry = b[0] - a[0], b[1] - a[1]
    sx, sy = q[0] - p[0], q[1] - p[1]
    den = rx * sy - ry * sx
    L = math.hypot(rx, ry)
    if L == 0.0 or den == 0.0:
        return False  # parallel: an obstacle along an edge is no crossing of it
    t = ((p[0] - a[0]) * sy - (p[1] - a[1]) * sx) / den  # along ab
    u = ((p[0] - a[0]) * ry - (p[1] - a[1]) * rx) / den  # along pq
    return margin / L < t < 1.0 - margin / L and 0.0 <= u <= 1.0


def crossed_pairs(
    points: dict[str, Point], lines: list[tuple[str, Point, Point]], margin: float = CROSS_MARGIN
) -> dict[Edge, str]:
    """Every pair of ``points`` (id -> position) whose segment one of ``lines`` (key, end, end)
    crosses farther than ``margin`` from both ends (:func:`crossing_along`, for all pairs at
    once), with the key of the first such line.

    >>> [(sorted(e), key) for e, key in crossed_pairs({"A": (0, 0), "B": (2, 0), "C": (0, 2)},
    ...                                                 [("f", (1, -1), (1, 0.5))]).items()]
    [(['A', 'B'], 'f')]
    """
    ids = sorted(points)
    out: dict[Edge, str] = {}
    if len(ids) < 2:
        return out
    pts = [points[k] for k in ids]
    for key, p, q in lines:  # plain Python: a dozen landmarks and a few lines cost less than numpy's calls
        px, py = p
        sx, sy = q[0] - px, q[1] - py
        side = [sx * (y - py) - sy * (x - px) for x, y in pts]  # each point's side of the line through pq
        for a in range(len(ids)):
            sa = side[a]
            for b in range(a + 1, len(ids)):
                if sa * side[b] >= 0.0:
                    continue  # both on one side of pq's line: pq cannot cross ab
                e = frozenset((ids[a], ids[b]))
                if e not in out and crossing_along(pts[a], pts[b], p, q, margin):
                    out[e] = key
    return out


def way_out(regions: Regions, robot: Point, blocked: Mapping[Edge, object], target: Point | None = None) -> bool:
    """Does the map show a way out of where the robot is: through edges not blocked, to the
    target's region or to an outer region (one with a virtual landmark: space the landmarks do
    not enclose)? False when the robot's regions are closed in by blocked edges."""
    start = regions.region_of(robot)
    goal = regions.region_of(target) if target is not None else -2
    outer = {i for i, tri in enumerate(regions.triangles) if any(regions.ids[v].startswith("~") for v in tri)}
    arcs: dict[int, list[int]] = {}
    for i, j, e in regions.edges():
        if not blocked.get(e):
            arcs.setdefault(i, []).append(j)
            arcs.setdefault(j, []).append(i)
    seen, todo = {start}, [start]
    while todo:
        i = todo.pop()
        if i == goal or i in outer:
            return True
        for j in arcs.get(i, ()):
            if j not in seen:
                seen.add(j)
                todo.append(j)
    return False


def triangulate(
    landmarks: dict[str, Point], virtual_distance: float = 10.0, obstacles: Sequence[tuple[str, Point, Point]] = ()
) -> Regions | None:
    """Regions of ``landmarks`` (id -> position) and of the known linear ``obstacles`` (key, end,
    end), which enter as points (:func:`obstacle_points`); ``None`` with fewer than 3 landmarks
    in general position."""
    if len(landmarks) < 3:
        return None
    points = obstacle_points(list(obstacles))
    marks = list(landmarks.values())
    # an obstacle's point on a landmark (a bump line drawn from it) is that landmark: Qhull keeps one of two
    points = {k: p for k, p in points.items() if all(math.dist(p, m) > CROSS_MARGIN for m in marks)}
    landmarks = dict(landmarks) | points
    ids = sorted(landmarks)
    from scipy.spatial import Delaunay, QhullError  # ~0.5 s the first time: only when there is something to triangulate

    pts = np.array([landmarks[k] for k in ids], dtype=float)
    try:
        hull = Delaunay(pts)
    except (QhullError, ValueError):
        return None
    extra_ids, extra = [], []
    centre = pts.mean(axis=0)
    for a, b in hull.convex_hull:
        mid = (pts[a] + pts[b]) / 2
        n = np.array([-(pts[b][1] - pts[a][1]), pts[b][0] - pts[a][0]])
        n /= np.linalg.norm(n)
        if np.dot(n, mid - centre) < 0:
            n = -n
        extra_ids.append("~" + "-".join(sorted((ids[a], ids[b]))))
        extra.append(mid + virtual_distance * n)
    all_ids = tuple(ids + extra_ids)
    all_pts = np.vstack([pts, np.array(extra)]) if extra else pts
    try:
        tri = Delaunay(all_pts)
    except (QhullError, ValueError):
        return None
    return Regions(all_ids, all_pts, tri.simplices.copy(), tri.neighbors.copy())


def first_crossing(
    regions: Regions,
    robot: Point,
    target: Point,
    blocked: dict[Edge, float] | None = None,
    blocked_cost: float = 1000.0,
    lines: list[tuple[str, Point, Point]] | None = None,
    whole: bool = False,
) -> Crossing | None:
    """The first edge of the cheapest path from the robot's region to the target's (arcs cost 1,
    or ``blocked_cost`` times the count in ``blocked``); ``None`` when they are the same region
    or no path is cheaper than a blocked arc.

    Given the known ``lines`` (obstacles and walls, key, end, end), the edge handed over is the
    farthest along the path that the robot sees straight (:func:`_farthest_in_sight`), not
    always the first: our design. The known obstacles' points cut the regions beside a fence
    into triangles a metre wide, and stepping across each of them sent the robot along the fence
    in half-metre hops, each a diverting target of its own, which the potential field, circling
    in front of the fence, crossed and crossed back; the thesis' regions, of landmarks only, are
    metres wide."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    start, goal = regions.region_of(robot), regions.region_of(target)
    if start < 0 or goal < 0 or start == goal:
        return None
    arcs = regions.edges()
    m = len(regions.triangles)
    rows, cols, costs = [], [], []
    for i, j, e in arcs:
        c = 1.0 + blocked_cost * (blocked or {}).get(e, 0.0)
        rows += [i, j]
        cols += [j, i]
        costs += [c, c]
    graph = csr_matrix((costs, (rows, cols)), shape=(m, m))
    dist, pred = dijkstra(graph, indices=start, return_predecessors=True)
    if not math.isfinite(dist[goal]) or dist[goal] >= blocked_cost:
        return None
    path = [goal]
    while path[-1] != start:
        path.append(int(pred[path[-1]]))
    path.reverse()
    shared_of = {frozenset((i, j)): e for i, j, e in arcs}
    edges = [shared_of[frozenset(pair)] for pair in zip(path, path[1:])]
    shared = _farthest_in_sight(regions, robot, edges, lines, whole) if lines is not None else edges[0]
    u, v = sorted(shared)
    (pu0, pu1), (pv0, pv1) = (regions.points[regions.ids.index(k)] for k in (u, v))
    pu, pv = (float(pu0), float(pu1)), (float(pv0), float(pv1))
    # left/right as seen from the robot looking across the edge
    if (pu[0] - robot[0]) * (pv[1] - robot[1]) - (pu[1] - robot[1]) * (pv[0] - robot[0]) > 0:
        right, left, right_at, left_at = u, v, pu, pv
    else:
        left, right, left_at, right_at = u, v, pu, pv
    return Crossing(left, right, left_at, right_at, float(dist[goal]))


def _farthest_in_sight(
    regions: Regions, robot: Point, edges: list[Edge], lines: list[tuple[str, Point, Point]], whole: bool = False
) -> Edge:
    """The last of the path's ``edges`` between two real things (landmarks or obstacle points:
    a virtual landmark may lie beyond the room's walls) whose middle half the robot sees whole
    (:func:`_seen_whole`; without ``whole``, whose middle it sees); the first edge when none
    farther is.

    Seeing the middle alone is not enough: past the end of a wall (or of a fence drawn short),
    the sight line to an edge's middle may clear it while the edge lies beyond the wall, and the
    robot, led at it, wedges between the wall's end and a landmark. The middle half is where
    the Pilot crosses (its safe corridor keeps it off the ends)."""
    pos = dict(zip(regions.ids, map(tuple, regions.points)))
    for e in reversed(edges[1:]):
        if any(k.startswith("~") for k in e):
            continue
        a, b = (pos[k] for k in sorted(e))
        if (
            _seen_whole(robot, a, b, lines)
            if whole
            else not any(crossing_along(robot, midpoint(a, b), p, q, 0.0) for _, p, q in lines)
        ):
            return e
    return edges[0]


def _seen_whole(robot: Point, a: Point, b: Point, lines: list[tuple[str, Point, Point]]) -> bool:
    """Does the robot see the middle half of edge ``ab`` whole: no line across the sight lines
    to its middle and to the points a quarter in from each end, and no line's end within the
    triangle of the robot and those two points?

    >>> wall = [("wall", (0.0, 1.0), (1.5, 1.0))]
    >>> _seen_whole((0.0, 0.0), (-1.0, 2.0), (1.0, 2.0), wall), _seen_whole((0.0, 0.0), (3.0, 2.0), (5.0, 2.0), wall)
    (False, True)
    >>> _seen_whole((0.0, 0.0), (0.0, 2.5), (4.0, 2.5), [("fence", (1.6, 3.5), (1.6, 2.1))])  # its end pokes in
    False
    """
    q1 = (a[0] + (b[0] - a[0]) / 4, a[1] + (b[1] - a[1]) / 4)
    q3 = (a[0] + 3 * (b[0] - a[0]) / 4, a[1] + 3 * (b[1] - a[1]) / 4)
    mid = midpoint(a, b)
    for _, p, q in lines:
        if any(crossing_along(robot, end, p, q, 0.0) for end in (mid, q1, q3)):
            return False
        if any(_strictly_inside(r, robot, q1, q3) for r in (p, q)):
            return False
    return True


def _strictly_inside(p: Point, a: Point, b: Point, c: Point) -> bool:
    """Is ``p`` inside triangle ``abc``, farther than ``CROSS_MARGIN`` from each of its sides?"""
    sides = [
        ((v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])) / (math.dist(u, v) or 1.0)
        for u, v in ((a, b), (b, c), (c, a))
    ]
    return all(d > CROSS_MARGIN for d in sides) or all(d < -CROSS_MARGIN for d in sides)


def _inside(p: Point, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> bool:
    def side(u, v) -> float:
        return (v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])

    s1, s2, s3 = side(a, b), side(b, c), side(c, a)
    return (s1 >= 0 and s2 >= 0 and s3 >= 0) or (s1 <= 0 and s2 <= 0 and s3 <= 0)
