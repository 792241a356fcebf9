"""Scenario files: YAML in, frozen dataclasses out (the scenario format, version 1, in
docs/scenario-format.md).

What is read is bounded before it is built (size, depth, aliases expanded, value length), and
every number is finite and within its documented range (:data:`RANGES`), so that whatever loads
can be simulated.

Every refusal names the file, the line and the field, says what is wrong and what was expected,
so that ``navcli validate`` and ``navcli run`` can print it and exit non-zero without a
traceback. Only PyYAML's safe loader is used. Angles are degrees in YAML (``*_deg``) and radians
in the dataclasses; lengths are metres.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import yaml

from .geometry import Point, distance_to_segment
from .params import CLUSTERS, DEFAULTS, NAVIGATION, PERCEPTIONS, PILOT_NAMES, ParamError, Params

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


def _param_range(name: str, unit: str) -> Range:
    """The range of a parameter a scenario block may set, as declared in :mod:`navcli.params`."""
    group, _, key = name.partition(".")
    m = next(f for f in dataclasses.fields(getattr(Params(), group)) if f.name == key).metadata
    lo, lo_open = (m["above"], True) if m.get("above") is not None else (m["at_least"], False)
    return Range(lo, m["at_most"], unit, lo_open)


PILOT_BLOCK = {"K": "eq. 2: repulsion constant", "A_t": "eq. 5: target attraction",
               "R_min": "metres: prohibited area beyond an obstacle's surface"}
"""The parameters a scenario's ``pilot:`` block sets (each ``pilot.<key>``), with what they are."""

RANGES: dict[str, Range] = {
    "arena.width": Range(1.0, 100.0, "m"),
    "arena.height": Range(1.0, 100.0, "m"),
    "point": Range(0.0, 100.0, "m"),  # any coordinate, before it is checked against the arena
    "robot.heading_deg": Range(-360.0, 360.0, "deg"),
    "robot.radius": _param_range("robot.radius", "m"),
    "robot.max_speed": _param_range("robot.max_speed", "m/s"),
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
    "pilot.K": _param_range("pilot.K", ""),
    "pilot.A_t": _param_range("pilot.A_t", ""),
    "pilot.R_min": _param_range("pilot.R_min", "m"),
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
        shown = [str(p) for p in problems[:MAX_PROBLEMS]]
        if len(problems) > MAX_PROBLEMS:
            shown.append(f"... and {len(problems) - MAX_PROBLEMS} more problems in {problems[0].file}")
        super().__init__("\n".join(shown))


# --- Loading -------------------------------------------------------------------------------
# What the loader reads at most, checked before the YAML is built into values (our design: a
# scenario is a few kilobytes; these bounds are hundreds of times that, and each keeps a hostile
# file from costing more than a fraction of a second or a few megabytes).
MAX_BYTES = 256_000
"""Largest scenario file read (bytes)."""
MAX_DEPTH = 32
"""Deepest nesting of mappings and lists (a scenario needs 5)."""
MAX_NODES = 20_000
"""Most values (keys, items, scalars) in the document, every alias counted as what it expands to,
so an alias bomb is refused before it is expanded."""
MAX_SCALAR = 10_000
"""Longest single value (characters)."""
MAX_DIGITS = 30
"""Longest plain number (characters); a longer one cannot be a seed or a size."""
MAX_PROBLEMS = 20
"""Problems printed for one file; the rest are counted."""
_NOT_YAML_CHARS = re.compile("[^\x09\x0A\x0D\x20-\x7E\x85\xA0-\uD7FF\uE000-\uFFFD\U00010000-\U0010FFFF]")
_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f]")
_SURROGATE = re.compile("[\ud800-\udfff]")
_LONG_NUMBER = re.compile(r"^[-+]?[0-9_.,:]+([eE][-+]?[0-9]+)?$")
_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
"""libyaml's safe loader when PyYAML was built with it (about 10x faster, and its nodes keep
their line); PyYAML's pure-Python safe loader otherwise. Both refuse every ``!!python`` tag."""


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file; raise :class:`ScenarioError` on any refusal."""
    p = Path(path)
    try:
        if p.is_dir():
            raise ScenarioError([Problem(str(p), None, "", "is a folder, expected a scenario file")])
        with p.open("rb") as f:
            data = f.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise ScenarioError([Problem(str(p), None, "", "no such file")]) from None
    except OSError as e:
        raise ScenarioError([Problem(str(p), None, "", f"cannot be read ({e.strerror or e})")]) from None
    if len(data) > MAX_BYTES:
        raise ScenarioError([Problem(str(p), None, "", f"is larger than {MAX_BYTES:,} bytes; a scenario is a few kilobytes")])
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        raise ScenarioError([Problem(str(p), line, "", f"is not UTF-8 text (byte 0x{data[e.start]:02x})")]) from None
    return parse_scenario(text, str(p))


def parse_scenario(text: str, source: str = "<string>") -> Scenario:
    """Validate YAML text as a scenario (``source`` names it in messages)."""
    data, lines = _parse_yaml(text, source)
    return _Reader(source, lines).scenario(data, text)


def _refuse(source: str, line: int | None, message: str, field: str = "") -> ScenarioError:
    return ScenarioError([Problem(source, line, field, message)])


def _bounded(text: str, source: str) -> None:
    """Refuse, before anything is built, a text that breaks one of the bounds above: characters
    YAML forbids, too deep, too many values (aliases expanded), an alias to itself, a value too
    long. One pass over the parser's events: linear in the file, whatever its aliases.

    libyaml has limits of its own: from PyYAML 6.0.4 its scanner refuses about 1,000 levels of
    flow nesting while it looks ahead, before our depth check has seen the events. So when
    libyaml refuses a text, what it read up to its error is read again by PyYAML's pure-Python
    parser, which streams the events: where one of our bounds is broken there, it is reported in
    our words; else libyaml's error is (the cut text's own end is no error of the file)."""
    if len(text) > MAX_BYTES:
        raise _refuse(source, None, f"is larger than {MAX_BYTES:,} characters; a scenario is a few kilobytes")
    bad = _NOT_YAML_CHARS.search(text)
    if bad:
        line = text.count("\n", 0, bad.start()) + 1
        raise _refuse(source, line, f"holds the character U+{ord(bad.group()):04X}, which a YAML file may not hold")
    try:
        _walk_events(_Loader(text), source)
    except yaml.YAMLError as e:
        if _Loader is not yaml.SafeLoader:
            mark = getattr(e, "problem_mark", None) or getattr(e, "context_mark", None)
            read = text[:mark.index + 1] if mark is not None and mark.index is not None else text
            try:
                _walk_events(yaml.SafeLoader(read), source)
            except yaml.YAMLError:
                pass
        if isinstance(e, yaml.MarkedYAMLError):
            raise _yaml_problem(e, source) from None
        raise _refuse(source, None, f"not valid YAML: {e}") from None


def _walk_events(loader: Any, source: str) -> None:
    """The bound pass of :func:`_bounded` with one parser; a bound broken raises
    :class:`ScenarioError`, the parser's own refusal its ``YAMLError``."""
    try:
        depth = nodes = 0
        sizes: dict[str, int] = {}  # anchor -> values it stands for
        open_: list[tuple[str | None, int]] = []  # collections being read: (anchor, nodes before it)
        while loader.check_event():
            ev = loader.get_event()
            line = ev.start_mark.line + 1 if ev.start_mark else None
            if isinstance(ev, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
                depth += 1
                if depth > MAX_DEPTH:
                    raise _refuse(source, line, f"is nested more than {MAX_DEPTH} levels deep")
                open_.append((ev.anchor, nodes))
                nodes += 1
            elif isinstance(ev, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                depth -= 1
                anchor, before = open_.pop()
                if anchor is not None:
                    sizes[anchor] = nodes - before
            elif isinstance(ev, yaml.ScalarEvent):
                if len(ev.value) > MAX_SCALAR:
                    raise _refuse(source, line, f"holds a value of {len(ev.value):,} characters (at most {MAX_SCALAR:,})")
                if not ev.style and len(ev.value) > MAX_DIGITS and _LONG_NUMBER.match(ev.value):
                    raise _refuse(source, line, f"holds a number of {len(ev.value)} characters, too large for any field")
                nodes += 1
                if ev.anchor is not None:
                    sizes[ev.anchor] = 1
            elif isinstance(ev, yaml.AliasEvent):
                if ev.anchor not in sizes:
                    inside = any(a == ev.anchor for a, _ in open_)
                    raise _refuse(source, line, f"the alias *{ev.anchor} " + (
                        "refers to the value that holds it (a loop)" if inside else "names no anchor defined before it"))
                nodes += sizes[ev.anchor]
            if nodes > MAX_NODES:
                raise _refuse(source, line, f"holds more than {MAX_NODES:,} values (aliases expanded)")
    finally:
        loader.dispose()


def _yaml_problem(e: yaml.MarkedYAMLError, source: str) -> ScenarioError:
    mark = e.problem_mark or e.context_mark
    line = mark.line + 1 if mark else None
    what = e.problem or e.context or "malformed"
    if e.problem and e.context and e.context_mark and e.context_mark.line + 1 != line:
        what += f" ({e.context} that began on line {e.context_mark.line + 1})"  # an unclosed [ or { is found at the end
    return _refuse(source, line, f"not valid YAML: {what}")


def _parse_yaml(text: str, source: str) -> tuple[Any, dict[tuple, int]]:
    """Safe-load ``text`` once it is known to be bounded, keeping the line of every key and item
    (1-based)."""
    _bounded(text, source)
    loader = _Loader(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.MarkedYAMLError as e:
        raise _yaml_problem(e, source) from None
    except yaml.YAMLError as e:
        raise _refuse(source, None, f"not valid YAML: {e}") from None
    except ValueError as e:  # a value the constructor cannot build (a date out of range ...)
        raise _refuse(source, None, f"not valid YAML: {e}") from None
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
                if not isinstance(key, str):  # a list or mapping used as a key
                    problems.append(Problem(source, k.start_mark.line + 1, _dotted(path), "a key must be a name"))
                    continue
                if key in seen:
                    problems.append(Problem(source, k.start_mark.line + 1, _dotted(path + (key,)), "appears twice in the same mapping"))
                seen.add(key)
                lines[path + (key,)] = k.start_mark.line + 1
                walk(v, path + (key,))
        elif isinstance(node, yaml.SequenceNode):
            for i, v in enumerate(node.value):
                lines[path + (i,)] = v.start_mark.line + 1
                walk(v, path + (i,))
        elif isinstance(node, yaml.ScalarNode) and not node.style and node.tag in _NUMBER_TAGS:
            hint = _yaml11_number(node.value, data_at(path))
            if hint:
                problems.append(Problem(source, node.start_mark.line + 1, _dotted(path), hint))

    def data_at(path: tuple) -> Any:
        v = data
        for k in path:
            v = v[k]
        return v

    walk(root, ())
    if problems:
        raise ScenarioError(problems)
    return data, lines


_NUMBER_TAGS = ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")
_PLAIN_NUMBER = re.compile(r"^[-+]?(0|[1-9][0-9]*)$|^[-+]?([0-9]+\.[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$"
                           r"|^[-+]?\.(inf|Inf|INF)$|^\.(nan|NaN|NAN)$")
"""The numbers YAML 1.1 and 1.2 read alike: decimal integers without a leading zero, decimal
fractions, infinities and NaN (the last two refused later by the fields' ranges)."""


def _yaml11_number(text: str, value: Any) -> str:
    """Why a plain number written ``text`` is refused, or "": YAML 1.1 (PyYAML's) reads ``010`` as 8
    (octal), ``1:30`` as 90 (base 60), ``0x6`` as 6 and ``6_0`` as 60, where YAML 1.2 and every
    reader of today would read something else or refuse; a scenario must mean one thing (our
    design), so such a number is refused with what to write instead."""
    if _PLAIN_NUMBER.match(text):
        return ""
    t = text.lstrip("+-")
    if ":" in t:
        why = f"YAML 1.1 reads {text} as a base-60 number ({value:g})"
    elif t[:2].lower() in ("0x", "0o", "0b"):
        why = f"{text} is written in base {dict(x=16, o=8, b=2)[t[1].lower()]} ({value:g})"
    elif "_" in t:
        why = f"YAML 1.1 ignores the _ of {text} ({value:g})"
    elif t[:1] == "0" and t[1:2].isdigit():
        why = f"YAML 1.1 reads {text} as octal ({value:g}), YAML 1.2 as {t.lstrip('0') or '0'}"
    else:
        why = f"{text} is not a plain decimal number"
    return f"{why}: write the number plainly in decimal, e.g. {value:g}, or quote it if it is text"


def _dotted(path: tuple) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _number_hint(v: Any) -> str:
    """The YAML 1.1 pitfall: ``1e-3`` (no point, or no sign in the exponent) is text, not a number."""
    if isinstance(v, str):
        try:
            float(v.replace("_", ""))
        except ValueError:
            return ""
        if v.strip().lower() in ("nan", "inf", "-inf", "+inf", "infinity", "-infinity"):
            return ""
        if "e" in v.lower():
            return ("; YAML 1.1 reads a number written like 1e-3 as text: write it with a point and a signed "
                    "exponent, 1.0e-3 or 1.0e+3 (or plainly, 0.001)")
        if v.strip().lstrip("+-")[:1] == "0":
            return f"; write it in decimal without a leading zero ({float(v.replace('_', '')):g}), unquoted"
    return ""


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

    def number(self, v: Any, path: tuple, rng: str | None = None) -> float:
        """A finite number within ``RANGES[rng]``."""
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.fail(path, f"expected a number, found {_type_name(v)}{_number_hint(v)}")
        try:
            f = float(v)
        except OverflowError:
            raise self.fail(path, f"expected a number of sensible size, found one of {len(str(v))} digits") from None
        if not math.isfinite(f):
            raise self.fail(path, f"expected a finite number, found {v}")
        problem = RANGES[rng].problem(f) if rng else None
        if problem:
            raise self.fail(path, problem)
        return f

    def integer(self, v: Any, path: tuple, rng: str) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(path, f"expected a whole number, found {_type_name(v)}")
        r = RANGES[rng]
        if not r.lo <= v <= r.hi:
            raise self.fail(path, f"must be a whole number from {r.lo} to {r.hi} (2**64 - 1), found {v}")
        return v

    def text(self, v: Any, path: tuple) -> str:
        if not isinstance(v, str):
            raise self.fail(path, f"expected text, found {_type_name(v)}")
        if _CONTROL.search(v) or _SURROGATE.search(v):
            raise self.fail(path, f"holds a control character or an unpaired surrogate ({v[:40]!r})")
        return v

    def point(self, v: Any, path: tuple) -> Point:
        if not isinstance(v, list) or len(v) != 2:
            raise self.fail(path, f"expected a point [x, y] in metres, found {_type_name(v)}")
        return (self.number(v[0], path + (0,), "point"), self.number(v[1], path + (1,), "point"))

    def ident(self, v: Any, path: tuple) -> str:
        """A landmark id: text or a whole number, printable, at most MAX_ID characters."""
        if isinstance(v, bool) or not isinstance(v, (str, int)):
            raise self.fail(path, f"expected a landmark id, found {_type_name(v)}")
        s = self.text(str(v), path)
        if not s.strip() or len(s) > MAX_ID or not s.isprintable():
            raise self.fail(path, f"a landmark id is 1 to {MAX_ID} printable characters, found {s[:80]!r}")
        return s

    def opt(self, m: dict, key: str, path: tuple, getter, default, **kw):
        return getter(m[key], path + (key,), **kw) if key in m else default

    # -- the blocks
    def scenario(self, d: Any, text: str) -> Scenario:
        try:
            top = self.mapping(d, (), ("version", "name", "arena", "robot", "target"),
                               ("description", "obstacles", "landmarks", "mission", "noise", "camera", "pilot",
                                "navigation"))
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
        nav_params = g(self.navigation, top.get("navigation", {}), default={})
        if self.problems:
            raise ScenarioError(self.problems)
        params = Params().override(robot_params | pilot_params | nav_params)
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
        if not NAME_RE.fullmatch(s):
            raise self.fail(("name",), f"{s[:80]!r} may hold only a-z, 0-9 and '-', 1 to 64 of them (it names log files)")
        return s

    def arena(self, v: Any) -> Arena:
        m = self.mapping(v, ("arena",), ("width", "height"), ())
        w = self.number(m["width"], ("arena", "width"), "arena.width")
        h = self.number(m["height"], ("arena", "height"), "arena.height")
        return Arena(w, h)

    def robot(self, v: Any) -> tuple[RobotSpec, dict[str, float]]:
        """The start, and the robot parameters the block sets (``radius``, ``max_speed``)."""
        P = ("robot",)
        m = self.mapping(v, P, ("start",), ("heading_deg", "radius", "max_speed"))
        spec = RobotSpec(start=self.point(m["start"], P + ("start",)),
                         heading=math.radians(self.opt(m, "heading_deg", P, self.number, DEFAULTS.heading_deg,
                                                       rng="robot.heading_deg")))
        return spec, {f"robot.{k}": self.number(m[k], P + (k,), f"robot.{k}") for k in ("radius", "max_speed") if k in m}

    def target(self, v: Any, landmarks: tuple[Landmark, ...]) -> Target:
        P = ("target",)
        m = self.mapping(v, P, (), ("at", "landmark", "line", "tolerance"))
        forms = [k for k in ("at", "landmark", "line") if k in m]
        if len(forms) != 1:
            found = " and ".join(forms) if forms else "none"
            raise self.fail(P, f"needs exactly one of 'at', 'landmark' or 'line', found {found}")
        tol = self.opt(m, "tolerance", P, self.number, DEFAULTS.target_tolerance, rng="target.tolerance")
        if "at" in m:
            return Target("point", self.point(m["at"], P + ("at",)), tol)
        if "landmark" in m:
            lid = self.ident(m["landmark"], P + ("landmark",))
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
        if len(v) > MAX_ITEMS:
            raise self.fail(P, f"holds {len(v)} obstacles, at most {MAX_ITEMS}")
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
                          self.number(c["radius"], P + ("circle", "radius"), "circle.radius"))
        s = self.mapping(m["segment"], P + ("segment",), ("from", "to"), ("thickness",))
        a = self.point(s["from"], P + ("segment", "from"))
        b = self.point(s["to"], P + ("segment", "to"))
        if math.dist(a, b) < 1e-6:
            raise self.fail(P + ("segment",), "is degenerate: 'from' and 'to' are the same point")
        t = self.opt(s, "thickness", P + ("segment",), self.number, DEFAULTS.segment_thickness, rng="segment.thickness")
        return Segment(a, b, t)

    def landmarks(self, v: Any) -> tuple[Landmark, ...]:
        P = ("landmarks",)
        if not isinstance(v, list):
            raise self.fail(P, f"expected a list of landmarks, found {_type_name(v)}")
        if len(v) > MAX_ITEMS:
            raise self.fail(P, f"holds {len(v)} landmarks, at most {MAX_ITEMS}")
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
        return Landmark(self.ident(m["id"], P + ("id",)), self.point(m["at"], P + ("at",)),
                        self.opt(m, "radius", P, self.number, DEFAULTS.landmark_radius, rng="landmark.radius"))

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
        return MissionSpec(pilot, self.opt(m, "time_limit", P, self.number, DEFAULTS.time_limit, rng="mission.time_limit"),
                           self.opt(m, "seed", P, self.integer, DEFAULTS.seed, rng="mission.seed"), perception)

    def noise(self, v: Any) -> Noise:
        P = ("noise",)
        m = self.mapping(v, P, (), ("odometry", "odometry_drift_deg_per_m", "vision_heading_deg", "vision_distance"))
        def get(key: str, default: float) -> float:
            return self.opt(m, key, P, self.number, default, rng=f"noise.{key}")

        return Noise(get("odometry", DEFAULTS.odometry_noise),
                     math.radians(get("vision_heading_deg", DEFAULTS.vision_heading_deg)),
                     get("vision_distance", DEFAULTS.vision_distance),
                     math.radians(get("odometry_drift_deg_per_m", 0.0)))

    def camera(self, v: Any) -> CameraSpec:
        P = ("camera",)
        m = self.mapping(v, P, (), ("fov_deg", "range", "pan_limit_deg", "pan_speed_deg", "look_time"))
        def get(key: str, default: float) -> float:
            return self.opt(m, key, P, self.number, default, rng=f"camera.{key}")

        return CameraSpec(math.radians(get("fov_deg", DEFAULTS.camera_fov_deg)), get("range", DEFAULTS.camera_range),
                          math.radians(get("pan_limit_deg", DEFAULTS.camera_pan_limit_deg)),
                          math.radians(get("pan_speed_deg", DEFAULTS.camera_pan_speed_deg)),
                          get("look_time", DEFAULTS.camera_look_time))

    def pilot(self, v: Any) -> dict[str, float]:
        """The pilot parameters the block sets."""
        P = ("pilot",)
        m = self.mapping(v, P, (), tuple(PILOT_BLOCK))
        return {f"pilot.{k}": self.number(m[k], P + (k,), f"pilot.{k}") for k in PILOT_BLOCK if k in m}

    def navigation(self, v: Any) -> dict[str, float]:
        """The Navigation system's parameters the block sets: ``cluster`` (``C1``, the default, or
        ``C2``: the thesis' GA-tuned sets, Table 5.2) and any of ``navigation.*`` by name, checked
        against its declared range."""
        P = ("navigation",)
        fields = {k: v for k, v in Params().flat().items() if k.startswith("navigation.") and not isinstance(v, list)}
        names = tuple(k.partition(".")[2] for k in fields)
        m = self.mapping(v, P, (), ("cluster",) + names)
        out: dict[str, float] = {}
        if "cluster" in m:
            c = self.text(m["cluster"], P + ("cluster",))
            if c not in CLUSTERS:
                raise self.fail(P + ("cluster",), f"unknown cluster {c!r} (expected one of: {', '.join(CLUSTERS)})")
            out = {f"navigation.{k}": x for k, x in dataclasses.asdict(CLUSTERS[c]).items() if not isinstance(x, tuple)}
        for k in names:
            if k in m:
                value = self.number(m[k], P + (k,))
                try:
                    Params().override({f"navigation.{k}": value})
                except ParamError as e:
                    raise self.fail(P + (k,), str(e).partition(" ")[2] or str(e)) from None
                out[f"navigation.{k}"] = value
        return out

    # -- where things are
    def reachable(self, sc: Scenario) -> None:
        """A point or landmark target the robot's centre can come within reach of: one obstacle
        (or wall) alone must not keep the robot's body from it. The robot's centre keeps ``r``
        from a surface, so a target whose clearance ``c`` to a convex thing is below ``r - reach``
        can never be reached (the whole room is not searched: that is the mission's job). The
        reach is the tolerance; for a landmark, also its radius and the robot's (the mission's
        rule). A landmark target whose centre lies inside an obstacle is refused as well (our
        design: a landmark is seen on a free surface; one buried in a wall is a typing slip)."""
        t = sc.target
        if t.kind == "line":
            return
        r, p = sc.params.robot.radius, t.point
        W, H = sc.arena.width, sc.arena.height
        reach = t.tolerance
        if t.kind == "landmark":
            reach += next(lm.radius for lm in sc.landmarks if lm.id == t.landmark) + r
        P = ("target", "at") if t.kind == "point" else ("target", "landmark")
        name = f"[{p[0]:g}, {p[1]:g}]" if t.kind == "point" else f"landmark {t.landmark!r}"
        if min(p[0], p[1], W - p[0], H - p[1]) < r - reach:
            self.fail(P, f"the target {name} is too close to a wall: the robot (radius {r:g} m) "
                         f"cannot come within its reach ({reach:g} m)")
        for o in sc.objects:
            if o.kind not in ("circle", "segment", "landmark") or (o.kind == "landmark" and o.key == t.landmark):
                continue
            c = o.clearance(p)
            if c < r - reach or (t.kind == "landmark" and c < 0):
                what = f"obstacles[{o.key[1:]}]" if o.kind != "landmark" else f"landmark {o.key!r}"
                inside = "lies inside" if c < 0 else "is too close to"
                self.fail(P, f"the target {name} {inside} {what}: the robot (radius {r:g} m) cannot "
                             f"come within its reach ({reach:g} m)")

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
        if self.problems:
            return

        def within_walls(p: Point, radius: float, path: tuple, what: str) -> None:
            out = -min(p[0], p[1], W - p[0], H - p[1]) + radius
            if out > 1e-9:
                self.fail(path, f"{what} of radius {radius:g} m at [{p[0]:g}, {p[1]:g}] sticks {out:.3g} m through "
                                f"a wall (expected at least {radius:g} m from every wall)")

        for i, o in enumerate(sc.obstacles):
            if isinstance(o, Circle):
                within_walls(o.center, o.radius, ("obstacles", i, "circle", "center"), "the circle")
        for i, lm in enumerate(sc.landmarks):
            within_walls(lm.at, lm.radius, ("landmarks", i, "at"), "the landmark")
        self.reachable(sc)

        s, r = sc.robot.start, sc.params.robot.radius
        P = ("robot", "start")
        if min(s[0], s[1], W - s[0], H - s[1]) < r and not self.problems:
            self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps a wall "
                         f"(expected at least {r:g} m from every wall)")
        for o in sc.objects:
            if o.kind in ("circle", "segment", "landmark") and o.clearance(s) < r:
                what = f"obstacles[{o.key[1:]}]" if o.kind != "landmark" else f"landmark {o.key!r}"
                self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps {what}")


# --- The format as a JSON Schema (for editors: the YAML language server) ---------------------
def _param_schema(f: dataclasses.Field) -> dict[str, Any]:
    """A parameter's JSON Schema from its declared range (:func:`navcli.params._p`)."""
    m = f.metadata
    d: dict[str, Any] = {"type": "integer" if isinstance(f.default, int) else "number", "default": f.default}
    if m.get("above") is not None:
        d["exclusiveMinimum"] = m["above"]
    elif m.get("at_least") is not None:
        d["minimum"] = m["at_least"]
    if m.get("at_most") is not None:
        d["maximum"] = m["at_most"]
    if m.get("below") is not None:
        d["exclusiveMaximum"] = m["below"]
    return d



def json_schema() -> dict[str, Any]:
    """The scenario format as a JSON Schema (draft-07), built from the same ranges the loader
    checks. It catches what a schema can (fields, types, ranges, names); where things are
    (inside the arena, clear of obstacles, a reachable target) only the loader checks."""

    def num(key: str, description: str) -> dict:
        r = RANGES[key]
        d: dict[str, Any] = {"type": "number", "description": description, "maximum": r.hi}
        d["exclusiveMinimum" if r.lo_open else "minimum"] = r.lo
        return d

    def obj(props: dict, required: tuple[str, ...] = (), description: str = "") -> dict:
        d = {"type": "object", "properties": props, "additionalProperties": False, "required": list(required)}
        return d | ({"description": description} if description else {})

    point = {"type": "array", "description": "[x, y] in metres, inside the arena", "minItems": 2, "maxItems": 2,
             "items": num("point", "metres")}
    ident = {"type": ["string", "integer"], "description": "a landmark id", "minLength": 1, "maxLength": MAX_ID}
    target = obj({"at": point, "landmark": ident,
                  "line": {"type": "array", "minItems": 2, "maxItems": 2, "items": point,
                           "description": "a diverting target: the line to cross"},
                  "tolerance": num("target.tolerance", "metres: how close to a point target counts as reached")},
                 description="exactly one of at, landmark, line")
    target["oneOf"] = [{"required": [k]} for k in ("at", "landmark", "line")]
    return {
        "$schema": "http://json-schema.org/draft-07/schema#",
        "$id": "https://navcli/scenario-v1.schema.json",
        "title": "navcli scenario, version 1",
        "description": "Metres, seconds, degrees in keys ending _deg. Write exponents with a point and a sign "
                       "(1.0e-3): YAML 1.1 reads 1e-3 as text.",
        **obj({
            "version": {"const": 1},
            "name": {"type": "string", "pattern": f"^{NAME_RE.pattern}$", "not": {"pattern": "\n"},  # no trailing newline
                     "description": "names the log folder"},
            "description": {"type": "string", "maxLength": MAX_SCALAR},
            "arena": obj({"width": num("arena.width", "metres"), "height": num("arena.height", "metres")},
                         ("width", "height")),
            "robot": obj({"start": point, "heading_deg": num("robot.heading_deg", "degrees, counter-clockwise from +x"),
                          "radius": num("robot.radius", "metres"), "max_speed": num("robot.max_speed", "m/s")},
                         ("start",)),
            "target": target,
            "obstacles": {"type": "array", "maxItems": MAX_ITEMS, "items": {"oneOf": [
                obj({"circle": obj({"center": point, "radius": num("circle.radius", "metres")},
                                   ("center", "radius"))}, ("circle",)),
                obj({"segment": obj({"from": point, "to": point,
                                     "thickness": num("segment.thickness", "metres")}, ("from", "to"))},
                    ("segment",))]}},
            "landmarks": {"type": "array", "maxItems": MAX_ITEMS, "items": obj(
                {"id": ident, "at": point, "radius": num("landmark.radius", "metres")}, ("id", "at"))},
            "mission": obj({"pilot": {"enum": list(PILOT_NAMES)}, "perception": {"enum": list(PERCEPTIONS)},
                            "time_limit": num("mission.time_limit", "simulated seconds"),
                            "seed": {"type": "integer", "minimum": 0, "maximum": 2 ** 64 - 1}}),
            "noise": obj({"odometry": num("noise.odometry", "relative standard deviation"),
                          "odometry_drift_deg_per_m": num("noise.odometry_drift_deg_per_m",
                                                          "degrees of heading drift per metre driven, standard deviation"),
                          "vision_heading_deg": num("noise.vision_heading_deg", "degrees, standard deviation"),
                          "vision_distance": num("noise.vision_distance", "relative standard deviation")}),
            "camera": obj({k: num(f"camera.{k}", u) for k, u in (
                ("fov_deg", "degrees"), ("range", "metres"), ("pan_limit_deg", "degrees either side of ahead"),
                ("pan_speed_deg", "degrees per second"), ("look_time", "seconds of processing per look"))}),
            "pilot": obj({k: num(f"pilot.{k}", what) for k, what in PILOT_BLOCK.items()}),
            "navigation": obj({"cluster": {"enum": list(CLUSTERS), "description": "the thesis' GA-tuned bidding "
                                           "parameters: C1 (default, targets reachable directly) or C2 (behind obstacles)"}}
                              | {f.name: _param_schema(f) for f in dataclasses.fields(NAVIGATION)
                                 if not isinstance(f.default, tuple)}),
        }, ("version", "name", "arena", "robot", "target")),
    }
