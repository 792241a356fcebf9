"""Read a navcli MCAP log into pandas: one DataFrame per topic, plus the summary and metadata.

This package reads the log format (shared/spec/log-format.md) and nothing else: it never imports
``navcli``, so it reads logs from any machine or version that wrote the format.

Every DataFrame has ``log_time_ns`` (simulation time, integer nanoseconds) and ``time_s``.
Pose topics (``/robot/pose``, ``/robot/odometry``, ``/tf``) become columns ``x``, ``y`` (m) and
``theta`` (rad); ``/events`` becomes ``level``, ``name``, ``message``; JSON topics are flattened
with dotted column names (``motion.pilot``); scene topics keep the entity ids.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

import pandas as pd
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

POSE_SCHEMAS = ("foxglove.PoseInFrame", "foxglove.FrameTransforms")
LOG_LEVELS = {0: "unknown", 1: "debug", 2: "info", 3: "warning", 4: "error", 5: "fatal"}


class LogError(ValueError):
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


def _yaw(q) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _row(schema: str, encoding: str, data: bytes, decoded) -> dict[str, Any]:
    if encoding == "json":
        return pd.json_normalize(json.loads(data)).iloc[0].to_dict() if data else {}
    if schema == "foxglove.PoseInFrame":
        p = decoded.pose
        return {"x": p.position.x, "y": p.position.y, "theta": _yaw(p.orientation), "frame_id": decoded.frame_id}
    if schema == "foxglove.FrameTransforms":
        t = decoded.transforms[0]
        return {"x": t.translation.x, "y": t.translation.y, "theta": _yaw(t.rotation),
                "parent": t.parent_frame_id, "child": t.child_frame_id}
    if schema == "foxglove.Log":
        return {"level": LOG_LEVELS.get(decoded.level, str(decoded.level)), "name": decoded.name,
                "message": decoded.message}
    if schema == "foxglove.SceneUpdate":
        return {"entities": [e.id for e in decoded.entities], "deletions": len(decoded.deletions)}
    return {"raw": decoded}


def read_log(path: str | Path, topics: Iterable[str] | None = None) -> RunLog:
    """Read ``path`` into a :class:`RunLog` (only ``topics`` if given)."""
    path = Path(path)
    rows: dict[str, list[dict]] = {}
    metadata: dict[str, dict[str, str]] = {}
    attachments: dict[str, bytes] = {}
    want = None if topics is None else list(topics) + ["/mission/summary"]
    try:
        with path.open("rb") as f:
            reader = make_reader(f, decoder_factories=[DecoderFactory()])
            for schema, channel, message, decoded in _decoded(reader, want):
                row = _row(schema.name if schema else "", channel.message_encoding, message.data, decoded)
                row["log_time_ns"] = message.log_time
                rows.setdefault(channel.topic, []).append(row)
            for m in reader.iter_metadata():
                metadata[m.name] = dict(m.metadata)
            for a in reader.iter_attachments():
                attachments[a.name] = a.data
    except FileNotFoundError:
        raise LogError(f"{path}: no such file") from None
    except Exception as e:  # the mcap reader raises many kinds on a damaged file
        raise LogError(f"{path}: not a readable MCAP log ({type(e).__name__}: {e})") from None
    frames = {}
    for topic, rs in rows.items():
        df = pd.DataFrame(rs).sort_values("log_time_ns", kind="stable").reset_index(drop=True)
        df["time_s"] = df["log_time_ns"] / 1e9
        frames[topic] = df
    summary_rows = rows.get("/mission/summary", [])
    summary = {k: v for k, v in summary_rows[-1].items() if k != "log_time_ns"} if summary_rows else {}
    return RunLog(path, frames, summary, metadata, attachments)


def _decoded(reader, topics):
    """(schema, channel, message, decoded-or-None): protobuf decoded, JSON left as bytes."""
    factory = DecoderFactory()
    decoders: dict[int, Any] = {}
    for schema, channel, message in reader.iter_messages(topics=topics, log_time_order=False):
        if channel.message_encoding == "json":
            yield schema, channel, message, None
            continue
        dec = decoders.get(channel.schema_id)
        if dec is None:
            dec = factory.decoder_for(channel.message_encoding, schema)
            decoders[channel.schema_id] = dec
        yield schema, channel, message, dec(message.data)


def path_length(poses: pd.DataFrame) -> float:
    """Length in metres of the polyline through ``x``, ``y`` of a pose DataFrame."""
    dx, dy = poses["x"].diff().fillna(0.0), poses["y"].diff().fillna(0.0)
    return float((dx * dx + dy * dy).pow(0.5).sum())
