"""The JSON messages of the log (the README's "The log"): one definition per message, from which
its JSON Schema is derived.

Each message is defined as a ``msgspec.Struct``, and :func:`json_schema` derives the schema
written into the log from that class. The recorder writes each tick's messages as plain values
(dicts keyed by the Struct's field names), which ``encode`` writes directly (by
measurement on paper-8x8: the four per-tick messages cost about 60 µs a tick converted to Structs
with ``msgspec.convert`` first, about 38 as plain values). So nothing checks a message against its
Struct while a run writes it; ``tests/test_messages.py`` checks every JSON message of real runs
against its schema instead.

msgspec's schemas use ``$ref``/``$defs``, enums without a ``type`` and maps without ``properties``;
Foxglove's JSON-schema parser accepts none of these, so :func:`json_schema` inlines the references,
types the enums and gives every map an empty ``properties`` (the rules of that parser
are checked by ``tests/test_messages.py``).

Fixed shapes are closed (``additionalProperties: false``); maps keyed by an obstacle's or a
detection's id are open. No message holds a null: an absent value is an absent key.
Units are in each field's description. Force units are those of the pilot paper's eq. 2-6.
"""

from __future__ import annotations

import functools
import typing
from typing import Annotated, Any, Mapping, Protocol, Sequence

import msgspec
from msgspec import UNSET, Meta, Struct, UnsetType


FORMAT_VERSION = 1
"""The version of the log's format (its topics and their JSON messages), written into every log's
``run`` metadata as ``log_format``. Any change to a message's schema makes a new version: the
schemas of each version are checked in (:mod:`navcli.log.published`), and the tests fail while
the code's differ from the current version's."""

# The topics of the log: each name is written here once, and every writer and reader uses these.
TF_TOPIC = "/tf"  # foxglove.FrameTransforms: world -> base_link (the true pose), base_link -> camera (the pan)
POSE_TOPIC = "/robot/pose"  # foxglove.PoseInFrame: the true pose
ODOMETRY_TOPIC = "/robot/odometry"  # foxglove.PoseInFrame: what the robot believes
WORLD_SCENE_TOPIC = "/world/scene"  # foxglove.SceneUpdate: the arena
ROBOT_SCENE_TOPIC = "/robot/scene"  # foxglove.SceneUpdate: the Pilot's forces and grown obstacles
ROBOT_BODY_TOPIC = "/robot/body"  # foxglove.SceneUpdate: the robot's body
CAMERA_SCENE_TOPIC = "/robot/camera"  # foxglove.SceneUpdate: the camera's field of view
ROBOT_PATH_TOPIC = "/robot/path"  # foxglove.SceneUpdate: the path driven so far (ground truth)
MEMORY_SCENE_TOPIC = "/memory/scene"  # foxglove.SceneUpdate: the visual memory (70 % cuts)
MEMORY_SUPPORTS_TOPIC = "/memory/supports"  # foxglove.SceneUpdate: the visual memory's supports
MAP_SCENE_TOPIC = (
    "/map/scene"  # foxglove.SceneUpdate: the Map Manager's map (landmarks, blocked edges, diverting lines)
)
MAP_REGIONS_TOPIC = "/map/regions"  # foxglove.SceneUpdate: the map's regions and beta-units
EVENTS_TOPIC = "/events"  # foxglove.Log
PILOT_TOPIC = "/pilot"  # navcli.Pilot
BIDS_TOPIC = "/bids"  # navcli.Bids
VISION_TOPIC = "/vision"  # navcli.Vision
NAVIGATION_TOPIC = "/navigation"  # navcli.Navigation
SUMMARY_TOPIC = "/mission/summary"  # navcli.MissionSummary
_SCENE = "foxglove.SceneUpdate"
TOPIC_SCHEMAS = {
    TF_TOPIC: "foxglove.FrameTransforms",
    POSE_TOPIC: "foxglove.PoseInFrame",
    ODOMETRY_TOPIC: "foxglove.PoseInFrame",
    WORLD_SCENE_TOPIC: _SCENE,
    ROBOT_SCENE_TOPIC: _SCENE,
    ROBOT_BODY_TOPIC: _SCENE,
    CAMERA_SCENE_TOPIC: _SCENE,
    ROBOT_PATH_TOPIC: _SCENE,
    MEMORY_SCENE_TOPIC: _SCENE,
    MEMORY_SUPPORTS_TOPIC: _SCENE,
    MAP_SCENE_TOPIC: _SCENE,
    MAP_REGIONS_TOPIC: _SCENE,
    EVENTS_TOPIC: "foxglove.Log",
    PILOT_TOPIC: "navcli.Pilot",
    BIDS_TOPIC: "navcli.Bids",
    VISION_TOPIC: "navcli.Vision",
    NAVIGATION_TOPIC: "navcli.Navigation",
    SUMMARY_TOPIC: "navcli.MissionSummary",
}
"""The schema of each topic, by name: Foxglove's (``foxglove.*``, protobuf messages) or navcli's
(``navcli.*``, JSON messages; a plugin pilot's ``/pilot`` is ``navcli.Pilot+<name>``). What a
reader checks a log from elsewhere against (:func:`topic_encoding`)."""


def topic_encoding(schema: str) -> str:
    """The message encoding of a topic whose schema is ``schema`` (:data:`TOPIC_SCHEMAS`)."""
    return "json" if schema.startswith("navcli.") else "protobuf"


ENUM = "x-navcli-enum"
"""Marks a field (in its schema) whose values are an enumeration declared by the code that produces
them (the Rescuer's states, the Pilot's modes ...), never here: :func:`json_schema` given ``enums``
turns the mark into an ``enum`` of those values, and the recorder gives it the producers'
(:data:`navcli.log.writer.ENUMS`)."""


def enumerated(name: str, description: str) -> Meta:
    """The ``Meta`` of a text field whose values are the enumeration ``name`` (see :data:`ENUM`):
    ``Annotated[str, enumerated("rescuer.state", "the Rescuer's state")]``."""
    return Meta(description=description, extra_json_schema={ENUM: name})


DEG = Annotated[float, Meta(description="degrees; 0 = straight ahead, positive to the left (egocentric)")]
BID = Annotated[float, Meta(ge=0.0, le=1.0, description="bid in [0, 1]")]
FORCE = Annotated[float, Meta(description="force units (eq. 2-6 of the pilot paper), egocentric: x ahead, y left")]


class _Msg(Struct, forbid_unknown_fields=True, omit_defaults=False):
    pass


# --- /pilot -----------------------------------------------------------------------------------
class Vector(_Msg):
    """A virtual force, egocentric (x ahead, y to the left), in force units."""

    x: FORCE
    y: FORCE


class ObstacleForce(_Msg):
    """The repulsion of one remembered obstacle (eq. 2-4)."""

    x: FORCE
    y: FORCE
    mag: Annotated[float, Meta(description="magnitude, force units")]
    facing: Annotated[bool, Meta(description="the obstacle is not occluded and counts in the net force")]


class Command(_Msg):
    """The wheel command sent this tick."""

    v: Annotated[float, Meta(description="forward speed, m/s (negative: backwards)")]
    omega_deg: Annotated[float, Meta(description="turn rate, deg/s, positive to the left")]


class Pilot(_Msg):
    """The Pilot's decision this tick and the quantities behind it. Every pilot writes mode, bid,
    look_bid and command; the potential-field pilot adds the forces (turn_deg ... obstacles,
    in_corridor on a target line), the geometric pilot its rule (nearest, clearance, rule, side,
    turn_deg); a reflex (section 3.5) writes its phase."""

    mode: Annotated[
        str,
        enumerated(
            "pilot.mode",
            "avoid: the pilot proposes a move; idle: it proposes none; reflex: section 3.5 after a bump or stall",
        ),
    ]
    bid: Annotated[
        float,
        Meta(ge=0.0, le=1.0, description="the pilot's motion bid in [0, 1] (eq. 9 for the potential-field pilot)"),
    ]
    look_bid: Annotated[float, Meta(ge=0.0, le=1.0, description="the pilot's look-ahead camera bid in [0, 1] (eq. 1)")]
    command: Command
    phase: Annotated[str, enumerated("pilot.phase", "the reflex's phase")] | UnsetType = UNSET
    turn_deg: (
        Annotated[float, Meta(description="the turn the pilot asks for, degrees, positive to the left")] | UnsetType
    ) = UNSET
    raw_turn_deg: (
        Annotated[float, Meta(description="eq. 7's angle before section 5's mean with the previous, degrees")]
        | UnsetType
    ) = UNSET
    in_distress: Annotated[bool, Meta(description="inside a prohibited area (grown obstacle)")] | UnsetType = UNSET
    passed: Annotated[bool, Meta(description="section 5: repulsion from obstacles behind was dropped")] | UnsetType = (
        UNSET
    )
    g_max: Annotated[float, Meta(description="the largest obstacle force, force units (eq. 9)")] | UnsetType = UNSET
    net: Vector | UnsetType = UNSET
    target: Vector | UnsetType = UNSET
    repulsive: Vector | UnsetType = UNSET
    obstacles: (
        Annotated[dict[str, ObstacleForce], Meta(description="per remembered obstacle, by its memory key")] | UnsetType
    ) = UNSET
    in_corridor: (
        Annotated[bool, Meta(description="section 3.3: inside the safe corridor of a target line")] | UnsetType
    ) = UNSET
    nearest: Annotated[str, Meta(description="memory key of the nearest prohibited area")] | UnsetType = UNSET
    clearance: (
        Annotated[float, Meta(description="m from the robot's centre to that area's edge (negative: inside)")]
        | UnsetType
    ) = UNSET
    rule: Annotated[str, enumerated("geometric.rule", "the geometric pilot's rule this tick")] | UnsetType = UNSET
    side: Annotated[str, enumerated("geometric.side", "the side the geometric pilot passes on")] | UnsetType = UNSET
    blocked_by: (
        Annotated[
            str,
            Meta(
                description=(
                    "memory key of the long obstacle ahead that the field cannot lead round this tick; with "
                    "pilot.blocked_report_m set, reported to the Navigation system once it has lasted the time to drive that far"
                )
            ),
        ]
        | UnsetType
    ) = UNSET


@functools.lru_cache(maxsize=None)
def pilot_message_type(info: type[Struct] | None = None, name: str = "", about: str = "") -> type[Struct]:
    """The ``/pilot`` message of a run whose pilot declares ``info``: :class:`Pilot` with the
    fields of ``info`` (a plugin's ``Info``, a ``msgspec.Struct``) added, each optional, so the
    log's schema says what the plugin writes; ``name`` titles it (``navcli.Pilot+vfh``) and
    ``about`` (the plugin's identity) goes into its description. :class:`Pilot` itself without one.
    Raises ``ValueError`` for a field that /pilot has already."""
    if info is None:
        return Pilot
    hints = typing.get_type_hints(info, include_extras=True)
    clash = sorted(set(hints) & set(Pilot.__struct_fields__))
    if clash:
        raise ValueError(f"its Info declares {', '.join(clash)}, which /pilot has already")
    merged = msgspec.defstruct(
        f"Pilot+{name}",
        [(k, typing.Union[t, UnsetType], UNSET) for k, t in hints.items()],
        bases=(Pilot,),
        forbid_unknown_fields=True,
        module=__name__,
    )
    merged.__doc__ = (
        f"{Pilot.__doc__} The fields {', '.join(hints)} are the {name} pilot's own, declared by the plugin ({about})."
    )
    return merged


class PilotPlugin(Protocol):
    """What the log needs of a pilot to declare its ``/pilot`` messages (a
    :class:`navcli.plugins.Component` is one): its ``Info`` (None for navcli's own pilots), the name
    its message is titled by, and where it came from and its version, which the schema cites."""

    @property
    def info_class(self) -> Any: ...

    @property
    def group(self) -> str: ...

    @property
    def origin(self) -> str: ...

    @property
    def version(self) -> str: ...


def plugin_pilot_message(pilot: PilotPlugin) -> type[Struct]:
    """The ``/pilot`` message of the runs of ``pilot``: :func:`pilot_message_type` of its ``Info``,
    titled by its name, its origin and version in the description."""
    return pilot_message_type(pilot.info_class, pilot.group, f"{pilot.origin}, version {pilot.version}")


def viewer_problems(schema: dict, path: str = "") -> list[str]:
    """Why Foxglove's ``parseJsonSchema`` (mcap-support) would refuse ``schema``, the viewer then
    dropping its whole topic: the root and every nested object needs ``"type": "object"`` and a
    ``properties`` object; each property one ``type`` among boolean, number, integer, string
    (base64 contentEncoding only), object, array (of those) or a ``oneOf`` of number constants.
    Empty: the viewer reads it."""
    if not isinstance(schema, dict) or schema.get("type") != "object":
        return [f'{path or "root"}: not "type": "object"']
    if not isinstance(schema.get("properties"), dict):
        return [f"{path or 'root'}: object without properties"]
    out = []
    for name, f in schema["properties"].items():
        at = f"{path}.{name}" if path else name
        if "oneOf" in f:
            if not all(isinstance(a.get("const"), (int, float)) for a in f["oneOf"]):
                out.append(f"{at}: oneOf alternatives must be number constants")
            continue
        kind = f.get("type")
        if kind in ("boolean", "number", "integer"):
            continue
        if kind == "string":
            if f.get("contentEncoding", "base64") != "base64":
                out.append(f"{at}: unsupported contentEncoding")
        elif kind == "object":
            out += viewer_problems(f, at)
        elif kind == "array":
            item = f.get("items", {})
            if item.get("type") == "object":
                out += viewer_problems(item, at)
            elif item.get("type") not in ("boolean", "number", "integer", "string"):
                out.append(f"{at}: unsupported array item type {item.get('type')!r}")
        else:
            out.append(f"{at}: unsupported type {kind!r}")
    return out


def pilot_message(info: dict[str, Any], v: float, omega_deg: float) -> dict[str, Any]:
    """The ``/pilot`` message (a :class:`Pilot` as plain values) from a pilot's explanation dict
    (``PilotOutput.info``, keyed by Pilot's fields) and the wheel command. ``None`` values are
    left out."""
    msg = {k: x for k, x in info.items() if x is not None}
    msg["command"] = {"v": v, "omega_deg": omega_deg}
    return msg


# --- /bids ------------------------------------------------------------------------------------
class Action(_Msg):
    """A bid's action: a move (heading_deg, speed) or a look (pan_deg)."""

    type: Annotated[str, enumerated("action.type", "what the action is")]
    heading_deg: DEG | UnsetType = UNSET
    speed: Annotated[float, Meta(description="m/s, negative backwards")] | UnsetType = UNSET
    pan_deg: (
        Annotated[float, Meta(description="camera pan, degrees from the heading, positive to the left")] | UnsetType
    ) = UNSET
    purpose: (
        Annotated[str, enumerated("look.purpose", "a look's purpose: the image-processing routine it asks for")]
        | UnsetType
    ) = UNSET


class ResourceBids(_Msg):
    """One resource's auction: each system's bid (0 when it did not bid), the winner, the actions."""

    pilot: BID
    navigation: BID
    actions: Annotated[dict[str, Action], Meta(description="the action each bidding system offered, by system")]
    winner: Annotated[str, Meta(description="the system that won (absent: nobody bid)")] | UnsetType = UNSET


class Bids(_Msg):
    """Per resource, every system's bid, the winner and the actions; ``agents`` holds the
    Navigation agents' bids to their Communicator (agent -> resource -> bid in [0, 1])."""

    motion: ResourceBids
    camera: ResourceBids
    agents: dict[str, dict[str, BID]]


# --- /vision ----------------------------------------------------------------------------------
class Cuts(_Msg):
    """A fuzzy number by its cuts: lo0/hi0 the support, lo70/hi70 the 70 % cut, core its middle."""

    lo0: float
    lo70: float
    core: float
    hi70: float
    hi0: float


class Sighting(_Msg):
    """One measured point, egocentric."""

    heading_deg: Annotated[Cuts, Meta(description="degrees, positive to the left")]
    distance_m: Annotated[Cuts, Meta(description="m")]


class DetectionMsg(_Msg):
    """What one image showed of one object: one point, or the two extremities of a linear
    obstacle in view."""

    kind: Annotated[str, enumerated("detection.kind", "what the image showed")]
    points: list[Sighting]
    ends: (
        Annotated[
            list[bool],
            Meta(
                description=(
                    "an identified linear obstacle: per end (a, b), whether the point seen toward it is the end itself "
                    "(false: where the view cut the obstacle, which goes on past it)"
                )
            ),
        ]
        | UnsetType
    ) = UNSET


class Vision(_Msg):
    """The camera each tick: pan, state, and the detections of an image taken this tick."""

    pan_deg: Annotated[float, Meta(description="degrees from the heading, positive to the left")]
    state: Annotated[str, enumerated("camera.state", "the camera: free, turning to a pan, or processing an image")]
    image: Annotated[bool, Meta(description="an image was taken this tick")]
    detections: Annotated[
        dict[str, DetectionMsg],
        Meta(
            description="by landmark id, target marker, segment:<key> or wall:<key> for an identified linear obstacle, "
            "or obstacle<i> for an unidentified obstacle"
        ),
    ]
    purpose: (
        Annotated[
            str,
            enumerated(
                "look.purpose",
                "what the look being carried out is for, the image-processing routine it runs (absent: idle)",
            ),
        ]
        | UnsetType
    ) = UNSET


# --- /mission/summary -------------------------------------------------------------------------
class LearningSummary(_Msg):
    """What the Learning Agent (or the hand-coded policy) did: actions taken, their total reward
    (learning-agent paper, section 5.3) and the count of each action."""

    actions: int
    reward: float
    action_counts: Annotated[dict[str, int], Meta(description="by action: MB, MLL, MOT, MVL, MVT")]


class MissionSummary(_Msg):
    """How the mission ended."""

    scenario: str
    seed: int
    pilot: str
    outcome: Annotated[str, enumerated("mission.outcome", "how the mission ended")]
    reason: str
    time_s: Annotated[float, Meta(description="simulated seconds")]
    path_length_m: Annotated[float, Meta(description="m driven (ground truth)")]
    collisions: Annotated[int, Meta(description="bumper contacts")]
    camera_looks: Annotated[int, Meta(description="images taken")]
    ticks: Annotated[int, Meta(description="control ticks of 0.1 s")]
    navcli_version: str
    run_id: Annotated[str, Meta(description="sha256 of the run configuration (hex)")]
    diverting_targets: Annotated[int, Meta(description="diverting targets the Rescuer set")] = 0
    navigation: Annotated[
        str, Meta(description="who chose the Navigation system's actions: agents, hand-coded, learned[:FILE]")
    ] = "agents"
    learning: (
        Annotated[LearningSummary, Meta(description="the Learning Agent's or hand-coded policy's actions and reward")]
        | UnsetType
    ) = UNSET


# --- /navigation ------------------------------------------------------------------------------
class AgentBid(_Msg):
    """One Navigation agent's bids this tick (0 where it did not bid)."""

    motion: BID = 0.0
    camera: BID = 0.0


class Forwarded(_Msg):
    """What the Communicator forwarded as the Navigation system's bids, and whose they were."""

    motion: BID = 0.0
    camera: BID = 0.0
    motion_agent: Annotated[str, Meta(description="the agent whose motion bid won (absent: none)")] | UnsetType = UNSET
    camera_agent: Annotated[str, Meta(description="the agent whose look bid won (absent: none)")] | UnsetType = UNSET


class XY(_Msg):
    """A point, egocentric (x ahead, y to the left), m."""

    x: float
    y: float


class Navigation(_Msg):
    """The Navigation system this tick: every agent's bids, what the Communicator forwarded, the
    target's imprecision I_a, the Risk Manager's risk R and qualities, the current target (a
    diverting one while the Rescuer holds one) and the Rescuer's state."""

    agents: Annotated[dict[str, AgentBid], Meta(description="by agent")]
    forwarded: Forwarded
    I_a: Annotated[float, Meta(ge=0.0, le=1.0, description="the target's heading imprecision (eps / 2 pi) ** beta")]
    risk: Annotated[float, Meta(ge=0.0, le=1.0, description="the Risk Manager's R")]
    quality_ahead: Annotated[float, Meta(description="q_S of the landmarks ahead, max(1 - Col) over triples")]
    quality_around: Annotated[float, Meta(description="q_S of all known landmarks")]
    landmarks_known: Annotated[int, Meta(description="landmarks in the visual memory")]
    landmarks_ahead: int
    target_source: Annotated[str, Meta(description="memory, map:<beta-unit>, line, or none")]
    rescuer: Annotated[str, enumerated("rescuer.state", "the Rescuer's state")]
    diverting: Annotated[bool, Meta(description="the current target is a diverting target")]
    diverting_targets: Annotated[int, Meta(description="diverting targets set so far")]
    failures: Annotated[int, Meta(description="diverting targets failed so far")]
    beta_units: Annotated[int, Meta(description="units in the beta-coefficient map")]
    target: Annotated[XY, Meta(description="the current target, egocentric")] | UnsetType = UNSET
    line_a: Annotated[XY, Meta(description="a line target's left end, egocentric")] | UnsetType = UNSET
    line_b: Annotated[XY, Meta(description="a line target's right end, egocentric")] | UnsetType = UNSET


MESSAGES: dict[str, type[Struct]] = {
    PILOT_TOPIC: Pilot,
    BIDS_TOPIC: Bids,
    VISION_TOPIC: Vision,
    SUMMARY_TOPIC: MissionSummary,
    NAVIGATION_TOPIC: Navigation,
}
"""The JSON topics of the log and their message types."""

encode = msgspec.json.Encoder().encode
"""Compact JSON of a message (msgspec writes NaN and infinity as null, which the schemas refuse)."""


def json_schema(cls: type[Struct], enums: Mapping[str, Sequence[str]] | None = None) -> dict[str, Any]:
    """The JSON Schema of ``cls`` as Foxglove's parser accepts it, titled ``navcli.<Name>``; with
    ``enums`` (enumeration name -> values), every :func:`enumerated` field gets its ``enum``
    (``KeyError`` for one it does not give); without, such a field is plain text."""
    raw = msgspec.json.schema(cls)
    defs = raw.get("$defs", {})

    def fix(node: dict[str, Any]) -> dict[str, Any]:
        if "$ref" in node:
            node = defs[node["$ref"].rsplit("/", 1)[1]] | {k: v for k, v in node.items() if k != "$ref"}
        out = {k: v for k, v in node.items() if k not in ("title", "default", "$defs", ENUM)}
        if ENUM in node and enums is not None:
            out["enum"] = list(enums[node[ENUM]])
        if "properties" in out:
            out["properties"] = {k: fix(v) for k, v in out["properties"].items()}
        for key in ("additionalProperties", "items"):
            if isinstance(out.get(key), dict):
                out[key] = fix(out[key])
        if "description" in out:
            out["description"] = " ".join(out["description"].split())  # docstrings' line breaks
        if "enum" in out and "type" not in out:
            out["type"] = "string" if all(isinstance(v, str) for v in out["enum"]) else "number"
        if out.get("type") == "object" and "properties" not in out:
            out["properties"] = {}
        return out

    schema = fix(raw)
    return {"title": f"navcli.{cls.__name__}"} | schema


SUMMARY_FIELDS = tuple(f.name for f in msgspec.structs.fields(MissionSummary) if f.required)
"""The fields every ``/mission/summary`` holds (the others have defaults): what a reader requires."""
