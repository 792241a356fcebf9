"""Read a navcli MCAP log into pandas: one DataFrame per topic, plus the summary and metadata.

This package reads the log format (the README's "The log") and nothing else: it never imports
``navcli``, so it reads logs from any machine or version that wrote the format.

Every DataFrame has ``log_time_ns`` (simulation time, integer nanoseconds) and ``time_s``.
Pose topics (``/robot/pose``, ``/robot/odometry``, ``/tf``) become columns ``x``, ``y`` (m) and
``theta`` (rad); ``/events`` becomes ``level``, ``name``, ``message``; JSON topics are flattened
with dotted column names (``motion.pilot``); scene topics keep the entity ids. Rows are collected
as plain dicts and each topic becomes one DataFrame, so a long log reads in a fraction of a second.
"""

from __future__ import annotations

import json
import math
import os
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

import pandas as pd
import yaml
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from .. import NavcliError
from ..checks.arguments import checked, instance, listing, optional, path, text
from ..log.format import SUMMARY_FIELDS, SUMMARY_TOPIC, TOPIC_SCHEMAS, topic_encoding

POSE_SCHEMAS = ("foxglove.PoseInFrame", "foxglove.FrameTransforms")
INT64 = (-(2**63), 2**63 - 1)
LOG_LEVELS = {0: "unknown", 1: "debug", 2: "info", 3: "warning", 4: "error", 5: "fatal"}
MAGIC = b"\x89MCAP0\r\n"
"""What an MCAP file begins and ends with (the format's magic)."""


class LogError(NavcliError):
    """A file that is not a readable navcli log."""


@dataclass
class RunLog:
    """One run's log: ``topics`` maps topic name to DataFrame; ``summary`` is the
    ``/mission/summary`` record (empty if the run was killed before writing it)."""

    path: Path
    topics: dict[str, pd.DataFrame]
    summary: dict[str, Any]
    metadata: dict[str, dict[str, str]] = field(default_factory=dict)
    attachments: dict[str, bytes] = field(default_factory=dict)

    def __getitem__(self, topic: str) -> pd.DataFrame:
        return self.topics[topic]

    @property
    def scenario(self) -> dict[str, Any]:
        """The run's scenario, parsed from the YAML attached to the log (``{}`` if none is)."""
        if not self.attachments:
            return {}
        return yaml.safe_load(next(iter(self.attachments.values())).decode()) or {}

    @property
    def config(self) -> dict[str, Any]:
        """The run's whole configuration (the ``config`` JSON of the ``run`` metadata: scenario
        name and sha256, seed, pilot, perception, time limit, every parameter); ``{}`` for logs
        written before navcli recorded it."""
        text = self.metadata.get("run", {}).get("config")
        return json.loads(text) if text else {}


def config_columns(config: dict[str, Any]) -> dict[str, Any]:
    """Every parameter of a configuration as a column ``params.<group>.<name>`` (lists as
    tuples), so a table of runs can be grouped by any of them."""
    return {
        f"params.{g}.{k}": tuple(v) if isinstance(v, list) else v
        for g, block in config.get("params", {}).items()
        for k, v in block.items()
    }


def _yaw(q) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def flatten(record: dict) -> dict[str, Any]:
    """``pd.json_normalize(record).iloc[0].to_dict()`` without a frame per message (that was ~85 %
    of a read): the same dotted keys in the same order, the same values. Per record, not one
    ``json_normalize`` per topic, so columns, dtypes and the summary's types stay what they were."""
    top = {k: v for k, v in record.items() if not isinstance(v, dict)}
    nested: dict[str, Any] = {}
    _nest({k: v for k, v in record.items() if isinstance(v, dict)}, "", nested)
    row = {**top, **nested}
    types = {type(v) for v in row.values()}
    if int in types and any(type(v) is int and not INT64[0] <= v <= INT64[1] for v in row.values()):
        return pd.json_normalize(record).iloc[0].to_dict()  # outside int64: leave it to pandas
    if types == {int, float}:  # a one-row frame of ints and floats is all float64
        row = {k: float(v) for k, v in row.items()}
    return row


def _nest(data: dict, key: str, out: dict[str, Any]) -> None:
    for k, v in data.items():
        name = f"{key}.{k}" if key else k
        if isinstance(v, dict):
            _nest(v, name, out)
        else:
            out[name] = v


def _row(schema: str, encoding: str, data: bytes, decoded) -> dict[str, Any]:
    if encoding == "json":
        if not data:
            return {}
        record = json.loads(data)
        return flatten(record) if isinstance(record, dict) else pd.json_normalize(record).iloc[0].to_dict()
    if schema == "foxglove.PoseInFrame":
        p = decoded.pose
        return {"x": p.position.x, "y": p.position.y, "theta": _yaw(p.orientation), "frame_id": decoded.frame_id}
    if schema == "foxglove.FrameTransforms":
        t = decoded.transforms[0]
        return {
            "x": t.translation.x,
            "y": t.translation.y,
            "theta": _yaw(t.rotation),
            "parent": t.parent_frame_id,
            "child": t.child_frame_id,
        }
    if schema == "foxglove.Log":
        return {
            "level": LOG_LEVELS.get(decoded.level, str(decoded.level)),
            "name": decoded.name,
            "message": decoded.message,
        }
    if schema == "foxglove.SceneUpdate":
        return {"entities": [e.id for e in decoded.entities], "deletions": len(decoded.deletions)}
    return {"raw": decoded}


def regular(path: Path) -> Path:
    """``path`` if it is a regular file that can be opened, else :class:`LogError` saying why (a
    device or a pipe would be read without end, or wait for a writer)."""
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        raise LogError(f"{path}: no such file") from None
    except OSError as e:  # a link to itself ...
        raise LogError(f"{path}: cannot be read ({e.strerror or e})") from None
    if stat.S_ISDIR(mode):
        raise LogError(f"{path}: is a folder; give a log file (.mcap)")
    if not stat.S_ISREG(mode):
        raise LogError(f"{path}: is not a regular file (a device, a pipe ...), not a log")
    return path


SUMMARY_NUMBERS = ("seed", "time_s", "path_length_m", "collisions", "camera_looks", "ticks", "diverting_targets")
"""The summary's numeric fields, checked when a log is read (a damaged or foreign summary is refused
by name, not met later as a string in a sum)."""


def whole_mcap(path: Path) -> Path:
    """``path`` if it begins and ends as an MCAP file does, else :class:`LogError` saying what is
    missing: an empty file, another kind of file, or one cut short (its end, the footer that
    indexes it, is missing: ``navcli recover`` rebuilds it from the records before the cut)."""
    with path.open("rb") as f:
        size = os.fstat(f.fileno()).st_size
        head = f.read(len(MAGIC))
        f.seek(max(0, size - len(MAGIC)))
        tail = f.read(len(MAGIC))
    if size == 0:
        raise LogError(f"{path}: an empty file, not a log")
    if head != MAGIC:
        raise LogError(f"{path}: not an MCAP file (it does not begin with MCAP's magic bytes)")
    if tail != MAGIC or size < 2 * len(MAGIC):
        raise LogError(
            f"{path}: cut short: the end of the file (MCAP's footer) is missing, so it cannot be read "
            f"(`navcli recover {path}` rebuilds a log from what it holds)"
        )
    return path


def check_channel(path: Path, topic: str, schema: str, encoding: str) -> None:
    """Refuse (:class:`LogError`) a channel on one of navcli's topics whose schema or encoding is
    not the one navcli writes there (:data:`~navcli.log.format.TOPIC_SCHEMAS`): a log written
    elsewhere under navcli's topic names, which would be misread."""
    want = TOPIC_SCHEMAS.get(topic)
    if want is None:
        return
    ok = schema == want or (want.startswith("navcli.") and schema.startswith(want + "+"))
    if not ok or encoding != topic_encoding(want):
        raise LogError(
            f"{path}: {topic} holds {encoding or 'unencoded'} messages of schema {schema or 'none'!r}, not navcli's "
            f"({topic_encoding(want)} {want}): not a navcli log"
        )


ARGUMENTS = {
    "path": path,
    "topics": optional(listing(text, "topic names", empty=True)),
    "poses": instance(pd.DataFrame, what="a DataFrame of poses (columns x and y)"),
}
"""The arguments of :func:`read_log` and :func:`path_length`, checked at each call."""


@checked(ARGUMENTS, "navcli.analysis")
def read_log(path: str | Path, topics: Iterable[str] | None = None) -> RunLog:
    """Read a run's log.

    Args:
        path: the log's path (an MCAP file navcli wrote).
        topics: read only these topics (``/robot/pose`` ...; the summary always); None: all.

    Returns:
        The log: a DataFrame per topic (columns as docs/log-format.md gives each topic's fields),
        its summary, its configuration and metadata.

    Raises:
        LogError: a file that is no whole MCAP file (:func:`whole_mcap`), has a navcli topic of
            another schema (:func:`check_channel`) or a summary without one of its fields.
    """
    path = whole_mcap(regular(Path(path)))
    rows: dict[str, list[dict]] = {}
    metadata: dict[str, dict[str, str]] = {}
    attachments: dict[str, bytes] = {}
    want = None if topics is None else list(topics) + [SUMMARY_TOPIC]
    try:
        with path.open("rb") as f:
            reader = make_reader(f, decoder_factories=[DecoderFactory()])
            for schema, channel, message, decoded in _decoded(reader, want, path):
                row = _row(schema.name if schema else "", channel.message_encoding, message.data, decoded)
                row["log_time_ns"] = message.log_time
                rows.setdefault(channel.topic, []).append(row)
            for m in reader.iter_metadata():
                metadata[m.name] = dict(m.metadata)
            for a in reader.iter_attachments():
                attachments[a.name] = a.data
    except FileNotFoundError:
        raise LogError(f"{path}: no such file") from None
    except LogError:
        raise
    except Exception as e:  # the mcap reader raises many kinds on a damaged file
        raise LogError(f"{path}: not a readable MCAP log ({type(e).__name__}: {e})") from None
    frames = topic_frames(rows)
    summary_rows = rows.get(SUMMARY_TOPIC, [])
    summary = {k: v for k, v in summary_rows[-1].items() if k != "log_time_ns"} if summary_rows else {}
    lacking = [k for k in SUMMARY_FIELDS if summary and k not in summary]
    if lacking:
        raise LogError(f"{path}: its summary lacks {', '.join(lacking)} (a damaged or foreign log)")
    for k in SUMMARY_NUMBERS:
        v = summary.get(k, 0)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise LogError(f"{path}: its summary's {k} is {v!r}, not a finite number (a damaged or foreign log)")
    return RunLog(path, frames, summary, metadata, attachments)


def topic_frames(rows: dict[str, list[dict]]) -> dict[str, pd.DataFrame]:
    """One DataFrame per topic from its rows (each with ``log_time_ns``), in log-time order, with
    ``time_s``: how :func:`read_log` builds them, and a run kept in memory too
    (:mod:`navcli.log.frames`)."""
    frames = {}
    for topic, rs in rows.items():
        df = pd.DataFrame(rs).sort_values("log_time_ns", kind="stable").reset_index(drop=True)
        df["time_s"] = df["log_time_ns"] / 1e9
        frames[topic] = df
    return frames


class _Decoders:
    """Each channel of a log checked once (:func:`check_channel`), and the decoder of each
    protobuf schema made once; JSON channels have none (their bytes are read as they are)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.factory = DecoderFactory()
        self.decoders: dict[int, Any] = {}
        self.seen: set[int] = set()

    def of(self, schema: Any, channel: Any) -> Any:
        if channel.id not in self.seen:
            self.seen.add(channel.id)
            check_channel(self.path, channel.topic, schema.name if schema else "", channel.message_encoding)
        if channel.message_encoding == "json":
            return None
        dec = self.decoders.get(channel.schema_id)
        if dec is None:
            dec = self.factory.decoder_for(channel.message_encoding, schema)
            if dec is None:
                raise LogError(f"{self.path}: {channel.topic}: no decoder for {channel.message_encoding!r} messages")
            self.decoders[channel.schema_id] = dec
        return dec


def _decoded(reader, topics, path: Path):
    """(schema, channel, message, decoded-or-None): protobuf decoded, JSON left as bytes."""
    decoders = _Decoders(path)
    for schema, channel, message in reader.iter_messages(topics=topics, log_time_order=False):
        dec = decoders.of(schema, channel)
        yield schema, channel, message, None if dec is None else dec(message.data)


def scene_messages(path: str | Path, topic: str, decode: bool = True):
    """``(log time ns, SceneUpdate)`` of every message on a scene ``topic``, in log order; with
    ``decode=False`` the raw bytes and a decoder instead, so a caller that wants one message
    decodes only that one."""
    path = whole_mcap(regular(Path(path)))
    with path.open("rb") as f:
        reader = make_reader(f)
        decoders = _Decoders(path)
        for schema, channel, message in reader.iter_messages(topics=[topic]):
            dec = decoders.of(schema, channel)
            if dec is None:  # a scene is protobuf (check_channel refuses a navcli topic of another encoding)
                raise LogError(f"{path}: {topic}: no decoder for {channel.message_encoding!r} messages")
            yield message.log_time, (dec(message.data) if decode else (dec, message.data))


@checked(ARGUMENTS, "navcli.analysis")
def path_length(poses: pd.DataFrame) -> float:
    """The length of a path.

    Args:
        poses: a pose DataFrame (``/robot/pose``'s): its ``x``, ``y`` columns (m), in order.

    Returns:
        The length of the polyline through them (m).
    """
    dx, dy = poses["x"].diff().fillna(0.0), poses["y"].diff().fillna(0.0)
    return float((dx * dx + dy * dy).pow(0.5).sum())


def require(log: RunLog, *topics: str, scenario: bool = False) -> RunLog:
    """``log`` if it is a complete navcli log with ``topics`` (and, with ``scenario``, its
    scenario attached), else :class:`LogError` listing all that is missing."""
    missing = [] if log.summary else [f"{SUMMARY_TOPIC} (the run never closed its log)"]
    missing += [t for t in topics if t not in log.topics or log.topics[t].empty]
    if "run" not in log.metadata:
        missing.append("the run's metadata (navcli's 'run' record)")
    if scenario and not log.attachments:
        missing.append("the scenario attachment")
    if missing:
        raise LogError(f"{log.path}: not a complete navcli log: no {'; no '.join(missing)}")
    return log
