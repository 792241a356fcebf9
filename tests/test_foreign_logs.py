"""Logs from elsewhere: any file that is not a complete navcli log is refused by ``report``,
``plot map`` and ``render`` with exit 2 and what is missing, never a traceback; ``recover``
rebuilds a log cut short after its summary. The foreign MCAPs are written here with the ``mcap``
library's writer, small."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from mcap.writer import Writer
from typer.testing import CliRunner

from navcli.cli import app
from navcli.log import format as fmt

COMMANDS = {
    "report": lambda log, tmp: ["report", str(log.parent), "--out", str(tmp / "report")],
    "plot map": lambda log, tmp: ["plot", "map", str(log), "--out", str(tmp / "map.png")],
    "render": lambda log, tmp: ["render", str(log), "--out", str(tmp / "run.gif")],
}


def cli(*args: str):
    r = CliRunner().invoke(app, list(args))
    assert "Traceback" not in r.output and "internal error" not in r.output, r.output
    return r


@pytest.fixture(scope="module")
def good_log(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("good") / "run.mcap"
    r = cli("run", "open-arena", "--time-limit", "2", "--out", str(out))
    assert r.exit_code == 3 and out.exists(), r.output  # a timeout: the log is complete
    return out


def mcap(path: Path, channels: dict[str, tuple[str, str, list[dict]]], run: bool = True) -> Path:
    """An MCAP at ``path``: per topic (schema name, message encoding, JSON messages), each
    message at 0.1 s after the last; with ``run``, navcli's ``run`` metadata."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as f:
        w = Writer(f)
        w.start(profile="", library="somebody else")
        for topic, (schema, encoding, messages) in channels.items():
            sid = w.register_schema(schema, "jsonschema", json.dumps({"type": "object"}).encode())
            cid = w.register_channel(topic, encoding, sid)
            for i, m in enumerate(messages):
                w.add_message(cid, (i + 1) * 100_000_000, json.dumps(m).encode(), (i + 1) * 100_000_000)
        if run:
            w.add_metadata("run", {"scenario": "open-arena", "seed": "1", "pilot": "geometric"})
        w.finish()
    return path


SUMMARY = {
    "scenario": "open-arena",
    "seed": 1,
    "pilot": "geometric",
    "outcome": "timeout",
    "reason": "time limit",
    "time_s": 0.2,
    "path_length_m": 0.0,
    "collisions": 0,
    "camera_looks": 0,
    "ticks": 2,
    "navcli_version": "0.1.0",
    "run_id": "ab",
}


def generic_json(path: Path) -> Path:
    """navcli's topic names, generic JSON schemas: the log of some other tool."""
    pose = [{"x": 0.0, "y": 0.0, "theta": 0.0}, {"x": 0.1, "y": 0.0, "theta": 0.0}]
    return mcap(
        path,
        {
            fmt.POSE_TOPIC: ("Pose", "json", pose),
            fmt.MAP_SCENE_TOPIC: ("Scene", "json", [{"entities": []}]),
            fmt.PILOT_TOPIC: ("Pilot", "json", [{}]),
            fmt.BIDS_TOPIC: ("Bids", "json", [{}]),
            fmt.SUMMARY_TOPIC: ("Summary", "json", [SUMMARY]),
        },
    )


def no_navcli_topics(path: Path) -> Path:
    return mcap(path, {"/chatter": ("Chat", "json", [{"text": "hello"}])}, run=False)


def summary_lacks_fields(path: Path) -> Path:
    """navcli's schema names, a summary without most of its fields."""
    return mcap(path, {fmt.SUMMARY_TOPIC: ("navcli.MissionSummary", "json", [{"outcome": "reached"}])})


def cut(good: Path, path: Path, keep: float) -> Path:
    data = good.read_bytes()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data[: int(len(data) * keep)])
    return path


FILES = {
    "generic JSON schemas on navcli's topics": (generic_json, "not navcli's"),
    "an empty file": (lambda p: (p.parent.mkdir(parents=True), p.write_bytes(b""), p)[-1], "an empty file"),
    "a text file": (lambda p: (p.parent.mkdir(parents=True), p.write_text("x,y\n1,2\n"), p)[-1], "not an MCAP file"),
    "no navcli topics": (no_navcli_topics, "not a complete navcli log: no /mission/summary"),
    "a summary lacking fields": (summary_lacks_fields, "its summary lacks scenario, seed, pilot, reason"),
}


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("case", FILES)
def test_a_file_that_is_no_navcli_log_is_refused_saying_what_is_missing(tmp_path, command, case):
    make, words = FILES[case]
    log = make(tmp_path / "logs" / "x.mcap")
    r = cli(*COMMANDS[command](log, tmp_path))
    assert r.exit_code == 2, r.output
    assert words in r.output, r.output
    assert not (tmp_path / "map.png").exists() and not (tmp_path / "run.gif").exists()


@pytest.mark.parametrize("command", COMMANDS)
def test_a_log_cut_short_is_refused_naming_recover(tmp_path, good_log, command):
    log = cut(good_log, tmp_path / "logs" / "x.mcap", 0.6)
    r = cli(*COMMANDS[command](log, tmp_path))
    assert r.exit_code == 2, r.output
    assert "cut short" in r.output and "navcli recover" in r.output, r.output


def test_the_topic_schemas_declared_are_those_a_run_writes(good_log):
    from mcap.reader import make_reader

    with good_log.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    written = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
    assert written == {t: s for t, s in fmt.TOPIC_SCHEMAS.items() if t in written}
    assert {fmt.POSE_TOPIC, fmt.PILOT_TOPIC, fmt.SUMMARY_TOPIC} <= written.keys()


def _tail_cut(good: Path, path: Path) -> Path:
    """``good`` without its last bytes: the footer and closing magic gone, the summary message
    (in the last chunk, before the summary section) kept."""
    data = good.read_bytes()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data[:-20])
    return path


def test_recover_rebuilds_a_log_cut_after_its_summary(tmp_path, good_log):
    from navcli.analysis import read_log

    log = _tail_cut(good_log, tmp_path / "logs" / "cut.mcap")
    assert cli("render", str(log), "--out", str(tmp_path / "a.gif")).exit_code == 2  # unreadable as it is
    r = cli("recover", str(log), "--out", str(tmp_path / "fixed.mcap"))
    assert r.exit_code == 0, r.output
    assert "outcome timeout" in r.output, r.output
    fixed, original = read_log(tmp_path / "fixed.mcap"), read_log(good_log)
    assert fixed.summary == original.summary  # its own summary kept, not an "interrupted" one made up
    assert fixed.topics.keys() == original.topics.keys()
    assert fixed[fmt.POSE_TOPIC].equals(original[fmt.POSE_TOPIC])
    assert log.read_bytes() == good_log.read_bytes()[:-20]  # the source is left as it was


def test_recover_refuses_a_whole_log_and_keeps_refusing_to_overwrite(tmp_path, good_log):
    log = shutil.copy(good_log, tmp_path / "whole.mcap")
    r = cli("recover", str(log))
    assert r.exit_code == 2 and "a complete log" in r.output and "nothing to recover" in r.output, r.output
    assert "--out" not in r.output  # a refusal of the input, not of the output
    cut_log = _tail_cut(good_log, tmp_path / "cut.mcap")
    r = cli("recover", str(cut_log), "--out", str(log))
    assert r.exit_code == 2 and f"error: --out: {log}: exists" in r.output and "--force" in r.output, r.output
    assert Path(log).read_bytes() == good_log.read_bytes()
    assert cli("recover", str(cut_log), "--out", str(log), "--force").exit_code == 0
