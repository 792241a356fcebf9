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
from typing import Any, Literal

from ..geometry import Point, distance_to_segment
from ..params import PERCEPTIONS, Params
from ..plugins.names import BUILTIN_PILOTS, forms

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


@dataclass(frozen=True)
class Field:
    """One field of the scenario format, declared once: the loader reads it by this (what it is, if
    it is required, its default, a number's range and unit), and ``navcli schema`` and the
    reference table of docs/scenario-format.md (``navcli schema --markdown``) are made from it.

    ``kind``: ``number``, ``integer``, ``text``, ``choice`` (one of ``choices``), ``point``
    ([x, y] in metres), ``id`` (a landmark's), ``line`` (two points), ``list`` or ``block``;
    ``param``: the number is that parameter's (its declaration gives the range and unit)."""

    description: str
    range: Range | None = None
    default: Any = None
    required: bool = False
    kind: str = "number"
    choices: tuple[str, ...] = ()
    param: str = ""


def _param(name: str) -> Field:
    """A field a scenario block sets that is the parameter ``name``: its description, range and unit
    as :mod:`navcli.params` declares them (so they are written once)."""
    d, default = next((d, v) for n, d, v in Params().declarations() if n == name)
    lo, lo_open = d.lower
    hi, _ = d.upper
    assert lo is not None and hi is not None  # the parameters a scenario sets are bounded
    return Field(
        f"{d.description} (the parameter {name})", Range(lo, hi, d.unit, lo_open), default, kind="param", param=name
    )


POINT = Range(0.0, 100.0, "m")
"""Any coordinate of a point (``start``, ``at``, ``center``, ``from``, ``to``, a line's ends),
before it is checked against the arena."""
FIELDS: dict[str, dict[str, Field]] = {
    "scenario": {
        "version": Field("the format's version: this navcli reads 1", required=True, kind="integer"),
        "name": Field("1 to 64 of a-z, 0-9 and '-': it names the log folder", required=True, kind="text"),
        "description": Field("free text", default="", kind="text"),
        "arena": Field("the room: its width and height (walls on its border)", required=True, kind="block"),
        "robot": Field("where the robot starts (its size and speed are parameters)", required=True, kind="block"),
        "target": Field("the mission's target: exactly one of at, landmark, line", required=True, kind="block"),
        "obstacles": Field(f"circle and segment obstacles, at most {MAX_ITEMS}", default=(), kind="list"),
        "landmarks": Field(f"landmarks, at most {MAX_ITEMS}, their ids unique", default=(), kind="list"),
        "mission": Field("the pilot, perception, time limit and seed", default={}, kind="block"),
        "noise": Field("the sensors' and the wheels' errors; 0 turns a source off", default={}, kind="block"),
        "camera": Field("the camera on its pan unit", default={}, kind="block"),
        "pilot": Field("the pilot's parameters of the pilot paper", default={}, kind="block"),
        "navigation": Field(
            "the Navigation system's parameters: a cluster, and any navigation.* parameter by name",
            default={},
            kind="block",
        ),
    },
    "arena": {
        "width": Field("the room's width", Range(1.0, 100.0, "m"), required=True),
        "height": Field("the room's height", Range(1.0, 100.0, "m"), required=True),
    },
    "robot": {
        "start": Field(
            "where the robot starts, clear of every obstacle, landmark and wall by its radius",
            required=True,
            kind="point",
        ),
        "heading_deg": Field(
            "its heading at the start, counter-clockwise from +x", Range(-360.0, 360.0, "deg"), default=0.0
        ),
        "radius": _param("robot.radius"),
        "max_speed": _param("robot.max_speed"),
    },
    "target": {
        "at": Field("a point target", kind="point"),
        "landmark": Field("the landmark with this id", kind="id"),
        "line": Field("a diverting target: the line [[x, y], [x, y]] to cross", kind="line"),
        "tolerance": Field(
            "how close to a point (or to a landmark's body, with the robot's) counts as reached",
            Range(0.01, 10.0, "m"),
            default=0.3,
        ),
    },
    "circle": {
        "center": Field("a point obstacle's centre", required=True, kind="point"),
        "radius": Field("its radius", Range(0.01, 50.0, "m"), required=True),
    },
    "segment": {
        "from": Field("a linear obstacle's one end", required=True, kind="point"),
        "to": Field("its other end", required=True, kind="point"),
        "thickness": Field("its physical width", Range(0.01, 1.0, "m"), default=0.05),
    },
    "landmark": {
        "id": Field(f"1 to {MAX_ID} printable characters, unique", required=True, kind="id"),
        "at": Field("where it stands", required=True, kind="point"),
        "radius": Field("its radius", Range(0.01, 5.0, "m"), default=0.15),
    },
    "mission": {
        "pilot": Field(
            forms("pilot"),
            default=BUILTIN_PILOTS[0],
            kind="text",
        ),
        "time_limit": Field(
            "simulated seconds before the mission ends as timeout", Range(0.1, 86_400.0, "s"), default=900.0
        ),  # a tick at least, up to a simulated day
        "seed": Field(
            "the run's seed; rerun i of a comparison uses one derived from it and i",
            Range(0, 2**64 - 1),
            default=1,
            kind="integer",
        ),
        "perception": Field(
            "vision (the camera and visual memory) or oracle (ground truth)",
            default=PERCEPTIONS[0],
            kind="choice",
            choices=PERCEPTIONS,
        ),
    },
    # noise * NOISE_BOUND < 1, so a clipped error never turns a distance or a scale negative
    "noise": {
        "odometry": Field(
            "relative standard deviation of travelled distance and turned angle", Range(0.0, 0.3), default=0.02
        ),
        "odometry_drift_deg_per_m": Field(
            "standard deviation of the heading's drift per metre driven (a per-run rate and a per-tick part)",
            Range(0.0, 10.0, "deg/m"),
            default=0.0,
        ),
        "vision_heading_deg": Field("standard deviation of a measured heading", Range(0.0, 20.0, "deg"), default=2.0),
        "vision_distance": Field("relative standard deviation of a measured distance", Range(0.0, 0.3), default=0.05),
        "slip": _param("robot.slip_noise"),
    },
    "camera": {
        "fov_deg": Field("the field of view", Range(0.0, 360.0, "deg", lo_open=True), default=60.0),
        "range": Field("how far it sees", Range(0.1, 100.0, "m"), default=6.0),
        "pan_limit_deg": Field(
            "how far the pan unit turns either side of ahead", Range(0.0, 180.0, "deg"), default=100.0
        ),
        "pan_speed_deg": Field("the pan unit's speed", Range(0.0, 3600.0, "deg/s", lo_open=True), default=90.0),
        "look_time": Field("image processing per look, the camera busy meanwhile", Range(0.0, 10.0, "s"), default=0.3),
    },
    "pilot": {"K": _param("pilot.K"), "A_t": _param("pilot.A_t"), "R_min": _param("pilot.R_min")},
}
"""Every field of the format by block (``scenario`` the top level; ``circle``, ``segment`` and
``landmark`` the items of the lists); the ``navigation`` block's are its parameters'."""

RANGES: dict[str, Range] = {"point": POINT} | {
    f"{block}.{key}": f.range for block, fields in FIELDS.items() for key, f in fields.items() if f.range is not None
}
"""Every number field's range, by its field (``circle.radius`` for ``obstacles[i].circle.radius``)."""
PILOT_BLOCK = tuple(FIELDS["pilot"])
"""The parameters a scenario's ``pilot:`` block sets (each ``pilot.<key>``)."""


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
    perception: str = PERCEPTIONS[0]  # vision | oracle


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
    pan_limit: float = math.radians(FIELDS["camera"]["pan_limit_deg"].default)  # rad either side of ahead
    pan_speed: float = math.radians(FIELDS["camera"]["pan_speed_deg"].default)  # rad/s
    look_time: float = FIELDS["camera"]["look_time"].default  # s of processing per look


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
    given: frozenset[str] = frozenset()  # the parameters the file sets itself (its blocks; a cluster's differences)
    text: str = field(default="", repr=False)  # the YAML itself, attached to every log

    @property
    def walls(self) -> tuple[tuple[str, Point, Point], ...]:
        """The arena's four walls as (name, from, to), counter-clockwise from the south wall."""
        W, H = self.arena.width, self.arena.height
        return (
            ("wall-s", (0.0, 0.0), (W, 0.0)),
            ("wall-e", (W, 0.0), (W, H)),
            ("wall-n", (W, H), (0.0, H)),
            ("wall-w", (0.0, H), (0.0, 0.0)),
        )

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
