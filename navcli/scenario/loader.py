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
from ..params import CLUSTERS, DEFAULTS, PERCEPTIONS, PILOT_NAMES, ParamError, Params
from .model import (MAX_ID, MAX_ITEMS, NAME_RE, PILOT_BLOCK, SUPPORTED_VERSIONS, Arena, CameraSpec, Circle, Landmark,
                    MissionSpec, Noise, Obstacle, RobotSpec, Scenario, Segment, Target)
from . import bundled
from .yaml_reader import MAX_BYTES, Invalid, Problem, Reader, ScenarioError, parse_yaml, read_bounded, type_name


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file, or the bundled scenario of that name (a file wins over a
    name: :mod:`~navcli.scenario.bundled`); raise :class:`ScenarioError` on any refusal."""
    file = bundled.resolve(path)
    if not (file.exists() or file.is_symlink()):
        raise ScenarioError([Problem(str(path), None, "", bundled.not_found(path))])
    return parse_scenario(read_bounded(file, MAX_BYTES, "a scenario file", ScenarioError), str(file))


def parse_scenario(text: str, source: str = "<string>") -> Scenario:
    """Validate YAML text as a scenario (``source`` names it in messages)."""
    data, lines = parse_yaml(text, source)
    return ScenarioReader(source, lines).scenario(data, text)



class ScenarioReader(Reader):
    """The typed reader of a scenario: the generic getters, and one method per block of the format."""

    def ident(self, v: Any, path: tuple) -> str:
        """A landmark id: text or a whole number, printable, at most MAX_ID characters."""
        if isinstance(v, bool) or not isinstance(v, (str, int)):
            raise self.fail(path, f"expected a landmark id, found {type_name(v)}")
        s = self.text(str(v), path)
        if not s.strip() or len(s) > MAX_ID or not s.isprintable():
            raise self.fail(path, f"a landmark id is 1 to {MAX_ID} printable characters, found {s[:80]!r}")
        return s

    # -- the blocks
    def scenario(self, d: Any, text: str) -> Scenario:
        try:
            top = self.mapping(d, (), ("version", "name", "arena", "robot", "target"),
                               ("description", "obstacles", "landmarks", "mission", "noise", "camera", "pilot",
                                "navigation"))
        except Invalid:
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
            raise self.fail(("version",), f"expected a whole number, found {type_name(v)}")
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
            raise self.fail(P + ("line",), f"expected two end points [[x, y], [x, y]], found {type_name(line)}")
        a, b = self.point(line[0], P + ("line", 0)), self.point(line[1], P + ("line", 1))
        if math.dist(a, b) < 1e-6:
            raise self.fail(P + ("line",), "is degenerate: its two end points coincide")
        return Target("line", ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), tol, line=(a, b))

    def obstacles(self, v: Any) -> tuple[Obstacle, ...]:
        P = ("obstacles",)
        if not isinstance(v, list):
            raise self.fail(P, f"expected a list of obstacles, found {type_name(v)}")
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
            raise self.fail(P, f"expected a list of landmarks, found {type_name(v)}")
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
        for thing in sc.objects:
            if thing.kind in ("circle", "segment", "landmark") and thing.clearance(s) < r:
                what = f"obstacles[{thing.key[1:]}]" if thing.kind != "landmark" else f"landmark {thing.key!r}"
                self.fail(P, f"the robot (radius {r:g} m) at [{s[0]:g}, {s[1]:g}] overlaps {what}")
