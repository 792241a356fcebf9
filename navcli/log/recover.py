"""Recovery of a killed run: the complete chunks of its ``.partial`` rewritten into a valid log
marked ``interrupted`` (see :mod:`navcli.log.writer` for why a ``.partial`` is left)."""

from __future__ import annotations

import math
import os
from pathlib import Path

import msgspec

from .. import NavcliError
from ..outputs import atomic
from . import format as fmt
from .format import MissionSummary, encode
from .writer import Lock, LogPathError, check_log_path, schema_of

RECOVERED_REASON = "recovered after an abrupt end"


class RecoverError(NavcliError):
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


def _recover(src: Path, out: Path) -> tuple[Path, dict]:
    from mcap.records import Attachment, Channel, Message, Metadata, Schema
    from mcap.stream_reader import StreamReader
    from mcap.writer import Writer
    from mcap_protobuf.decoder import DecoderFactory

    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    messages: list[Message] = []
    metadata: list[Metadata] = []
    attachments: list[Attachment] = []
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
    if any(topic.get(m.channel_id) == fmt.SUMMARY_TOPIC for m in messages):
        raise RecoverError(f"{src}: already holds a summary; it is a complete log, rename it")
    pose_channel = next((cid for cid, t in topic.items() if t == fmt.POSE_TOPIC), None)
    decode = (
        DecoderFactory().decoder_for("protobuf", schemas[channels[pose_channel].schema_id])
        if pose_channel is not None
        else None
    )
    poses = (
        [(m.log_time, decode(m.data).pose.position) for m in messages if m.channel_id == pose_channel]
        if decode is not None
        else []
    )
    if not poses:
        raise RecoverError(f"{src}: no pose was written before the run died")
    poses.sort(key=lambda tp: tp[0])
    end_ns = poses[-1][0]
    messages = [m for m in messages if m.log_time <= end_ns]
    events = [m for m in messages if topic[m.channel_id] == fmt.EVENTS_TOPIC]
    log_dec = (
        DecoderFactory().decoder_for("protobuf", schemas[channels[events[0].channel_id].schema_id]) if events else None
    )
    summary = {
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
    }
    summary["damaged_bytes"] = lost
    with atomic(out) as tmp, tmp.open("wb") as f:  # a temporary name: never the source, <out>.partial
        w = Writer(f)
        w.start(profile="", library="navcli recover")
        schema_ids = {sid: w.register_schema(s.name, s.encoding, s.data) for sid, s in schemas.items()}
        channel_ids = {
            cid: w.register_channel(c.topic, c.message_encoding, schema_ids.get(c.schema_id, 0), c.metadata)
            for cid, c in channels.items()
        }
        for md in metadata:
            w.add_metadata(md.name, md.metadata)
        for a in attachments:
            w.add_attachment(a.create_time, a.log_time, a.name, a.media_type, a.data)
        for m in messages:
            w.add_message(channel_ids[m.channel_id], m.log_time, m.data, m.publish_time, m.sequence)
        schema = schema_of(MissionSummary)  # the same bytes as a normal log's
        sid = w.register_schema(schema.name, schema.encoding, schema.data)
        cid = w.register_channel(fmt.SUMMARY_TOPIC, "json", sid)
        w.add_message(
            cid,
            end_ns,
            encode(msgspec.convert({k: v for k, v in summary.items() if k != "damaged_bytes"}, MissionSummary)),
            end_ns,
        )
        w.finish()
    return out, summary
