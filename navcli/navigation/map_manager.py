"""The Map Manager (notes, section 2; thesis node 40): keeps the landmark map and answers the other
agents' questions. It makes no bids.

- **Learning**: after every image that showed landmarks, the precise landmarks of the visual
  memory form a viewframe; each landmark the image showed is encoded in the beta-coefficient
  network (:mod:`.beta_map`) when at least four are known.
- **Locating** a landmark or the target: the least imprecise (lowest I(l)) of what the visual
  memory holds and what the network recalls from three landmarks the memory holds now. A recall
  is recomputed every ``map_recall_every`` ticks and carried between times by odometry (our
  design: a recall costs about a quarter of a millisecond per unit; the half-second of drift it
  ignores is small beside a recall's own imprecision).
- **Quality** of a landmark set for the Risk Manager: ``q_S = max(1 - Col(S'))`` over its triples
  (the notes' ``Col``; the six best-known landmarks are enough, since the risk saturates at six).
- **Diverting targets** for the Rescuer: the regions of :mod:`.regions` over the mapped landmarks
  and the known long obstacles (which split the regions they cross), arcs blocked when a known
  long obstacle crosses their edge or the edge runs along one, when it is too narrow, when a wall
  leaves no room between it and the edge's end, or when a diverting target through them failed, and the first edge of the cheapest path to the target's
  region. What the long obstacles block between two landmarks is kept from every image
  (``seen_blocked``), as the thesis' map keeps the arcs reported blocked: the visual memory
  forgets a fence and sees it again under a new key, landmark ids stay (our design). A failed edge is
  also known by where its ends were (:data:`SAME_PLACE_M`), since obstacle points are named anew,
  and as a dead end by place: edges whose middle lies within ``dead_end_radius`` of its middle
  cost ``seen_closed_cost``. A way closed only by such a record (``seen_blocked``) costs
  ``seen_closed_cost`` too, is not counted as closing the robot in, and its record goes when an
  image shows both its landmarks with no known long obstacle across.
  When there is none, why (:class:`~.regions.NoCrossing`), telling apart a map that knows too
  little (look around: too few landmarks, or every way to the target blocked by known obstacles
  and failed diverting targets, which more landmarks may open) from one that shows no way out:
  every edge out of the robot's region closed by known obstacles.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Iterator

from ..beliefs import Beliefs
from ..fuzzy import FuzzyPoint
from ..geometry import Point, Pose, midpoint, wrap_angle
from ..params import CONTROL_DT, NAVIGATION, NavigationParams
from .beta_map import BetaNetwork, collinearity
from .regions import (
    Crossing,
    Edge,
    NoCrossing,
    Regions,
    blocked_edges,
    ends,
    crossed_pairs,
    first_crossing,
    triangulate,
    way_out,
)

TARGET = "target"  # the key of a point target's marker, as the visual memory holds it
SAME_PLACE_M = 0.5
"""m: a new edge whose ends (those that are not virtual) lie this near those of an edge whose
diverting target failed is that edge again (our design: the memory names the points of a bumped
or re-seen obstacle anew, so a robot wedged in a corner was sent across the "same" edge under 20
names, bumping each time; half a metre is about the robot's width, one place to the Pilot). An
edge with one virtual end is that edge again only if its virtual end lies the same way, within
``SAME_WAY_DEG``: from one landmark, the ways out to either side are different edges."""
SAME_WAY_DEG = 45.0
SEEN_EVERY = 4
"""Images between two records of what the known fences block between landmarks (our design: a
fence stays in the memory for dozens of images, so every fourth is enough, and the record costs
some 50 µs, a sixth of a tick's whole cost, when taken at every image)."""


@dataclass
class _Recalled:
    x: float  # in the odometry frame
    y: float
    radii: tuple[float, ...]
    tick: int
    unit: str


@dataclass(frozen=True)
class MapSnapshot:
    """What the map holds, for the log: landmark estimates (egocentric), beta-units as triangles
    of ids, region triangles (of landmarks, virtual landmarks and the known obstacles' points, as
    the diverting targets are computed), blocked edges as pairs of ids, where every id of the
    regions is (``vertices``, egocentric), and the Rescuer's diverting lines ended so far with how
    each ended (``tried``: crossed, crossed but led nowhere, abandoned, replaced)."""

    landmarks: dict[str, FuzzyPoint]
    units: tuple[tuple[str, str, str, str], ...]
    regions: tuple[tuple[Point, Point, Point], ...]
    blocked: tuple[tuple[str, str], ...]
    vertices: dict[str, Point] = field(default_factory=dict)
    tried: tuple[tuple[Point, Point, str], ...] = ()  # every diverting line ended so far (egocentric) and how


class MapManager:
    name = "map-manager"

    def __init__(self, params: NavigationParams = NAVIGATION, target_key: str = TARGET, passable: float = 0.8):
        """``passable``: the narrowest edge (m, between its ends' centres) the robot can be sent
        across (the Navigation system gives twice the Pilot's R_min: both ends' prohibited areas)."""
        self.params = params
        self.passable = passable
        self.network = BetaNetwork(params.map_units_per_landmark)
        self.target_key = target_key
        self.blocked: dict[Edge, float] = {}  # edges of failed diverting targets: how often
        self.failed_at: list[tuple[tuple[Point, ...], float | None]] = []  # where each one was (_place), odometry frame
        self._where: dict[str, Point] = {}  # where the regions' points were when last asked, odometry frame
        self.seen_blocked: dict[Edge, str] = {}  # landmark pairs a known long obstacle was seen across: by what
        self.dead_ends: list[Point] = []  # where each failed diverting target's edge was (_dead_end), odometry frame
        self._recalled: dict[str, _Recalled] = {}
        self._tick = 0
        self._images = 0
        self._quality: dict[tuple[str, ...], float] = {}  # q_S by the six keys, for the image count below
        self._quality_images = 0
        self._points_of: Beliefs | None = None
        self._points: dict[str, FuzzyPoint] = {}

    # -- learning
    def observe(self, beliefs: Beliefs) -> int:
        """Learn from the image taken last tick, if any; returns the units added."""
        self._tick += 1
        if beliefs.looked is None:
            return 0
        self._images += 1
        known = self.memory_points(beliefs)
        fresh = beliefs.time - CONTROL_DT - 1e-6
        shown = {k for k, lm in self._landmarks(beliefs) if lm[1] >= fresh}
        if (self._images - 1) % SEEN_EVERY == 0:  # the first image, then every fourth
            self._record_closed(beliefs, known, shown)
        if not shown:
            return 0
        viewframe = {k: p for k, p in known.items() if p.imprecision() <= self.params.map_encode_imprecision}
        if len(viewframe) < 4:
            return 0
        return len(self.network.learn(viewframe, targets=shown & set(viewframe)))

    def _record_closed(self, beliefs: Beliefs, known: dict[str, FuzzyPoint], shown: set[str]) -> None:
        """What the known long obstacles block between landmarks stays known when the memory
        forgets them (``seen_blocked``); with ``seen_closed_cost``, a pair whose two landmarks
        this image showed with no known obstacle across is seen open, and its record goes (a
        remembered fence drifts with odometry, and may lie across a door it never closed)."""
        lines = [(o.key, o.a, o.b) for o in beliefs.obstacles if not o.is_point and not o.wall]
        marks = {k: (p.x, p.y) for k, p in known.items() if k != self.target_key}
        closed = crossed_pairs(marks, lines) if lines else {}
        if self.params.seen_closed_cost > 0:
            for e in [e for e in self.seen_blocked if e <= shown and e not in closed]:
                del self.seen_blocked[e]
        for e, key in closed.items():
            self.seen_blocked.setdefault(e, key)

    def _landmarks(self, beliefs: Beliefs) -> Iterator[tuple[str, tuple[FuzzyPoint, float]]]:
        for lm in beliefs.landmarks:
            yield lm.key, (lm.where, lm.seen)
        if beliefs.target_at is not None and self._has_marker(beliefs):
            yield self.target_key, (beliefs.target_at, beliefs.target_seen)

    def _has_marker(self, beliefs: Beliefs) -> bool:
        """Does the memory's target marker stand for ``target_key``: a point target, or a landmark
        told of that the memory does not hold as a landmark?"""
        return beliefs.target_at is not None and (
            self.target_key == TARGET or all(lm.key != self.target_key for lm in beliefs.landmarks)
        )

    def memory_points(self, beliefs: Beliefs) -> dict[str, FuzzyPoint]:
        """Landmarks (and the target's marker) as the visual memory holds them, in its order (what
        :meth:`_landmarks` gives; built once per tick, without the seen times)."""
        if self._points_of is not beliefs:
            self._points_of, self._points = beliefs, {k: where for k, (where, _) in self._landmarks(beliefs)}
        return self._points

    # -- answering
    def locate(self, key: str, beliefs: Beliefs, recall: bool = True) -> tuple[FuzzyPoint, str] | None:
        """The least imprecise estimate of ``key``, egocentric, and where it came from
        (``memory`` or ``map:<unit>``). The network is asked only when the memory's estimate is
        missing or no sharper than what the map is trusted with (``map_encode_imprecision``);
        ``recall=False`` uses only recalls already made."""
        known = self.memory_points(beliefs)
        best = (known[key], "memory") if key in known else None
        if best is not None and best[0].imprecision() <= self.params.map_encode_imprecision:
            return best
        recalled = self._recall(key, known, beliefs.odometry, recall)
        if recalled is not None and (best is None or recalled[0].imprecision() < best[0].imprecision()):
            best = recalled
        return best

    def _recall(
        self, key: str, known: dict[str, FuzzyPoint], odo: Pose, fresh: bool = True
    ) -> tuple[FuzzyPoint, str] | None:
        r = self._recalled.get(key)
        if fresh and (r is None or self._tick - r.tick >= self.params.map_recall_every):
            basis = {k: p for k, p in known.items() if k != key}
            found = self.network.locate(key, basis)
            if found is None:
                self._recalled.pop(key, None)
                return None
            p, unit = found
            wx, wy = odo.to_world((p.x, p.y))
            r = self._recalled[key] = _Recalled(wx, wy, p.radii, self._tick, unit.name)
        if r is None:
            return None
        x, y = odo.to_local((r.x, r.y))
        return FuzzyPoint(x, y, r.radii), f"map:{r.unit}"

    def quality(self, points: dict[str, FuzzyPoint]) -> float:
        """``q_S = max(1 - Col(S'))`` over the triples of ``S'``, the six best-known (least
        imprecise) of ``points``; 0 below three.

        Which six are best changes as the robot moves (a point's I(l) depends on its distance),
        so they are chosen anew at every call. Their collinearity changes only when something is
        seen again: between two images the memory carries every point by the same odometry (a
        rigid motion, which keeps the shape of a triangle). So the value is cached by the six
        chosen and the image count, and the cache is emptied at each image (our design, to keep
        the twenty triangles off the per-tick cost; a cached value equals a fresh one to
        rounding). The six are taken in the order of their keys, so the triples, and the last
        bits of the maximum, do not depend on the order of ``points``; they do depend on the tick
        that first asks for a six after an image, so asking earlier or more often can change a
        run's last bits (not its sense)."""
        if self._quality_images != self._images:
            self._quality.clear()
            self._quality_images = self._images
        six = points if len(points) <= 6 else sorted(points, key=lambda k: points[k].imprecision())[:6]
        best = tuple(sorted(six))
        cached = self._quality.get(best)
        if cached is None:
            cached = max(
                (1.0 - collinearity(*((points[k].x, points[k].y) for k in t)) for t in itertools.combinations(best, 3)),
                default=0.0,
            )
            self._quality[best] = cached
        return cached

    def landmark_estimates(self, beliefs: Beliefs, recall: bool = True) -> dict[str, FuzzyPoint]:
        """Every mapped landmark (memory or recall), egocentric, by id: sorted, so that the
        regions' triangulation and the log's map never follow the order of a set of strings,
        which Python's hash seed changes from one process to the next."""
        out = {}
        for k in sorted(self.network.landmarks | set(self.memory_points(beliefs))):
            found = self.locate(k, beliefs, recall)
            if found is not None and k != self.target_key:
                out[k] = found[0]
        return out

    def diverting_target(self, beliefs: Beliefs, target: Point) -> Crossing | NoCrossing:
        """The first edge to cross toward ``target`` (egocentric), or why there is none."""
        marks = self.landmark_estimates(beliefs)
        regions, now = self._regions(beliefs, marks, remembered=False)
        known = self._with_records(now)
        if regions is None:
            return NoCrossing(f"{len(marks)} landmark(s) mapped, too few for regions")
        # with seen_closed_cost, a way closed only by the record of an obstacle the memory no longer
        # holds costs more and stays open to try; without, it blocks as a known obstacle does
        remembered = set(known) - set(now) if self.params.seen_closed_cost > 0 else set()
        now = known if not remembered else now
        if not way_out(regions, (0.0, 0.0), now, target):  # what is known to close it in, not what failed
            return NoCrossing(
                "the known obstacles close in the robot's regions: every edge out is blocked", trapped=True
            )
        odo = beliefs.odometry
        self._where = {k: odo.to_world((float(x), float(y))) for k, (x, y) in zip(regions.ids, regions.points)}
        again = (
            [e for _, _, e in regions.edges() if e not in self.blocked and self._failed_before(self._place(e))]
            if self.failed_at
            else []
        )  # failed before, under other names
        blocked = dict(self.blocked)
        for e in (*now, *again):
            blocked[e] = blocked.get(e, 0.0) + 1.0
        # a way seen closed, or through a dead end's place, costs more and stays open to try (the
        # only way out of a U may pass by the place where a diverting target failed)
        share = self.params.seen_closed_cost / self.params.blocked_cost if self.params.seen_closed_cost > 0 else 1.0
        for e in (*remembered, *self._at_dead_ends(regions, again)):
            blocked[e] = blocked.get(e, 0.0) + share
        sight = (
            [(o.key, o.a, o.b) for o in beliefs.obstacles if not o.is_point] if self.params.diverting_in_sight else None
        )
        c = first_crossing(
            regions, (0.0, 0.0), target, blocked, self.params.blocked_cost, sight, self.params.diverting_seen_whole
        )
        if c is None:
            same = regions.region_of((0.0, 0.0)) == regions.region_of(target)
            if same:
                return NoCrossing("the target is in the robot's region", here=True)
            return NoCrossing(
                "every way to the target is blocked, by known obstacles or by diverting targets that failed"
            )
        return c

    def _regions(
        self, beliefs: Beliefs, marks: dict[str, FuzzyPoint], remembered: bool = True
    ) -> tuple[Regions | None, dict[Edge, str]]:
        """The regions of the mapped ``marks`` and the known long obstacles, and the edges the
        known obstacles block (:func:`~.regions.blocked_edges`, with what blocks each). The long
        obstacles split the regions and block the edges they cross; the room's walls only where
        they leave no room beside an edge's end: they bound the room, and an edge to a virtual
        landmark crosses one outside it."""
        lines = [(o.key, o.a, o.b) for o in beliefs.obstacles if not o.is_point and not o.wall]
        regions = triangulate({k: (p.x, p.y) for k, p in marks.items()}, self.params.virtual_distance, lines)
        if regions is None:
            return None, {}
        walls = [(o.key, o.a, o.b) for o in beliefs.obstacles if o.wall]
        known = blocked_edges(regions, lines, self.passable, walls)
        return regions, self._with_records(known) if remembered else known

    def _with_records(self, known: dict[Edge, str]) -> dict[Edge, str]:
        """``known`` and the edges recorded as seen blocked (``seen_blocked``)."""
        out = dict(known)
        for e, key in self.seen_blocked.items():
            out.setdefault(e, key)
        return out

    def _at_dead_ends(self, regions: Regions, skip: list[Edge]) -> list[Edge]:
        """Edges not yet known as failed whose place (:func:`_dead_end`) lies within
        ``dead_end_radius`` of that of an edge whose diverting target failed: the same dead end
        under other landmarks (our design: a robot sent again and again into the pocket where a
        wall meets the side wall, each time across an edge of other ends). They cost as a way
        seen closed does, not as a failure: the only way out of a U passes by its mouth, where
        the first diverting target may have failed."""
        radius = self.params.dead_end_radius
        if radius <= 0 or not self.dead_ends:
            return []
        odo_where = self._where
        out = []
        for _, _, e in regions.edges():
            if e in self.blocked or e in skip:
                continue
            at = _dead_end(e, odo_where, radius)
            if at is not None and any(math.dist(at, d) <= radius for d in self.dead_ends):
                out.append(e)
        return out

    def report_blocked(self, edge: Edge) -> None:
        """A diverting target through ``edge`` failed: make its arc costly, and that of any edge
        later found where its ends were (:data:`SAME_PLACE_M`) or near its place
        (``dead_end_radius``)."""
        self.blocked[edge] = self.blocked.get(edge, 0.0) + 1.0
        if all(k in self._where for k in edge):
            at = _dead_end(edge, self._where, self.params.dead_end_radius)
            if at is not None and all(math.dist(at, d) > SAME_PLACE_M for d in self.dead_ends):
                self.dead_ends.append(at)
        place = self._place(edge)
        if place is not None and not self._failed_before(place):  # once per place: the list stays short
            self.failed_at.append(place)

    def _place(self, edge: Edge) -> tuple[tuple[Point, ...], float | None] | None:
        """Where ``edge`` is, as the last request saw it (odometry frame): its real ends (landmarks,
        obstacle points) and, with one virtual end, the heading from the real end toward it (rad);
        None for an edge of two virtual ends or one not seen."""
        if not all(k in self._where for k in edge):
            return None
        real = tuple(self._where[k] for k in sorted(edge) if k[0] != "~")
        if len(real) != 1:
            return (real, None) if real else None
        (v,) = (self._where[k] for k in edge if k[0] == "~")
        return real, math.atan2(v[1] - real[0][1], v[0] - real[0][0])

    def _failed_before(self, place: tuple[tuple[Point, ...], float | None] | None) -> bool:
        """Is ``place`` (:meth:`_place`) where a failed edge was: its real ends within
        ``SAME_PLACE_M``, and for an edge with a virtual end, its way out within ``SAME_WAY_DEG``?"""
        if place is None:
            return False
        ends, heading = place
        for was, way in self.failed_at:
            if (way is None) != (heading is None) or len(was) != len(ends):
                continue
            if heading is not None and way is not None and abs(wrap_angle(heading - way)) > math.radians(SAME_WAY_DEG):
                continue
            if any(all(math.dist(a, b) <= SAME_PLACE_M for a, b in zip(was, order)) for order in (ends, ends[::-1])):
                return True
        return False

    def snapshot(self, beliefs: Beliefs) -> MapSnapshot:
        """For the log: what the map knows now, from the memory and the recalls already made."""
        marks = self.landmark_estimates(beliefs, recall=False)
        units = tuple((*basis, target) for target, per in self.network.units.items() for basis in per)
        r, known = self._regions(beliefs, marks)
        blocked = tuple(sorted(ends(e) for e in set(self.blocked) | set(known)))
        if r is None:
            return MapSnapshot(marks, units, (), blocked)
        corners = [(float(x), float(y)) for x, y in r.points]
        tris = tuple((corners[a], corners[b], corners[c]) for a, b, c in r.triangles.tolist())
        vertices = {k: (float(x), float(y)) for k, (x, y) in zip(r.ids, r.points)}
        return MapSnapshot(marks, units, tris, blocked, vertices)


def _dead_end(edge: Edge, where: dict[str, Point], radius: float) -> Point | None:
    """The place of ``edge`` (its ends ``where`` they are, odometry frame) as a dead end: its
    middle; with one virtual end, the point ``radius`` from its real end toward the virtual one
    (a virtual landmark lies metres out, beyond the room's walls); None for two virtual ends."""
    keys = sorted(edge)
    (a, b), (va, vb) = (where[k] for k in keys), (k.startswith("~") for k in keys)
    if va and vb:
        return None
    if not (va or vb):
        return midpoint(a, b)
    real, out = (b, a) if va else (a, b)
    d = math.dist(real, out)
    f = min(1.0, radius / d) if d > 0 else 0.0
    return (real[0] + (out[0] - real[0]) * f, real[1] + (out[1] - real[1]) * f)
