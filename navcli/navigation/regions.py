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
- two regions sharing an edge are joined by an arc whose cost is 1, or ``blocked_cost`` when the
  edge is known to be blocked (a long obstacle crosses it, or a diverting target through it
  failed); the shortest path is ``scipy.sparse.csgraph.dijkstra``;
- the robot's region (and the target's) is the triangle holding it, or the nearest one.

Everything is in one frame (the robot's, egocentric); landmark ids keep edges stable over time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Point = tuple[float, float]
Edge = frozenset  # of two landmark ids


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
        return self.left.startswith("~") or self.right.startswith("~")


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


def triangulate(landmarks: dict[str, Point], virtual_distance: float = 10.0) -> Regions | None:
    """Regions of ``landmarks`` (id -> position); ``None`` with fewer than 3 in general position."""
    ids = sorted(landmarks)
    if len(ids) < 3:
        return None
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


def first_crossing(regions: Regions, robot: Point, target: Point, blocked: dict[Edge, float] | None = None,
                   blocked_cost: float = 1000.0) -> Crossing | None:
    """The first edge of the cheapest path from the robot's region to the target's (arcs cost 1,
    or ``blocked_cost`` times the count in ``blocked``); ``None`` when they are the same region
    or no path is cheaper than a blocked arc."""
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
    step = goal
    while pred[step] != start:
        step = int(pred[step])
    shared = next(e for i, j, e in arcs if {i, j} == {start, step})
    u, v = sorted(shared)
    pu, pv = (tuple(map(float, regions.points[regions.ids.index(k)])) for k in (u, v))
    # left/right as seen from the robot looking across the edge
    if (pu[0] - robot[0]) * (pv[1] - robot[1]) - (pu[1] - robot[1]) * (pv[0] - robot[0]) > 0:
        right, left, right_at, left_at = u, v, pu, pv
    else:
        left, right, left_at, right_at = u, v, pu, pv
    return Crossing(left, right, left_at, right_at, float(dist[goal]))


def _inside(p: Point, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> bool:
    def side(u, v) -> float:
        return (v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])

    s1, s2, s3 = side(a, b), side(b, c), side(c, a)
    return (s1 >= 0 and s2 >= 0 and s3 >= 0) or (s1 <= 0 and s2 <= 0 and s3 <= 0)
