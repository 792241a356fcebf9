"""The execution layer: Ctrl-C and SIGTERM stop a real `navcli compare` and every worker it forked."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import ROOT, SCENARIOS


def _children(pid: int) -> list[int]:
    """The pids of the direct children of ``pid``, from /proc (every thread's children list)."""
    out = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        with open(task / "children") as f:
            out += [int(c) for c in f.read().split()]
    return out


def _alive(pid: int) -> bool:
    """True while ``pid`` exists and is not a zombie (a zombie has exited; only its entry remains)."""
    try:
        os.kill(pid, 0)
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (ProcessLookupError, FileNotFoundError):
        return False
    return state not in ("Z", "X")


def _long_comparison(out) -> tuple[dict[str, str], list[str]]:
    """The environment and command of a comparison long enough to be stopped in the middle: 20
    reruns of paper-8x8 on two workers, writing into ``out``."""
    env = dict(os.environ, PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    cmd = [sys.executable, "-m", "navcli", "compare", "pilots", str(SCENARIOS / "paper-8x8.yaml")]
    return env, [*cmd, "--reruns", "20", "--jobs", "2", "--out", str(out)]


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize("to", ["main", "group"])
@pytest.mark.parametrize(
    "sig, code, words, reason",
    [
        (signal.SIGTERM, 143, "stopped by SIGTERM", "stopped by SIGTERM"),
        (signal.SIGINT, 130, "interrupted (Ctrl-C)", "stopped by the user (Ctrl-C)"),
    ],
)
def test_a_signal_stops_compare_and_all_its_workers(tmp_path, sig, code, words, reason, to):
    """To the main process (a scheduler's kill) or to the whole process group (a terminal's Ctrl-C,
    which reaches the workers too): exit 128 + the signal, one line, no worker left, and the runs
    under way logged as ended by that signal."""
    env, cmd = _long_comparison(tmp_path)
    # its own process group, with SIGINT's default disposition as in a terminal (a shell may start
    # background jobs ignoring it)
    proc = subprocess.Popen(
        cmd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        deadline = time.monotonic() + 30
        while len(kids := _children(proc.pid)) < 2 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(kids) >= 2, "the two workers never started"
        time.sleep(0.5)  # the workers are in the middle of runs
        t0 = time.monotonic()
        if to == "group":
            os.killpg(proc.pid, sig)
        else:
            proc.send_signal(sig)
        _, err = proc.communicate(timeout=15)
        took = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == code, err
    assert took < 5, f"took {took:.1f} s to stop"
    assert "Traceback" not in err and words in err, err
    assert words in err.strip().splitlines()[-1]  # the last line says what stopped it
    time.sleep(0.2)
    assert not [k for k in kids if _alive(k)], "workers left behind"
    # the runs under way were ended like the main process: their logs closed, renamed and marked
    from navcli.analysis import read_log

    assert not list(tmp_path.rglob("*.partial"))
    summaries = [read_log(p, topics=[]).summary for p in tmp_path.rglob("*.mcap")]
    stopped = [s for s in summaries if s["outcome"] == "interrupted"]
    assert stopped and {s["reason"] for s in stopped} == {reason}
    assert {s["outcome"] for s in summaries} <= {"interrupted", "reached", "timeout", "blocked"}


def test_a_worker_whose_parent_died_stops_itself(tmp_path):
    """SIGKILL of the main process (nothing of it runs to stop the pool): the workers notice within
    about a second that their parent is gone and stop themselves."""
    env, cmd = _long_comparison(tmp_path)
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 30
        while len(kids := _children(proc.pid)) < 2 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(kids) >= 2, "the two workers never started"
        proc.kill()
        proc.wait()
        deadline = time.monotonic() + 10
        while [k for k in kids if _alive(k)] and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not [k for k in kids if _alive(k)], "workers left behind"
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)


def test_sigterm_in_a_serial_run_is_logged_as_sigterm(tmp_path):
    """With one job the run is in this process: SIGTERM must end it as SIGTERM, not as Ctrl-C."""
    from navcli.config import RunSpec
    from navcli.experiments.executor import interruptible
    from navcli.signals import exit_code
    from navcli.runner import run_mission
    from navcli.scenario import load_scenario

    spec = RunSpec.build(load_scenario(SCENARIOS / "paper-8x8.yaml"), seed=1)

    def kill_at_tick_20(mission, tick):
        if tick.index == 20:
            os.kill(os.getpid(), signal.SIGTERM)

    with pytest.raises(KeyboardInterrupt) as e, interruptible():
        run_mission(spec, out=tmp_path / "t.mcap", on_tick=kill_at_tick_20)
    assert exit_code(e.value) == 128 + signal.SIGTERM
    from navcli.analysis import read_log

    assert read_log(tmp_path / "t.mcap", topics=[]).summary["reason"] == "stopped by SIGTERM"


def test_the_default_count_of_workers_is_made_in_one_place(monkeypatch):
    """``--jobs`` and ``jobs=`` left out: one worker per core, at most MAX_JOBS; every command and
    the API take it from :func:`workers`, the one module that asks for the cores."""
    import ast
    import os

    from conftest import ROOT
    from navcli.checks.arguments import MAX_JOBS
    from navcli.experiments.executor import workers

    assert workers(3) == 3
    monkeypatch.setattr(os, "cpu_count", lambda: MAX_JOBS + 10)
    assert workers(None) == MAX_JOBS
    monkeypatch.setattr(os, "cpu_count", lambda: None)
    assert workers(None) == 1
    asking = {
        str(p.relative_to(ROOT))
        for p in (ROOT / "navcli").rglob("*.py")
        for node in ast.walk(ast.parse(p.read_text()))
        if isinstance(node, ast.Attribute) and node.attr == "cpu_count"
    }
    assert asking == {"navcli/experiments/executor.py"}
