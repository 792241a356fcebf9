"""The Vision system's camera: a 60-degree camera on a pan unit (notes, section 1).

Vision does not bid; it carries out the winning look. A look pans the camera (finite pan speed,
limited pan range), takes an image when the pan arrives, and then processes it for
``look_time`` seconds, busy meanwhile, with the routine of the look's purpose
(:mod:`.routines`): what that routine finds is all the image registers. While the camera pans it
serves the look that wins the camera at each tick: a look asked for elsewhere turns it there, and
when no look is asked for any more (a move without a look, the learning paper's MB) the pan is
cancelled where it got to, without an image. The image shows an object when it lies inside the
field of view, within range, and no other object or wall blocks the line of sight to it.

What comes out are :class:`Detection` s, egocentric, with heading and distance as fuzzy numbers:
the measured values carry the scenario's noise (bounded at ``noise_bound`` standard deviations,
as a physical sensor's errors are), and the fuzzy support is exactly that bound, so the true
value always lies in the 0 % cut; the distance's spread grows with the distance. Landmarks and
the target markers are identified by id; a point obstacle is only "an obstacle". **A linear
obstacle is one object** (``vision.line_objects`` 1): the camera recognises a fence, or one of
the room's walls, as that object (key ``segment:<key>``, ``wall:<key>``) and measures its two
extremities in the image, toward its ends ``a`` and ``b``: each is either that end itself, in
view (:attr:`Detection.ends` says so), or where the view cuts the obstacle (the field of view's
edge, the range, something in front), a point of it beyond which it goes on. The memory fuses
them end by end (:mod:`.visual_memory`). With ``vision.line_objects`` 0 a linear
obstacle is reported, unidentified, by the end points of each stretch of it in view (a point if
only a sliver shows), and the memory re-joins the pieces by geometry. A wall is reported as a
``wall`` (a wall is told apart from the obstacles in the room by its size, and the Pilot treats
it as such); with ``vision.walls`` ``felt`` the camera registers no wall at all.
"""

from __future__ import annotations

import math
from typing import Callable, Container, NamedTuple

import numpy as np

from ..bidding import Look, LookPurpose, looked_at
from ..fuzzy import TWO_PI, Fuzzy, FuzzyAngle
from ..geometry import Point, Pose, distance_to_segment, wrap_angle
from ..noise import bounded_normals
from ..params import VISION, VisionParams
from ..scenario import ArenaObject, Scenario
from .routines import EVERYTHING, registers


SEGMENT_STEP = 0.2  # m between the samples of a linear obstacle tested for visibility
SEGMENT_SAMPLES = 40  # at most this many samples per linear obstacle
VIEW_MARGIN = 1e-3  # rad: the field of view widened by this much to choose the samples worth testing


def segment_steps(a: Point, b: Point) -> int:
    """How many steps segment ``ab`` is sampled in for visibility: its samples are
    ``a + (b - a) k / n`` for ``k = 0 .. n``, about ``SEGMENT_STEP`` apart, at most
    ``SEGMENT_SAMPLES`` steps."""
    return max(1, min(SEGMENT_SAMPLES, math.ceil(math.hypot(b[0] - a[0], b[1] - a[1]) / SEGMENT_STEP)))


class Sighting(NamedTuple):
    """One measured point: fuzzy egocentric heading (rad) and distance (m); one per point in an
    image (a NamedTuple: docs/design.md, "Values made every tick")."""

    heading: FuzzyAngle
    distance: Fuzzy


class Detection(NamedTuple):
    """What one image showed of one object.

    ``key`` is the landmark id, ``target``/``target-a``/``target-b`` for the target's markers,
    ``segment:<key>``/``wall:<key>`` for an identified linear obstacle, and ``""`` for a plain
    obstacle (not identified). ``points`` holds one sighting (a point obstacle, a landmark, a
    single sample of a linear obstacle) or two (the extremities of a linear obstacle in view,
    toward its end ``a`` first for an identified one). ``ends`` says, for an identified linear
    obstacle, which of those extremities are the obstacle's own ends (the others are where the
    view cut it); one flag per end ``a``, ``b`` (a single sample stands for both).
    A NamedTuple, as :class:`Sighting` (several per image).
    """

    key: str
    kind: str  # "landmark" | "target" | "obstacle" | "wall" (a stretch of the room's wall: big, flat, told apart)
    points: tuple[Sighting, ...]
    radius: float
    ends: tuple[bool, ...] = ()

    def as_json(self) -> dict:
        def f(x: Fuzzy, k: float = 1.0) -> dict:
            c = [tuple(v * k for v in cut) for cut in x.cuts]
            return {"lo0": c[0][0], "lo70": c[2][0], "core": (c[3][0] + c[3][1]) / 2, "hi70": c[2][1], "hi0": c[0][1]}

        out: dict[str, object] = {
            "kind": self.kind,
            "points": [
                {"heading_deg": f(p.heading.value, 180 / math.pi), "distance_m": f(p.distance)} for p in self.points
            ],
        }
        if self.ends:
            out["ends"] = list(self.ends)
        return out


STATES = ("idle", "panning", "processing")
"""The camera's states, as ``/vision.state`` says: free, turning to a pan, processing an image."""
KINDS = ("landmark", "target", "obstacle", "wall")
"""What a detection is, as ``/vision``'s detections say."""


class Camera:
    """The pan unit, the image and the measurement model (see the module docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, params: VisionParams = VISION):
        self.spec = scenario.camera
        self.noise = scenario.noise
        self.rng = rng
        self.params = params
        self.pan = 0.0  # rad, relative to the robot's heading
        self.state = "idle"  # idle | panning | processing
        self.goal = 0.0
        self.request: Look | None = None  # the look being carried out (panning or processing)
        self.looked: Look | None = None  # the look of the image taken at the last step, None if none
        self._capture_at = 0.0
        self._free_at = 0.0
        objs = scenario.objects  # landmarks, obstacles, target markers, walls: the draw order of the noise
        self.objects = objs
        t = scenario.target
        self.target_keys = frozenset(({t.landmark} if t.landmark else set()) | {"target", "target-a", "target-b"})
        # what may block a line of sight: every physical object (target markers are not)
        self._points = [(o.key, o.a, o.radius) for o in objs if o.kind in ("landmark", "circle")]
        self._lines = [(o.key, o.a, o.b) for o in objs if o.kind in ("segment", "wall")]

    def sight(self, pose: Pose) -> Callable[[float, float, str], bool]:
        """The visibility test of an image taken now from ``pose``: ``sees(x, y, own)``, is world
        point ``(x, y)`` (of object ``own``) in the field of view, in range and unoccluded (no
        physical object other than ``own`` blocks the line of sight: a disc by its body, strictly
        between eye and point, a segment by crossing it properly)?

        Everything that does not depend on the point is prepared once per image (an
        image tests ~180 points): only the objects that can block a line of sight inside the
        field of view and range are kept, so the occlusion tests cost (objects in view) per
        point, not n; their offsets from the eye, and a segment's side of the eye, are computed
        once. The arithmetic is :func:`navcli.geometry.blocks_sight` and
        :func:`navcli.geometry.crosses_sight`, inlined, to the last bit."""
        ex, ey, theta, pan = pose.x, pose.y, pose.theta, self.pan
        rng, half = self.spec.range, self.spec.fov / 2
        discs = self._discs_in_view(ex, ey, theta + pan, rng, half)
        lines = self._segments_in_range(ex, ey, rng)
        remainder, atan2, hypot = math.remainder, math.atan2, math.hypot

        def sees(px: float, py: float, own: str) -> bool:
            dx, dy = px - ex, py - ey
            if hypot(dx, dy) > rng:
                return False
            if abs(remainder(atan2(dy, dx) - theta - pan, TWO_PI)) > half:
                return False  # (math.remainder: |wrap_angle|, a hot spot's cheaper form)
            L2 = dx * dx + dy * dy
            if L2 != 0.0:
                for key, cex, cey, cx, cy, r2 in discs:
                    t = (cex * dx + cey * dy) / L2
                    if 0.0 < t < 1.0 and key != own:
                        qx, qy = ex + t * dx - cx, ey + t * dy - cy
                        if qx * qx + qy * qy < r2:
                            return False
            for key, ax, ay, ux, uy, left, aye, axe, bye, bxe in lines:
                d2 = ux * (py - ay) - uy * (px - ax)
                if d2 == 0 or (d2 > 0) == left or key == own:
                    continue
                d3 = dx * aye - dy * axe  # sides of a and b relative to the sight line
                d4 = dx * bye - dy * bxe
                if (d3 > 0) != (d4 > 0) and d3 != 0 and d4 != 0:
                    return False
            return True

        return sees

    def _discs_in_view(
        self, ex: float, ey: float, axis: float, rng: float, half: float
    ) -> list[tuple[str, float, float, float, float, float]]:
        """The discs (landmarks, circles) that reach into the field of view (``axis`` ± ``half``)
        within ``rng`` of the eye: key, offset of the centre from the eye, centre, r^2."""
        discs = []
        for key, (cx, cy), r in self._points:
            d = math.hypot(cx - ex, cy - ey)
            if d - r > rng:
                continue
            if d > r and abs(wrap_angle(math.atan2(cy - ey, cx - ex) - axis)) > half + math.asin(r / d):
                continue
            discs.append((key, cx - ex, cy - ey, cx, cy, r * r))
        return discs

    def _segments_in_range(
        self, ex: float, ey: float, rng: float
    ) -> list[tuple[str, float, float, float, float, bool, float, float, float, float]]:
        """The segments (obstacles, walls) within ``rng`` of the eye that a sight line can cross:
        key, a, b - a, the eye's side of ab, a and b relative to the eye."""
        lines = []
        for key, (ax, ay), (bx, by) in self._lines:
            if distance_to_segment((ex, ey), (ax, ay), (bx, by)) > rng:
                continue
            ux, uy = bx - ax, by - ay
            d1 = ux * (ey - ay) - uy * (ex - ax)
            if d1 == 0:
                continue  # the eye on the segment's line: no sight line crosses it properly
            lines.append((key, ax, ay, ux, uy, d1 > 0, ay - ey, ax - ex, by - ey, bx - ex))
        return lines

    # -- the pan unit
    def step(
        self, time: float, pose: Pose, request: Look | None, dt: float, known: Container[str] = ()
    ) -> list[Detection] | None:
        """Advance the camera by one control tick at ``time``; return detections when an image is taken.

        ``request`` is the winning look (ignored while the camera processes an image); ``pose``
        the true pose; ``known`` the keys the visual memory holds (the routines ask: :mod:`.routines`).
        While panning, the camera follows the winning look, and cancels the pan without an image
        when there is none (module docstring); with ``vision.routines`` 0 a pan, once begun,
        ends in an image whatever wins meanwhile.
        """
        self.looked = None
        if self.state == "processing" and time >= self._free_at - 1e-9:
            self.state = "idle"
        lim = self.spec.pan_limit
        if self.state == "panning" and self.params.routines:
            assert self.request is not None  # set when the pan began
            if request is None:
                self.state, self.request = "idle", None  # no look asked for: cancelled, no image
            elif not looked_at(Look(self.goal, self.request.purpose), request):
                self.request = request  # another look wins: the camera turns to it from where it is
                self.goal = max(-lim, min(lim, wrap_angle(request.pan)))
                self._capture_at = time + abs(self.goal - self.pan) / self.spec.pan_speed
        if self.state == "idle" and request is not None:
            self.request = request
            self.goal = max(-lim, min(lim, wrap_angle(request.pan)))
            self._capture_at = time + abs(self.goal - self.pan) / self.spec.pan_speed
            self.state = "panning"
        if self.state == "panning":
            if time >= self._capture_at - 1e-9:
                self.pan = self.goal
                self.state = "processing"
                self._free_at = time + self.spec.look_time
                assert self.request is not None  # set when the pan began
                purpose = self.request.purpose if self.params.routines else EVERYTHING
                self.looked = Look(self.pan, purpose)
                return self.capture(pose, purpose, known)
            step = self.spec.pan_speed * dt
            self.pan += max(-step, min(step, self.goal - self.pan))
        return None

    # -- the image
    def capture(self, pose: Pose, purpose: LookPurpose = EVERYTHING, known: Container[str] = ()) -> list[Detection]:
        """The objects the routine of ``purpose`` registers in the image taken now from ``pose``
        (:func:`.routines.registers`; ``EVERYTHING``: all in view), measured with noise."""
        sees = self.sight(pose)
        out = []
        walls = self.params.walls != "felt"
        lines = self.params.line_objects
        target = self.target_keys
        for o in self.objects:
            how = registers(purpose, o.kind, o.key, known, target)
            if how is None:
                continue
            if o.kind in ("segment", "wall"):
                kind = "wall" if o.kind == "wall" else "obstacle"  # a lone sample of a wall is still a wall
                if kind == "wall" and not walls:
                    continue
                if lines:
                    det = self.line_of(pose, o, sees, f"{o.kind}:{o.key}", kind)
                    if det is not None:
                        out.append(det)
                    continue
                for run in self.visible_runs(pose, o, sees):
                    out.append(Detection("", kind, tuple(self.measure(pose, p) for p in run), o.radius))
            elif sees(o.a[0], o.a[1], o.key):
                if how == "as-obstacle":
                    out.append(Detection("", "obstacle", (self.measure(pose, o.a),), o.radius))
                else:
                    out.append(Detection(o.key, o.kind, (self.measure(pose, o.a),), o.radius))
        return out

    def line_of(
        self, pose: Pose, o: ArenaObject, sees: Callable[[float, float, str], bool], key: str, kind: str
    ) -> Detection | None:
        """A linear obstacle in the image as one identified object: its extremities in view
        toward ``a`` and toward ``b`` (the first and last of its samples that ``sees`` passes,
        :meth:`visible_runs`' sampling), each flagged as the obstacle's own end or not; one
        sample alone is one point, for both ends; None if none is in view."""
        (ax, ay), (bx, by) = o.a, o.b
        if distance_to_segment((pose.x, pose.y), o.a, o.b) > self.spec.range:
            return None
        n = segment_steps(o.a, o.b)
        first = last = -1
        for k in self.in_view(pose, o.a, o.b, n):
            if sees(ax + (bx - ax) * k / n, ay + (by - ay) * k / n, o.key):
                if first < 0:
                    first = k
                last = k
        if first < 0:
            return None
        ends = (first == 0, last == n)
        pa = self.measure(pose, (ax + (bx - ax) * first / n, ay + (by - ay) * first / n))
        if first == last:
            return Detection(key, kind, (pa,), o.radius, ends)
        pb = self.measure(pose, (ax + (bx - ax) * last / n, ay + (by - ay) * last / n))
        return Detection(key, kind, (pa, pb), o.radius, ends)

    def visible_runs(
        self, pose: Pose, o: ArenaObject, sees: Callable[[float, float, str], bool]
    ) -> list[tuple[Point, ...]]:
        """The parts of a linear obstacle in view (``sees``: the image's :meth:`sight`), as the
        end points of each visible stretch.

        The segment is sampled about every ``SEGMENT_STEP`` metres (:func:`segment_steps`, its
        ends included); consecutive visible samples form a stretch; a stretch is reported by its
        two ends (a linear obstacle), a lone sample as a point. Quick rejection: no sample can be in range when the
        whole segment is farther than the range, and only the samples that can lie in the field
        of view (:meth:`in_view`) are tested."""
        (ax, ay), (bx, by) = o.a, o.b
        if distance_to_segment((pose.x, pose.y), o.a, o.b) > self.spec.range:
            return []
        n = segment_steps(o.a, o.b)
        runs, cur = [], []
        key = o.key
        for k in self.in_view(pose, o.a, o.b, n):
            p = (ax + (bx - ax) * k / n, ay + (by - ay) * k / n)
            if sees(p[0], p[1], key):
                cur.append(p)
            elif cur:
                runs.append(cur)
                cur = []
        if cur:
            runs.append(cur)
        return [(r[0], r[-1]) if len(r) > 1 else (r[0],) for r in runs]

    def in_view(self, pose: Pose, a: Point, b: Point, n: int) -> range:
        """The indices ``k`` of the samples ``a + (b - a) k / n`` that may lie in the field of view:
        those in the wedge of the view widened by ``VIEW_MARGIN`` either side, and one more each
        end (a wall is sampled ~40 times and the 60-degree view holds a few of them;
        the samples left out lie well outside the view, so :meth:`sight` would refuse them
        anyway, and the stretches found are the same). A view of 180 degrees or more is no wedge:
        every sample is kept."""
        half = self.spec.fov / 2 + VIEW_MARGIN
        if half >= math.pi / 2:
            return range(n + 1)
        (ax, ay), (bx, by) = a, b
        ex, ey = pose.x, pose.y
        axis = pose.theta + self.pan
        lo, hi = 0.0, 1.0  # the part of the segment inside the wedge, as a fraction of ab
        for sign, edge in ((1.0, axis - half), (-1.0, axis + half)):  # left of the right edge, right of the left
            ux, uy = math.cos(edge), math.sin(edge)
            fa = sign * (ux * (ay - ey) - uy * (ax - ex))
            fb = sign * (ux * (by - ey) - uy * (bx - ex))
            if fa < 0.0 and fb < 0.0:
                return range(0)
            if fa < 0.0:
                lo = max(lo, fa / (fa - fb))
            elif fb < 0.0:
                hi = min(hi, fa / (fa - fb))
        if lo > hi:
            return range(0)
        return range(max(0, math.floor(lo * n) - 1), min(n, math.ceil(hi * n) + 1) + 1)

    def measure(self, pose: Pose, p: Point) -> Sighting:
        """Heading and distance of world point ``p`` with bounded noise, as fuzzy numbers whose
        support is the noise bound (so it holds the true value) and whose core is the reading."""
        P = self.params
        dx, dy = p[0] - pose.x, p[1] - pose.y
        d = math.hypot(dx, dy)
        h = wrap_angle(math.atan2(dy, dx) - pose.theta)
        k = P.noise_bound
        eh, ed = bounded_normals(self.rng, k)
        sh, sd = self.noise.vision_heading, self.noise.vision_distance
        h_m = h + sh * eh
        d_m = d * (1.0 + sd * ed)
        spread_h = k * sh + P.heading_floor
        lo = d_m / (1.0 + k * sd) - P.distance_floor  # d_m = d (1 + sd e), |e| <= k
        hi = d_m / (1.0 - k * sd) + P.distance_floor if k * sd < 1.0 else d_m * 1e3
        return Sighting(FuzzyAngle.around(h_m, spread_h), Fuzzy.trapezoid(max(0.0, lo), d_m, d_m, hi))
