"""Beliefs: what the agents know of the world, egocentric, and where it comes from.

The agents never see the world; they see :class:`Beliefs`, made each tick by a perception:

- :class:`VisionPerception` (the default): the camera (:mod:`navcli.vision.camera`) and the visual
  memory (:mod:`navcli.vision.visual_memory`). The robot knows what it has seen, where its
  memory and odometry put it, and what it was told at the start: where the target is (with
  ``vision.told_target`` 0, as in the learning paper's task, nothing: the target is known once
  the camera has seen it).

  **The walls are a stated condition** (``vision.walls``; the papers say nothing of how the
  robot knows the room's walls): ``seen`` (the default), found by the camera's looks for
  obstacles as fences are, each wall one object; ``known``, told at the start as the target is
  (to within ``distance_floor``, carried by odometry, never forgotten, sharpened when seen);
  ``felt``, found by the bumpers only (the camera registers no wall). The default is ``seen``
  because nothing in the papers tells the robot of the room, and the Vision system "is
  responsible for ... detecting obstacles to support obstacle avoidance"; the sensitivity table
  reports the other two.
- :class:`OraclePerception` (``--perception oracle``): ground truth of every obstacle, landmark,
  wall and the target; for experiments that isolate the pilot from vision. Never the default.
  It senses exactly, by design: it is the condition without a sensor's error, the camera's
  measurement noise being vision's; its reruns vary through the wheels' slip
  (:class:`navcli.world.Slip`), which moves the robot under either perception.

Both own the camera, so looks are arbitrated, timed and counted the same way, and both pass on
what the agents hear of the last tick: the look of the image taken (pan and purpose), the bumps felt.
"""

from __future__ import annotations

import math
from typing import Container, Iterable

import numpy as np

from ..beliefs import Beliefs, Bump, KnownLandmark, KnownObstacle
from ..fuzzy import ALPHAS, CUT, FuzzyPoint
from ..bidding import Look
from ..geometry import Point, Pose, midpoint, motion_between
from ..params import COLLISION_SLOP, CONTROL_DT, PHYSICS_DT, ROBOT, VISION, Params, RobotParams, VisionParams
from ..scenario import Scenario
from .camera import Camera, Detection
from .visual_memory import Memory, Remembered, Spot, VisualMemory


_CRISP = (0.0,) * len(ALPHAS)  # what the oracle knows, it knows exactly


class _Senses:
    """What both perceptions share: the camera, and what the agents hear of the last tick (the
    pan of the image taken, the bumps felt, whether the bumper stayed pressed)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, params: VisionParams):
        self.scenario = scenario
        self.params = params
        self.camera = Camera(scenario, rng, params)
        self._looked: Look | None = None
        self._bumps: tuple[Bump, ...] = ()
        self._touching = False

    def _beliefs(
        self,
        time: float,
        odometry: Pose,
        target: Point | None,
        line: tuple[Point, Point] | None,
        obstacles: Iterable[KnownObstacle],
        spread: float,
        landmarks: tuple[KnownLandmark, ...] = (),
        target_at: FuzzyPoint | None = None,
        target_seen: float = 0.0,
    ) -> Beliefs:
        return Beliefs(
            time,
            odometry,
            target,
            line,
            tuple(obstacles),
            spread,
            self._looked,
            self._bumps,
            self._touching,
            landmarks,
            target_at,
            target_seen,
        )

    @property
    def camera_state(self) -> tuple[float, str, str | None]:
        """The camera's pan (rad, from the heading), its state (idle, panning or processing) and
        the purpose of the look it carries out (None when idle)."""
        cam = self.camera
        return cam.pan, cam.state, cam.request.purpose if cam.state != "idle" and cam.request is not None else None

    def look(self, time: float, truth: Pose, request: Look | None) -> list[Detection] | None:
        """Carry out the winning look; the detections if an image was taken."""
        dets = self.camera.step(time, truth, request, CONTROL_DT, self.known())
        self._looked = self.camera.looked
        return dets

    def known(self) -> Container[str]:
        """The keys of what the robot remembers (the routines ask whether a landmark is new):
        nothing, without a memory."""
        return ()

    def moved(
        self, before: Pose, after: Pose, bumps: tuple[Bump, ...], touching: bool = False, slip: float = 0.0
    ) -> None:
        """Odometry says the robot went from ``before`` to ``after``; ``bumps`` began and the
        bumper was ``touching`` during the tick; ``slip`` (m) is how far it may have slid along
        what it touched, unmeasured."""
        self._bumps, self._touching = bumps, touching

    def snapshot(self) -> tuple[Remembered, ...] | None:
        """What is remembered, as values for the log (nothing, without a memory)."""
        return None

    def glimpse_target(self, truth: Pose) -> None:
        """The learning task's first sighting of the target: nothing to add without a memory."""


class OraclePerception(_Senses):
    """Ground truth for the agents (see the module docstring)."""

    name = "oracle"

    def __init__(self, scenario: Scenario, rng: np.random.Generator, params: VisionParams = VISION):
        super().__init__(scenario, rng, params)
        # everything physical the camera could ever see, landmarks keyed as the memory keys them
        order = {"circle": 0, "segment": 0, "landmark": 1, "wall": 2}  # obstacles, landmarks, walls
        self._objects = [
            (f"L{o.key}" if o.kind == "landmark" else o.key, o.a, o.b, o.radius, o.kind == "wall")
            for o in sorted(self.camera.objects, key=lambda o: order.get(o.kind, 3))
            if o.kind != "target"
        ]

    def observe(self, time: float, truth: Pose, odometry: Pose) -> Beliefs:
        seen = [KnownObstacle(k, truth.to_local(a), truth.to_local(b), r, w) for k, a, b, r, w in self._objects]
        t = self.scenario.target
        line = (truth.to_local(t.line[0]), truth.to_local(t.line[1])) if t.line else None
        landmarks = tuple(
            KnownLandmark(lm.id, FuzzyPoint(*truth.to_local(lm.at), _CRISP), time) for lm in self.scenario.landmarks
        )
        target = truth.to_local(t.point)
        return self._beliefs(
            time, odometry, target, line, seen, 0.0, landmarks, None if line else FuzzyPoint(*target, _CRISP), time
        )


class VisionPerception(_Senses):
    """The camera and the visual memory (see the module docstring)."""

    name = "vision"

    def __init__(
        self, scenario: Scenario, rng: np.random.Generator, params: VisionParams = VISION, robot: RobotParams = ROBOT
    ):
        super().__init__(scenario, rng, params)
        self.robot = robot
        self.memory = VisualMemory(
            scenario.noise.odometry, params, heading_drift=scenario.noise.heading_drift, robot_radius=robot.radius
        )
        start = Pose(*scenario.robot.start, scenario.robot.heading)
        told = params.distance_floor  # what the robot is told is precise to a couple of cm
        t = scenario.target
        if params.told_target:  # (untold, the learning paper's robot "knows nothing": the camera finds the target)
            if t.line is not None:
                self.memory.add("target-a", "target", [start.to_local(t.line[0])], 0.0, told, prior=True)
                self.memory.add("target-b", "target", [start.to_local(t.line[1])], 0.0, told, prior=True)
            else:
                self.memory.add("target", "target", [start.to_local(t.point)], 0.0, told, prior=True)
        self._target_key = t.landmark if t.kind == "landmark" else "target"
        if params.walls == "known":  # told of the room at the start, as of the target: never forgotten
            for key, a, b in scenario.walls:
                m = self.memory.add(
                    f"wall:{key}", "wall", [start.to_local(a), start.to_local(b)], 0.0, told, prior=True
                )
                m.exact = (True, True)
        self._anchors: dict[str, list[str | None]] = {}
        self._ticks = 0

    def observe(self, time: float, truth: Pose, odometry: Pose) -> Beliefs:
        """Beliefs from the memory alone: crisp centres for the pilot (as the paper computes its
        forces), the target's heading spread for the Target Tracker."""
        items = self.memory.items
        obstacles, landmarks = [], []
        for m in items.values():
            kind = m.kind
            if kind == "target":
                continue
            spots = m.spots
            s0 = spots[0]
            a = (s0.x, s0.y)
            if len(spots) == 2:
                s1 = spots[1]
                b = (s1.x, s1.y)
            else:
                b = a
            if kind == "landmark":
                obstacles.append(KnownObstacle(f"L{m.key}", a, b, m.radius, False))
                landmarks.append(KnownLandmark(m.key, s0.point(), m.seen))
            else:
                if m.key in self._anchors:
                    a, b = self._anchored(m, a, b)
                obstacles.append(KnownObstacle(m.key, a, b, m.radius, kind == "wall"))
        line, target_at, seen = None, None, 0.0
        if self.scenario.target.kind == "line":
            end_a, end_b = items["target-a"].spots[0], items["target-b"].spots[0]
            line = ((end_a.x, end_a.y), (end_b.x, end_b.y))
            target = midpoint(line[0], line[1])
            spread = max(end_a.heading().width(), end_b.heading().width())
        else:
            told_of = items.get(self._target_key or "target") or items.get("target")
            if told_of is None:  # not told, not seen yet (or forgotten): no belief of it at all
                target, spread = None, 2 * math.pi
            else:
                target_at, seen = told_of.spots[0].point(), told_of.seen
                target, spread = (target_at.x, target_at.y), target_at.heading_width()
        return self._beliefs(time, odometry, target, line, obstacles, spread, tuple(landmarks), target_at, seen)

    def known(self) -> Container[str]:
        return self.memory.items

    def glimpse_target(self, truth: Pose) -> None:
        """Remember the target as a look straight at it from ``truth`` measures it, if it is in
        range with nothing in the way (the learning task's first sighting, when it is given)."""
        cam = self.camera
        t = self.scenario.target
        key = t.landmark or "target"
        kind = "landmark" if t.landmark else "target"
        facing = Pose(truth.x, truth.y, math.atan2(t.point[1] - truth.y, t.point[0] - truth.x))
        if cam.sight(Pose(facing.x, facing.y, facing.theta - cam.pan))(t.point[0], t.point[1], key):
            radius = next((lm.radius for lm in self.scenario.landmarks if lm.id == key), 0.0)
            self.memory.observe([Detection(key, kind, (cam.measure(truth, t.point),), radius)], 0.0)

    def _anchored(self, m: Memory, a: Point, b: Point) -> tuple[Point, Point]:
        """The ends of a fence that stands between landmarks (:func:`anchors`): an end at a
        landmark the memory holds is that landmark's position, unless the fence's own end was
        seen and is the sharper of the two."""
        ends = [a, b]
        for i, lm in enumerate(self._anchors[m.key]):
            held = self.memory.items.get(lm) if lm is not None else None
            if held is not None and len(m.spots) == 2:
                own, at = m.spots[i], held.spots[0]
                if not (m.exact and m.exact[i]) or at.r0 < own.r0:
                    ends[i] = (at.x, at.y)
        return ends[0], ends[1]

    def look(self, time: float, truth: Pose, request: Look | None) -> list[Detection] | None:
        """Carry out the winning look; fold an image's detections into the memory."""
        dets = super().look(time, truth, request)
        if dets:
            self.memory.observe(dets, time)
            self.learn_anchors()
        return dets

    def learn_anchors(self) -> None:
        """Take in the fences that, as now remembered, end at landmarks (:func:`anchors`): once
        seen so, an end stays anchored at its landmark (where the memory holds the landmark, when
        that is the sharper: :meth:`_anchored`)."""
        for key, ends in anchors(self.memory).items():
            held = self._anchors.setdefault(key, [None, None])
            for i, lm in enumerate(ends):
                held[i] = lm or held[i]

    def snapshot(self) -> tuple[Remembered, ...]:
        """The memory as values, for the log."""
        return self.memory.snapshot()

    def moved(
        self, before: Pose, after: Pose, bumps: tuple[Bump, ...], touching: bool = False, slip: float = 0.0
    ) -> None:
        """Move the memory by the odometry; widen it by ``slip``; add what the bumpers found (at
        the robot's rim, in the direction of the contact); forget what became too imprecise."""
        super().moved(before, after, bumps, touching, slip)
        mem = self.memory
        mem.move(*motion_between(before, after))
        if slip:
            mem.shove(slip)
        if bumps:
            r = self.robot.radius + self.params.bump_radius
            # the support reaches back past the rim by how far the body may have driven into what it
            # hit in the physics step that felt it, and the overlap the physics allows
            depth = self.robot.max_speed * PHYSICS_DT + COLLISION_SLOP
            for b in bumps:
                mem.add_bump(
                    Spot(r * math.cos(b.bearing), r * math.sin(b.bearing), self.params.bump_radius + depth, 0.0),
                    self.params.bump_radius / 2,
                )
        self._ticks += 1
        if self._ticks % self.params.forget_every == 0:  # imprecision creeps: twice a second is enough
            mem.forget()


ANCHOR_GAP = 0.05
"""m: a fence whose end is this close to a landmark's body (beyond the fence's half-width, and
what the memory may be off by) ends at that landmark (:func:`anchors`)."""


def anchors(memory: VisualMemory) -> dict[str, tuple[str | None, str | None]]:
    """The fences that, as the robot perceives them, stand between landmarks, by their memory key:
    for each end, the landmark it ends at, or None.

    The thesis' linear obstacles run between landmarks ("landmark-to-landmark line obstacles", the
    Pilot grows them into rounded rectangles), so the robot knows such a fence by its landmarks,
    and its ends are where it holds them to be (:meth:`VisionPerception._anchored`). The robot
    learns it by sight: an end of an identified fence that it has seen (not where a view cut the
    fence) lies, in memory, at a remembered landmark: the gap between their bodies (the centres'
    distance less the landmark's and the fence's half-widths) at most :data:`ANCHOR_GAP` plus the
    70 % cuts of both (how far either may be off), never more than :data:`ANCHOR_GAP` plus the
    robot's radius (ours: a gap the robot's body might pass, a door beside a landmark, is never
    closed by a blurred sighting; the rooms put landmarks 0.36-0.55 m from fence ends, and one
    room two at them). A fence's end never seen is anchored nowhere: its end is its own, measured
    by the camera like a landmark. The oracle perception needs none of this: it knows every end."""
    marks = [m for m in memory.items.values() if m.kind == "landmark"]
    out: dict[str, tuple[str | None, str | None]] = {}
    for m in memory.items.values():
        if m.kind != "obstacle" or len(m.spots) != 2 or len(m.exact) != 2:
            continue
        ends = tuple(
            _landmark_at(e, m.radius, marks, memory.robot_radius) if m.exact[i] else None for i, e in enumerate(m.spots)
        )
        if ends != (None, None):
            out[m.key] = (ends[0], ends[1])
    return out


def _landmark_at(end: Spot, radius: float, marks: list[Memory], most: float) -> str | None:
    """The key of the remembered landmark nearest the fence end ``end`` (of half-width ``radius``)
    that it may stand at, its uncertainty counted up to ``most`` m (see :func:`anchors`), or None."""
    best, best_d = None, math.inf
    for lm in marks:
        s = lm.spots[0]
        d = math.hypot(s.x - end.x, s.y - end.y)
        gap = d - lm.radius - radius
        if gap <= ANCHOR_GAP + min(end.radius(CUT) + s.radius(CUT), most) and d < best_d:
            best, best_d = lm.key, d
    return best


Perception = OraclePerception | VisionPerception


def make_perception(name: str, scenario: Scenario, rng: np.random.Generator, params: Params = Params()) -> Perception:
    if name == "oracle":
        return OraclePerception(scenario, rng, params.vision)
    if name == "vision":
        return VisionPerception(scenario, rng, params.vision, params.robot)
    raise ValueError(f"unknown perception {name!r} (expected vision or oracle)")
