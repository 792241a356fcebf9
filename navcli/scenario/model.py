"""The scenario model: the frozen dataclasses a scenario file becomes (the scenario format,
version 1, in docs/scenario-format.md), and the ranges every number of it must lie in.

Angles are radians in the dataclasses (degrees in YAML, ``*_deg``); lengths are metres. The
file is read by :mod:`navcli.scenario.loader`; its JSON Schema is :mod:`navcli.scenario.schema`.
"""

from __future__ import annotations

import hashlib
import math
import re
from dataclasses import dataclass, field
from typing import Literal

from ..geometry import Point, distance_to_segment
from ..params import DEFAULTS, Params

SUPPORTED_VERSIONS = (1,)
NAME_RE = re.compile(r"[a-z0-9-]{1,64}")
"""A scenario's name: it names a folder and log files, so 1 to 64 of a-z, 0-9 and '-' (matched whole)."""
MAX_ITEMS = 1000
"""Most obstacles, and most landmarks, in one scenario (the benchmark measures 200 objects)."""
MAX_ID = 64
"""Longest landmark id (characters)."""


@dataclass(frozen=True)
class Range:
    """The values a number field accepts: ``lo <= v <= hi`` (``lo < v`` if ``lo_open``), in
    ``unit``. Chosen so that anything accepted can be simulated (our design, see docs/scenario-format.md)."""

    lo: float
    hi: float
    unit: str = ""
    lo_open: bool = False

    def problem(self, v: float) -> str | None:
        """Why ``v`` is out of range, or None."""
        if (v <= self.lo if self.lo_open else v < self.lo) or v > self.hi:
            u = f" {self.unit}" if self.unit else ""
            low = f"greater than {self.lo:g}" if self.lo_open else f"at least {self.lo:g}"
            if v <= 0 < self.lo or (self.lo_open and self.lo == 0 and v <= 0):  # a size of zero or less
                return f"must be greater than zero, found {v:g}"
            return f"must be {low} and at most {self.hi:g}{u}, found {v:g}{u}"
        return None


def _param_range(name: str) -> Range:
    """The range and unit of a parameter a scenario block may set, as declared in :mod:`navcli.params`."""
    d = next(d for n, d, _ in Params().declarations() if n == name)
    lo, lo_open = d.lower
    hi, _ = d.upper
    assert lo is not None and hi is not None  # the parameters a scenario sets are bounded
    return Range(lo, hi, d.unit, lo_open)


PILOT_BLOCK = {"K": "eq. 2: repulsion constant", "A_t": "eq. 5: target attraction",
               "R_min": "metres: prohibited area beyond an obstacle's surface"}
"""The parameters a scenario's ``pilot:`` block sets (each ``pilot.<key>``), with what they are."""

RANGES: dict[str, Range] = {
    "arena.width": Range(1.0, 100.0, "m"),
    "arena.height": Range(1.0, 100.0, "m"),
    "point": Range(0.0, 100.0, "m"),  # any coordinate, before it is checked against the arena
    "robot.heading_deg": Range(-360.0, 360.0, "deg"),
    "robot.radius": _param_range("robot.radius"),
    "robot.max_speed": _param_range("robot.max_speed"),
    "target.tolerance": Range(0.01, 10.0, "m"),
    "circle.radius": Range(0.01, 50.0, "m"),
    "segment.thickness": Range(0.01, 1.0, "m"),
    "landmark.radius": Range(0.01, 5.0, "m"),
    "mission.time_limit": Range(0.1, 86_400.0, "s"),  # a tick at least, up to a simulated day
    "mission.seed": Range(0, 2 ** 64 - 1),
    # noise * NOISE_BOUND < 1, so a clipped error never turns a distance or a scale negative
    "noise.odometry": Range(0.0, 0.3),
    "noise.odometry_drift_deg_per_m": Range(0.0, 10.0, unit="deg/m"),
    "noise.vision_heading_deg": Range(0.0, 20.0, "deg"),
    "noise.vision_distance": Range(0.0, 0.3),
    "camera.fov_deg": Range(0.0, 360.0, "deg", lo_open=True),
    "camera.range": Range(0.1, 100.0, "m"),
    "camera.pan_limit_deg": Range(0.0, 180.0, "deg"),
    "camera.pan_speed_deg": Range(0.0, 3600.0, "deg/s", lo_open=True),
    "camera.look_time": Range(0.0, 10.0, "s"),
    "pilot.K": _param_range("pilot.K"),
    "pilot.A_t": _param_range("pilot.A_t"),
    "pilot.R_min": _param_range("pilot.R_min"),
}
"""Every number field's range, by its field (``circle.radius`` for ``obstacles[i].circle.radius``);
``navcli schema`` and docs/scenario-format.md show the same table."""


# --- The values a scenario is made of -------------------------------------------------------
@dataclass(frozen=True)
class Arena:
    width: float
    height: float


@dataclass(frozen=True)
class RobotSpec:
    """Where the robot starts; its size and speed are parameters (``params.robot``)."""

    start: Point
    heading: float  # rad


@dataclass(frozen=True)
class Circle:
    """A point obstacle of the papers: a cylinder of this radius."""

    center: Point
    radius: float


@dataclass(frozen=True)
class Segment:
    """A linear obstacle of the papers: a wall piece from ``start`` to ``end``."""

    start: Point
    end: Point
    thickness: float

    @property
    def center(self) -> Point:
        return ((self.start[0] + self.end[0]) / 2, (self.start[1] + self.end[1]) / 2)


Obstacle = Circle | Segment


@dataclass(frozen=True)
class Landmark:
    id: str
    at: Point
    radius: float


@dataclass(frozen=True)
class Target:
    """The mission's target. ``point`` is where to head: the point, the landmark, or the line's centre."""

    kind: Literal["point", "landmark", "line"]
    point: Point
    tolerance: float
    landmark: str | None = None
    line: tuple[Point, Point] | None = None


@dataclass(frozen=True)
class MissionSpec:
    pilot: str
    time_limit: float  # simulated seconds
    seed: int
    perception: str = DEFAULTS.perception  # vision | oracle


@dataclass(frozen=True)
class Noise:
    odometry: float  # relative error of travelled distance and of turned angle
    vision_heading: float  # rad, standard deviation
    vision_distance: float  # relative standard deviation
    heading_drift: float = 0.0  # rad per metre driven: standard deviation of the odometry's heading drift


@dataclass(frozen=True)
class CameraSpec:
    fov: float  # rad
    range: float  # m
    pan_limit: float = math.radians(DEFAULTS.camera_pan_limit_deg)  # rad either side of ahead
    pan_speed: float = math.radians(DEFAULTS.camera_pan_speed_deg)  # rad/s
    look_time: float = DEFAULTS.camera_look_time  # s of processing per look


@dataclass(frozen=True)
class ArenaObject:
    """One physical thing of the arena, as every part of navcli sees it (the world's bodies, the
    camera's objects, the oracle's obstacles, the log's scene, the figures): the one place that
    turns the scenario's obstacles, landmarks, target markers and walls into geometry.

    ``a == b`` for a round thing (a circle, a landmark, a target marker); a linear one runs from
    ``a`` to ``b``. ``radius`` is the physical half-width (0 for a wall's face and a target
    marker). ``key`` is stable (a landmark's id, ``o3``, ``target``, ``wall-s``); ``label`` is how
    events name it (``obstacle 3``, ``landmark A``, ``wall``).
    """

    key: str
    kind: Literal["landmark", "circle", "segment", "target", "wall"]
    a: Point
    b: Point
    radius: float
    label: str

    def clearance(self, p: Point) -> float:
        """Distance (m) from ``p`` to the thing's surface; negative inside it."""
        return distance_to_segment(p, self.a, self.b) - self.radius


@dataclass(frozen=True)
class Scenario:
    version: int
    name: str
    description: str
    arena: Arena
    robot: RobotSpec
    target: Target
    obstacles: tuple[Obstacle, ...]
    landmarks: tuple[Landmark, ...]
    mission: MissionSpec
    noise: Noise
    camera: CameraSpec
    params: Params  # the defaults with the file's robot (radius, max_speed) and pilot blocks applied
    source: str = ""  # the file it came from
    text: str = field(default="", repr=False)  # the YAML itself, attached to every log

    @property
    def walls(self) -> tuple[tuple[str, Point, Point], ...]:
        """The arena's four walls as (name, from, to), counter-clockwise from the south wall."""
        W, H = self.arena.width, self.arena.height
        return (("wall-s", (0.0, 0.0), (W, 0.0)), ("wall-e", (W, 0.0), (W, H)),
                ("wall-n", (W, H), (0.0, H)), ("wall-w", (0.0, H), (0.0, 0.0)))

    @property
    def objects(self) -> tuple[ArenaObject, ...]:
        """Landmarks, obstacles, target markers and walls, in that order (see :class:`ArenaObject`)."""
        objs = [ArenaObject(lm.id, "landmark", lm.at, lm.at, lm.radius, f"landmark {lm.id}") for lm in self.landmarks]
        for i, o in enumerate(self.obstacles):
            if isinstance(o, Circle):
                objs.append(ArenaObject(f"o{i}", "circle", o.center, o.center, o.radius, f"obstacle {i}"))
            else:
                objs.append(ArenaObject(f"o{i}", "segment", o.start, o.end, o.thickness / 2, f"obstacle {i}"))
        t = self.target
        if t.kind == "point":
            objs.append(ArenaObject("target", "target", t.point, t.point, 0.0, "target"))
        elif t.kind == "line":
            objs += [ArenaObject(f"target-{s}", "target", p, p, 0.0, "target") for s, p in zip("ab", t.line or ())]
        objs += [ArenaObject(key, "wall", a, b, 0.0, "wall") for key, a, b in self.walls]
        return tuple(objs)

    @property
    def sha256(self) -> str:
        return hashlib.sha256(self.text.encode("utf-8")).hexdigest()
