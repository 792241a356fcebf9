"""Every command, fed a generated table of bad inputs (files, paths and numbers): exit 2, one
message, no traceback, and nothing written (the folder it ran in is as it was).

The table is the product of each command's inputs (a scenario, a log, a plan, a study file, an
output path, a numeric option) with the kinds of bad value each can meet; a new command or option
is one more row. Every case runs in-process (typer's runner), in a folder of its own holding good
copies of every other input, so the only thing wrong is the one the case names."""

from __future__ import annotations

import os
import re
import shutil
import stat
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.cli import app

GOOD = (SCENARIOS / "open-arena.yaml").read_text()

# -- bad scenario files: (name, content as text or bytes; None: the path does not exist; "/": a folder)
SCENARIO_CASES = {
    "missing": None,
    "a folder": "/",
    "empty": "",
    "binary": bytes(range(256)) * 4,
    "invalid UTF-8": GOOD.encode() + b"\xff\xfe\n",
    "a YAML list": "- 1\n- 2\n",
    "octal width": GOOD.replace("width: 6.0", "width: 010"),
    "base-60 width": GOOD.replace("width: 6.0", "width: 1:30"),
    "hex width": GOOD.replace("width: 6.0", "width: 0x6"),
    "underscored width": GOOD.replace("width: 6.0", "width: 6_0"),
    "NaN height": GOOD.replace("height: 4.0", "height: .nan"),
    "infinite height": GOOD.replace("height: 4.0", "height: .inf"),
    "5000 levels deep": GOOD + "extra: " + "[" * 5000 + "]" * 5000 + "\n",
    "an alias bomb": "a: &a [x, x, x, x, x, x, x, x, x]\n"
    + "".join(f"{c}: &{c} [{', '.join(['*' + p] * 9)}]\n" for p, c in zip("abcdefgh", "bcdefghi")),
    "an unknown block": GOOD + "pilots: {K: 1}\n",
    "a tiny time limit": GOOD.replace("time_limit: 120", "time_limit: 1.0e-300"),
    "a target outside the arena": GOOD.replace("at: [5.4, 3.0]", "at: [50.0, 3.0]"),
    "a landmark target inside an obstacle": GOOD.replace("target:\n  at: [5.4, 3.0]", "target: {landmark: L1}")
    + "landmarks: [{id: L1, at: [4.0, 2.0]}]\nobstacles: [{circle: {center: [4.0, 2.0], radius: 0.5}}]\n",
    "over 256 kB": GOOD + "# " + "x" * 300_000 + "\n",
    "a FIFO": "|",  # opening it would wait for a writer for ever
    "a link to /dev/zero": "->/dev/zero",  # reading it would never end
    "a link to itself": "->self",
    "a number as a key": GOOD + "1: 2\n",
    "~ as a key": GOOD.replace("arena: {width: 6.0, height: 4.0}", "arena: {width: 6.0, height: 4.0, ~: 3}"),
    "an ordered map as the arena": GOOD.replace(
        "arena: {width: 6.0, height: 4.0}", "arena: !!omap [width: 6.0, height: 4.0]"
    ),
}

# the commands that take a scenario, with what they need beside it ({s}: the scenario's path)
SCENARIO_COMMANDS = {
    "run": ["run", "{s}"],
    "validate": ["validate", "{s}"],
    "bench": ["bench", "{s}", "--repeat", "1"],
    "plot field": ["plot", "field", "{s}"],
    "plot bids": ["plot", "bids", "{s}"],
    "compare pilots": ["compare", "pilots", "{s}", "--reruns", "1", "--jobs", "1"],
    "compare policies": ["compare", "policies", "{s}", "--runs", "1", "--starts", "1", "--jobs", "1"],
    "params": ["params", "{s}"],
    "tune": ["tune", "{s}", "--param", "pilot.K=1:2", "--trials", "1", "--jobs", "1"],
    "train": ["train", "{s}", "--trials", "1", "--jobs", "1"],
    "tune-softmax": ["tune-softmax", "{s}", "--starts", "1", "--temperature", "1", "--jobs", "1"],
}

# numeric options and names out of range, each with the command that takes it ({s} a good scenario,
# {log} a good log)
OPTION_CASES = {
    "run": (
        ["run", "{s}"],
        [
            ["--seed", "-1"],
            ["--seed", str(2**64)],
            ["--seed", "1.5"],
            ["--time-limit", "nan"],
            ["--time-limit", "inf"],
            ["--time-limit", "0.05"],
            ["--time-limit", "1e999"],
            ["--port", "70000"],
            ["--pilot", "sonar"],
            ["--pilot", "nosuchmodule:Pilot"],
            ["--pilot", "os:path"],
            ["--pilot", "collections:NoSuchClass"],
            ["--pilot", "./nope.py:P"],
            ["--navigation", "agents+bogus"],
            ["--navigation", "agents+agents"],
            ["--navigation", "hand-coded+agents"],
            ["--param", "vfh.threshold=3"],
            ["--perception", "lidar"],
            ["--navigation", "bogus"],
            ["--navigation", "learned:nope.npz"],
            ["--param", "pilot.K=nan"],
            ["--param", "pilot.K=abc"],
            ["--param", "nope=1"],
            ["--param", "pilot.K"],
            ["--param", "pilot.K=-1"],
            ["--param", "pilot.reflex_look_pans_deg=[1,,2]"],
            ["--param", "pilot.reflex_look_pans_deg=[" + ",".join(["1"] * 65) + "]"],
            ["--param", "learning.distance_bounds=[1, 2]"],
            ["--param", "pilot.K=1", "--param", "pilot.K=2"],
            ["--navigation", "learned:"],
        ],
    ),
    "bench": (["bench", "{s}"], [["--repeat", "0"], ["--repeat", "1001"], ["--seed", "-1"]]),
    "plot field": (
        ["plot", "field", "{s}"],
        [["--step", "nan"], ["--step", "inf"], ["--step", "0"], ["--step", "-1"], ["--step", "1e-9"]],
    ),
    "plot bids": (["plot", "bids", "{s}"], [["--step", "nan"], ["--step", "-inf"], ["--step", "0"]]),
    "compare pilots": (
        ["compare", "pilots", "{s}"],
        [
            ["--reruns", "0"],
            ["--reruns", "10001"],
            ["--jobs", "0"],
            ["--jobs", "257"],
            ["--time-limit", "inf"],
            ["--pilots", "sonar"],
            ["--perception", "x"],
            ["--pilots", "geometric,geometric"],
            ["./{s}"],
            ["--scheduler", "junk"],
        ],
    ),
    "compare policies": (
        ["compare", "policies", "{s}"],
        [
            ["--runs", "0"],
            ["--runs", "1001"],
            ["--starts", "0"],
            ["--starts", "100000000"],
            ["--policy", "bogus"],
            ["--policy", "learned:"],
            ["--jobs", "0"],
        ],
    ),
    "tune": (
        ["tune", "{s}", "--param", "pilot.K=1:2"],
        [
            ["--crossover", "nan"],
            ["--crossover", "2"],
            ["--mutation", "-0.1"],
            ["--population", "1"],
            ["--population", "100000000"],
            ["--generations", "0"],
            ["--trials", "0"],
            ["--seeds", "0"],
            ["--seeds", "100000000"],
            ["--algorithm", "sa"],
            ["--objective", "speed"],
            ["--time-limit", "nan"],
            ["--param", "pilot.K=2:1"],
            ["--param", "pilot.K=nan:1"],
            ["--param", "pilot.K=3"],
            ["--scheduler", "tcp://h:0"],
        ],
    ),
    "train-rl": (
        ["train-rl", "{s}"],
        [["--agent", "a2c"], ["--steps", "0"], ["--seed", "-1"], ["--seed", str(2**32)]],
    ),
    "tune-softmax": (
        ["tune-softmax", "{s}", "--starts", "1", "--jobs", "1"],
        [
            ["--temperature", "-1"],
            ["--temperature", "nan"],
            ["--temperature", "inf"],
            ["--starts", "0"],
            ["--seed", "-1"],
            ["{s}"],  # a room twice
        ],
    ),
    "train": (
        ["train", "{s}"],
        [
            ["--trials", "0"],
            ["--trials", "100000000"],
            ["--eval-every", "0"],
            ["--eval-starts", "100000000"],
            ["--eval-starts", "0"],
            ["--seed", "-1"],
            ["--algorithm", "sarsa"],
            ["--log", "everything"],
            ["--jobs", "0"],
            ["--resume", "nope.npz"],
        ],
    ),
    "render": (
        ["render", "{log}"],
        [
            ["--speed", "nan"],
            ["--speed", "inf"],
            ["--speed", "0"],
            ["--fps", "nan"],
            ["--fps", "0"],
            ["--fps", "1000"],
            ["--dpi", "1000"],
            ["--from", "-1"],
            ["--from", "nan"],
            ["--to", "inf"],
            ["--from", "5", "--to", "1"],
        ],
    ),
    "report": (["report", "logs"], [["--baseline", "sonar"]]),
    "plugins check": (["plugins", "check"], [["robot", "geometric"], ["pilot", "sonar"], ["policy", "nosuchmodule:X"]]),
    "sweep": (
        ["sweep", "plan.yaml"],
        [["--jobs", "0"], ["--jobs", "257"], ["--scheduler", "junk"], ["--scheduler", "tcp://127.0.0.1:99999"]],
    ),
    "layout": (["layout"], [["--format", "xml"]]),
    "scenarios": (["scenarios"], [["paper-8x9"], ["no-such-room"], ["../paper-8x8"]]),
    "reproduce": (
        ["reproduce"],
        [
            ["everything"],
            ["--jobs", "0"],
            ["--scheduler", "junk"],
            ["--quick", "x"],
            ["--pilot", "sonar"],
            ["--pilot", "geometric"],
        ],
    ),
}

# output paths: (command, option, the bad path, what the folder holds for it)
_FOLDER, _FILE, _DEVICE = "folder", "a-file", "/dev/null"
OUT_CASES = {
    "run": (
        ["run", "{s}"],
        "--out",
        ["{folder}", "x.txt", "{s}", "{file}/x.mcap", _DEVICE, "notes.mcap", "fifo.mcap", "zero.mcap"],
    ),
    "plot field": (
        ["plot", "field", "{s}"],
        "--out",
        ["x.txt", "{folder}", "{folder}/", _DEVICE, "{file}/x.png", "notes.png"],
    ),
    "plot bids": (["plot", "bids", "{s}"], "--out", ["x.txt", "{folder}", _DEVICE, "{file}/x.png", "notes.png"]),
    "plot map": (["plot", "map", "{log}"], "--out", ["x.txt", "{folder}", _DEVICE, "{file}/x.png", "notes.png"]),
    "render": (["render", "{log}"], "--out", ["x.txt", "{folder}", _DEVICE, "{file}/x.gif", "notes.gif"]),
    "layout": (
        ["layout"],
        "--out",
        ["x.txt", "{folder}", _DEVICE, "{file}/x.json", "{s}", "notes.json", "settings.json"],
    ),
    "report": (["report", "logs"], "--out", ["{file}", "{file}/x", _DEVICE, "mine"]),
    "compare pilots": (
        ["compare", "pilots", "{s}", "--reruns", "1", "--jobs", "1"],
        "--out",
        ["{file}", "{file}/x", "mine"],
    ),
    "compare policies": (
        ["compare", "policies", "{s}", "--runs", "1", "--starts", "1", "--jobs", "1"],
        "--out",
        ["{file}", "{file}/x", "mine"],
    ),
    "sweep": (["sweep", "plan.yaml", "--jobs", "1"], "--out", ["{file}", "{file}/x", "mine", "mine2"]),
    "sweep --csv": (["sweep", "plan.yaml", "--jobs", "1", "--csv"], "--out", ["mine3"]),
    "sweep --no-logs": (["sweep", "plan.yaml", "--jobs", "1", "--no-logs"], "--out", ["{file}/x"]),
    "tune": (
        ["tune", "{s}", "--param", "pilot.K=1:2", "--trials", "1", "--jobs", "1"],
        "--out",
        ["{file}", "{file}/x", "mine"],
    ),
    "tune --storage": (
        ["tune", "{s}", "--param", "pilot.K=1:2", "--trials", "1", "--jobs", "1"],
        "--storage",
        ["x.txt", "{folder}", _DEVICE, "{s}", "notes.journal"],
    ),
    "tune --storage (ga)": (
        [
            "tune",
            "{s}",
            "--param",
            "pilot.K=1:2",
            "--algorithm",
            "ga",
            "--generations",
            "1",
            "--population",
            "2",
            "--jobs",
            "1",
        ],
        "--storage",
        ["x.txt", "notes.json", "{folder}"],
    ),
    "train": (
        ["train", "{s}", "--trials", "1", "--eval-every", "1", "--eval-starts", "1", "--jobs", "1"],
        "--out",
        ["{s}", "{folder}", "{folder}/", "x.txt", _DEVICE, "{file}/m.npz", "notes.npz", "m-notes.npz"],
    ),
    "tune-softmax": (
        ["tune-softmax", "{s}", "--starts", "1", "--temperature", "1", "--jobs", "1"],
        "--out",
        ["x.txt", "{folder}", "{s}", "settings.json", "notes.json"],
    ),
    "recover": (["recover", "good.mcap.partial"], "--out", ["x.txt", "{folder}", "{s}"]),
    "reproduce": (["reproduce", "--quick"], "--out", ["{file}", "{file}/x", "mine4"]),
}

# log and plan inputs: (command with {x} for the bad input, the bad inputs)
_LOG_BAD = {
    "missing": None,
    "a folder": "/",
    "empty": b"",
    "garbage": b"\x89MCAP0\r\n" + b"\0" * 64,
    "a scenario": GOOD.encode(),
    "truncated": "half",
    "a FIFO": "|",
    "a link to /dev/zero": "->/dev/zero",
    "a link to itself": "->self",
}
_MODEL_BAD = {
    "a FIFO": "|",
    "a link to /dev/zero": "->/dev/zero",
    "a link to itself": "->self",
    "an array declared of 745 GiB": "huge-model",
}
INPUT_CASES = {
    "plot map": (["plot", "map", "{x}"], "x.mcap", _LOG_BAD),
    "render": (["render", "{x}"], "x.mcap", _LOG_BAD),
    "recover": (
        ["recover", "{x}"],
        "x.mcap.partial",  # a truncated log is what it recovers
        {**{k: v for k, v in _LOG_BAD.items() if k != "truncated"}, "a complete log": "whole"},
    ),
    "report": (
        ["report", "{x}"],
        "ld",
        {
            "missing": None,
            "a file": b"x",
            "an empty folder": "/",
            "a folder of garbage": "/garbage",
            "a folder of a FIFO": "/fifo",
            "a log whose summary says NaN": "/nan-summary",
        },
    ),
    "run --navigation learned:FILE": (["run", "s.yaml", "--navigation", "learned:{x}"], "m.npz", _MODEL_BAD),
    "train --resume": (["train", "s.yaml", "--trials", "1", "--jobs", "1", "--resume", "{x}"], "m.npz", _MODEL_BAD),
    "sweep": (
        ["sweep", "{x}", "--jobs", "1"],
        "p.yaml",
        {
            "missing": None,
            "a folder": "/",
            "empty": "",
            "binary": bytes(range(256)),
            "a list": "- 1\n",
            "no scenarios": "version: 1\nseeds: 1\n",
            "seeds 0": "version: 1\nseeds: 0\nscenarios: [s.yaml]\n",
            "huge random": "version: 1\nseeds: 1\nscenarios: [s.yaml]\nrandom: {samples: 100000000, ranges: "
            "{pilot.K: [1, 2]}}\n",
            "a grid beside params": "version: 1\nseeds: 1\nscenarios: [s.yaml]\nparams: {pilot.K: 3}\n"
            "grid: {pilot.K: [1, 2]}\n",
            "a scenario twice": "version: 1\nseeds: 1\nscenarios: [s.yaml, ./s.yaml]\n",
            "octal seeds": "version: 1\nseeds: 010\nscenarios: [s.yaml]\n",
            "a bad scenario": "version: 1\nseeds: 1\nscenarios: [bad.yaml]\n",
            "over 1 MiB": "version: 1\n# " + "x" * (1 << 20) + "\n",
            "a FIFO": "|",
            "a link to /dev/zero": "->/dev/zero",
            "a whole number sampled": "version: 1\nseeds: 1\nscenarios: [s.yaml]\nrandom: {samples: 2, ranges: "
            "{pilot.looks: [0, 1]}}\n",
            "a number as a grid key": "version: 1\nseeds: 1\nscenarios: [s.yaml]\ngrid: {1: [1, 2]}\n",
            "a FIFO scenario": "version: 1\nseeds: 1\nscenarios: [fifo.yaml]\n",
        },
    ),
    "tune (study file)": (
        ["tune", "s.yaml", "--param", "pilot.K=1:2", "--trials", "1", "--jobs", "1", "--storage", "{x}"],
        "st.journal",
        {"garbage": '{"op_code": 99}\n', "not JSON": "{\n"},
    ),
    "tune (GA checkpoint)": (
        [
            "tune",
            "s.yaml",
            "--param",
            "pilot.K=1:2",
            "--algorithm",
            "ga",
            "--generations",
            "1",
            "--population",
            "2",
            "--jobs",
            "1",
            "--storage",
            "{x}",
        ],
        "ga.json",
        {"a list": "[1]\n", "no key": "{}\n", "deep": "[" * 100_000 + "\n"},
    ),
}


def _cases():
    for sc, content in SCENARIO_CASES.items():
        for cmd, args in SCENARIO_COMMANDS.items():
            yield pytest.param(("scenario", args, content), id=f"{cmd}: scenario {sc}")
    for cmd, (args, options) in OPTION_CASES.items():
        for o in options:
            yield pytest.param(("option", args + o, None), id=f"{cmd} {' '.join(o)}")
    for cmd, (args, option, paths) in OUT_CASES.items():
        for p in paths:
            yield pytest.param(("out", args + [option, p], None), id=f"{cmd} {option} {p}")
    for cmd, (args, name, bad) in INPUT_CASES.items():
        for kind, content in bad.items():
            yield pytest.param(("input", args, (name, content)), id=f"{cmd}: {kind}")


CASES = list(_cases())


@pytest.fixture(scope="module")
def good_log(tmp_path_factory) -> Path:
    """A short complete log, and a ``.partial`` (a copy taken mid-run) beside it."""
    from navcli import RunSpec, load_scenario
    from navcli.runner import run_mission

    d = tmp_path_factory.mktemp("good")
    out = d / "good.mcap"

    def snapshot(mission, tick) -> None:
        if tick.index == 25:
            shutil.copyfile(d / "good.mcap.partial", d / "copy.partial")

    run_mission(RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"), time_limit=3.0), out=out, on_tick=snapshot)
    return out


def _tree(root: Path) -> dict[str, tuple[int, int]]:
    return {str(p.relative_to(root)): (p.lstat().st_size, p.lstat().st_mtime_ns) for p in root.rglob("*")}


def _place(path: Path, content, good_log: Path) -> None:
    if content is None:
        return
    if content == "|":
        os.mkfifo(path)
        return
    if isinstance(content, str) and content.startswith("->"):
        path.symlink_to(path if content == "->self" else content[2:])
        return
    if content == "huge-model":
        _huge_model(path)
        return
    if isinstance(content, str) and content.startswith("/"):
        path.mkdir()
        if content == "/garbage":
            (path / "a.mcap").write_bytes(b"garbage")
        elif content == "/fifo":
            os.mkfifo(path / "b.mcap")
        elif content == "/nan-summary":
            _nan_summary(good_log, path / "nan.mcap")
        return
    if content == "half":
        data = good_log.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    elif content == "whole":
        shutil.copyfile(good_log, path)
    else:
        path.write_bytes(content if isinstance(content, bytes) else content.encode())


def _huge_model(path: Path) -> None:
    """The bundled model with its ``values`` array's header declaring 10^11 floats (64 bytes of data)."""
    import io
    import zipfile

    import numpy as np

    from navcli.learning import model_file

    with zipfile.ZipFile(model_file.BUNDLED) as z:
        members = {n: z.read(n) for n in z.namelist()}
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(head, {"descr": "<f8", "fortran_order": False, "shape": (10**11,)})
    members["values.npy"] = head.getvalue() + bytes(64)
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)


def _nan_summary(good_log: Path, out: Path) -> None:
    """``good_log`` rewritten with its summary's time as the text "NaN" (every other record as it was)."""
    import json

    from mcap.reader import make_reader
    from mcap.writer import Writer

    with good_log.open("rb") as f, out.open("wb") as g:
        reader, w = make_reader(f), Writer(g)
        w.start()
        summary = reader.get_summary()
        schemas = {sid: w.register_schema(s.name, s.encoding, s.data) for sid, s in summary.schemas.items()}
        channels = {
            cid: w.register_channel(c.topic, c.message_encoding, schemas.get(c.schema_id, 0), c.metadata)
            for cid, c in summary.channels.items()
        }
        for _, channel, m in reader.iter_messages(log_time_order=False):
            data = m.data
            if channel.topic == "/mission/summary":
                data = json.dumps(json.loads(data) | {"time_s": "NaN"}).encode()
            w.add_message(channels[channel.id], m.log_time, data, m.publish_time)
        for md in reader.iter_metadata():
            w.add_metadata(md.name, md.metadata)
        w.finish()


def _workspace(d: Path, good_log: Path) -> None:
    """Good copies of every input a case does not spoil, and the things bad outputs point at."""
    (d / "s.yaml").write_text(GOOD)
    (d / "bad.yaml").write_text("nope: [\n")
    shutil.copyfile(good_log, d / "good.mcap")
    shutil.copyfile(good_log.with_name("copy.partial"), d / "good.mcap.partial")
    (d / "logs").mkdir()
    shutil.copyfile(good_log, d / "logs" / "good.mcap")
    (d / "plan.yaml").write_text("version: 1\nseeds: 1\ntime_limit: 1\nscenarios: [s.yaml]\n")
    (d / _FOLDER).mkdir()
    (d / _FILE).write_text("a file, not a folder\n")
    for notes in (
        "notes.png",
        "notes.gif",
        "notes.json",
        "notes.journal",
        "notes.npz",
        "m-notes-curve.png",
        "notes.mcap",
    ):
        (d / notes).write_text("my notes, not navcli's\n")
    (d / "settings.json").write_text('{"my": "settings"}\n')  # JSON, but not navcli's
    os.mkfifo(d / "fifo.mcap")
    os.mkfifo(d / "fifo.yaml")
    (d / "zero.mcap").symlink_to("/dev/zero")
    for folder, names in (
        ("mine", ("table.md", "history.csv", "policies.csv", "results.parquet")),
        ("mine2", ()),
        ("mine3", ("results.csv",)),
        ("mine4", ("report.md",)),
    ):
        (d / folder).mkdir()
        for n in names:
            (d / folder / n).write_text("mine, not navcli's\n")
    (d / "mine2" / "results.parquet").mkdir()  # a folder where the table goes
    (d / "m-notes-curve.png").rename(d / "m-notes-curve.png")  # a side file of --out m-notes.npz


@pytest.mark.parametrize("case", CASES)
def test_a_bad_input_is_refused_with_exit_2_one_message_and_nothing_written(case, tmp_path, good_log, monkeypatch):
    kind, args, extra = case
    monkeypatch.chdir(tmp_path)
    _workspace(tmp_path, good_log)
    s = "s.yaml"
    if kind == "scenario":
        s = "x.yaml"
        _place(tmp_path / s, extra, good_log)
    elif kind == "input":
        name, content = extra
        _place(tmp_path / name, content, good_log)
        args = [a.replace("{x}", name) for a in args]
    args = [a.format(s=s, log="good.mcap", folder=_FOLDER, file=_FILE) for a in args]
    before = _tree(tmp_path)
    device = os.stat(_DEVICE) if _DEVICE in args else None
    assert device is None or stat.S_ISCHR(device.st_mode), f"{_DEVICE} is no device here: the case tests nothing"
    r = CliRunner().invoke(app, args)
    out = r.output
    assert r.exit_code == 2, f"exit {r.exit_code}: {out[-2000:]}"
    assert "Traceback" not in out and "internal error" not in out, out[-2000:]
    if args[0] == "validate":  # its report: a line per problem of each file, then the count
        assert re.fullmatch(r"x\.yaml(:\d+)?: [^\n]+\n1 of 1 files refused\n", out), out[-2000:]
    else:
        assert len(re.findall(r"^(error|Error)\b", out, flags=re.M)) == 1, out[-2000:]  # one message
    assert _tree(tmp_path) == before, "something was written"
    if device is not None:  # the device named as the output is still that device: not replaced, not removed
        after = os.stat(_DEVICE)
        assert stat.S_ISCHR(after.st_mode) and (after.st_ino, after.st_rdev) == (device.st_ino, device.st_rdev)


def test_the_table_is_large_enough_and_every_command_is_in_it():
    """At least 200 cases, and every command of the CLI meets at least one (``schema`` takes no input)."""
    assert all(c != GOOD for c in SCENARIO_CASES.values())  # each edit of the good scenario took hold
    import typer.main

    assert len(CASES) >= 200
    click_app = typer.main.get_command(app)
    names = set()
    for name, cmd in click_app.commands.items():
        names |= {f"{name} {sub}" for sub in getattr(cmd, "commands", {})} or {name}
    covered = {
        " ".join(c.values[0][1][:2]) if c.values[0][1][0] in ("plot", "compare", "plugins") else c.values[0][1][0]
        for c in CASES
    }
    assert names - covered - {"schema", "plugins list"} == set(), names - covered
