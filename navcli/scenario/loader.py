"""Scenario files read into the model: every number finite and within its documented range
(:data:`~navcli.scenario.model.RANGES`), every object inside the arena and clear of the robot's
start, the target reachable, so that whatever loads can be simulated.

Every refusal names the file, the line and the field, says what is wrong and what was expected,
so that ``navcli validate`` and ``navcli run`` can print it and exit non-zero without a
traceback.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

from ..geometry import Point
from .. import NavcliError
from ..checks.arguments import checked, path, text
from ..params import CLUSTERS, NavigationParams, ParamError, Params
from ..plugins import registry
from .model import (
    FIELDS,
    MAX_ID,
    MAX_ITEMS,
    NAME_RE,
    SUPPORTED_VERSIONS,
    Arena,
    CameraSpec,
    Circle,
    Landmark,
    MissionSpec,
    Noise,
    Obstacle,
    RobotSpec,
    Scenario,
    Segment,
    Target,
)
from . import bundled
from .yaml_reader import MAX_BYTES, Invalid, Problem, Reader, ScenarioError, parse_yaml, read_bounded, type_name


def _words(v: Any) -> str | None:
    """A scenario's text: a ``str`` (empty is the loader's to refuse, with its line)."""
    return None if isinstance(v, str) else f"expected the YAML text (a str), got {type(v).__name__}"


ARGUMENTS = {"path": path, "text": _words, "source": text}
"""The arguments of :func:`load_scenario` and :func:`parse_scenario`, checked at each call."""


@checked(ARGUMENTS)
def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario.

    Args:
        path: a scenario file, or the name of a bundled scenario (a file wins over a name:
            :mod:`~navcli.scenario.bundled`).

    Returns:
        The scenario.

    Raises:
        ScenarioError: every problem found, each with its place in the file.
    """
    file = bundled.resolve(path)
    if not (file.exists() or file.is_symlink()):
        raise ScenarioError([Problem(str(path), None, "", bundled.not_found(path))])
    return parse_scenario(read_bounded(file, MAX_BYTES, "a scenario file", ScenarioError), str(file))


@checked(ARGUMENTS)
def parse_scenario(text: str, source: str = "<string>") -> Scenario:
    """Validate YAML text as a scenario.

    Args:
        text: the scenario's YAML.
        source: what names it in messages (a file's path).

    Returns:
        The scenario.

    Raises:
        ScenarioError: every problem found, each with its place in the text.
    """
    data, lines = parse_yaml(text, source)
    return ScenarioReader(source, lines).scenario(data, text)


class ScenarioReader(Reader):
    """The typed reader of a scenario: the generic getters, and one method per block of the format."""

    named_navigation: frozenset[str] = frozenset()  # the navigation parameters the file names (not through a cluster)

    def ident(self, v: Any, path: tuple) -> str:
        """A landmark id: text or a whole number, printable, at most MAX_ID characters."""
        if isinstance(v, bool) or not isinstance(v, (str, int)):
            raise self.fail(path, f"expected a landmark id, found {type_name(v)}")
        s = self.text(str(v), path)
        if not s.strip() or len(s) > MAX_ID or not s.isprintable():
            raise self.fail(path, f"a landmark id is 1 to {MAX_ID} printable characters, found {s[:80]!r}")
        return s

    def block(self, v: Any, name: str, path: tuple) -> dict:
        """The mapping of the block ``name`` at ``path``: every required field of it there, no field
        the format does not declare (:data:`~navcli.scenario.model.FIELDS`)."""
        fields = FIELDS[name]
        return self.mapping(
            v,
            path,
            tuple(k for k, f in fields.items() if f.required),
            tuple(k for k, f in fields.items() if not f.required),
        )

    def field(self, m: dict, block: str, key: str, path: tuple) -> Any:
        """Field ``key`` of the block ``block`` read from the mapping ``m`` (at ``path``) as its
        declaration says (its kind, its range), or its default when absent."""
        f = FIELDS[block][key]
        if key not in m:
            return f.default
        v, at = m[key], path + (key,)
        if f.kind in ("number", "param"):
            return self.number(v, at, f"{block}.{key}" if f.range is not None else None)
        if f.kind == "integer":
            return self.integer(v, at, f"{block}.{key}")
        if f.kind == "point":
            return self.point(v, at)
        if f.kind == "id":
            return self.ident(v, at)
        text = self.text(v, at)
        if f.kind == "choice" and text not in f.choices:
            raise self.fail(at, f"unknown {key} {text!r} (expected one of: {', '.join(f.choices)})")
        return text

    # -- the blocks
    def scenario(self, d: Any, text: str) -> Scenario:
        try:
            top = self.block(d, "scenario", ())
        except Invalid:
            raise ScenarioError(self.problems) from None
        g = self.guard
        default = {k: f.default for k, f in FIELDS["scenario"].items()}
        version = g(self.version, top["version"])
        name = g(self.name, top["name"])
        description = g(self.field, top, "scenario", "description", (), default="")
        arena = g(self.arena, top["arena"])
        robot, robot_params = g(self.robot, top["robot"], default=(None, {}))
        landmarks = g(self.landmarks, top.get("landmarks", default["landmarks"]), default=())
        target = g(self.target, top["target"], landmarks or ())
        obstacles = g(self.obstacles, top.get("obstacles", default["obstacles"]), default=())
        mission = g(self.mission, top.get("mission", default["mission"]))
        noise, noise_params = g(self.noise, top.get("noise", default["noise"]), default=(None, {}))
        camera = g(self.camera, top.get("camera", default["camera"]))
        pilot_params = g(self.pilot, top.get("pilot", default["pilot"]), default={})
        nav_params = g(self.navigation, top.get("navigation", default["navigation"]), default={})
        if self.problems:
            raise ScenarioError(self.problems)
        params = Params().override(robot_params | noise_params | pilot_params | nav_params)
        defaults = (
            Params().flat()
        )  # a cluster sets every bidding parameter: those it leaves at navcli's are not the file's
        named = set(robot_params) | set(noise_params) | set(pilot_params) | self.named_navigation
        given = frozenset(
            k
            for k, v in (robot_params | noise_params | pilot_params | nav_params).items()
            if k in named or defaults[k] != v
        )
        sc = Scenario(
            version, name, description, arena, robot, target, obstacles, landmarks, mission, noise, camera, params
        )
        self.placement(sc)
        if self.problems:
            raise ScenarioError(self.problems)
        return Scenario(
            version,
            name,
            description,
            arena,
            robot,
            target,
            obstacles,
            landmarks,
            mission,
            noise,
            camera,
            params,
            source=self.source,
            text=text,
            given=given,
        )

    def version(self, v: Any) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(("version",), f"expected a whole number, found {type_name(v)}")
        if v not in SUPPORTED_VERSIONS:
            raise self.fail(("version",), f"unsupported version {v} (this navcli reads version 1)")
        return v

    def name(self, v: Any) -> str:
        s = self.text(v, ("name",))
        if not NAME_RE.fullmatch(s):
            raise self.fail(
                ("name",), f"{s[:80]!r} may hold only a-z, 0-9 and '-', 1 to 64 of them (it names log files)"
            )
        return s

    def arena(self, v: Any) -> Arena:
        P = ("arena",)
        m = self.block(v, "arena", P)
        return Arena(self.field(m, "arena", "width", P), self.field(m, "arena", "height", P))

    def robot(self, v: Any) -> tuple[RobotSpec, dict[str, float]]:
        """The start, and the robot parameters the block sets (``radius``, ``max_speed``)."""
        P = ("robot",)
        m = self.block(v, "robot", P)
        spec = RobotSpec(
            start=self.field(m, "robot", "start", P), heading=math.radians(self.field(m, "robot", "heading_deg", P))
        )
        return spec, self.params_of(m, "robot", P)

    def params_of(self, m: dict, block: str, path: tuple) -> dict[str, float]:
        """The parameters the block ``block`` sets (its fields of kind ``param``), by their names."""
        return {
            f.param: self.field(m, block, k, path) for k, f in FIELDS[block].items() if f.kind == "param" and k in m
        }

    def target(self, v: Any, landmarks: tuple[Landmark, ...]) -> Target:
        P = ("target",)
        m = self.block(v, "target", P)
        forms = [k for k in ("at", "landmark", "line") if k in m]
        if len(forms) != 1:
            found = " and ".join(forms) if forms else "none"
            raise self.fail(P, f"needs exactly one of 'at', 'landmark' or 'line', found {found}")
        tol = self.field(m, "target", "tolerance", P)
        if "at" in m:
            return Target("point", self.field(m, "target", "at", P), tol)
        if "landmark" in m:
            lid = self.field(m, "target", "landmark", P)
            by_id = {lm.id: lm for lm in landmarks}
            if lid not in by_id:
                known = ", ".join(sorted(by_id)) or "none defined"
                raise self.fail(P + ("landmark",), f"names unknown landmark {lid!r} (landmarks: {known})")
            return Target("landmark", by_id[lid].at, tol, landmark=lid)
        line = m["line"]
        if not isinstance(line, list) or len(line) != 2:
            raise self.fail(P + ("line",), f"expected two end points [[x, y], [x, y]], found {type_name(line)}")
        a, b = self.point(line[0], P + ("line", 0)), self.point(line[1], P + ("line", 1))
        if math.dist(a, b) < 1e-6:
            raise self.fail(P + ("line",), "is degenerate: its two end points coincide")
        return Target("line", ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), tol, line=(a, b))

    def obstacles(self, v: Any) -> tuple[Obstacle, ...]:
        return tuple(o for o in self.items(v, "obstacles", self.obstacle) if o is not None)

    def items(self, v: Any, name: str, read: Any) -> list:
        """The list ``name`` (obstacles, landmarks): at most MAX_ITEMS, each item read by ``read``
        (None where it was refused, so every item's problems show)."""
        P = (name,)
        if not isinstance(v, (list, tuple)):  # a tuple: the declared default, none
            raise self.fail(P, f"expected a list of {name}, found {type_name(v)}")
        if len(v) > MAX_ITEMS:
            raise self.fail(P, f"holds {len(v)} {name}, at most {MAX_ITEMS}")
        return [self.guard(read, item, P + (i,)) for i, item in enumerate(v)]

    def obstacle(self, v: Any, P: tuple) -> Obstacle:
        m = self.mapping(v, P, (), ("circle", "segment"))
        if len(m) != 1:
            raise self.fail(P, "expected exactly one of 'circle' or 'segment'")
        if "circle" in m:
            Q = P + ("circle",)
            c = self.block(m["circle"], "circle", Q)
            return Circle(self.field(c, "circle", "center", Q), self.field(c, "circle", "radius", Q))
        Q = P + ("segment",)
        s = self.block(m["segment"], "segment", Q)
        a, b = self.field(s, "segment", "from", Q), self.field(s, "segment", "to", Q)
        if math.dist(a, b) < 1e-6:
            raise self.fail(Q, "is degenerate: 'from' and 'to' are the same point")
        return Segment(a, b, self.field(s, "segment", "thickness", Q))

    def landmarks(self, v: Any) -> tuple[Landmark, ...]:
        out: list[Landmark] = []
        seen: dict[str, int] = {}
        for i, lm in enumerate(self.items(v, "landmarks", self.landmark)):
            if lm is None:
                continue
            if lm.id in seen:
                self.fail(("landmarks", i, "id"), f"landmark id {lm.id!r} is already used by landmarks[{seen[lm.id]}]")
                continue
            seen[lm.id] = i
            out.append(lm)
        return tuple(out)

    def landmark(self, v: Any, P: tuple) -> Landmark:
        m = self.block(v, "landmark", P)
        return Landmark(*(self.field(m, "landmark", k, P) for k in ("id", "at", "radius")))

    def mission(self, v: Any) -> MissionSpec:
        P = ("mission",)
        m = self.block(v, "mission", P)
        pilot = self.field(m, "mission", "pilot", P)
        try:
            registry.pilot(pilot)  # any form of plugins.names
        except NavcliError as e:
            raise self.fail(P + ("pilot",), str(e)) from None
        return MissionSpec(pilot, *(self.field(m, "mission", k, P) for k in ("time_limit", "seed", "perception")))

    def noise(self, v: Any) -> tuple[Noise, dict[str, float]]:
        """The sensors' errors, and the parameters the block sets (``slip``, the wheels')."""
        P = ("noise",)
        m = self.block(v, "noise", P)
        get = {k: self.field(m, "noise", k, P) for k, f in FIELDS["noise"].items() if f.kind != "param"}
        noise = Noise(
            get["odometry"],
            math.radians(get["vision_heading_deg"]),
            get["vision_distance"],
            math.radians(get["odometry_drift_deg_per_m"]),
        )
        return noise, self.params_of(m, "noise", P)

    def camera(self, v: Any) -> CameraSpec:
        P = ("camera",)
        m = self.block(v, "camera", P)
        get = {k: self.field(m, "camera", k, P) for k in FIELDS["camera"]}
        return CameraSpec(
            math.radians(get["fov_deg"]),
            get["range"],
            math.radians(get["pan_limit_deg"]),
            math.radians(get["pan_speed_deg"]),
            get["look_time"],
        )

    def pilot(self, v: Any) -> dict[str, float]:
        """The pilot parameters the block sets."""
        return self.params_of(self.block(v, "pilot", ("pilot",)), "pilot", ("pilot",))

    def navigation(self, v: Any) -> dict[str, Any]:
        """The Navigation system's parameters the block sets: ``cluster`` (``C1``, the default, or
        ``C2``: the thesis' GA-tuned sets, Table 5.2) and any of ``navigation.*`` by name, checked
        against its declaration (a switch is true or false)."""
        P = ("navigation",)
        decls = {k: d for k, d, _ in NavigationParams.declarations() if d.kind not in ("numbers", "intervals")}
        m = self.mapping(v, P, (), ("cluster",) + tuple(decls))
        self.named_navigation = frozenset(f"navigation.{k}" for k in decls if k in m)
        out: dict[str, Any] = {}
        if "cluster" in m:
            c = self.text(m["cluster"], P + ("cluster",))
            if c not in CLUSTERS:
                raise self.fail(P + ("cluster",), f"unknown cluster {c!r} (expected one of: {', '.join(CLUSTERS)})")
            out = {f"navigation.{k}": x for k, x in dataclasses.asdict(CLUSTERS[c]).items() if not isinstance(x, tuple)}
        for k, d in decls.items():
            if k in m:
                raw = m[k]
                value = raw if d.kind == "switch" and isinstance(raw, bool) else self.number(raw, P + (k,))
                try:
                    out[f"navigation.{k}"] = d.check(f"navigation.{k}", value)
                except ParamError as e:
                    raise self.fail(P + (k,), str(e).partition(" ")[2] or str(e)) from None
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
            self.fail(
                P,
                f"the target {name} is too close to a wall: the robot (radius {r:g} m) "
                f"cannot come within its reach ({reach:g} m)",
            )
        for o in sc.objects:
            if o.kind not in ("circle", "segment", "landmark") or (o.kind == "landmark" and o.key == t.landmark):
                continue
            c = o.clearance(p)
            if c < r - reach or (t.kind == "landmark" and c < 0):
                what = f"obstacles[{o.key[1:]}]" if o.kind != "landmark" else f"landmark {o.key!r}"
                inside = "lies inside" if c < 0 else "is too close to"
                self.fail(
                    P,
                    f"the target {name} {inside} {what}: the robot (radius {r:g} m) cannot "
                    f"come within its reach ({reach:g} m)",
                )

    def placement(self, sc: Scenario) -> None:
        """Every point inside the arena; the robot's start clear of walls, obstacles, landmarks."""
        self.points_inside(sc)
        if self.problems:
            return
        self.shapes_within_walls(sc)
        self.reachable(sc)
        self.start_clear(sc)

    def points_inside(self, sc: Scenario) -> None:
        """Every point the scenario gives (start, target, obstacles, landmarks) inside the arena."""
        W, H = sc.arena.width, sc.arena.height

        def inside(p: Point, path: tuple) -> None:
            if not (0 <= p[0] <= W and 0 <= p[1] <= H):
                self.fail(
                    path,
                    f"point [{p[0]:g}, {p[1]:g}] lies outside the {W:g} m x {H:g} m arena "
                    f"(expected 0 <= x <= {W:g} and 0 <= y <= {H:g})",
                )

        inside(sc.robot.start, ("robot", "start"))
        if sc.target.kind == "point":
            inside(sc.target.point, ("target", "at"))
        elif sc.target.kind == "line":
            for i, p in enumerate(sc.target.line or ()):
                inside(p, ("target", "line", i))
        for i, o in enumerate(sc.obstacles):
            if isinstance(o, Circle):
                inside(o.center, ("obstacles", i, "circle", "center"))
            else:
                inside(o.start, ("obstacles", i, "segment", "from"))
                inside(o.end, ("obstacles", i, "segment", "to"))
        for i, lm in enumerate(sc.landmarks):
            inside(lm.at, ("landmarks", i, "at"))

    def shapes_within_walls(self, sc: Scenario) -> None:
        """Every circle and landmark whole inside the walls, not only its centre."""
        W, H = sc.arena.width, sc.arena.height

        def within_walls(p: Point, radius: float, path: tuple, what: str) -> None:
            out = -min(p[0], p[1], W - p[0], H - p[1]) + radius
            if out > 1e-9:
                self.fail(
                    path,
                    f"{what} of radius {radius:g} m at [{p[0]:g}, {p[1]:g}] sticks {out:.3g} m through "
                    f"a wall (expected at least {radius:g} m from every wall)",
                )

        for i, o in enumerate(sc.obstacles):
            if isinstance(o, Circle):
                within_walls(o.center, o.radius, ("obstacles", i, "circle", "center"), "the circle")
        for i, lm in enumerate(sc.landmarks):
            within_walls(lm.at, lm.radius, ("landmarks", i, "at"), "the landmark")

    def start_clear(self, sc: Scenario) -> None:
        """The robot's start at least its radius from every wall, obstacle and landmark."""
        W, H = sc.arena.width, sc.arena.height
        s, r = sc.robot.start, sc.params.robot.radius
        P = ("robot", "start")
        if min(s[0], s[1], W - s[0], H - s[1]) < r and not self.problems:
            self.fail(
                P,
                f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps a wall "
                f"(expected at least {r:g} m from every wall)",
            )
        for thing in sc.objects:
            if thing.kind in ("circle", "segment", "landmark") and thing.clearance(s) < r:
                what = f"obstacles[{thing.key[1:]}]" if thing.kind != "landmark" else f"landmark {thing.key!r}"
                self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps {what}")
