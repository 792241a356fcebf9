"""The recorder: the only writer of navcli's log format (the README's "The log").

One MCAP file per run, written with Foxglove's SDK so Foxglove's 3D, Plot and Log panels read it
by schema name. Log time is simulation time (integer nanoseconds from the start); no wall clock
reaches the file. The file is written under ``<name>.partial`` and renamed when closed, so a
finished name is always a complete file; a run ended by Ctrl-C or an error still closes its file
properly, with a summary whose outcome says ``interrupted`` or ``error`` and why.

Crash safety (our design): the writer finishes its chunk every simulated second
(:data:`FLUSH_EVERY_NS`), so a run killed outright (SIGKILL, power loss) leaves a ``.partial``
whose complete chunks hold all but at most the last simulated second; :func:`recover` rewrites
them into a valid log marked ``interrupted``. A lock file (``<name>.lock``, held while the run
writes) keeps two runs from writing one log; the ``.partial`` of a killed run is never deleted,
only renamed aside (``<name>.partial-1`` ...) for :func:`recover`.


The JSON messages and their schemas are defined once, in :mod:`navcli.messages`. State a viewer
needs at any time (the arena, the robot's body, the camera's field of view) has topics of its own,
republished every ``params.SCENE_REFRESH`` s (see :meth:`Recorder._state`); the camera's pan is
the frame ``camera`` in ``/tf``, so its field of view turns without being redrawn.

With ``live`` the same Foxglove context also feeds a WebSocket server on localhost, which
advertises the time capability and broadcasts simulation time every tick.
"""

from __future__ import annotations

import fcntl
import functools
import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

import foxglove
import msgspec
from foxglove.mcap import MCAPCompression, MCAPWriteOptions
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
from .outputs import atomic
from .messages import Bids, MissionSummary, Navigation, Pilot, Vision, encode, json_schema, pilot_message
from .params import DRAW_PERIOD, SCENE_REFRESH
from .scenario import Scenario

if TYPE_CHECKING:
    from foxglove._foxglove_py import BaseChannel

    from .config import RunSpec
    from .navigation.map_manager import MapSnapshot
    from .geometry import Pose
    from .mission import Event, Tick
    from .vision.visual_memory import Remembered

FLUSH_EVERY_NS = 1_000_000_000
"""A chunk is finished every simulated second: what a hard kill can lose (the README promises it).
The trade, measured on paper-8x8 by callgrind: finishing a chunk costs about 135 k instructions
beyond the compression its bytes need anyway (message indexes, chunk record, write), some 13 k a
tick at one a second, under 3 % of logging. Flushing every 5 s would save 11 k a tick and risk 5 s;
never flushing (a chunk then closes at 1 MiB, some 20 simulated seconds here) would save 13 k and
risk those 20 s. Kept at a second: the rest of logging is far larger (about 0.45 M a tick)."""
WRITE_OPTIONS = MCAPWriteOptions(compression=MCAPCompression.Lz4, compression_threads=0)
"""LZ4, in this thread (our design, by measurement): zstd's chunk of a simulated second cost about
1.1 ms to finish, a tenth of a tick's budget; LZ4 is several times cheaper for logs about half
again as large, and every MCAP reader (the mcap library, Foxglove) reads it."""
RECOVERED_REASON = "recovered after an abrupt end"
SCENE_NS = round(SCENE_REFRESH * 1e9)  # the state topics are republished at least this often
DRAW_NS = round(DRAW_PERIOD * 1e9)  # the Pilot's decorations in /robot/scene are drawn at most this often
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
_RING = [(math.cos(2 * math.pi * k / 16), math.sin(2 * math.pi * k / 16)) for k in range(16)]  # a support ring's vertices
_NO_TURN = Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)  # the yaw of 0, built once: most primitives are not turned
_ARROW_BASE = Vector3(x=0.0, y=0.0, z=0.35)  # m: where the force arrows start, in base_link
_CAMERA_AT = Vector3(x=0.0, y=0.0, z=0.4)  # m: the camera frame's origin in base_link (its field of view's height)


def _ts(ns: int) -> Timestamp:
    return Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)


def _yaw(theta: float) -> Quaternion:
    return Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2))


def _pose(x: float, y: float, theta: float = 0.0, z: float = 0.0) -> FxPose:
    return FxPose(position=Vector3(x=x, y=y, z=z), orientation=_yaw(theta) if theta else _NO_TURN)


def _cylinder(x: float, y: float, radius: float, bottom: float, height: float, color: Color) -> CylinderPrimitive:
    """An upright cylinder (or flat disc) of ``radius`` standing on ``z = bottom`` at (x, y)."""
    d = 2 * radius
    return CylinderPrimitive(pose=_pose(x, y, z=bottom + height / 2), size=Vector3(x=d, y=d, z=height),
                             bottom_scale=1.0, top_scale=1.0, color=color)


def _json_channel(topic: str, cls: type, ctx: foxglove.Context) -> BaseChannel:
    """A JSON topic of message class ``cls``, as the channel's Rust base, whose ``log(data,
    log_time)`` takes our encoded bytes as they are: the Python ``Channel.log`` around it reads the
    channel's encoding and checks the message's type at every call, about a fifth of the cost of
    logging one of our messages (our design, by measurement; the bytes written are the same)."""
    return foxglove.Channel(topic, schema=_schema(cls), message_encoding="json", context=ctx).base


@functools.cache
def _schema(cls: type) -> foxglove.Schema:
    """The JSON Schema of a message class as the log stores it, derived once per process (about
    1 ms a class: a run in a process that runs many, ``compare`` or a benchmark, no longer pays it)."""
    schema = json_schema(cls)
    return foxglove.Schema(name=schema["title"], encoding="jsonschema", data=json.dumps(schema).encode())


class LogPathError(ValueError):
    """A log path that cannot be written (a folder, not ``.mcap``, being written by another run)."""


def check_log_path(path: Path, protect: tuple[str, ...] = ()) -> Path:
    """``path`` as a log file name, or :class:`LogPathError` saying why not: it must end in
    ``.mcap``, not be a folder, not be one of ``protect`` (the scenario file), and its folder
    must be creatable and writable. Checked before a mission starts, so a bad ``--out`` costs
    nothing."""
    if str(path) in ("", ".") or path.name in ("", ".", ".."):
        raise LogPathError(f"{str(path)!r} is not a file name")
    if path.is_dir():
        raise LogPathError(f"{path} is a folder; give a file name ending in .mcap")
    if path.suffix != ".mcap":
        raise LogPathError(f"{path}: a log file name ends in .mcap")
    for other in protect:
        if other and path.exists() and Path(other).exists() and path.samefile(other):
            raise LogPathError(f"{path} is the scenario file itself")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise LogPathError(f"cannot create the folder {path.parent}: {e.strerror or e}") from None
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise LogPathError(f"cannot write in the folder {path.parent} (permission denied)")
    if path.exists() and not os.access(path, os.W_OK):
        raise LogPathError(f"cannot overwrite {path} (permission denied)")
    return path


class _Lock:
    """An exclusive, non-blocking ``flock`` on ``<log>.lock`` for the life of a run; the file is
    removed on release (re-checked by inode, so a run never holds a lock on a removed file)."""

    def __init__(self, path: Path):
        self.path = path
        while True:
            try:
                fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as e:  # a folder the permission bits allow but the file system refuses (/proc)
                raise LogPathError(f"cannot write the log {path.with_suffix('')}: {e.strerror or e}") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                raise LogPathError(f"{path.with_suffix('')} is being written by another run") from None
            try:
                same = os.fstat(fd).st_ino == os.stat(path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self.fd = fd
                return
            os.close(fd)  # the file was removed by the run that held it: take the new one

    def release(self) -> None:
        if self.fd is not None:
            try:
                os.unlink(self.path)
            finally:
                os.close(self.fd)
                self.fd = None


def _aside(partial: Path) -> Path:
    """The first free ``<partial>-<n>``: where the ``.partial`` of a killed run is kept."""
    n = 1
    while partial.with_name(f"{partial.name}-{n}").exists():
        n += 1
    return partial.with_name(f"{partial.name}-{n}")


class Recorder:
    """Writes one run to ``path`` (see module docstring). Use :meth:`start`, :meth:`tick` per
    control tick, then :meth:`finish` exactly once, also after an interruption."""

    def __init__(self, path: str | Path, *, live: bool = False, port: int = 8765, protect: tuple[str, ...] = ()):
        self.path = check_log_path(Path(path), protect)
        self.partial = self.path.with_name(self.path.name + ".partial")
        self.lock = _Lock(self.path.with_name(self.path.name + ".lock"))
        self.kept_aside: Path | None = None  # where a killed run's .partial was moved
        try:
            if self.partial.exists():
                self.kept_aside = _aside(self.partial)
                os.replace(self.partial, self.kept_aside)
            ctx = foxglove.Context()
            self.ctx = ctx  # held for the run: the channels stop logging once their context is collected
            self.writer = foxglove.open_mcap(self.partial, context=ctx, writer_options=WRITE_OPTIONS)
            try:
                self.server = foxglove.start_server(name="navcli", port=port, context=ctx,
                                                    capabilities=[Capability.Time]) if live else None
            except Exception as e:
                self.writer.close()
                os.unlink(self.partial)
                raise LogPathError(f"cannot serve on port {port}: {e}") from None
        except BaseException:
            self.lock.release()
            raise
        self.port = self.server.port if self.server is not None else None  # the one taken (--port 0: any free)
        self.tf = FrameTransformsChannel("/tf", context=ctx)
        self.pose = PoseInFrameChannel("/robot/pose", context=ctx)
        self.odom = PoseInFrameChannel("/robot/odometry", context=ctx)
        self.world_scene = SceneUpdateChannel("/world/scene", context=ctx)
        self.robot_scene = SceneUpdateChannel("/robot/scene", context=ctx)
        self.robot_body = SceneUpdateChannel("/robot/body", context=ctx)
        self.camera_scene = SceneUpdateChannel("/robot/camera", context=ctx)
        self.events = LogChannel("/events", context=ctx)
        self.pilot = _json_channel("/pilot", Pilot, ctx)
        self.bids = _json_channel("/bids", Bids, ctx)
        self.summary = _json_channel("/mission/summary", MissionSummary, ctx)
        self.vision = _json_channel("/vision", Vision, ctx)
        self.memory_scene = SceneUpdateChannel("/memory/scene", context=ctx)
        self.navigation = _json_channel("/navigation", Navigation, ctx)
        self.map_scene = SceneUpdateChannel("/map/scene", context=ctx)
        self._closed = False
        self._drawn_ns = -DRAW_NS  # when the Pilot's decorations were last drawn: the first tick draws them
        self._R_min = 0.0
        self._fov: LinePrimitive | None = None  # the camera's field of view in its frame, built at start
        self._pan = 0.0  # rad: the camera's pan in the last /tf
        self._flushed_ns = 0
        self.pose_ns = -1  # the time of the last pose written
        self._arena: list[tuple[str, dict]] = []  # the arena's and the body's primitives, built at start
        self._body: dict = {}
        self._state_ns = 0  # when the state topics were last published
        self._map = None  # the Map Manager's last snapshot
        self._diverting_drawn = False

    # -- the run
    def start(self, spec: RunSpec, pose: Pose, odometry: Pose) -> None:
        """Metadata ``run`` (the whole configuration), the scenario attached, the arena, the
        robot's body, and the first poses."""
        sc = spec.scenario
        self._R_min = spec.params.pilot.R_min
        self._fov = LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.02, color=_FOV,
                                  points=_fan(sc.camera.fov, sc.camera.range))
        self.writer.write_metadata("run", spec.metadata())
        self.writer.attach(log_time=0, create_time=0, name=Path(sc.source).name or f"{sc.name}.yaml",
                           media_type="application/yaml", data=sc.text.encode())
        r = spec.params.robot.radius
        self._arena = _arena_shapes(sc)
        self._body = {"cylinders": [_cylinder(0.0, 0.0, r, 0.0, 0.3, _ROBOT)],
                      "arrows": [ArrowPrimitive(pose=_pose(0, 0, z=0.32), shaft_length=r, shaft_diameter=0.04,
                                                head_length=0.1, head_diameter=0.1, color=_ROBOT)]}
        self._state(0)
        self._pose_msgs(pose, odometry, 0, 0.0)

    def _state(self, ns: int) -> None:
        """The state a viewer needs at any time, each on a topic of its own and complete in every
        message: the arena (``/world/scene``), the robot's body (``/robot/body``) and the camera's
        field of view (``/robot/camera``, in the frame ``camera`` that /tf turns by the pan).
        Published at the start and every ``SCENE_REFRESH`` s, so a viewer that seeks or joins late
        finds them (a viewer restores the latest message of each topic)."""
        ts = _ts(ns)
        arena = [SceneEntity(timestamp=ts, frame_id="world", id=key, **shapes) for key, shapes in self._arena]
        self.world_scene.log(SceneUpdate(entities=arena), log_time=ns)
        body = SceneEntity(timestamp=ts, frame_id="base_link", id="robot", frame_locked=True, **self._body)
        self.robot_body.log(SceneUpdate(entities=[body]), log_time=ns)
        self.camera_scene.log(SceneUpdate(entities=[SceneEntity(timestamp=ts, frame_id="camera", id="camera",
                                                                frame_locked=True, lines=[self._fov])]), log_time=ns)
        self._state_ns = ns

    def _pose_msgs(self, truth: Pose, odom: Pose, ns: int, pan: float) -> None:
        """/tf (``world`` to ``base_link``: the true pose; ``base_link`` to ``camera``: the pan),
        /robot/odometry and, last, /robot/pose at ``ns``. The pan is a frame (our design): the
        field of view drawn once in it turns with the camera, where redrawing it at each change
        of the pan cost some 10 µs a tick. ``pose_ns`` is set once the pose is written, so a run
        stopped by a signal in between has them written again by :meth:`finish` (before,
        ``pose_ns`` was set first: 2 runs in 12 of the SIGTERM test ended with the summary a tick
        after its last pose). Every tick: the poses' parts are built inline, not by :func:`_ts`,
        :func:`_yaw` and :func:`_pose` (the same values; the camera's turn, often none, by :func:`_yaw`)."""
        ts = Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)
        half = truth.theta / 2
        q = Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half))
        at = Vector3(x=truth.x, y=truth.y, z=0.0)
        self.tf.log(FrameTransforms(transforms=[
            FrameTransform(timestamp=ts, parent_frame_id="world", child_frame_id="base_link", translation=at, rotation=q),
            FrameTransform(timestamp=ts, parent_frame_id="base_link", child_frame_id="camera", translation=_CAMERA_AT,
                           rotation=_yaw(pan) if pan else _NO_TURN)]), log_time=ns)
        self._pan = pan
        half = odom.theta / 2
        self.odom.log(PoseInFrame(timestamp=ts, frame_id="world", pose=FxPose(
            position=Vector3(x=odom.x, y=odom.y, z=0.0),
            orientation=Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)) if odom.theta else _NO_TURN)),
            log_time=ns)
        self.pose.log(PoseInFrame(timestamp=ts, frame_id="world", pose=FxPose(position=at, orientation=q)), log_time=ns)
        self.pose_ns = ns

    def tick(self, t: Tick) -> None:
        ns = t.time_ns
        pan, state = t.camera
        self._pose_msgs(t.pose, t.odometry, ns, pan)
        if self.server is not None:
            self.server.broadcast_time(ns)
        v, w = t.command
        self.pilot.log(encode(pilot_message(t.pilot.info, v, math.degrees(w))), ns)
        self.bids.log(encode(bids_record(t)), ns)
        if ns - self._drawn_ns >= DRAW_NS:
            self._pilot_scene(t, ns)
        if ns - self._state_ns >= SCENE_NS:
            self._state(ns)
        dets = t.detections
        self.vision.log(encode({"pan_deg": math.degrees(pan), "state": state, "image": dets is not None, "detections":
                                {d.key or f"obstacle{i}": d.as_json() for i, d in enumerate(dets)} if dets else {}}), ns)
        if t.memory is not None:
            self.memory_scene.log(SceneUpdate(deletions=[SceneEntityDeletion(timestamp=_ts(ns), type=SceneEntityDeletionType.All)],
                                              entities=_memory_entities(t.memory, ns)), log_time=ns)
        if t.navigation is not None:
            self.navigation.log(encode(navigation_record(t)), ns)
            if t.map is not None or t.navigation.diverting != self._diverting_drawn:
                self._diverting_drawn = t.navigation.diverting
                if t.map is not None:
                    self._map = t.map
                if self._map is not None:
                    self.map_scene.log(SceneUpdate(
                        deletions=[SceneEntityDeletion(timestamp=_ts(ns), type=SceneEntityDeletionType.All)],
                        entities=_map_entities(self._map, t.navigation.target_line if t.navigation.diverting else None,
                                               ns)), log_time=ns)
        for e in t.events:
            self.event(e, ns)
        if ns - self._flushed_ns >= FLUSH_EVERY_NS:
            self.writer.flush()
            self._flushed_ns = ns

    def _pilot_scene(self, t: Tick, ns: int) -> None:
        """``/robot/scene`` every :data:`DRAW_NS`: the Pilot's force arrows and its grown obstacles
        (the forces themselves are in ``/pilot`` every tick)."""
        self._drawn_ns = ns
        ents = [_grown(t.pilot.obstacles, t.pose, self._R_min, ns)]
        if t.pilot.arrows:
            ents.append(_force_arrows(t.pilot.arrows, ns))
        self.robot_scene.log(SceneUpdate(entities=ents), log_time=ns)

    def event(self, e: Event, ns: int) -> None:
        self.events.log(Log(timestamp=_ts(ns), level=_LEVEL[e.level], message=e.message, name=e.source),
                        log_time=ns)

    def finish(self, summary: dict, ns: int, poses: tuple[Pose, Pose] | None = None) -> Path:
        """Write the summary, close the file and give it its final name. Idempotent.

        ``poses`` (truth, odometry) at ``ns`` are written first if no pose was written at that
        time (a run stopped inside a tick), so the summary's time is always the last pose's."""
        if self._closed:
            return self.path
        self._closed = True
        try:
            if poses is not None and self.pose_ns != ns:
                self._pose_msgs(*poses, ns, self._pan)
            self.summary.log(encode(msgspec.convert(summary, MissionSummary)), ns)
        finally:
            self.writer.close()
            if self.server is not None:
                self.server.stop()
            os.replace(self.partial, self.path)
            self.lock.release()
        return self.path


_NO_BIDS = dict.fromkeys(SYSTEMS, 0.0)


def bids_record(t: Tick) -> dict:
    """The ``/bids`` message (a :class:`~navcli.messages.Bids` as plain values): fixed keys per
    resource so every value is plottable in Foxglove."""
    msg: dict = {r: {**_NO_BIDS, "actions": {}} for r in RESOURCES}
    for b in t.bids:
        per = msg[b.resource]
        per[b.bidder] = b.value
        per["actions"][b.bidder] = b.action.as_json()
    for r in RESOURCES:
        win = t.winners[r]
        if win is not None:
            msg[r]["winner"] = win.bidder
    agents: dict = {}
    for b in t.agent_bids:
        per = agents.get(b.bidder)
        if per is None:
            per = agents[b.bidder] = {}
        per[b.resource] = b.value
    msg["agents"] = agents
    return msg


def _force_arrows(arrows: list[tuple[str, float, float]], ns: int) -> SceneEntity:
    """Egocentric force vectors as arrows in ``base_link`` (length scaled: 100 force units = 1 m)."""
    prims = []
    for _name, fx, fy in arrows:
        mag = math.hypot(fx, fy)
        if mag < ARROW_MIN:
            continue
        L = min(mag / 100.0, 1.5)
        prims.append(ArrowPrimitive(pose=FxPose(position=_ARROW_BASE, orientation=_yaw(math.atan2(fy, fx))),
                                    shaft_length=max(L - 0.08, 0.01), shaft_diameter=0.025, head_length=0.08,
                                    head_diameter=0.07, color=_ARROW))
    return SceneEntity(timestamp=_ts(ns), frame_id="base_link", id="forces", frame_locked=True, arrows=prims)


def _fan(fov: float, rng: float) -> list[Point3]:
    """The camera's field of view (``fov`` rad wide, ``rng`` m deep) in its frame: a closed fan."""
    pts = [Point3(x=0.0, y=0.0, z=0.0)]
    for k in range(9):
        a = -fov / 2 + fov * k / 8
        pts.append(Point3(x=rng * math.cos(a), y=rng * math.sin(a), z=0.0))
    pts.append(Point3(x=0.0, y=0.0, z=0.0))
    return pts


def navigation_record(t: Tick) -> dict:
    """The ``/navigation`` message (a :class:`~navcli.messages.Navigation` as plain values): every
    agent's bids, what was forwarded, and why."""
    nav = t.navigation
    agents: dict[str, dict[str, float]] = {}
    for b in nav.agent_bids:
        a = agents.get(b.bidder)
        if a is None:
            a = agents[b.bidder] = {"motion": 0.0, "camera": 0.0}
        if b.value > a[b.resource]:  # max(), as a test: no call
            a[b.resource] = b.value
    fwd: dict = {"motion": 0.0, "camera": 0.0}
    for b in nav.bids:
        fwd[b.resource] = b.value
        fwd[f"{b.resource}_agent"] = nav.forwarded_by[b.resource]
    msg = {"agents": agents, "forwarded": fwd, **nav.info, "diverting": nav.diverting}  # info: the scalar fields
    if nav.target is not None:
        msg["target"] = {"x": nav.target[0], "y": nav.target[1]}
    if nav.target_line is not None:
        (ax, ay), (bx, by) = nav.target_line
        msg["line_a"], msg["line_b"] = {"x": ax, "y": ay}, {"x": bx, "y": by}
    return msg


_MAP = Color(r=0.55, g=0.3, b=0.85, a=0.9)
_MAP_FAINT = Color(r=0.55, g=0.3, b=0.85, a=0.35)
_BLOCKED = Color(r=0.9, g=0.2, b=0.7, a=0.9)  # pink: apart from the true obstacles (red) in a plot
_DIVERTING = Color(r=0.1, g=0.8, b=0.3, a=1.0)
_DIVERTING_ENDED = Color(r=0.1, g=0.55, b=0.25, a=0.8)  # a diverting line the Rescuer is done with


def _map_entities(m: MapSnapshot, diverting, ns: int) -> list[SceneEntity]:
    """The Map Manager's map in ``base_link``: each mapped landmark with the disc of its 70 % cut
    and its name, the regions' triangles (faint), the beta-units as lines from the encoded landmark
    to its three basis landmarks, blocked edges in red, and the diverting line in green. Not
    frame-locked: drawn every few seconds, a viewer keeps it where the robot was when it was drawn."""
    ts = _ts(ns)
    z = 0.06
    P = lambda xy: Point3(x=xy[0], y=xy[1], z=z)  # noqa: E731
    marks = {k: (p.x, p.y) for k, p in m.landmarks.items()}
    cyl = [_cylinder(p.x, p.y, max(p.radius(0.7), 0.05), z - 0.01, 0.02, _MAP) for p in m.landmarks.values()]
    texts = [TextPrimitive(pose=_pose(p.x, p.y, z=0.7), billboard=True, font_size=12.0, scale_invariant=True,
                           color=_MAP, text=f"{k}'") for k, p in m.landmarks.items()]
    lines = [LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=0.01, color=_MAP_FAINT,
                           points=[P(v) for v in tri]) for tri in m.regions]
    for a, b, c, d in m.units:
        if d in marks and all(k in marks for k in (a, b, c)):
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineList, thickness=0.008, color=_MAP_FAINT,
                                       points=[P(marks[d]), P(marks[a]), P(marks[d]), P(marks[b]),
                                               P(marks[d]), P(marks[c])]))
    at = marks | m.vertices  # a blocked edge may end at an obstacle's point or a virtual landmark
    for u, v in m.blocked:
        if u in at and v in at:
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.04, color=_BLOCKED,
                                       points=[P(at[u]), P(at[v])]))
    for a, b, ending in m.tried:  # the diverting lines ended, thin, named by how they ended
        lines.append(LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.02, color=_DIVERTING_ENDED,
                                   points=[P(a), P(b)]))
        mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        texts.append(TextPrimitive(pose=_pose(*mid, z=0.5), billboard=True, font_size=11.0, scale_invariant=True,
                                   color=_DIVERTING_ENDED, text=ending))
    if diverting is not None:
        lines.append(LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.06, color=_DIVERTING,
                                   points=[P(diverting[0]), P(diverting[1])]))
    return [SceneEntity(timestamp=ts, frame_id="base_link", id="map", frame_locked=False, cylinders=cyl,
                        texts=texts, lines=lines)]


def _memory_entities(memory: tuple[Remembered, ...], ns: int) -> list[SceneEntity]:
    """The visual memory in ``base_link``: per remembered point a disc the size of its 70 % cut
    (the visible belief) and a faint thin ring for its support, which is often 1-2 m wide and would
    hide the arena if filled, so Foxglove shows belief (here) next to truth (/world/scene). Not
    frame-locked: drawn every few seconds, a viewer keeps it where the robot was when it was drawn
    (frame-locked, it would drift along with the robot until the next drawing)."""
    ents = []
    ts = _ts(ns)
    for m in memory:
        cyl, lines = [], []
        color, faint = _MEMORY.get(m.kind, _MEMORY["obstacle"])
        for x, y, r70, r0 in m.spots:
            cyl.append(_cylinder(x, y, max(r70, 0.03), 0.015, 0.03, color))
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=0.01, color=faint, points=[
                Point3(x=x + r0 * c, y=y + r0 * s, z=0.01) for c, s in _RING]))
        if len(m.spots) == 2:
            (ax, ay, *_), (bx, by, *_) = m.spots
            lines.append(LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.03, color=color,
                                       points=[Point3(x=ax, y=ay, z=0.04), Point3(x=bx, y=by, z=0.04)]))
        ents.append(SceneEntity(timestamp=ts, frame_id="base_link", id=f"memory-{m.key}", frame_locked=False,
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


def _arena_shapes(sc: Scenario) -> list[tuple[str, dict]]:
    """The arena's entities (id, primitives), built once per run and stamped at each refresh."""
    W, H, t = sc.arena.width, sc.arena.height, 0.1
    walls = [CubePrimitive(pose=_pose(x, y, z=HEIGHT / 2), size=Vector3(x=sx, y=sy, z=HEIGHT), color=_GREY)
             for x, y, sx, sy in ((W / 2, -t / 2, W + 2 * t, t), (W / 2, H + t / 2, W + 2 * t, t),
                                  (-t / 2, H / 2, t, H), (W + t / 2, H / 2, t, H))]
    ents = [("walls", {"cubes": walls})]
    for o in sc.objects:
        if o.kind == "circle":
            ents.append((f"obstacle-{o.key[1:]}", {"cylinders": [_cylinder(*o.a, o.radius, 0.0, HEIGHT, _RED)]}))
        elif o.kind == "segment":
            (ax, ay), (bx, by) = o.a, o.b
            ents.append((f"obstacle-{o.key[1:]}", {"cubes": [CubePrimitive(
                pose=_pose((ax + bx) / 2, (ay + by) / 2, math.atan2(by - ay, bx - ax), z=HEIGHT / 2),
                size=Vector3(x=math.hypot(bx - ax, by - ay), y=2 * o.radius, z=HEIGHT), color=_RED)]}))
        elif o.kind == "landmark":
            ents.append((f"landmark-{o.key}", {
                "cylinders": [_cylinder(*o.a, o.radius, 0.0, HEIGHT, _BLUE)],
                "texts": [TextPrimitive(pose=_pose(*o.a, z=HEIGHT + 0.15), billboard=True, font_size=14.0,
                                        scale_invariant=True, color=_BLUE, text=o.key)]}))
    tg = sc.target
    if tg.kind == "line":
        (ax, ay), (bx, by) = tg.line
        target = {"lines": [LinePrimitive(type=LinePrimitiveLineType.LineStrip, thickness=0.05, color=_GREEN,
                                          points=[Point3(x=ax, y=ay, z=0.01), Point3(x=bx, y=by, z=0.01)])]}
    else:
        r = tg.tolerance
        target = {"cylinders": [_cylinder(*tg.point, r, 0.0, 0.02, _GREEN)]}
    ents.append(("target", target))
    return ents


class RecoverError(ValueError):
    """A file :func:`recover` cannot make a log of (not an MCAP, no navcli run in it)."""


def recover(partial: str | Path, out: str | Path | None = None) -> tuple[Path, dict]:
    """Rewrite the complete chunks of a killed run's ``.partial`` into a valid log; return its
    path and summary.

    Records are read in order with CRCs checked, up to the first incomplete or damaged one (the
    chunk being written when the process died); schemas, channels, messages, the ``run``
    metadata and the scenario attachment are copied unchanged. A ``/mission/summary`` is added,
    outcome ``interrupted``, reason :data:`RECOVERED_REASON`, at the time of the last pose kept,
    with the path length of the poses kept, the bumper contacts of ``/events``, the images of
    ``/vision`` and the ticks of ``/pilot``, so it agrees with the poses by construction.
    ``out`` defaults to the name without ``.partial`` (or ``-<n>``); an existing file is never
    overwritten. The summary's ``damaged_bytes`` (not written to the log) counts the bytes after a
    damaged record that were not the last, unfinished chunk: more than 0 says the file was damaged
    before its end, not only cut short by a kill. A ``.partial`` whose run still holds its lock is
    refused; a lock its SIGKILLed run left is removed."""
    src = Path(partial)
    if out is None:
        stem = src.name.rpartition(".partial")[0] if ".partial" in src.name else src.stem + "-recovered"
        out = src.with_name(stem if stem.endswith(".mcap") else stem + ".mcap")
    out = check_log_path(Path(out), (str(src),))
    if out.exists():
        raise RecoverError(f"{out} exists; give another --out")
    lock = _lock_of_partial(src)
    try:
        return _recover(src, out)
    finally:
        if lock is not None:
            lock.release()  # and a stale lock a SIGKILLed run left is gone with it


def _lock_of_partial(src: Path) -> _Lock | None:
    """The lock of the run whose ``.partial`` ``src`` is (refused while that run still writes it)."""
    if not src.name.endswith(".partial"):
        return None  # a .partial-<n> kept aside: no run writes it any more
    try:
        return _Lock(src.with_name(src.name[: -len(".partial")] + ".lock"))
    except LogPathError as e:
        if "another run" in str(e):
            raise RecoverError(f"{src}: its run is still going (it holds {src.name[:-len('.partial')]}.lock); "
                               "stop it first") from None
        return None  # a folder we may not write a lock into: read-only recovery from elsewhere


def _recover(src: Path, out: Path) -> tuple[Path, dict]:
    from mcap.records import Attachment, Channel, Message, Metadata, Schema
    from mcap.stream_reader import StreamReader
    from mcap.writer import Writer
    from mcap_protobuf.decoder import DecoderFactory

    schemas, channels, messages, metadata, attachments = {}, {}, [], [], []
    lost = 0  # bytes after a damaged record that are not the last, unfinished chunk
    try:
        with src.open("rb") as f:
            size = os.fstat(f.fileno()).st_size
            try:
                for r in StreamReader(f, validate_crcs=True).records:
                    if isinstance(r, Schema):
                        schemas[r.id] = r
                    elif isinstance(r, Channel):
                        channels[r.id] = r
                    elif isinstance(r, Message):
                        messages.append(r)
                    elif isinstance(r, Metadata):
                        metadata.append(r)
                    elif isinstance(r, Attachment):
                        attachments.append(r)
            except Exception:  # the record being written when the run died: everything before it is kept
                lost = size - f.tell()  # > 0: damage before the end, not only an unfinished last chunk
    except OSError as e:
        raise RecoverError(f"{src}: cannot be read ({e.strerror or e})") from None
    run = next((m.metadata for m in metadata if m.name == "run"), None)
    if run is None or not channels:
        raise RecoverError(f"{src}: no navcli run found in it (not a navcli log, or killed before its first chunk)")
    topic = {cid: c.topic for cid, c in channels.items()}
    if any(topic.get(m.channel_id) == "/mission/summary" for m in messages):
        raise RecoverError(f"{src}: already holds a summary; it is a complete log, rename it")
    pose_channel = next((cid for cid, t in topic.items() if t == "/robot/pose"), None)
    decode = DecoderFactory().decoder_for("protobuf", schemas[channels[pose_channel].schema_id]) \
        if pose_channel is not None else None
    poses = [(m.log_time, decode(m.data).pose.position) for m in messages if m.channel_id == pose_channel]
    if not poses:
        raise RecoverError(f"{src}: no pose was written before the run died")
    poses.sort(key=lambda tp: tp[0])
    end_ns = poses[-1][0]
    messages = [m for m in messages if m.log_time <= end_ns]
    events = [m for m in messages if topic[m.channel_id] == "/events"]
    log_dec = DecoderFactory().decoder_for("protobuf", schemas[channels[events[0].channel_id].schema_id]) if events else None
    summary = {
        "scenario": run.get("scenario", ""), "seed": int(run.get("seed", 0)), "pilot": run.get("pilot", ""),
        "outcome": "interrupted", "reason": RECOVERED_REASON, "time_s": end_ns / 1e9,
        "path_length_m": sum(math.hypot(b.x - a.x, b.y - a.y) for (_, a), (_, b) in zip(poses, poses[1:])),
        "collisions": sum(1 for m in events if log_dec(m.data).message.startswith("bumper contact")),
        "camera_looks": sum(1 for m in messages if topic[m.channel_id] == "/vision" and msgspec.json.decode(m.data).get("image")),
        "ticks": sum(1 for m in messages if topic[m.channel_id] == "/pilot"),
        "navcli_version": run.get("navcli_version", ""), "run_id": run.get("run_id", ""),
    }
    summary["damaged_bytes"] = lost
    with atomic(out) as tmp, tmp.open("wb") as f:  # a temporary name: never the source, <out>.partial
        w = Writer(f)
        w.start(profile="", library="navcli recover")
        schema_ids = {sid: w.register_schema(s.name, s.encoding, s.data) for sid, s in schemas.items()}
        channel_ids = {cid: w.register_channel(c.topic, c.message_encoding, schema_ids.get(c.schema_id, 0), c.metadata)
                       for cid, c in channels.items()}
        for m in metadata:
            w.add_metadata(m.name, m.metadata)
        for a in attachments:
            w.add_attachment(a.create_time, a.log_time, a.name, a.media_type, a.data)
        for m in messages:
            w.add_message(channel_ids[m.channel_id], m.log_time, m.data, m.publish_time, m.sequence)
        schema = _schema(MissionSummary)  # the same bytes as a normal log's
        sid = w.register_schema(schema.name, schema.encoding, schema.data)
        cid = w.register_channel("/mission/summary", "json", sid)
        w.add_message(cid, end_ns, encode(msgspec.convert(
            {k: v for k, v in summary.items() if k != "damaged_bytes"}, MissionSummary)), end_ns)
        w.finish()
    return out, summary
