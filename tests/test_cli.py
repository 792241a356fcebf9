"""``navcli`` end to end through typer's runner, and as a real process for Ctrl-C."""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from navcli.analysis import read_log
from conftest import ROOT, SCENARIOS, scenario_dict
from navcli.cli import app
from navcli.params import Params

runner = CliRunner()


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args])


def test_run_reaches_the_target_and_prints_the_result(tmp_path):
    out = tmp_path / "run.mcap"
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--seed", 2, "--out", out)
    assert r.exit_code == 0, r.output
    for word in ("outcome      reached", "sim time", "path length", "collisions   0", f"log          {out}"):
        assert word in r.output
    assert read_log(out).summary["seed"] == 2


def test_run_writes_the_default_log_path(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--pilot", "geometric", "--seed", 4)
    assert r.exit_code == 0, r.output
    logs = list((tmp_path / "logs" / "open-arena").glob("geometric-seed4-*.mcap"))
    assert len(logs) == 1 and str(logs[0].relative_to(tmp_path)) in r.output
    run_id = read_log(logs[0], topics=[]).metadata["run"]["run_id"]
    assert logs[0].name == f"geometric-seed4-{run_id[:8]}.mcap"


def test_a_mission_that_runs_out_of_time_exits_3(tmp_path):
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--time-limit", 1, "--out", tmp_path / "t.mcap")
    assert r.exit_code == 3 and "outcome      timeout" in r.output


def test_refused_scenario_exits_2_with_the_reason_and_no_traceback(write_scenario, tmp_path):
    bad = write_scenario(scenario_dict(target={"at": [9, 9]}))
    r = invoke("run", bad, "--out", tmp_path / "never.mcap")
    assert r.exit_code == 2
    assert f"{bad}:" in r.output and "target.at" in r.output and "outside" in r.output
    assert "Traceback" not in r.output
    assert not (tmp_path / "never.mcap").exists()


def test_missing_scenario_file_exits_2(tmp_path):
    r = invoke("run", tmp_path / "nope.yaml")
    assert r.exit_code == 2 and "no such file" in r.output


def test_bad_options_exit_2_without_traceback():
    for args in (
        ["run", SCENARIOS / "open-arena.yaml", "--pilot", "autopilot"],
        ["run", SCENARIOS / "open-arena.yaml", "--seed", "-1"],
        ["run", SCENARIOS / "open-arena.yaml", "--time-limit", "0"],
    ):
        r = invoke(*args)
        assert r.exit_code == 2, (args, r.output)
        assert "Traceback" not in r.output


def test_unwritable_log_path_is_a_clear_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--out", blocker / "run.mcap")
    assert r.exit_code == 2 and f"cannot create the folder {blocker}" in r.output and "Traceback" not in r.output


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_a_folder_that_refuses_files_is_a_clear_error():
    """/proc passes the permission check as root but refuses to create a file: the log's lock file
    is the first file made, and it must come out as bad input too, not an internal error."""
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--out", "/proc/navcli-test.mcap")
    assert r.exit_code == 2 and "cannot write" in r.output and "Traceback" not in r.output


def test_validate_reports_each_file(write_scenario):
    good = SCENARIOS / "paper-8x8.yaml"
    bad = write_scenario(scenario_dict(landmarks=[{"id": "A", "at": [3, 1]}, {"id": "A", "at": [3, 2]}]))
    r = invoke("validate", good)
    assert r.exit_code == 0 and "paper-8x8.yaml: ok" in r.output
    r = invoke("validate", good, bad)
    assert r.exit_code == 2
    assert "paper-8x8.yaml: ok" in r.output and "landmarks[1].id" in r.output and "1 of 2 files refused" in r.output


def test_help_lists_every_command_with_its_summary():
    r = invoke("--help")
    assert r.exit_code == 0
    commands_part = r.output.split("Commands:", 1)[1]
    listed = dict(re.findall(r"^  ([a-z][a-z-]*)\s{2,}(\S.*?)\s*$", commands_part, re.M))
    commands = {c.name or c.callback.__name__: c.callback.__doc__ for c in app.registered_commands}
    groups = {g.name: g.typer_instance.info.help for g in app.registered_groups}
    assert set(listed) == set(commands) | set(groups)
    for name, doc in (commands | groups).items():
        assert doc.split()[:3] == listed[name].split()[:3], name  # each with the first words of its summary


def test_cli_module_imports_no_heavy_library():
    code = (
        "import sys, navcli.cli; heavy = [m for m in ('numpy', 'pymunk', 'foxglove', 'pandas', 'matplotlib')"
        " if m in sys.modules]; print(heavy); sys.exit(1 if heavy else 0)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_ctrl_c_on_a_live_run_leaves_a_log_marked_interrupted(tmp_path):
    """A real process, paced to real time by --live, stopped with SIGINT as a terminal would."""
    out = tmp_path / "live.mcap"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "navcli",
            "run",
            str(SCENARIOS / "open-arena.yaml"),
            "--live",
            "--port",
            "0",
            "--out",
            str(out),
        ],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    partial = out.with_name(out.name + ".partial")
    deadline = time.monotonic() + 20
    while not partial.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(1.0)  # about a second of simulated time
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=20)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr
    log = read_log(out)
    assert log.summary["outcome"] == "interrupted"
    assert 0 < log.summary["time_s"] < 10
    assert not partial.exists()


def test_param_overrides_any_parameter_and_is_recorded_as_json(tmp_path):
    out = tmp_path / "k.mcap"
    r = invoke(
        "run",
        SCENARIOS / "open-arena.yaml",
        "--param",
        "pilot.K=30",
        "--param",
        "pilot.A_t=40",
        "--param",
        "navigation.kappa1=0.5",
        "--param",
        "robot.max_speed=0.25",
        "--out",
        out,
    )
    assert r.exit_code == 0, r.output
    params = read_log(out, topics=[]).config["params"]
    assert (params["pilot"]["K"], params["pilot"]["A_t"], params["navigation"]["kappa1"]) == (30.0, 40.0, 0.5)
    assert params["robot"]["max_speed"] == 0.25
    others = {
        k: v
        for k, v in Params().flat().items()
        if k not in ("pilot.K", "pilot.A_t", "navigation.kappa1", "robot.max_speed")
    }
    assert {f"{g}.{k}": v for g, b in params.items() for k, v in b.items()}.items() >= others.items()


def test_bad_param_exits_2_naming_it():
    for bad, words in (
        ("Q=1", "unknown parameter 'Q'"),
        ("K=1", "did you mean pilot.K?"),
        ("pilot.K=abc", "'abc' is not a number"),
        ("pilot.R_min=0", "pilot.R_min must be at least 0.01"),
        ("pilot.K", "expected NAME=VALUE"),
        ("pilot.K=nan", "finite number"),
        ("navigation.kappa1=1.5", "at most 1"),
        ("vision.forget_every=2.5", "whole number"),
    ):
        r = invoke("run", SCENARIOS / "open-arena.yaml", "--param", bad)
        assert r.exit_code == 2 and words in r.output and "Traceback" not in r.output, (bad, r.output)


def test_bench_reports_the_floor_and_the_stack_against_it():
    r = invoke("bench", SCENARIOS / "open-arena.yaml", "--repeat", "1")
    assert r.exit_code == 0, r.output
    lines = {
        ln.split()[0] + (" " + ln.split()[1] if ln.startswith("logging") else ""): ln for ln in r.output.splitlines()
    }
    assert {"floor", "logging off", "logging on"} <= set(lines)
    assert "x floor" not in lines["floor"]  # the floor against itself would say nothing
    us = {k: float(re.search(r"(\d+) us/tick", v).group(1)) for k, v in lines.items() if "us/tick" in v}
    # the report's ratios are of the unrounded times; the printed times are rounded to 1 us and the
    # ratios to 0.01 (1 %): what rounding can move a ratio q = a / b by is q (0.5 / a + 0.5 / b)
    slack = lambda a, b: a / b * (0.5 / a + 0.5 / b)  # noqa: E731
    for label in ("logging off", "logging on"):
        ratio = float(re.search(r"([\d.]+)x floor", lines[label]).group(1))
        assert abs(ratio - us[label] / us["floor"]) <= slack(us[label], us["floor"]) + 0.005
    cost = float(re.search(r"logging costs (-?\d+) %", r.output).group(1))
    on, off = us["logging on"], us["logging off"]
    assert abs(cost - 100 * (on / off - 1)) <= 100 * slack(on, off) + 0.5


def test_params_shows_each_range_as_the_overrides_enforce_it():
    """Every numeric range `navcli params` prints holds the default and refuses a value just past
    each finite end (so the listing says what `--param` accepts); every parameter has a unit (``-``
    for a pure number) and a description, and a switch takes true and false."""
    import re

    from navcli.params import ParamError, Params

    r = CliRunner().invoke(app, ["params"])
    assert r.exit_code == 0, r.output
    checked = switches = 0
    lines = r.output.splitlines()
    assert re.fullmatch(r"name\s+value\s+unit\s+range\s+description", lines[0])
    from navcli.plugins import GROUPS, installed
    from navcli.plugins.registry import with_params

    plugins = [c for kind in GROUPS for c in installed(kind) if not isinstance(c, tuple)]
    known = with_params(Params(), plugins)  # navcli's parameters, and any installed plugin's
    assert len(lines) - 1 == len(known.flat())
    for line in lines[1:]:
        name, value, unit, rng, description = re.split(r"\s{2,}", line.strip(), maxsplit=4)
        assert unit and len(description) > 10, line
        if rng == "true or false":
            switches += 1
            assert known.override({name: value == "false"}).flat()[name] is (value == "false")
            with pytest.raises(ParamError):
                known.override({name: 0.5})
            continue
        if rng.startswith("one of "):  # a parameter that names a choice: its default among them, another word refused
            assert value in rng.removeprefix("one of ").split(", ")
            with pytest.raises(ParamError):
                known.override({name: value + "x"})
            continue
        m = re.fullmatch(r"(?:whole number in )?([\[(])(\S+), (\S+)([\])])", rng)
        if m is None:
            assert "numbers" in rng, line  # the list-valued ones
            continue
        lo_open, lo, hi, hi_open = m.groups()
        assert float(lo) <= float(value) <= float(hi)
        for bound, closed, step in ((lo, lo_open == "[", -1), (hi, hi_open == "]", +1)):
            b = float(bound)
            if abs(b) == float("inf"):
                continue
            past = b + step * max(1e-6, abs(b) * 1e-6)
            with pytest.raises(ParamError):
                known.override({name: past})
            if not closed:
                with pytest.raises(ParamError):
                    known.override({name: b})
            checked += 1
    assert switches >= 15
    assert checked > 50


def test_run_writes_its_log_with_the_compression_asked_for_and_refuses_an_unknown_one(tmp_path):
    from mcap.reader import make_reader

    out = tmp_path / "run.mcap"
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--time-limit", 1, "--out", out, "--log-compression", "lz4")
    assert r.exit_code == 3 and "timeout" in r.output, r.output  # a mission out of time: the log is whole
    with out.open("rb") as f:
        assert {c.compression for c in make_reader(f).get_summary().chunk_indexes} == {"lz4"}
    r = invoke("run", SCENARIOS / "open-arena.yaml", "--out", tmp_path / "t.mcap", "--log-compression", "gzip")
    assert r.exit_code == 2 and "'gzip' is not one of 'zstd-1', 'zstd-3', 'lz4', 'none'" in r.output, r.output
    assert not (tmp_path / "t.mcap").exists()
