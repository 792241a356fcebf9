"""The Vision system's camera: a 60-degree camera on a pan unit (notes, section 1).

Vision does not bid; it carries out the winning look. A look pans the camera (finite pan speed,
limited pan range), takes an image when the pan arrives, and then processes it for
``look_time`` seconds, busy meanwhile. The image shows an object when it lies inside the field of
view, within range, and no other object or wall blocks the line of sight to it.

What comes out are :class:`Detection` s, egocentric, with heading and distance as fuzzy numbers:
the measured values carry the scenario's noise (bounded at ``noise_bound`` standard deviations,
as a physical sensor's errors are), and the fuzzy support is exactly that bound, so the true
value always lies in the 0 % cut; the distance's spread grows with the distance. Landmarks and
the target markers are identified by id; plain obstacles are only "an obstacle": a circle as a
point, a segment by the end points of each stretch of it in view (a linear obstacle; a point if
only a sliver shows). A stretch of the room's walls is reported as a ``wall`` (our design: a wall
is told apart from the obstacles in the room by its size, and the Pilot treats it as such).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bidding import Look
from ..fuzzy import TWO_PI, Fuzzy, FuzzyAngle
from ..geometry import Point, Pose, blocks_sight, crosses_sight, distance_to_segment, wrap_angle
from ..params import VISION, VisionParams
from ..scenario import ArenaObject, Scenario


SEGMENT_STEP = 0.2  # m between the samples of a linear obstacle tested for visibility
SEGMENT_SAMPLES = 40  # at most this many samples per linear obstacle


@dataclass(frozen=True)
class Sighting:
    """One measured point: fuzzy egocentric heading (rad) and distance (m)."""

    heading: FuzzyAngle
    distance: Fuzzy


@dataclass(frozen=True)
class Detection:
    """What one image showed of one object.

    ``key`` is the landmark id, ``target``/``target-a``/``target-b`` for the target's markers,
    and ``""`` for a plain obstacle (not identifiable). ``points`` holds one sighting (a point
    obstacle, a landmark, a single end of a linear obstacle) or two (both ends of one).
    """

    key: str
    kind: str  # "landmark" | "target" | "obstacle" | "wall" (a stretch of the room's wall: big, flat, told apart)
    points: tuple[Sighting, ...]
    radius: float

    def as_json(self) -> dict:
        def f(x: Fuzzy, k: float = 1.0) -> dict:
            c = [tuple(v * k for v in cut) for cut in x.cuts]
            return {"lo0": c[0][0], "lo70": c[2][0], "core": (c[3][0] + c[3][1]) / 2, "hi70": c[2][1], "hi0": c[0][1]}

        return {"kind": self.kind, "points": [{"heading_deg": f(p.heading.value, 180 / math.pi),
                                               "distance_m": f(p.distance)} for p in self.points]}


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
        self._capture_at = 0.0
        self._free_at = 0.0
        objs = scenario.objects  # landmarks, obstacles, target markers, walls: the draw order of the noise
        self.objects = objs
        # what may block a line of sight: every physical object (target markers are not)
        self._all_points = [(o.key, o.a, o.radius) for o in objs if o.kind in ("landmark", "circle")]
        self._all_lines = [(o.key, o.a, o.b, o.radius) for o in objs if o.kind in ("segment", "wall")]
        self._points, self._lines = self._all_points, self._all_lines

    def _blockers(self, pose: Pose) -> None:
        """Keep, for this image, only the objects that can block a line of sight inside the field
        of view and range: the occlusion tests then cost (objects in view) squared, not n squared."""
        rng, half = self.spec.range, self.spec.fov / 2
        axis = pose.theta + self.pan
        pts = []
        for key, (cx, cy), r in self._all_points:
            d = math.hypot(cx - pose.x, cy - pose.y)
            if d - r > rng:
                continue
            if d > r and abs(wrap_angle(math.atan2(cy - pose.y, cx - pose.x) - axis)) > half + math.asin(r / d):
                continue
            pts.append((key, (cx, cy), r))
        eye = (pose.x, pose.y)
        self._points = pts
        self._lines = [ln for ln in self._all_lines if distance_to_segment(eye, ln[1], ln[2]) <= rng]

    # -- the pan unit
    def step(self, time: float, pose: Pose, request: Look | None, dt: float) -> list[Detection] | None:
        """Advance the camera by one control tick at ``time``; return detections when an image is taken.

        ``request`` is the winning look (ignored while the camera is busy); ``pose`` the true pose.
        """
        if self.state == "processing" and time >= self._free_at - 1e-9:
            self.state = "idle"
        if self.state == "idle" and request is not None:
            lim = self.spec.pan_limit
            self.goal = max(-lim, min(lim, wrap_angle(request.pan)))
            self._capture_at = time + abs(self.goal - self.pan) / self.spec.pan_speed
            self.state = "panning"
        if self.state == "panning":
            if time >= self._capture_at - 1e-9:
                self.pan = self.goal
                self.state = "processing"
                self._free_at = time + self.spec.look_time
                return self.capture(pose)
            step = self.spec.pan_speed * dt
            self.pan += max(-step, min(step, self.goal - self.pan))
        return None

    # -- the image
    def visible(self, pose: Pose, p: Point, own: str) -> bool:
        """Is world point ``p`` (of object ``own``) in the field of view, in range and unoccluded?"""
        dx, dy = p[0] - pose.x, p[1] - pose.y
        d = math.hypot(dx, dy)
        if d > self.spec.range:
            return False
        if abs(math.remainder(math.atan2(dy, dx) - pose.theta - self.pan, TWO_PI)) > self.spec.fov / 2:
            return False  # (math.remainder: |wrap_angle|, a hot spot's cheaper form)
        return not self.occluded((pose.x, pose.y), p, own)

    def occluded(self, eye: Point, p: Point, own: str) -> bool:
        """Does any physical object other than ``own`` cross the line of sight ``eye -> p``?"""
        return any(key != own and blocks_sight(eye, p, c, r) for key, c, r in self._points) or \
            any(key != own and crosses_sight(eye, p, a, b) for key, a, b, _r in self._lines)

    def capture(self, pose: Pose) -> list[Detection]:
        """The objects in the image taken now from ``pose``, measured with noise."""
        self._blockers(pose)
        try:
            out = []
            for o in self.objects:
                if o.kind in ("segment", "wall"):
                    for run in self.visible_runs(pose, o):
                        kind = "wall" if o.kind == "wall" and len(run) == 2 else "obstacle"
                        out.append(Detection("", kind, tuple(self.measure(pose, p) for p in run), o.radius))
                elif self.visible(pose, o.a, o.key):
                    key = "" if o.kind == "circle" else o.key
                    kind = "obstacle" if o.kind == "circle" else o.kind
                    out.append(Detection(key, kind, (self.measure(pose, o.a),), o.radius))
            return out
        finally:
            self._points, self._lines = self._all_points, self._all_lines

    def visible_runs(self, pose: Pose, o: ArenaObject) -> list[tuple[Point, ...]]:
        """The parts of a linear obstacle in view, as the end points of each visible stretch.

        The segment is sampled every ``SEGMENT_STEP`` metres (its ends included); consecutive
        visible samples form a stretch; a stretch is reported by its two ends (a linear
        obstacle), a lone sample as a point. Quick rejection: no sample can be in range when the
        whole segment is farther than the range."""
        (ax, ay), (bx, by) = o.a, o.b
        if distance_to_segment((pose.x, pose.y), o.a, o.b) > self.spec.range:
            return []
        n = max(1, min(SEGMENT_SAMPLES, math.ceil(math.hypot(bx - ax, by - ay) / SEGMENT_STEP)))
        runs, cur = [], []
        for k in range(n + 1):
            p = (ax + (bx - ax) * k / n, ay + (by - ay) * k / n)
            if self.visible(pose, p, o.key):
                cur.append(p)
            elif cur:
                runs.append(cur)
                cur = []
        if cur:
            runs.append(cur)
        return [(r[0], r[-1]) if len(r) > 1 else (r[0],) for r in runs]

    def measure(self, pose: Pose, p: Point) -> Sighting:
        """Heading and distance of world point ``p`` with bounded noise, as fuzzy numbers whose
        support is the noise bound (so it holds the true value) and whose core is the reading."""
        P = self.params
        dx, dy = p[0] - pose.x, p[1] - pose.y
        d = math.hypot(dx, dy)
        h = wrap_angle(math.atan2(dy, dx) - pose.theta)
        k = P.noise_bound
        eh, ed = np.clip(self.rng.standard_normal(2), -k, k).tolist()
        sh, sd = self.noise.vision_heading, self.noise.vision_distance
        h_m = h + sh * eh
        d_m = d * (1.0 + sd * ed)
        spread_h = k * sh + P.heading_floor
        lo = d_m / (1.0 + k * sd) - P.distance_floor  # d_m = d (1 + sd e), |e| <= k
        hi = d_m / (1.0 - k * sd) + P.distance_floor if k * sd < 1.0 else d_m * 1e3
        return Sighting(FuzzyAngle.around(h_m, spread_h), Fuzzy.trapezoid(max(0.0, lo), d_m, d_m, hi))
