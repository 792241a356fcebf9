"""Nothing overwritten unasked: every command that writes a file it is given (or its default
name) refuses an existing one with exit 2, naming --force, before any work; with --force it is
replaced, whole (a new file renamed over it). The commands that resume keep their folder's files."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.cli import app

ARENA = str(SCENARIOS / "open-arena.yaml")


def cli(*args: str | Path):
    r = CliRunner().invoke(app, [str(a) for a in args])
    assert "Traceback" not in r.output and "internal error" not in r.output, r.output
    return r


@pytest.fixture(scope="module")
def logs(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("logs")
    r = cli("run", ARENA, "--seed", "1", "--time-limit", "2", "--out", folder / "run.mcap")
    assert r.exit_code == 3, r.output  # a timeout
    return folder


# (command line, the file it writes, its exit when it succeeds); {t}: the test's folder, {logs}: the logs'
COMMANDS = {
    "run --out": (["run", ARENA, "--seed", "1", "--time-limit", "1", "--out", "{t}/ow.mcap"], "ow.mcap", 3),
    "render": (["render", "{logs}/run.mcap", "--to", "0.3", "--fps", "5", "--out", "{t}/v.gif"], "v.gif", 0),
    "plot field": (["plot", "field", ARENA, "--step", "2", "--out", "{t}/f.png"], "f.png", 0),
    "plot bids": (["plot", "bids", ARENA, "--step", "2", "--out", "{t}/b.png"], "b.png", 0),
    "plot map": (["plot", "map", "{logs}/run.mcap", "--out", "{t}/m.png"], "m.png", 0),
    "layout": (["layout", "--out", "{t}/layout.json"], "layout.json", 0),
    "report": (["report", "{logs}", "--out", "{t}/rep"], "rep/runs.csv", 0),
}


@pytest.mark.parametrize("name", COMMANDS)
def test_an_existing_output_is_refused_unless_forced(tmp_path, monkeypatch, logs, name):
    monkeypatch.chdir(tmp_path)
    args, target, ok = COMMANDS[name]
    args = [a.format(t=tmp_path, logs=logs) for a in args]
    first = cli(*args)
    assert first.exit_code == ok, first.output
    path = tmp_path / target if target else next(tmp_path.rglob("*.mcap"))
    before = path.read_bytes(), path.stat().st_ino
    files = sorted(tmp_path.rglob("*"))
    again = cli(*args)
    assert again.exit_code == 2, again.output
    assert f"{path.relative_to(tmp_path) if target is None else path}: exists" in again.output
    assert "--force replaces it" in again.output, again.output
    assert (path.read_bytes(), path.stat().st_ino) == before and sorted(tmp_path.rglob("*")) == files
    forced = cli(*args, "--force")
    assert forced.exit_code == ok, forced.output
    assert path.stat().st_ino != before[1]  # a new file, renamed over the old one


def test_a_rerun_under_the_default_name_writes_beside_the_log_before_it(tmp_path, monkeypatch):
    """The default name is the run's id: a rerun of the same run keeps the first log and writes
    `<name>-2.mcap`, then `-3`; --force writes over the first."""
    monkeypatch.chdir(tmp_path)
    args = ["run", ARENA, "--seed", "1", "--time-limit", "1"]
    assert cli(*args).exit_code == 3
    (first,) = tmp_path.rglob("*.mcap")
    before = first.read_bytes(), first.stat().st_ino
    for n in (2, 3):
        again = cli(*args)
        assert again.exit_code == 3, again.output
        assert f"{first.stem}-{n}.mcap" in again.output
        assert (first.read_bytes(), first.stat().st_ino) == before
    assert sorted(p.name for p in tmp_path.rglob("*.mcap")) == sorted(
        [first.name, f"{first.stem}-2.mcap", f"{first.stem}-3.mcap"]
    )
    forced = cli(*args, "--force")
    assert forced.exit_code == 3 and first.stat().st_ino != before[1], forced.output
    assert len(list(tmp_path.rglob("*.mcap"))) == 3


def test_a_second_seed_does_not_replace_the_first_runs_log(tmp_path):
    log = tmp_path / "ow.mcap"
    assert cli("run", ARENA, "--seed", "1", "--time-limit", "1", "--out", log).exit_code == 3
    first = log.read_bytes()
    r = cli("run", ARENA, "--seed", "2", "--time-limit", "1", "--out", log)
    assert r.exit_code == 2 and "--out: " in r.output and "--force" in r.output, r.output
    assert log.read_bytes() == first and sorted(os.listdir(tmp_path)) == ["ow.mcap"]  # no .partial, no lock left
    assert cli("run", ARENA, "--seed", "2", "--time-limit", "1", "--out", log, "--force").exit_code == 3
    from navcli.analysis import read_log

    assert read_log(log).summary["seed"] == 2


def test_train_keeps_an_existing_model_unless_forced_and_resumes_its_own(tmp_path):
    model = tmp_path / "m.npz"
    base = ["train", "landmarks-12", "--eval-every", "1", "--eval-starts", "1", "--jobs", "1", "--out", model]
    first = cli(*base, "--trials", "1")
    assert first.exit_code == 0, first.output
    before = model.read_bytes()
    again = cli(*base, "--trials", "1")
    assert again.exit_code == 2 and f"{model}: exists" in again.output and "--force" in again.output, again.output
    assert model.read_bytes() == before
    resumed = cli(*base, "--trials", "2", "--resume", model)  # continuing its own file is what --resume asks
    assert resumed.exit_code == 0, resumed.output
    assert cli(*base, "--trials", "1", "--force").exit_code == 0


def test_a_resumed_comparison_keeps_its_logs_and_remakes_its_table(tmp_path, logs):
    out = tmp_path / "cmp"
    args = ["compare", "pilots", ARENA, "--reruns", "1", "--pilots", "geometric", "--time-limit", "1"]
    args += ["--jobs", "1", "--out", out]
    assert cli(*args).exit_code == 0
    log = next(out.rglob("*.mcap"))
    inode = log.stat().st_ino
    r = cli(*args)
    assert r.exit_code == 0 and "0 run now, 1 already complete" in r.output, r.output
    assert log.stat().st_ino == inode  # kept, not rewritten
    shutil.rmtree(out)
