"""Crash-safe logs: a run killed outright is recovered into a readable log; a killed run's
.partial is never deleted; two runs cannot write one log; bad --out paths are refused before the
mission; SIGTERM is logged as such and exits 143."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from navcli.analysis import read_log
from navcli.analysis.tables import load_runs
from conftest import ROOT, SCENARIOS, scenario_dict
from typer.testing import CliRunner

from navcli.cli import app
from navcli.config import RunSpec
from navcli.log.writer import FLUSH_EVERY_NS, LogPathError, Recorder
from navcli.log.recover import RECOVERED_REASON
from navcli.runner import run_mission
from navcli.scenario import load_scenario

# A wall across the room, and a Rescuer that never gives up: the run lasts until its (long) time
# limit, long enough to be killed (with 3 failed diverting targets it ended "blocked" after 152 s,
# about a second of wall time, which a loaded machine could let pass before the test's signal).
BLOCKED = scenario_dict(
    name="blocked",
    obstacles=[{"segment": {"from": [3, 0], "to": [3, 4]}}],
    mission={"time_limit": 3000, "seed": 1},
    navigation={"gives_up": 0},
)


def start_run(write_scenario, out, *extra):
    sc = write_scenario(BLOCKED)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.Popen(
        [sys.executable, "-m", "navcli", "run", str(sc), "--out", str(out), *extra],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def wait_for_chunks(partial, proc, size=200_000, timeout=30.0):
    """Until the .partial holds some finished chunks (its size grows one chunk a simulated second)."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout and proc.poll() is None:
        if partial.exists() and partial.stat().st_size > size:
            return
        time.sleep(0.05)
    pytest.fail("the run wrote no chunks in time")


def test_a_run_killed_with_sigkill_is_recovered(write_scenario, tmp_path):
    out = tmp_path / "run.mcap"
    proc = start_run(write_scenario, out)
    partial = tmp_path / "run.mcap.partial"
    wait_for_chunks(partial, proc)
    proc.kill()
    proc.wait()
    assert not out.exists() and partial.exists()
    r = subprocess.run(
        [sys.executable, "-m", "navcli", "recover", str(partial)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
    )
    assert r.returncode == 0, r.stderr
    log = read_log(out)
    s = log.summary
    assert s["outcome"] == "interrupted" and s["reason"] == RECOVERED_REASON
    poses = log["/robot/pose"]
    assert s["time_s"] == poses["time_s"].iloc[-1] > 0
    # chunks are finished every simulated second, so the log ends on a whole second
    assert (s["time_s"] * 1e9) % FLUSH_EVERY_NS == 0
    assert s["ticks"] == len(log["/pilot"]) == round(s["time_s"] / 0.1)
    assert (
        log.metadata["run"]["scenario"] == "blocked"
        and log.attachments["scenario.yaml"] == (tmp_path / "scenario.yaml").read_bytes()
    )
    runs = load_runs(tmp_path)  # the summary agrees with the poses, as report checks
    assert list(runs["outcome"]) == ["interrupted"]
    # the .partial stays; a second recover refuses to overwrite
    assert partial.exists()
    r2 = subprocess.run(
        [sys.executable, "-m", "navcli", "recover", str(partial)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
    )
    assert r2.returncode == 2 and "exists" in r2.stderr


def test_sigterm_is_logged_as_such_and_exits_143(write_scenario, tmp_path):
    out = tmp_path / "run.mcap"
    proc = start_run(write_scenario, out)
    wait_for_chunks(tmp_path / "run.mcap.partial", proc, size=50_000)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 143, err
    s = read_log(out).summary
    assert s["outcome"] == "interrupted" and s["reason"] == "stopped by SIGTERM"
    load_runs(tmp_path)  # the summary's time is the last pose's, even when stopped mid-tick


def test_a_killed_runs_partial_is_kept_aside_and_a_locked_log_refused(tmp_path):
    from navcli.config import RunSpec
    from navcli.mission import Mission
    from navcli.scenario import load_scenario

    summary = Mission(RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"))).summary()  # not started
    out = tmp_path / "run.mcap"
    (tmp_path / "run.mcap.partial").write_bytes(b"the remains of a killed run")
    rec = Recorder(out)
    assert (tmp_path / "run.mcap.partial-1").read_bytes() == b"the remains of a killed run"
    with pytest.raises(LogPathError, match="being written by another run"):
        Recorder(out)
    rec.finish(summary, 0)
    assert not (tmp_path / "run.mcap.lock").exists()
    with pytest.raises(LogPathError, match="overwrite=True replaces it"):  # free, but finished: never replaced unasked
        Recorder(out)
    Recorder(out, overwrite=True).finish(summary, 0)


@pytest.mark.parametrize(
    "out, words",
    [
        ("", "not a file name"),
        ("/", "not a file name"),
        (".", "not a file name"),
        ("{dir}", "is a folder"),
        ("{scenario}", "ends in .mcap"),
        ("{dir}/x.txt", "ends in .mcap"),
    ],
)
def test_bad_log_paths_are_refused_before_the_mission(tmp_path, write_scenario, out, words):
    sc = write_scenario(scenario_dict())
    out = out.format(dir=tmp_path, scenario=sc)
    ticks = []
    with pytest.MonkeyPatch.context() as mp:  # no mission may start
        mp.setattr("navcli.mission.Mission.step", lambda self: ticks.append(1))
        r = CliRunner().invoke(app, ["run", str(sc), "--out", out])
    assert r.exit_code == 2 and words in r.output and "Traceback" not in r.output, r.output
    assert ticks == [] and sc.read_text().startswith("version")


def test_the_scenario_file_itself_is_never_the_log(tmp_path):
    sc = tmp_path / "mine.mcap"  # a scenario saved under a log's name
    sc.write_text("x")
    with pytest.raises(LogPathError, match="scenario file itself"):
        Recorder(sc, protect=(str(sc),))
    assert sc.read_text() == "x"


def test_a_run_stopped_inside_a_tick_logs_its_pose_at_the_summarys_time(tmp_path, monkeypatch):
    """The world has stepped, the tick is not yet logged: the summary's time is still the last pose's."""
    spec = RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"))
    real_tick = Recorder.tick

    def tick(self, t):
        if t.index == 25:
            raise KeyboardInterrupt
        real_tick(self, t)

    monkeypatch.setattr(Recorder, "tick", tick)
    with pytest.raises(KeyboardInterrupt):
        run_mission(spec, out=tmp_path / "run.mcap")
    log = read_log(tmp_path / "run.mcap")
    assert log.summary["time_s"] == pytest.approx(2.5) == log["/robot/pose"]["time_s"].iloc[-1]
    assert list(load_runs(tmp_path)["outcome"]) == ["interrupted"]


@pytest.fixture(scope="module")
def killed_partial(tmp_path_factory):
    """A copy of a run's ``.partial`` taken at 6 simulated seconds, as a SIGKILL would leave it
    (its finished chunks and part of the one being written)."""
    d = tmp_path_factory.mktemp("killed")
    out, copy = d / "run.mcap", d / "copy.mcap.partial"

    def snapshot(mission, tick) -> None:
        if tick.index == 60:
            copy.write_bytes((d / "run.mcap.partial").read_bytes())

    run_mission(RunSpec.build(load_scenario(SCENARIOS / "blocked-wall.yaml")), out=out, on_tick=snapshot)
    return copy.read_bytes()


def _inside_a_chunk(data: bytes, k: int) -> int:
    """The offset of a byte in the middle of the ``k``-th chunk record of the MCAP bytes ``data``."""
    import io

    from mcap.records import Chunk
    from mcap.stream_reader import StreamReader

    f = io.BytesIO(data)
    records = StreamReader(f, emit_chunks=True).records
    seen, start = 0, f.tell()
    for r in records:
        end = f.tell()
        if isinstance(r, Chunk):
            if seen == k:
                return (start + end) // 2
            seen += 1
        start = end
    raise AssertionError("too few chunks")


def _recover(path, *extra):
    return CliRunner().invoke(app, ["recover", str(path), *extra])


def test_recover_says_when_a_partial_is_damaged_before_its_end(tmp_path, killed_partial):
    whole = tmp_path / "whole.mcap.partial"
    whole.write_bytes(killed_partial)
    r = _recover(whole)
    assert r.exit_code == 0 and "warning" not in r.output, r.output
    ticks = read_log(tmp_path / "whole.mcap").summary["ticks"]
    assert ticks >= 50
    damaged = tmp_path / "damaged.mcap.partial"
    b = bytearray(killed_partial)
    b[_inside_a_chunk(killed_partial, 1)] ^= 0xFF  # inside an early chunk: its CRC fails, the chunks after it are lost
    damaged.write_bytes(bytes(b))
    r = _recover(damaged)
    assert r.exit_code == 0 and "damaged before its end" in r.output and "Traceback" not in r.output, r.output
    assert read_log(tmp_path / "damaged.mcap").summary["ticks"] < ticks


def test_recover_refuses_a_folder_and_a_partial_whose_run_still_writes_it(tmp_path, killed_partial):
    from navcli.log.writer import Lock

    r = _recover(tmp_path)
    assert r.exit_code == 2 and "is a folder" in r.output
    partial = tmp_path / "run.mcap.partial"
    partial.write_bytes(killed_partial)
    held = Lock(tmp_path / "run.mcap.lock")  # a run still going
    try:
        r = _recover(partial)
        assert r.exit_code == 2 and "still going" in r.output and not (tmp_path / "run.mcap").exists()
    finally:
        held.release()
    (tmp_path / "run.mcap.lock").write_text("")  # the lock file a SIGKILLed run leaves (no flock held)
    r = _recover(partial)
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.mcap", "run.mcap.partial"]


def test_a_note_of_a_partial_kept_aside_only_when_this_run_took_the_log(tmp_path):
    """The note that a killed run's .partial is kept aside comes once the log is this run's: a run
    refused because another holds the log says only that."""
    from navcli.log.writer import Lock

    sc = SCENARIOS / "open-arena.yaml"
    out = tmp_path / "run.mcap"
    (tmp_path / "run.mcap.partial").write_bytes(b"remains")
    held = Lock(tmp_path / "run.mcap.lock")
    try:
        r = CliRunner().invoke(app, ["run", str(sc), "--out", str(out), "--time-limit", "0.5"])
        assert r.exit_code == 2 and "another run" in r.output and "note:" not in r.output, r.output
    finally:
        held.release()
    r = CliRunner().invoke(app, ["run", str(sc), "--out", str(out), "--time-limit", "0.5"])
    assert r.exit_code == 3 and f"kept as {tmp_path / 'run.mcap.partial-1'}" in r.output, r.output
    assert (tmp_path / "run.mcap.partial-1").read_bytes() == b"remains"
