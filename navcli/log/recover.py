"""Recovery of a killed run: the complete chunks of its ``.partial`` rewritten into a valid log
marked ``interrupted`` (see :mod:`navcli.log.writer` for why a ``.partial`` is left)."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import msgspec

from .. import NavcliError
from ..outputs import atomic
from . import format as fmt
from .format import MissionSummary, encode
from .writer import Lock, LogPathError, check_log_path, schema_of

RECOVERED_REASON = "recovered after an abrupt end"


class RecoverError(NavcliError):
    """A file :func:`recover` cannot make a log of (not an MCAP, no navcli run in it)."""


def recover(partial: str | Path, out: str | Path | None = None, *, overwrite: bool = False) -> tuple[Path, dict]:
    """Rewrite the complete chunks of a killed run's ``.partial`` into a valid log; return its
    path and summary. A log whose run ended but whose file lost its end after the summary (the
    summary section and footer that let a reader open it) is rebuilt as it was, its own summary
    kept; a log that is whole is refused.

    Records are read in order with CRCs checked, up to the first incomplete or damaged one (the
    chunk being written when the process died); schemas, channels, messages, the ``run``
    metadata and the scenario attachment are copied unchanged. A ``/mission/summary`` is added,
    outcome ``interrupted``, reason :data:`RECOVERED_REASON`, at the time of the last pose kept,
    with the path length of the poses kept, the bumper contacts of ``/events``, the images of
    ``/vision`` and the ticks of ``/pilot``, so it agrees with the poses by construction.
    ``out`` defaults to the name without ``.partial`` (or ``-<n>``); an existing file is not
    replaced unless ``overwrite`` (and never the source). The summary's ``damaged_bytes`` (not written to the log) counts the bytes after a
    damaged record that were not the last, unfinished chunk: more than 0 says the file was damaged
    before its end, not only cut short by a kill. A ``.partial`` whose run still holds its lock is
    refused; a lock its SIGKILLed run left is removed."""
    src = Path(partial)
    if out is None:
        stem = src.name.rpartition(".partial")[0] if ".partial" in src.name else src.stem + "-recovered"
        out = src.with_name(stem if stem.endswith(".mcap") else stem + ".mcap")
    out = check_log_path(Path(out), (str(src),), overwrite=overwrite)
    lock = _lock_of_partial(src)
    try:
        return _recover(src, out)
    finally:
        if lock is not None:
            lock.release()  # and a stale lock a SIGKILLed run left is gone with it


def _lock_of_partial(src: Path) -> Lock | None:
    """The lock of the run whose ``.partial`` ``src`` is (refused while that run still writes it)."""
    if not src.name.endswith(".partial"):
        return None  # a .partial-<n> kept aside: no run writes it any more
    try:
        return Lock(src.with_name(src.name[: -len(".partial")] + ".lock"))
    except LogPathError as e:
        if "another run" in str(e):
            raise RecoverError(
                f"{src}: its run is still going (it holds {src.name[: -len('.partial')]}.lock); stop it first"
            ) from None
        return None  # a folder we may not write a lock into: read-only recovery from elsewhere


@dataclass
class Records:
    """What a damaged or cut MCAP file holds, read in order up to its first bad record."""

    schemas: dict[int, Any] = field(default_factory=dict)
    channels: dict[int, Any] = field(default_factory=dict)
    messages: list[Any] = field(default_factory=list)
    metadata: list[Any] = field(default_factory=list)
    attachments: list[Any] = field(default_factory=list)
    lost: int = 0  # bytes after a damaged record that are not the last, unfinished chunk
    end_ns: int = 0  # the last pose's log time: where a recovered run ends


def _read(src: Path) -> Records:
    """The records of ``src``, CRCs checked, up to the first incomplete or damaged one."""
    from mcap.records import Attachment, Channel, Message, Metadata, Schema
    from mcap.stream_reader import StreamReader

    got = Records()
    try:
        with src.open("rb") as f:
            size = os.fstat(f.fileno()).st_size
            try:
                for r in StreamReader(f, validate_crcs=True).records:
                    if isinstance(r, Schema):
                        got.schemas[r.id] = r
                    elif isinstance(r, Channel):
                        got.channels[r.id] = r
                    elif isinstance(r, Message):
                        got.messages.append(r)
                    elif isinstance(r, Metadata):
                        got.metadata.append(r)
                    elif isinstance(r, Attachment):
                        got.attachments.append(r)
            except Exception:  # the record being written when the run died: everything before it is kept
                got.lost = size - f.tell()  # > 0: damage before the end, not only an unfinished last chunk
    except OSError as e:
        raise RecoverError(f"{src}: cannot be read ({e.strerror or e})") from None
    return got


def _readable(src: Path) -> bool:
    """Does the MCAP reader read ``src`` whole (its summary section and footer there)?"""
    from mcap.reader import make_reader

    try:
        with src.open("rb") as f:
            for _ in make_reader(f).iter_messages():
                pass
    except Exception:  # the reader's many errors for a file without its end
        return False
    return True


def _recover(src: Path, out: Path) -> tuple[Path, dict]:
    got = _read(src)
    run = next((m.metadata for m in got.metadata if m.name == "run"), None)
    if run is None or not got.channels:
        raise RecoverError(f"{src}: no navcli run found in it (not a navcli log, or killed before its first chunk)")
    topic = {cid: c.topic for cid, c in got.channels.items()}
    ended = [m for m in got.messages if topic.get(m.channel_id) == fmt.SUMMARY_TOPIC]
    if ended:  # the run closed its log, and the file lost its end after the summary: rebuilt as it was
        if _readable(src):
            raise RecoverError(f"{src}: a complete log (it holds its summary and its end); nothing to recover")
        summary = msgspec.json.decode(ended[-1].data) | {"damaged_bytes": got.lost}
        return _write(out, got, None), summary
    summary = _interrupted(src, got, topic, run)
    return _write(out, got, summary), summary


def _interrupted(src: Path, got: Records, topic: dict[int, str], run: dict) -> dict:
    """The summary of a killed run from what its log kept (the messages after its last pose are
    dropped from ``got``): outcome ``interrupted``, with its ``damaged_bytes``."""
    from mcap_protobuf.decoder import DecoderFactory

    schemas, channels = got.schemas, got.channels
    pose_channel = next((cid for cid, t in topic.items() if t == fmt.POSE_TOPIC), None)
    decode = (
        DecoderFactory().decoder_for("protobuf", schemas[channels[pose_channel].schema_id])
        if pose_channel is not None
        else None
    )
    poses = (
        [(m.log_time, decode(m.data).pose.position) for m in got.messages if m.channel_id == pose_channel]
        if decode is not None
        else []
    )
    if not poses:
        raise RecoverError(f"{src}: no pose was written before the run died")
    poses.sort(key=lambda tp: tp[0])
    got.end_ns = end_ns = poses[-1][0]
    got.messages = messages = [m for m in got.messages if m.log_time <= end_ns]
    events = [m for m in messages if topic[m.channel_id] == fmt.EVENTS_TOPIC]
    log_dec = (
        DecoderFactory().decoder_for("protobuf", schemas[channels[events[0].channel_id].schema_id]) if events else None
    )
    return {
        "scenario": run.get("scenario", ""),
        "seed": int(run.get("seed", 0)),
        "pilot": run.get("pilot", ""),
        "outcome": "interrupted",
        "reason": RECOVERED_REASON,
        "time_s": end_ns / 1e9,
        "path_length_m": sum(math.hypot(b.x - a.x, b.y - a.y) for (_, a), (_, b) in zip(poses, poses[1:])),
        "collisions": sum(
            1 for m in events if log_dec is not None and log_dec(m.data).message.startswith("bumper contact")
        ),
        "camera_looks": sum(
            1 for m in messages if topic[m.channel_id] == fmt.VISION_TOPIC and msgspec.json.decode(m.data).get("image")
        ),
        "ticks": sum(1 for m in messages if topic[m.channel_id] == fmt.PILOT_TOPIC),
        "navcli_version": run.get("navcli_version", ""),
        "run_id": run.get("run_id", ""),
        "damaged_bytes": got.lost,
    }


def _write(out: Path, got: Records, summary: dict | None) -> Path:
    """``got`` as a whole MCAP file at ``out``, with ``summary`` added as the run's
    ``/mission/summary`` at its last pose's time (None: the records hold one already)."""
    from mcap.writer import Writer

    with atomic(out) as tmp, tmp.open("wb") as f:  # a temporary name: never the source, <out>.partial
        w = Writer(f)
        w.start(profile="", library="navcli recover")
        schema_ids = {sid: w.register_schema(s.name, s.encoding, s.data) for sid, s in got.schemas.items()}
        channel_ids = {
            cid: w.register_channel(c.topic, c.message_encoding, schema_ids.get(c.schema_id, 0), c.metadata)
            for cid, c in got.channels.items()
        }
        for md in got.metadata:
            w.add_metadata(md.name, md.metadata)
        for a in got.attachments:
            w.add_attachment(a.create_time, a.log_time, a.name, a.media_type, a.data)
        for m in got.messages:
            w.add_message(channel_ids[m.channel_id], m.log_time, m.data, m.publish_time, m.sequence)
        if summary is not None:
            end_ns = got.end_ns
            schema = schema_of(MissionSummary)  # the same bytes as a normal log's
            sid = w.register_schema(schema.name, schema.encoding, schema.data)
            cid = w.register_channel(fmt.SUMMARY_TOPIC, "json", sid)
            fields = {k: v for k, v in summary.items() if k != "damaged_bytes"}
            w.add_message(cid, end_ns, encode(msgspec.convert(fields, MissionSummary)), end_ns)
        w.finish()
    return out
