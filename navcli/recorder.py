"""The recorder: the only writer of navcli's log format (the README's "The log").

One MCAP file per run, written with Foxglove's SDK so Foxglove's 3D, Plot and Log panels read it
by schema name. Log time is simulation time (integer nanoseconds from the start); no wall clock
reaches the file. The file is written under ``<name>.partial`` and renamed when closed, so a
finished name is always a complete file; a run ended by Ctrl-C or an error still closes its file
properly, with a summary whose outcome says ``interrupted`` or ``error`` and why.

The JSON messages and their schemas are defined once, in :mod:`navcli.messages`. State a viewer
needs at any time (the arena, the robot's body, the camera's field of view) has topics of its own,
republished every ``params.SCENE_REFRESH`` s (see :meth:`Recorder._state`).

With ``live`` the same Foxglove context also feeds a WebSocket server on localhost, which
advertises the time capability and broadcasts simulation time every tick.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

import foxglove
import msgspec
from foxglove.websocket import Capability
from foxglove.channels import FrameTransformsChannel, LogChannel, PoseInFrameChannel, SceneUpdateChannel
from foxglove.messages import (
    ArrowPrimitive,
    Color,
    CubePrimitive,
    CylinderPrimitive,
    FrameTransform,
    FrameTransforms,
    LinePrimitive,
    LinePrimitiveLineType,
    Log,
    LogLevel,
    Point3,
    Pose as FxPose,
    PoseInFrame,
    Quaternion,
    SceneEntity,
    SceneEntityDeletion,
    SceneEntityDeletionType,
    SceneUpdate,
    TextPrimitive,
    Timestamp,
    Vector3,
)

from .bidding import RESOURCES
from .messages import Action, Bids, DetectionMsg, MissionSummary, Pilot, ResourceBids, Vision, encode, json_schema, pilot_message
from .params import SCENE_REFRESH
from .scenario import Scenario

if TYPE_CHECKING:
    from .config import RunSpec
    from .geometry import Pose
    from .mission import Event, Tick
    from .vision.visual_memory import Remembered

GROWN_REFRESH_NS = 1_000_000_000  # grown obstacles are redrawn on change, or every simulated second
ARROW_MIN = 2.0  # force units: weaker forces are not drawn (2 cm at 100 units per metre)
SYSTEMS = ("pilot", "navigation")  # the bidders at the robot-level auction, always in /bids
HEIGHT = 0.5  # m: drawn height of walls, obstacles and landmarks
_LEVEL = {"info": LogLevel.Info, "warning": LogLevel.Warning, "error": LogLevel.Error}
_GREY, _RED, _BLUE, _GREEN = (Color(r=0.55, g=0.55, b=0.6, a=1.0), Color(r=0.85, g=0.3, b=0.25, a=1.0),
                              Color(r=0.2, g=0.45, b=0.9, a=1.0), Color(r=0.2, g=0.75, b=0.3, a=0.6))
_ROBOT, _ARROW = Color(r=0.95, g=0.75, b=0.1, a=0.8), Color(r=0.9, g=0.2, b=0.8, a=1.0)
_GROWN = Color(r=0.95, g=0.5, b=0.1, a=0.25)
_FOV = Color(r=0.3, g=0.8, b=0.95, a=0.8)
_MEMORY_RGB = {"landmark": (0.2, 0.45, 0.9), "obstacle": (0.85, 0.3, 0.25), "bump": (1.0, 0.1, 0.1),
               "target": (0.2, 0.75, 0.3)}
_MEMORY = {k: (Color(r=r, g=g, b=b, a=0.45), Color(r=r, g=g, b=b, a=0.3)) for k, (r, g, b) in _MEMORY_RGB.items()}
_RING = [2 * math.pi * k / 16 for k in range(16)]  # rad: the vertices of a support ring


def _ts(ns: int) -> Timestamp:
    return Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)


def _yaw(theta: float) -> Quaternion:
    return Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2))


def _pose(x: float, y: float, theta: float = 0.0, z: float = 0.0) -> FxPose:
    return FxPose(position=Vector3(x=x, y=y, z=z), orientation=_yaw(theta))


def _cylinder(x: float, y: float, radius: float, bottom: float, height: float, color: Color) -> CylinderPrimitive:
    """An upright cylinder (or flat disc) of ``radius`` standing on ``z = bottom`` at (x, y)."""
    return CylinderPrimitive(pose=_pose(x, y, z=bottom + height / 2), size=Vector3(x=2 * radius, y=2 * radius, z=height),
                             bottom_scale=1.0, top_scale=1.0, color=color)


class Recorder:
    """Writes one run to ``path`` (see module docstring). Use :meth:`start`, :meth:`tick` per
    control tick, then :meth:`finish` exactly once, also after an interruption."""

    def __init__(self, path: str | Path, *, live: bool = False, port: int = 8765):
        self.path = Path(path)
        self.partial = self.path.with_name(self.path.name + ".partial")
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if self.partial.exists():
            self.partial.unlink()  # the remains of a run that was killed outright
        ctx = foxglove.Context()
        self.ctx = ctx
        self.writer = foxglove.open_mcap(self.partial, context=ctx)
        self.server = foxglove.start_server(name="navcli", port=port, context=ctx,
                                            capabilities=[Capability.Time]) if live else None
        self.tf = FrameTransformsChannel("/tf", context=ctx)
        self.pose = PoseInFrameChannel("/robot/pose", context=ctx)
        self.odom = PoseInFrameChannel("/robot/odometry", context=ctx)
        self.world_scene = SceneUpdateChannel("/world/scene", context=ctx)
        self.robot_scene = SceneUpdateChannel("/robot/scene", context=ctx)
        self.robot_body = SceneUpdateChannel("/robot/body", context=ctx)
        self.camera_scene = SceneUpdateChannel("/robot/camera", context=ctx)
        self.events = LogChannel("/events", context=ctx)
        self.pilot = foxglove.Channel("/pilot", schema=json_schema(Pilot), context=ctx)
        self.bids = foxglove.Channel("/bids", schema=json_schema(Bids), context=ctx)
        self.summary = foxglove.Channel("/mission/summary", schema=json_schema(MissionSummary), context=ctx)
        self.vision = foxglove.Channel("/vision", schema=json_schema(Vision), context=ctx)
        self.memory_scene = SceneUpdateChannel("/memory/scene", context=ctx)
        self._closed = False
        self._grown_keys: tuple = ()
        self._grown_ns = 0
        self._R_min = 0.0
        self._fov = (0.0, 0.0)  # camera field of view (rad) and range (m)
        self._pan_drawn: float | None = None
        self._scenario: Scenario | None = None
        self._radius = 0.0
        self._state_ns = 0  # when the state topics were last published

    @property
    def port(self) -> int | None:
        return self.server.port if self.server else None

    # -- the run
    def start(self, spec: RunSpec, pose: Pose, odometry: Pose) -> None:
        """Metadata ``run`` (the whole configuration), the scenario attached, the arena, the
        robot's body, and the first poses."""
        sc = spec.scenario
        self._R_min = spec.params.pilot.R_min
        self._fov = (sc.camera.fov, sc.camera.range)
        self.writer.write_metadata("run", spec.metadata())
        self.writer.attach(log_time=0, create_time=0, name=Path(sc.source).name or f"{sc.name}.yaml",
                           media_type="application/yaml", data=sc.text.encode())
        self._scenario, self._radius = sc, spec.params.robot.radius
        self._state(0, 0.0)
        self._pose_msgs(pose, odometry, 0)

    def _state(self, ns: int, pan: float) -> None:
        """The state a viewer needs at any time, each on a topic of its own and complete in every
        message: the arena (``/world/scene``), the robot's body (``/robot/body``) and the camera's
        field of view (``/robot/camera``). Published at the start and every ``SCENE_REFRESH`` s,
        so a viewer that seeks or joins late finds them (a viewer restores the latest message of
        each topic); the field of view also when the pan changes."""
        self.world_scene.log(SceneUpdate(entities=_arena_entities(self._scenario, ns)), log_time=ns)
        r = self._radius
        body = SceneEntity(
            timestamp=_ts(ns), frame_id="base_link", id="robot", frame_locked=True,
            cylinders=[_cylinder(0.0, 0.0, r, 0.0, 0.3, _ROBOT)],
            arrows=[ArrowPrimitive(pose=_pose(0, 0, z=0.32), shaft_length=r, shaft_diameter=0.04,
                                   head_length=0.1, head_diameter=0.1, color=_ROBOT)])
        self.robot_body.log(SceneUpdate(entities=[body]), log_time=ns)
        self._camera(ns, pan)
        self._state_ns = ns

    def _camera(self, ns: int, pan: float) -> None:
        self.camera_scene.log(SceneUpdate(entities=[_field_of_view(pan, *self._fov, ns)]), log_time=ns)
        self._pan_drawn = pan

    def _pose_msgs(self, truth: Pose, odom: Pose, ns: int) -> None:
        ts = _ts(ns)
        q = _yaw(truth.theta)
        self.tf.log(FrameTransforms(transforms=[FrameTransform(
            timestamp=ts, parent_frame_id="world", child_frame_id="base_link",
            translation=Vector3(x=truth.x, y=truth.y, z=0.0), rotation=q)]), log_time=ns)
        self.pose.log(PoseInFrame(timestamp=ts, frame_id="world", pose=FxPose(
            position=Vector3(x=truth.x, y=truth.y, z=0.0), orientation=q)), log_time=ns)
        self.odom.log(PoseInFrame(timestamp=ts, frame_id="world", pose=_pose(odom.x, odom.y, odom.theta)),
                      log_time=ns)

    def tick(self, t: Tick) -> None:
        ns = t.time_ns
        self._pose_msgs(t.pose, t.odometry, ns)
        if self.server is not None:
            self.server.broadcast_time(ns)
        v, w = t.command
        self.pilot.log(encode(pilot_message(t.pilot.info, v, math.degrees(w))), log_time=ns)
        self.bids.log(encode(bids_record(t)), log_time=ns)
        ents = [_force_arrows(t.pilot.arrows, ns)] if t.pilot.arrows else []
        keys = tuple(o.key for o in t.pilot.obstacles)
        if keys != self._grown_keys or ns - self._grown_ns >= GROWN_REFRESH_NS:
            ents.append(_grown(t.pilot.obstacles, t.pose, self._R_min, ns))
            self._grown_keys, self._grown_ns = keys, ns
        if ents:
            self.robot_scene.log(SceneUpdate(entities=ents), log_time=ns)
        pan, state = t.camera
        if ns - self._state_ns >= round(SCENE_REFRESH * 1e9):
            self._state(ns, pan)
        elif pan != self._pan_drawn:
            self._camera(ns, pan)
        dets = {d.key or f"obstacle{i}": msgspec.convert(d.as_json(), DetectionMsg)
                for i, d in enumerate(t.detections or ())}
        self.vision.log(encode(Vision(pan_deg=math.degrees(pan), state=state, image=t.detections is not None,
                                      detections=dets)), log_time=ns)
        if t.memory is not None:
            self.memory_scene.log(SceneUpdate(deletions=[SceneEntityDeletion(timestamp=_ts(ns), type=SceneEntityDeletionType.All)],
                                              entities=_memory_entities(t.memory, ns)), log_time=ns)
        for e in t.events:
            self.event(e, ns)

    def event(self, e: Event, ns: int) -> None:
        self.events.log(Log(timestamp=_ts(ns), level=_LEVEL[e.level], message=e.message, name=e.source),
                        log_time=ns)

    def finish(self, summary: dict, ns: int) -> Path:
        """Write the summary, close the file and give it its final name. Idempotent."""
        if self._closed:
            return self.path
        self._closed = True
        try:
            self.summary.log(encode(msgspec.convert(summary, MissionSummary)), log_time=ns)
        finally:
            self.writer.close()
            if self.server is not None:
                self.server.stop()
            os.replace(self.partial, self.path)
        return self.path


def bids_record(t: Tick) -> Bids:
    """The ``/bids`` message: fixed keys per resource so every value is plottable in Foxglove."""
    per: dict = {}
    for r in RESOURCES:
        values = dict.fromkeys(SYSTEMS, 0.0)
        actions = {}
        for b in t.bids:
            if b.resource == r:
                values[b.bidder] = b.value
                actions[b.bidder] = msgspec.convert(b.action.as_json(), Action)
        win = t.winners[r]
        per[r] = ResourceBids(**values, actions=actions, winner=win.bidder if win else msgspec.UNSET)
    agents: dict = {}
    for b in t.agent_bids:
        agents.setdefault(b.bidder, {})[b.resource] = b.value
    return Bids(**per, agents=agents)


def _force_arrows(arrows: list[tuple[str, float, float]], ns: int) -> SceneEntity:
    """Egocentric force vectors as arrows in ``base_link`` (length scaled: 100 force units = 1 m)."""
    prims = []
    for _name, fx, fy in arrows:
        mag = math.hypot(fx, fy)
        if mag < ARROW_MIN:
            continue
        L = min(mag / 100.0, 1.5)
        prims.append(ArrowPrimitive(pose=_pose(0, 0, math.atan2(fy, fx), z=0.35), shaft_length=max(L - 0.08, 0.01),
                                    shaft_diameter=0.025, head_length=0.08, head_diameter=0.07, color=_ARROW))
    return SceneEntity(timestamp=_ts(ns), frame_id="base_link", id="forces", frame_locked=True, arrows=prims)


def _field_of_view(pan: float, fov: float, rng: float, ns: int) -> SceneEntity:
    """The camera's field of view: a fan in ``base_link``, turned by the pan."""
    pts = [Point3(x=0.0, y=0.0, z=0.4)]
    for k in range(9):
        a = pan - fov / 2 + fov * k / 8
        pts.append(Point3(x=rng * math.cos(a), y=rng * math.sin(a), z=0.4))
    pts.append(Point3(x=0.0, y=0.0, z=0.4))
    return SceneEntity(timestamp=_ts(ns), frame_id="base_link", id="camera", frame_locked=True,
                       lines=[LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.02, color=_FOV, points=pts)])


def _memory_entities(memory: tuple[Remembered, ...], ns: int) -> list[SceneEntity]:
    """The visual memory in ``base_link``: per remembered point a disc the size of its 70 % cut
    (the visible belief) and a faint thin ring for its support, which is often 1-2 m wide and would
    hide the arena if filled, so Foxglove shows belief (here) next to truth (/world/scene)."""
    ents = []
    ts = _ts(ns)
    for m in memory:
        cyl, lines = [], []
        color, faint = _MEMORY.get(m.kind, _MEMORY["obstacle"])
        for x, y, r70, r0 in m.spots:
            cyl.append(_cylinder(x, y, max(r70, 0.03), 0.015, 0.03, color))
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=0.01, color=faint, points=[
                Point3(x=x + r0 * math.cos(a), y=y + r0 * math.sin(a), z=0.01) for a in _RING]))
        if len(m.spots) == 2:
            (ax, ay, *_), (bx, by, *_) = m.spots
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.03, color=color,
                                       points=[Point3(x=ax, y=ay, z=0.04), Point3(x=bx, y=by, z=0.04)]))
        ents.append(SceneEntity(timestamp=ts, frame_id="base_link", id=f"memory-{m.key}", frame_locked=True,
                                cylinders=cyl, lines=lines))
    return ents


def _grown(obstacles, pose: Pose, R: float, ns: int) -> SceneEntity:
    """The pilot's prohibited areas (section 3.1): known obstacles grown by R_min from their
    surface, drawn flat in ``world`` where the robot perceives them (egocentric positions placed
    with the true pose)."""
    cyl, cubes = [], []
    for o in obstacles:
        g = o.radius + R
        a = pose.to_world(o.a)
        cyl.append(_cylinder(*a, g, 0.0, 0.01, _GROWN))
        if o.a != o.b:
            b = pose.to_world(o.b)
            cyl.append(_cylinder(*b, g, 0.0, 0.01, _GROWN))
            cubes.append(CubePrimitive(pose=_pose((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, math.atan2(b[1] - a[1], b[0] - a[0]),
                                                  z=0.005),
                                       size=Vector3(x=math.dist(a, b), y=2 * g, z=0.01), color=_GROWN))
    return SceneEntity(timestamp=_ts(ns), frame_id="world", id="grown-obstacles", cylinders=cyl, cubes=cubes)


def _arena_entities(sc: Scenario, ns: int) -> list[SceneEntity]:
    W, H, t = sc.arena.width, sc.arena.height, 0.1
    ts = _ts(ns)
    walls = [CubePrimitive(pose=_pose(x, y, z=HEIGHT / 2), size=Vector3(x=sx, y=sy, z=HEIGHT), color=_GREY)
             for x, y, sx, sy in ((W / 2, -t / 2, W + 2 * t, t), (W / 2, H + t / 2, W + 2 * t, t),
                                  (-t / 2, H / 2, t, H), (W + t / 2, H / 2, t, H))]
    ents = [SceneEntity(timestamp=ts, frame_id="world", id="walls", cubes=walls)]
    for o in sc.objects:
        if o.kind == "circle":
            ents.append(SceneEntity(timestamp=ts, frame_id="world", id=f"obstacle-{o.key[1:]}",
                                    cylinders=[_cylinder(*o.a, o.radius, 0.0, HEIGHT, _RED)]))
        elif o.kind == "segment":
            (ax, ay), (bx, by) = o.a, o.b
            ents.append(SceneEntity(timestamp=ts, frame_id="world", id=f"obstacle-{o.key[1:]}", cubes=[CubePrimitive(
                pose=_pose((ax + bx) / 2, (ay + by) / 2, math.atan2(by - ay, bx - ax), z=HEIGHT / 2),
                size=Vector3(x=math.hypot(bx - ax, by - ay), y=2 * o.radius, z=HEIGHT), color=_RED)]))
        elif o.kind == "landmark":
            ents.append(SceneEntity(
                timestamp=ts, frame_id="world", id=f"landmark-{o.key}",
                cylinders=[_cylinder(*o.a, o.radius, 0.0, HEIGHT, _BLUE)],
                texts=[TextPrimitive(pose=_pose(*o.a, z=HEIGHT + 0.15), billboard=True, font_size=14.0,
                                     scale_invariant=True, color=_BLUE, text=o.key)]))
    tg = sc.target
    if tg.kind == "line":
        (ax, ay), (bx, by) = tg.line
        target = {"lines": [LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.05, color=_GREEN,
                                          points=[Point3(x=ax, y=ay, z=0.01), Point3(x=bx, y=by, z=0.01)])]}
    else:
        r = tg.tolerance
        target = {"cylinders": [_cylinder(*tg.point, r, 0.0, 0.02, _GREEN)]}
    ents.append(SceneEntity(timestamp=ts, frame_id="world", id="target", **target))
    return ents
