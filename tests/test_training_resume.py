"""An interrupted training resumed with ``--resume`` ends exactly where an uninterrupted one does:
the same model arrays (bit for bit), learning curve and trials CSV, wherever it was interrupted
(right after a save, between saves, more than once, with evaluations still running); and
``navcli train`` stops cleanly on Ctrl-C (130) and SIGTERM (143), its workers with it."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import Executor, Future
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, SCENARIOS

TOTAL, EVERY, STARTS, SEED = 7, 3, 2, 5  # saves at 3, 6 and 7 trials
SHORT = {"learning.max_actions": 4}  # short trials (each well under 0.1 s)


@pytest.fixture(scope="module")
def spec():
    from navcli import load_scenario
    from navcli.training.task import task_spec

    return task_spec(load_scenario(SCENARIOS / "landmarks-12.yaml"), SHORT)


def _train(spec, out: Path, **kw):
    from navcli.training.trainer import train

    kw = {"trials": TOTAL, "eval_every": EVERY, "eval_starts": STARTS, "seed": SEED, "workers": 1, **kw}
    return train(spec, out=out, **kw)


def _stop_after(k: int):
    """An ``on_trial`` that interrupts the training (like Ctrl-C) once trial ``k`` (from 0) is done."""

    def on_trial(i, r, result) -> None:
        if i == k:
            raise KeyboardInterrupt

    return on_trial


def _saved_trials(out: Path) -> int:
    return json.loads(out.with_suffix(".json").read_text())["trials"]


def _model(out: Path) -> tuple[dict[str, np.ndarray], dict]:
    with np.load(out, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    return arrays, json.loads(str(arrays.pop("meta")))


def _trials_csv(out: Path) -> str:
    from navcli.training.trainer import trials_paths

    return trials_paths(out)[0].read_text()


def assert_same_training(out: Path, ref: Path) -> None:
    """Every array of the two model files equal, their metadata (the curve first) and trials CSVs too."""
    a, meta = _model(out)
    b, ref_meta = _model(ref)
    assert sorted(a) == sorted(b)
    differ = [k for k in a if not (a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k]))]
    assert not differ, f"arrays that differ from the uninterrupted run's: {differ}"
    assert meta["curve"] == ref_meta["curve"]
    assert meta == ref_meta
    assert _trials_csv(out) == _trials_csv(ref)


def _resume_to_total(spec, out: Path, **kw):
    return _train(spec, out, trials=TOTAL, resume=out, **kw)  # --trials: the total to reach


@pytest.fixture(scope="module", params=["prioritized-sweeping", "q-learning"])
def reference(request, spec, tmp_path_factory):
    """An uninterrupted training of TOTAL trials: (algorithm, its model file)."""
    out = tmp_path_factory.mktemp(request.param) / "ref.npz"
    _train(spec, out, algorithm=request.param)
    assert [p["trials"] for p in _model(out)[1]["curve"]] == [0, 3, 6, 7]
    return request.param, out


@pytest.mark.parametrize("k", [2, 3, 4, 5], ids=lambda k: f"after-trial-{k}")
def test_an_interrupted_training_resumes_to_the_same_model_curve_and_trials(spec, reference, tmp_path, k):
    # k=2, 5 (trials 3, 6 done): right after a save; k=3, 4: between saves
    algorithm, ref = reference
    out = tmp_path / "m.npz"
    with pytest.raises(KeyboardInterrupt):
        _train(spec, out, algorithm=algorithm, on_trial=_stop_after(k))
    assert _saved_trials(out) == {2: 3, 3: 3, 4: 3, 5: 6}[k]
    _resume_to_total(spec, out, algorithm=algorithm)
    assert_same_training(out, ref)


def test_a_training_interrupted_twice_resumes_to_the_same_model(spec, reference, tmp_path):
    algorithm, ref = reference
    out = tmp_path / "m.npz"
    with pytest.raises(KeyboardInterrupt):
        _train(spec, out, algorithm=algorithm, on_trial=_stop_after(3))  # saved at 3
    with pytest.raises(KeyboardInterrupt):  # trial indices go on from the save: 3, 4, 5 -> saved at 6
        _resume_to_total(spec, out, algorithm=algorithm, on_trial=_stop_after(5))
    _resume_to_total(spec, out, algorithm=algorithm)
    assert_same_training(out, ref)


class LazyExecutor(Executor):
    """Evaluations that have not run when the model is saved (slow workers): each runs only when
    its result is asked for, which a training does at its very end."""

    workers = 1

    def submit(self, fn, /, *args, **kwargs) -> Future:
        f = _LazyFuture()
        f.job = lambda: fn(*args, **kwargs)
        return f


class _LazyFuture(Future):
    job = None

    def result(self, timeout=None):
        if self.job is not None:
            job, self.job = self.job, None
            self.set_result(job())
        return super().result(timeout)


@pytest.mark.parametrize("k", [2, 4, 6], ids=lambda k: f"after-trial-{k}")
def test_evaluations_still_running_at_the_save_are_run_on_resume(spec, reference, tmp_path, monkeypatch, k):
    from navcli.experiments import executor as ex

    algorithm, ref = reference
    monkeypatch.setattr(ex, "executor", lambda workers, *a, **kw: contextlib.nullcontext(LazyExecutor()))
    out = tmp_path / "m.npz"
    with pytest.raises(KeyboardInterrupt):
        _train(spec, out, algorithm=algorithm, on_trial=_stop_after(k))
    assert _model(out)[1]["curve"] == []  # every evaluation was still running at the save
    _resume_to_total(spec, out, algorithm=algorithm)
    assert_same_training(out, ref)


# the worker processes' interruption is the same for both learners: one of them is enough
@pytest.mark.parametrize("reference", ["prioritized-sweeping"], indirect=True)
def test_evaluations_in_worker_processes_survive_an_interruption(spec, reference, tmp_path):
    algorithm, ref = reference
    out = tmp_path / "m.npz"
    with pytest.raises(KeyboardInterrupt):  # the workers are stopped as the evaluation of 3 trials runs
        _train(spec, out, algorithm=algorithm, workers=2, on_trial=_stop_after(2))
    _resume_to_total(spec, out, algorithm=algorithm, workers=2)
    assert_same_training(out, ref)


def test_resume_into_another_file_keeps_the_trials_before_the_save(spec, reference, tmp_path):
    algorithm, ref = reference
    out, other = tmp_path / "m.npz", tmp_path / "other.npz"
    with pytest.raises(KeyboardInterrupt):
        _train(spec, out, algorithm=algorithm, on_trial=_stop_after(4))
    _train(spec, other, algorithm=algorithm, trials=TOTAL, resume=out)
    assert_same_training(other, ref)


# -- the command line: Ctrl-C and SIGTERM
def _children(pid: int) -> list[int]:
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            with contextlib.suppress(OSError):
                if int((d / "stat").read_text().rsplit(")", 1)[1].split()[1]) == pid:
                    out.append(int(d.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


CLI_TRIALS, CLI_EVERY = 12, 3
CLI_PARAMS = ["--param", "learning.max_actions=40"]  # trials of about 0.1 s: the signal lands in training


def _cli(out: Path, *args: str) -> list[str]:
    return [
        sys.executable,
        "-m",
        "navcli",
        "train",
        str(SCENARIOS / "landmarks-12.yaml"),
        "--eval-every",
        str(CLI_EVERY),
        "--eval-starts",
        str(STARTS),
        "--seed",
        str(SEED),
        "--jobs",
        "2",
        "--out",
        str(out),
        *CLI_PARAMS,
        *args,
    ]


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="finds the worker processes in /proc")
@pytest.mark.parametrize("how", ["SIGTERM", "Ctrl-C"])
def test_the_command_stops_cleanly_on_sigterm_and_ctrl_c_and_resumes(tmp_path, how):
    out = tmp_path / "m.npz"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.Popen(
        _cli(out, "--trials", str(CLI_TRIALS)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,
    )  # its own process group, SIGINT not ignored
    try:
        deadline = time.monotonic() + 60
        while not out.with_suffix(".json").exists():  # the first save: an evaluation was just submitted
            assert p.poll() is None and time.monotonic() < deadline, p.communicate()
            time.sleep(0.01)
        workers = _children(p.pid)
        if how == "SIGTERM":
            os.kill(p.pid, signal.SIGTERM)  # the main process only, as a scheduler's kill
        else:
            os.killpg(p.pid, signal.SIGINT)  # the whole group, as a terminal's Ctrl-C
        _, err = p.communicate(timeout=30)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert p.returncode == (143 if how == "SIGTERM" else 130), err
    assert ("stopped by SIGTERM" if how == "SIGTERM" else "interrupted (Ctrl-C)") in err
    assert "Traceback" not in err, err
    assert len(workers) == 2
    time.sleep(0.2)
    assert not [w for w in workers if _alive(w)], "workers left behind"
    saved = _saved_trials(out)
    assert 0 < saved < CLI_TRIALS
    r = subprocess.run(
        _cli(out, "--trials", str(CLI_TRIALS), "--resume", str(out)),
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    ref = tmp_path / "ref.npz"  # the same training uninterrupted, in this process
    from navcli import load_scenario
    from navcli.training.task import task_spec
    from navcli.training.trainer import train

    train(
        task_spec(load_scenario(SCENARIOS / "landmarks-12.yaml"), {"learning.max_actions": 40}),
        trials=CLI_TRIALS,
        eval_every=CLI_EVERY,
        eval_starts=STARTS,
        seed=SEED,
        out=ref,
        workers=1,
    )
    a, meta = _model(out)
    b, ref_meta = _model(ref)
    assert all(np.array_equal(a[k], b[k]) for k in b) and sorted(a) == sorted(b)
    assert meta == ref_meta and _trials_csv(out) == _trials_csv(ref)
