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
    FrameTransform,
    FrameTransforms,
    LinePrimitive,
    LinePrimitiveLineType,
    Log,
    LogLevel,
    Pose as FxPose,
    PoseInFrame,
    Quaternion,
    SceneEntity,
    SceneEntityDeletion,
    SceneEntityDeletionType,
    SceneUpdate,
    Timestamp,
    Vector3,
)

from ..params import DRAW_PERIOD, SCENE_REFRESH
from . import format as fmt
from .compression import COMPRESSIONS, DEFAULT as DEFAULT_COMPRESSION
from .files import Lock, LogPathError, aside_name, check_log_path
from .format import Bids, MissionSummary, Navigation, Pilot, Vision, encode, json_schema, pilot_message
from .records import bids_record, navigation_record, vision_record
from .scenes import (
    CAMERA_AT,
    FOV,
    NO_TURN,
    ROBOT,
    PathDrawing,
    arena_shapes,
    cylinder,
    fan,
    force_arrows,
    grown,
    map_entities,
    memory_entities,
    place,
    region_entities,
    stamp,
    support_entities,
    yaw,
)

if TYPE_CHECKING:
    from foxglove._foxglove_py import BaseChannel

    from ..config import RunSpec
    from ..geometry import Pose
    from ..mission import Event, Tick
    from ..navigation.map_manager import MapSnapshot

FLUSH_EVERY_NS = 1_000_000_000
"""A chunk is finished every simulated second: what a hard kill can lose (the README promises it).
The trade, measured on paper-8x8 by callgrind: finishing a chunk costs about 135 k instructions
beyond the compression its bytes need anyway (message indexes, chunk record, write), some 13 k a
tick at one a second, under 3 % of logging. Flushing every 5 s would save 11 k a tick and risk 5 s;
never flushing (a chunk then closes at 1 MiB, some 20 simulated seconds here) would save 13 k and
risk those 20 s. Kept at a second: the rest of logging is far larger (about 0.45 M a tick)."""


def write_options(compression: str = DEFAULT_COMPRESSION) -> MCAPWriteOptions:
    """The MCAP writer's options for a compression of :data:`~navcli.log.compression.COMPRESSIONS`
    (the default chosen by measure in docs/howto/speed.md), compressed in this thread."""
    kind, level = COMPRESSIONS[compression]
    codec = {"zstd": MCAPCompression.Zstd, "lz4": MCAPCompression.Lz4, None: None}[kind]
    return MCAPWriteOptions(compression=codec, compression_level=level, compression_threads=0)


SCENE_NS = round(SCENE_REFRESH * 1e9)  # the state topics are republished at least this often
DRAW_NS = round(DRAW_PERIOD * 1e9)  # the Pilot's decorations in /robot/scene are drawn at most this often
_LEVEL = {"info": LogLevel.Info, "warning": LogLevel.Warning, "error": LogLevel.Error}


def _json_channel(topic: str, cls: type, ctx: foxglove.Context) -> BaseChannel:
    """A JSON topic of message class ``cls``, as the channel's Rust base, whose ``log(data,
    log_time)`` takes our encoded bytes as they are: the Python ``Channel.log`` around it reads the
    channel's encoding and checks the message's type at every call, about a fifth of the cost of
    logging one of our messages (our design, by measurement; the bytes written are the same)."""
    return foxglove.Channel(topic, schema=schema_of(cls), message_encoding="json", context=ctx).base


@functools.cache
def enums() -> dict[str, tuple[str, ...]]:
    """Every enumeration a log carries, taken from the code that produces it (each field of the log
    format marked :func:`~navcli.log.format.enumerated` names one of these)."""
    from ..bidding import ACTION_TYPES, PURPOSES
    from ..mission import OUTCOMES
    from ..navigation.rescuer import STATES as RESCUER_STATES
    from ..pilot import ENUMERATIONS as PILOT_ENUMERATIONS
    from ..vision.camera import KINDS, STATES as CAMERA_STATES

    return dict(PILOT_ENUMERATIONS) | {
        "action.type": ACTION_TYPES,
        "camera.state": CAMERA_STATES,
        "detection.kind": KINDS,
        "mission.outcome": OUTCOMES,
        "rescuer.state": RESCUER_STATES,
        "look.purpose": PURPOSES,
    }


def log_schema(cls: type) -> dict:
    """The JSON Schema of a message class as the log stores it: with the producers' enumerations."""
    return json_schema(cls, enums())


@functools.cache
def schema_of(cls: type) -> foxglove.Schema:
    """The JSON Schema of a message class as the log stores it (:func:`log_schema`), derived once per
    process (about 1 ms a class, which a process that runs many, ``compare`` or a benchmark, pays once)."""
    schema = log_schema(cls)
    return foxglove.Schema(name=schema["title"], encoding="jsonschema", data=json.dumps(schema).encode())


class Recorder:
    """Writes one run to ``path`` (see module docstring). Use :meth:`start`, :meth:`tick` per
    control tick, then :meth:`finish` exactly once, also after an interruption. ``pilot_message``
    is the run's ``/pilot`` message type (a plugin pilot's adds the fields its ``Info`` declares:
    :func:`~navcli.log.format.pilot_message_type`). An existing log at ``path`` is refused unless
    ``overwrite``. ``compression``: how the chunks are compressed, a name of
    :data:`~navcli.log.compression.COMPRESSIONS`."""

    def __init__(
        self,
        path: str | Path,
        *,
        live: bool = False,
        port: int = 8765,
        protect: tuple[str, ...] = (),
        pilot_message: type = Pilot,
        overwrite: bool = False,
        compression: str = DEFAULT_COMPRESSION,
    ):
        self.path = check_log_path(Path(path), protect, overwrite=overwrite, ask="overwrite=True")
        self.partial = self.path.with_name(self.path.name + ".partial")
        self.lock = Lock(self.path.with_name(self.path.name + ".lock"))
        self.kept_aside: Path | None = None  # where a killed run's .partial was moved
        try:
            if self.partial.exists():
                self.kept_aside = aside_name(self.partial)
                os.replace(self.partial, self.kept_aside)
            ctx = foxglove.Context()
            self.ctx = ctx  # held for the run: the channels stop logging once their context is collected
            self.writer = foxglove.open_mcap(self.partial, context=ctx, writer_options=write_options(compression))
            try:
                self.server = (
                    foxglove.start_server(name="navcli", port=port, context=ctx, capabilities=[Capability.Time])
                    if live
                    else None
                )
            except Exception as e:
                self.writer.close()
                os.unlink(self.partial)
                raise LogPathError(f"cannot serve on port {port}: {e}") from None
        except BaseException:
            self.lock.release()
            raise
        self.port = self.server.port if self.server is not None else None  # the one taken (--port 0: any free)
        self.tf = FrameTransformsChannel(fmt.TF_TOPIC, context=ctx)
        self.pose = PoseInFrameChannel(fmt.POSE_TOPIC, context=ctx)
        self.odom = PoseInFrameChannel(fmt.ODOMETRY_TOPIC, context=ctx)
        self.world_scene = SceneUpdateChannel(fmt.WORLD_SCENE_TOPIC, context=ctx)
        self.robot_scene = SceneUpdateChannel(fmt.ROBOT_SCENE_TOPIC, context=ctx)
        self.robot_body = SceneUpdateChannel(fmt.ROBOT_BODY_TOPIC, context=ctx)
        self.camera_scene = SceneUpdateChannel(fmt.CAMERA_SCENE_TOPIC, context=ctx)
        self.events = LogChannel(fmt.EVENTS_TOPIC, context=ctx)
        self.pilot = _json_channel(fmt.PILOT_TOPIC, pilot_message, ctx)  # a plugin pilot's: with its Info's fields
        self.bids = _json_channel(fmt.BIDS_TOPIC, Bids, ctx)
        self.summary = _json_channel(fmt.SUMMARY_TOPIC, MissionSummary, ctx)
        self.vision = _json_channel(fmt.VISION_TOPIC, Vision, ctx)
        self.memory_scene = SceneUpdateChannel(fmt.MEMORY_SCENE_TOPIC, context=ctx)
        self.memory_supports = SceneUpdateChannel(fmt.MEMORY_SUPPORTS_TOPIC, context=ctx)
        self.navigation = _json_channel(fmt.NAVIGATION_TOPIC, Navigation, ctx)
        self.map_scene = SceneUpdateChannel(fmt.MAP_SCENE_TOPIC, context=ctx)
        self.map_regions = SceneUpdateChannel(fmt.MAP_REGIONS_TOPIC, context=ctx)
        self.robot_path = SceneUpdateChannel(fmt.ROBOT_PATH_TOPIC, context=ctx)
        self._path = PathDrawing(0.0, 0.0)  # the path driven, begun again at start
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
        self._map: MapSnapshot | None = None  # the Map Manager's last snapshot
        self._diverting_drawn = False
        self._poses: tuple[Pose, Pose] | None = None  # the last poses (truth, odometry), kept by finish

    # -- the run
    def start(self, spec: RunSpec, pose: Pose, odometry: Pose) -> None:
        """Metadata ``run`` (the whole configuration), the scenario attached, the arena, the
        robot's body, and the first poses."""
        sc = spec.scenario
        self._R_min = spec.params.pilot.R_min
        self._fov = LinePrimitive(
            type=LinePrimitiveLineType.LineStrip, thickness=0.02, color=FOV, points=fan(sc.camera.fov, sc.camera.range)
        )
        self.writer.write_metadata("run", spec.metadata() | {"log_format": str(fmt.FORMAT_VERSION)})
        self.writer.attach(
            log_time=0,
            create_time=0,
            name=Path(sc.source).name or f"{sc.name}.yaml",
            media_type="application/yaml",
            data=sc.text.encode(),
        )
        r = spec.params.robot.radius
        self._arena = arena_shapes(sc)
        self._body = {
            "cylinders": [cylinder(0.0, 0.0, r, 0.0, 0.3, ROBOT)],
            "arrows": [
                ArrowPrimitive(
                    pose=place(0, 0, z=0.32),
                    shaft_length=r,
                    shaft_diameter=0.04,
                    head_length=0.1,
                    head_diameter=0.1,
                    color=ROBOT,
                )
            ],
        }
        self._path = PathDrawing(pose.x, pose.y)
        self._state(0)
        self._pose_msgs(pose, odometry, 0, 0.0)

    def _state(self, ns: int) -> None:
        """The state a viewer needs at any time, each on a topic of its own and complete in every
        message: the arena (``/world/scene``), the robot's body (``/robot/body``), the camera's
        field of view (``/robot/camera``, in the frame ``camera`` that /tf turns by the pan) and
        the path driven so far (``/robot/path``, when :class:`~.scenes.PathDrawing` says so).
        Published at the start and every ``SCENE_REFRESH`` s, so a viewer that seeks or joins late
        finds them (a viewer restores the latest message of each topic)."""
        ts = stamp(ns)
        arena = [SceneEntity(timestamp=ts, frame_id="world", id=key, **shapes) for key, shapes in self._arena]
        self.world_scene.log(SceneUpdate(entities=arena), log_time=ns)
        body = SceneEntity(timestamp=ts, frame_id="base_link", id="robot", frame_locked=True, **self._body)
        self.robot_body.log(SceneUpdate(entities=[body]), log_time=ns)
        self.camera_scene.log(
            SceneUpdate(
                entities=[
                    SceneEntity(
                        timestamp=ts,
                        frame_id="camera",
                        id="camera",
                        frame_locked=True,
                        lines=[self._fov] if self._fov else [],
                    )
                ]
            ),
            log_time=ns,
        )
        if (path := self._path.due(ns)) is not None:
            self.robot_path.log(SceneUpdate(entities=[path]), log_time=ns)
        self._state_ns = ns

    def _pose_msgs(self, truth: Pose, odom: Pose, ns: int, pan: float) -> None:
        """/tf (``world`` to ``base_link``: the true pose; ``base_link`` to ``camera``: the pan),
        /robot/odometry and, last, /robot/pose at ``ns``. The pan is a frame (our design): the
        field of view drawn once in it turns with the camera, where redrawing it at each change
        of the pan cost some 10 µs a tick. ``pose_ns`` is set once the pose is written, so a run
        stopped by a signal in between has them written again by :meth:`finish` and its summary's
        time is always its last pose's. Every tick: the poses' parts are built inline, not by :func:`stamp`,
        :func:`yaw` and :func:`place` (the same values; the camera's turn, often none, by :func:`yaw`)."""
        ts = Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)
        half = truth.theta / 2
        q = Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half))
        at = Vector3(x=truth.x, y=truth.y, z=0.0)
        self.tf.log(
            FrameTransforms(
                transforms=[
                    FrameTransform(
                        timestamp=ts, parent_frame_id="world", child_frame_id="base_link", translation=at, rotation=q
                    ),
                    FrameTransform(
                        timestamp=ts,
                        parent_frame_id="base_link",
                        child_frame_id="camera",
                        translation=CAMERA_AT,
                        rotation=yaw(pan) if pan else NO_TURN,
                    ),
                ]
            ),
            log_time=ns,
        )
        self._pan = pan
        self._path.moved(truth.x, truth.y)
        half = odom.theta / 2
        self.odom.log(
            PoseInFrame(
                timestamp=ts,
                frame_id="world",
                pose=FxPose(
                    position=Vector3(x=odom.x, y=odom.y, z=0.0),
                    orientation=Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)) if odom.theta else NO_TURN,
                ),
            ),
            log_time=ns,
        )
        self.pose.log(PoseInFrame(timestamp=ts, frame_id="world", pose=FxPose(position=at, orientation=q)), log_time=ns)
        self.pose_ns = ns

    def tick(self, t: Tick) -> None:
        ns = t.time_ns
        pan = t.camera[0]
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
        self.vision.log(encode(vision_record(t)), ns)
        if t.memory is not None:
            self._redraw(self.memory_scene, memory_entities(t.memory, ns), ns)
            self._redraw(self.memory_supports, support_entities(t.memory, ns), ns)
        if t.navigation is not None:
            self.navigation.log(encode(navigation_record(t)), ns)
            if t.map is not None or t.navigation.diverting != self._diverting_drawn:
                self._diverting_drawn = t.navigation.diverting
                if t.map is not None:
                    self._map = t.map
                    self._redraw(self.map_regions, region_entities(t.map, ns), ns)
                if self._map is not None:
                    self._redraw(
                        self.map_scene,
                        map_entities(self._map, t.navigation.target_line if t.navigation.diverting else None, ns),
                        ns,
                    )
        for e in t.events:
            self.event(e, ns)
        if ns - self._flushed_ns >= FLUSH_EVERY_NS:
            self.writer.flush()
            self._flushed_ns = ns

    def _redraw(self, channel: SceneUpdateChannel, entities: list[SceneEntity], ns: int) -> None:
        """``entities`` on ``channel``, in place of all it drew before."""
        deleted = [SceneEntityDeletion(timestamp=stamp(ns), type=SceneEntityDeletionType.All)]
        channel.log(SceneUpdate(deletions=deleted, entities=entities), log_time=ns)

    def _pilot_scene(self, t: Tick, ns: int) -> None:
        """``/robot/scene`` every :data:`DRAW_NS`: the Pilot's force arrows and its grown obstacles
        (the forces themselves are in ``/pilot`` every tick)."""
        self._drawn_ns = ns
        ents = [grown(t.pilot.obstacles, t.pose, self._R_min, ns)]
        if t.pilot.arrows:
            ents.append(force_arrows(t.pilot.arrows, ns))
        self.robot_scene.log(SceneUpdate(entities=ents), log_time=ns)

    def event(self, e: Event, ns: int) -> None:
        self.events.log(Log(timestamp=stamp(ns), level=_LEVEL[e.level], message=e.message, name=e.source), log_time=ns)

    def finish(
        self, summary: dict, ns: int, poses: tuple[Pose, Pose] | None = None, *, keep_serving: bool = False
    ) -> Path:
        """Write the summary, close the file and give it its final name. Idempotent.

        ``poses`` (truth, odometry) at ``ns`` are written first if no pose was written at that
        time (a run stopped inside a tick), so the summary's time is always the last pose's.
        ``keep_serving``: a live run's server stays up, its viewers keeping the final state on
        screen, until :meth:`stop_serving` (the log is complete either way)."""
        if self._closed:
            return self.path
        self._closed = True
        self._poses = poses  # what serve_final_state republishes
        try:
            if poses is not None and self.pose_ns != ns:
                self._pose_msgs(*poses, ns, self._pan)
            self.summary.log(encode(msgspec.convert(summary, MissionSummary)), ns)
        finally:
            self.writer.close()
            if not keep_serving:
                self.stop_serving()
            os.replace(self.partial, self.path)
            self.lock.release()
        return self.path

    def serve_final_state(self) -> None:
        """For a live run's viewers after the end (the log is closed, so these reach the server
        only): the state topics and the last poses again at the last log time, and that time, so
        a viewer that joins or seeks then still finds the arena, the robot and where it ended."""
        if self.server is None or self._poses is None:
            return
        ns = self.pose_ns
        self._state(ns)
        self._pose_msgs(*self._poses, ns, self._pan)
        self.server.broadcast_time(ns)

    def stop_serving(self) -> None:
        """Close a live run's server (idempotent; nothing without ``live``)."""
        if self.server is not None:
            server, self.server = self.server, None
            server.stop()
