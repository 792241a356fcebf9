"""Scenario files: YAML in, frozen dataclasses out (the scenario format, version 1, in the README).

Every refusal names the file, the line and the field, says what is wrong and what was expected,
so that ``navcli validate`` and ``navcli run`` can print it and exit non-zero without a
traceback. Only PyYAML's safe loader is used. Angles are degrees in YAML (``*_deg``) and radians
in the dataclasses; lengths are metres.
"""

from __future__ import annotations

import hashlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import yaml

from .geometry import Point, distance_to_segment
from .params import DEFAULTS, PERCEPTIONS, PILOT_NAMES, Params

SUPPORTED_VERSIONS = (1,)
NAME_RE = re.compile(r"^[a-z0-9-]+$")


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
            objs += [ArenaObject(f"target-{s}", "target", p, p, 0.0, "target") for s, p in zip("ab", t.line)]
        objs += [ArenaObject(key, "wall", a, b, 0.0, "wall") for key, a, b in self.walls]
        return tuple(objs)

    @property
    def sha256(self) -> str:
        return hashlib.sha256(self.text.encode("utf-8")).hexdigest()


# --- Refusals ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Problem:
    file: str
    line: int | None
    field: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{where}: {self.field}: {self.message}" if self.field else f"{where}: {self.message}"


class ScenarioError(ValueError):
    """A scenario file was refused; ``problems`` lists every reason found."""

    def __init__(self, problems: list[Problem]):
        self.problems = problems
        super().__init__("\n".join(str(p) for p in problems))


# --- Loading -------------------------------------------------------------------------------
def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file; raise :class:`ScenarioError` on any refusal."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ScenarioError([Problem(str(p), None, "", "no such file")]) from None
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError([Problem(str(p), None, "", f"cannot be read ({e})")]) from None
    return parse_scenario(text, str(p))


def parse_scenario(text: str, source: str = "<string>") -> Scenario:
    """Validate YAML text as a scenario (``source`` names it in messages)."""
    data, lines = _parse_yaml(text, source)
    return _Reader(source, lines).scenario(data, text)


def _parse_yaml(text: str, source: str) -> tuple[Any, dict[tuple, int]]:
    """Safe-load ``text`` once, keeping the line of every key and item (1-based)."""
    loader = yaml.SafeLoader(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        line = mark.line + 1 if mark else None
        what = e.problem or e.context or "malformed"
        raise ScenarioError([Problem(source, line, "", f"not valid YAML: {what}")]) from None
    except yaml.YAMLError as e:
        raise ScenarioError([Problem(source, None, "", f"not valid YAML: {e}")]) from None
    finally:
        loader.dispose()
    if root is None:
        raise ScenarioError([Problem(source, None, "", "the file is empty (expected a scenario mapping)")])
    if not isinstance(root, yaml.MappingNode):
        kind = "a list" if isinstance(root, yaml.SequenceNode) else "a single value"
        raise ScenarioError([Problem(source, root.start_mark.line + 1, "", f"the file holds {kind}, expected a mapping of scenario fields")])
    lines: dict[tuple, int] = {(): root.start_mark.line + 1}
    problems: list[Problem] = []

    def walk(node: yaml.Node, path: tuple) -> None:
        if isinstance(node, yaml.MappingNode):
            seen: set = set()
            for k, v in node.value:
                key = k.value
                if key in seen:
                    problems.append(Problem(source, k.start_mark.line + 1, _dotted(path + (key,)), "appears twice in the same mapping"))
                seen.add(key)
                lines[path + (key,)] = k.start_mark.line + 1
                walk(v, path + (key,))
        elif isinstance(node, yaml.SequenceNode):
            for i, v in enumerate(node.value):
                lines[path + (i,)] = v.start_mark.line + 1
                walk(v, path + (i,))

    walk(root, ())
    if problems:
        raise ScenarioError(problems)
    return data, lines


def _dotted(path: tuple) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _type_name(v: Any) -> str:
    if v is None:
        return "nothing"
    if isinstance(v, bool):
        return f"a boolean ({str(v).lower()})"
    if isinstance(v, (int, float)):
        return f"a number ({v})"
    if isinstance(v, str):
        return f"text ({v!r})"
    if isinstance(v, list):
        return "a list"
    if isinstance(v, dict):
        return "a mapping"
    return type(v).__name__


class _Invalid(Exception):
    """Raised inside the reader to abandon one field; the problem is already recorded."""


class _Reader:
    """Typed access to the loaded YAML that records a :class:`Problem` per refusal."""

    def __init__(self, source: str, lines: dict[tuple, int]):
        self.source = source
        self.lines = lines
        self.problems: list[Problem] = []

    # -- recording
    def fail(self, path: tuple, message: str) -> _Invalid:
        p = path
        while p not in self.lines and p:
            p = p[:-1]
        self.problems.append(Problem(self.source, self.lines.get(p), _dotted(path), message))
        return _Invalid()

    def guard(self, fn, *args, default=None):
        """Run one field's reader; on refusal keep going with ``default`` so all problems show."""
        try:
            return fn(*args)
        except _Invalid:
            return default

    # -- typed getters
    def mapping(self, v: Any, path: tuple, required: tuple[str, ...], optional: tuple[str, ...]) -> dict:
        if not isinstance(v, dict):
            raise self.fail(path, f"expected a mapping, found {_type_name(v)}")
        for k in v:
            if k not in required and k not in optional:
                allowed = ", ".join(required + optional)
                raise self.fail(path + (k,), f"unknown field {k!r} (expected one of: {allowed})")
        for k in required:
            if k not in v:
                raise self.fail(path, f"missing required field {k!r}")
        return v

    def number(self, v: Any, path: tuple, *, positive: bool = False, nonneg: bool = False) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise self.fail(path, f"expected a number, found {_type_name(v)}")
        if positive and v <= 0:
            raise self.fail(path, f"must be greater than zero, found {v}")
        if nonneg and v < 0:
            raise self.fail(path, f"must not be negative, found {v}")
        return float(v)

    def integer(self, v: Any, path: tuple) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(path, f"expected a whole number, found {_type_name(v)}")
        if v < 0:
            raise self.fail(path, f"must not be negative, found {v}")
        return v

    def text(self, v: Any, path: tuple) -> str:
        if not isinstance(v, str):
            raise self.fail(path, f"expected text, found {_type_name(v)}")
        return v

    def point(self, v: Any, path: tuple) -> Point:
        if not isinstance(v, list) or len(v) != 2:
            raise self.fail(path, f"expected a point [x, y] in metres, found {_type_name(v)}")
        return (self.number(v[0], path + (0,)), self.number(v[1], path + (1,)))

    def opt(self, m: dict, key: str, path: tuple, getter, default, **kw):
        return getter(m[key], path + (key,), **kw) if key in m else default

    # -- the blocks
    def scenario(self, d: Any, text: str) -> Scenario:
        try:
            top = self.mapping(d, (), ("version", "name", "arena", "robot", "target"),
                               ("description", "obstacles", "landmarks", "mission", "noise", "camera", "pilot"))
        except _Invalid:
            raise ScenarioError(self.problems) from None
        g = self.guard
        version = g(self.version, top["version"])
        name = g(self.name, top["name"])
        description = g(self.text, top.get("description", ""), ("description",), default="")
        arena = g(self.arena, top["arena"])
        robot, robot_params = g(self.robot, top["robot"], default=(None, {}))
        landmarks = g(self.landmarks, top.get("landmarks", []), default=())
        target = g(self.target, top["target"], landmarks or ())
        obstacles = g(self.obstacles, top.get("obstacles", []), default=())
        mission = g(self.mission, top.get("mission", {}))
        noise = g(self.noise, top.get("noise", {}))
        camera = g(self.camera, top.get("camera", {}))
        pilot_params = g(self.pilot, top.get("pilot", {}), default={})
        if self.problems:
            raise ScenarioError(self.problems)
        params = Params().override(robot_params | pilot_params)
        sc = Scenario(version, name, description, arena, robot, target, obstacles, landmarks,
                      mission, noise, camera, params)
        self.placement(sc)
        if self.problems:
            raise ScenarioError(self.problems)
        return Scenario(version, name, description, arena, robot, target, obstacles, landmarks,
                        mission, noise, camera, params, source=self.source, text=text)

    def version(self, v: Any) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(("version",), f"expected a whole number, found {_type_name(v)}")
        if v not in SUPPORTED_VERSIONS:
            raise self.fail(("version",), f"unsupported version {v} (this navcli reads version 1)")
        return v

    def name(self, v: Any) -> str:
        s = self.text(v, ("name",))
        if not NAME_RE.match(s):
            raise self.fail(("name",), f"{s!r} may hold only a-z, 0-9 and '-' (it names log files)")
        return s

    def arena(self, v: Any) -> Arena:
        m = self.mapping(v, ("arena",), ("width", "height"), ())
        w = self.number(m["width"], ("arena", "width"), positive=True)
        h = self.number(m["height"], ("arena", "height"), positive=True)
        return Arena(w, h)

    def robot(self, v: Any) -> tuple[RobotSpec, dict[str, float]]:
        """The start, and the robot parameters the block sets (``radius``, ``max_speed``)."""
        P = ("robot",)
        m = self.mapping(v, P, ("start",), ("heading_deg", "radius", "max_speed"))
        spec = RobotSpec(start=self.point(m["start"], P + ("start",)),
                         heading=math.radians(self.opt(m, "heading_deg", P, self.number, DEFAULTS.heading_deg)))
        return spec, {f"robot.{k}": self.number(m[k], P + (k,), positive=True) for k in ("radius", "max_speed") if k in m}

    def target(self, v: Any, landmarks: tuple[Landmark, ...]) -> Target:
        P = ("target",)
        m = self.mapping(v, P, (), ("at", "landmark", "line", "tolerance"))
        forms = [k for k in ("at", "landmark", "line") if k in m]
        if len(forms) != 1:
            found = " and ".join(forms) if forms else "none"
            raise self.fail(P, f"needs exactly one of 'at', 'landmark' or 'line', found {found}")
        tol = self.opt(m, "tolerance", P, self.number, DEFAULTS.target_tolerance, positive=True)
        if "at" in m:
            return Target("point", self.point(m["at"], P + ("at",)), tol)
        if "landmark" in m:
            lid = m["landmark"]
            if isinstance(lid, bool) or not isinstance(lid, (str, int)):
                raise self.fail(P + ("landmark",), f"expected a landmark id, found {_type_name(lid)}")
            lid = str(lid)
            by_id = {lm.id: lm for lm in landmarks}
            if lid not in by_id:
                known = ", ".join(sorted(by_id)) or "none defined"
                raise self.fail(P + ("landmark",), f"names unknown landmark {lid!r} (landmarks: {known})")
            return Target("landmark", by_id[lid].at, tol, landmark=lid)
        line = m["line"]
        if not isinstance(line, list) or len(line) != 2:
            raise self.fail(P + ("line",), f"expected two end points [[x, y], [x, y]], found {_type_name(line)}")
        a, b = self.point(line[0], P + ("line", 0)), self.point(line[1], P + ("line", 1))
        if math.dist(a, b) < 1e-6:
            raise self.fail(P + ("line",), "is degenerate: its two end points coincide")
        return Target("line", ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), tol, line=(a, b))

    def obstacles(self, v: Any) -> tuple[Obstacle, ...]:
        P = ("obstacles",)
        if not isinstance(v, list):
            raise self.fail(P, f"expected a list of obstacles, found {_type_name(v)}")
        out = []
        for i, item in enumerate(v):
            out.append(self.guard(self.obstacle, item, P + (i,)))
        return tuple(o for o in out if o is not None)

    def obstacle(self, v: Any, P: tuple) -> Obstacle:
        m = self.mapping(v, P, (), ("circle", "segment"))
        if len(m) != 1:
            raise self.fail(P, "expected exactly one of 'circle' or 'segment'")
        if "circle" in m:
            c = self.mapping(m["circle"], P + ("circle",), ("center", "radius"), ())
            return Circle(self.point(c["center"], P + ("circle", "center")),
                          self.number(c["radius"], P + ("circle", "radius"), positive=True))
        s = self.mapping(m["segment"], P + ("segment",), ("from", "to"), ("thickness",))
        a = self.point(s["from"], P + ("segment", "from"))
        b = self.point(s["to"], P + ("segment", "to"))
        if math.dist(a, b) < 1e-6:
            raise self.fail(P + ("segment",), "is degenerate: 'from' and 'to' are the same point")
        t = self.opt(s, "thickness", P + ("segment",), self.number, DEFAULTS.segment_thickness, positive=True)
        return Segment(a, b, t)

    def landmarks(self, v: Any) -> tuple[Landmark, ...]:
        P = ("landmarks",)
        if not isinstance(v, list):
            raise self.fail(P, f"expected a list of landmarks, found {_type_name(v)}")
        out: list[Landmark] = []
        seen: dict[str, int] = {}
        for i, item in enumerate(v):
            lm = self.guard(self.landmark, item, P + (i,))
            if lm is None:
                continue
            if lm.id in seen:
                self.fail(P + (i, "id"), f"landmark id {lm.id!r} is already used by landmarks[{seen[lm.id]}]")
                continue
            seen[lm.id] = i
            out.append(lm)
        return tuple(out)

    def landmark(self, v: Any, P: tuple) -> Landmark:
        m = self.mapping(v, P, ("id", "at"), ("radius",))
        lid = m["id"]
        if isinstance(lid, bool) or not isinstance(lid, (str, int)):
            raise self.fail(P + ("id",), f"expected a name, found {_type_name(lid)}")
        return Landmark(str(lid), self.point(m["at"], P + ("at",)),
                        self.opt(m, "radius", P, self.number, DEFAULTS.landmark_radius, positive=True))

    def mission(self, v: Any) -> MissionSpec:
        P = ("mission",)
        m = self.mapping(v, P, (), ("pilot", "time_limit", "seed", "perception"))
        pilot = self.opt(m, "pilot", P, self.text, DEFAULTS.pilot)
        if pilot not in PILOT_NAMES:
            raise self.fail(P + ("pilot",), f"unknown pilot {pilot!r} (expected one of: {', '.join(PILOT_NAMES)})")
        perception = self.opt(m, "perception", P, self.text, DEFAULTS.perception)
        if perception not in PERCEPTIONS:
            raise self.fail(P + ("perception",),
                            f"unknown perception {perception!r} (expected one of: {', '.join(PERCEPTIONS)})")
        return MissionSpec(pilot, self.opt(m, "time_limit", P, self.number, DEFAULTS.time_limit, positive=True),
                           self.opt(m, "seed", P, self.integer, DEFAULTS.seed), perception)

    def noise(self, v: Any) -> Noise:
        P = ("noise",)
        m = self.mapping(v, P, (), ("odometry", "vision_heading_deg", "vision_distance"))
        return Noise(self.opt(m, "odometry", P, self.number, DEFAULTS.odometry_noise, nonneg=True),
                     math.radians(self.opt(m, "vision_heading_deg", P, self.number, DEFAULTS.vision_heading_deg, nonneg=True)),
                     self.opt(m, "vision_distance", P, self.number, DEFAULTS.vision_distance, nonneg=True))

    def camera(self, v: Any) -> CameraSpec:
        P = ("camera",)
        m = self.mapping(v, P, (), ("fov_deg", "range", "pan_limit_deg", "pan_speed_deg", "look_time"))
        fov = self.opt(m, "fov_deg", P, self.number, DEFAULTS.camera_fov_deg, positive=True)
        if fov > 360:
            raise self.fail(P + ("fov_deg",), f"must be at most 360 degrees, found {fov}")
        pan = self.opt(m, "pan_limit_deg", P, self.number, DEFAULTS.camera_pan_limit_deg, nonneg=True)
        if pan > 180:
            raise self.fail(P + ("pan_limit_deg",), f"must be at most 180 degrees, found {pan}")
        return CameraSpec(math.radians(fov), self.opt(m, "range", P, self.number, DEFAULTS.camera_range, positive=True),
                          math.radians(pan),
                          math.radians(self.opt(m, "pan_speed_deg", P, self.number, DEFAULTS.camera_pan_speed_deg,
                                                positive=True)),
                          self.opt(m, "look_time", P, self.number, DEFAULTS.camera_look_time, nonneg=True))

    def pilot(self, v: Any) -> dict[str, float]:
        """The pilot parameters the block sets."""
        P = ("pilot",)
        m = self.mapping(v, P, (), ("K", "A_t", "R_min"))
        return {f"pilot.{k}": self.number(m[k], P + (k,), positive=True) for k in ("K", "A_t", "R_min") if k in m}

    # -- where things are
    def placement(self, sc: Scenario) -> None:
        """Every point inside the arena; the robot's start clear of walls, obstacles, landmarks."""
        W, H = sc.arena.width, sc.arena.height

        def inside(p: Point, path: tuple) -> None:
            if not (0 <= p[0] <= W and 0 <= p[1] <= H):
                self.fail(path, f"point [{p[0]:g}, {p[1]:g}] lies outside the {W:g} m x {H:g} m arena "
                                f"(expected 0 <= x <= {W:g} and 0 <= y <= {H:g})")

        inside(sc.robot.start, ("robot", "start"))
        if sc.target.kind == "point":
            inside(sc.target.point, ("target", "at"))
        elif sc.target.kind == "line":
            for i, p in enumerate(sc.target.line):
                inside(p, ("target", "line", i))
        for i, o in enumerate(sc.obstacles):
            if isinstance(o, Circle):
                inside(o.center, ("obstacles", i, "circle", "center"))
            else:
                inside(o.start, ("obstacles", i, "segment", "from"))
                inside(o.end, ("obstacles", i, "segment", "to"))
        for i, lm in enumerate(sc.landmarks):
            inside(lm.at, ("landmarks", i, "at"))

        s, r = sc.robot.start, sc.params.robot.radius
        P = ("robot", "start")
        if min(s[0], s[1], W - s[0], H - s[1]) < r and not self.problems:
            self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps a wall "
                         f"(expected at least {r:g} m from every wall)")
        for o in sc.objects:
            if o.kind in ("circle", "segment", "landmark") and o.clearance(s) < r:
                what = f"obstacles[{o.key[1:]}]" if o.kind != "landmark" else f"landmark {o.key!r}"
                self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps {what}")
