"""Beliefs: what the agents know of the world, egocentric, and where it comes from.

The agents never see the world; they see :class:`Beliefs`. Until the Vision system and its
visual memory land, :class:`RangePerception` stands in for them: it reports the obstacles and
landmarks within camera range (without field-of-view or occlusion limits, and without noise), the
arena's walls as linear obstacles, and the target: exactly when it is within camera range,
otherwise relative to the pose the robot *believes* it has (its odometry), as a robot told the
target's coordinates would. It is a seam: Vision replaces it without the agents changing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .geometry import Point, Pose, distance_to_segment
from .scenario import Circle, Scenario


@dataclass(frozen=True)
class KnownObstacle:
    """An obstacle as the robot knows it, egocentric (x ahead, y left, metres).

    A point obstacle has ``a == b`` (its centre); a linear one runs from ``a`` to ``b``.
    ``radius`` is its physical half-width, ``key`` names it stably across ticks for logs.
    """

    key: str
    a: Point
    b: Point
    radius: float

    @property
    def is_point(self) -> bool:
        return self.a == self.b


@dataclass(frozen=True)
class Beliefs:
    """Everything an agent may use at one tick. Positions are egocentric, in metres."""

    time: float
    odometry: Pose  # where the robot believes it is, in the arena frame
    target: Point | None  # egocentric target point (the line's centre for a line target)
    target_line: tuple[Point, Point] | None  # egocentric diverting-target line, if any
    obstacles: tuple[KnownObstacle, ...]


class RangePerception:
    """The stand-in for Vision: everything within camera range, exact (see module docstring)."""

    def __init__(self, scenario: Scenario):
        self.scenario = scenario
        self.range = scenario.camera.range
        self._objects: list[tuple[str, Point, Point, float]] = []
        for i, o in enumerate(scenario.obstacles):
            if isinstance(o, Circle):
                self._objects.append((f"o{i}", o.center, o.center, o.radius))
            else:
                self._objects.append((f"o{i}", o.start, o.end, o.thickness / 2))
        for lm in scenario.landmarks:
            self._objects.append((f"L{lm.id}", lm.at, lm.at, lm.radius))
        W, H = scenario.arena.width, scenario.arena.height  # the walls are linear obstacles too
        for key, a, b in (("wall-s", (0.0, 0.0), (W, 0.0)), ("wall-e", (W, 0.0), (W, H)),
                          ("wall-n", (W, H), (0.0, H)), ("wall-w", (0.0, H), (0.0, 0.0))):
            self._objects.append((key, a, b, 0.0))

    def observe(self, time: float, truth: Pose, odometry: Pose) -> Beliefs:
        rng = self.range
        seen = []
        for key, a, b, r in self._objects:
            la, lb = truth.to_local(a), truth.to_local(b)
            if distance_to_segment((0.0, 0.0), la, lb) <= rng:
                seen.append(KnownObstacle(key, la, lb, r))
        t = self.scenario.target
        # the target is seen like any object within range; beyond it, it is dead-reckoned
        ref = truth if math.dist((truth.x, truth.y), t.point) <= rng else odometry
        line = (ref.to_local(t.line[0]), ref.to_local(t.line[1])) if t.line else None
        return Beliefs(time, odometry, ref.to_local(t.point), line, tuple(seen))
