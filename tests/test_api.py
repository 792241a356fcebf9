"""The Python API (navcli.api): a run's tables in memory are the log's, observers may stop a run,
batches return one row per run, nothing is written unless asked, and every snippet of
docs/python-api.md runs in an empty folder and leaves it empty."""

from __future__ import annotations

import os
import re

import pandas as pd
import pytest

import navcli
from conftest import ROOT, SCENARIOS
from navcli.analysis import read_log
from navcli.analysis.tables import improvements, pilot_table

ROOM = SCENARIOS / "u-trap.yaml"
TOPICS = ("/robot/pose", "/robot/odometry", "/pilot", "/bids", "/vision", "/navigation", "/events")


def _tree(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def test_a_runs_tables_in_memory_are_its_logs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    kept = navcli.run(ROOM, seed=2, time_limit=40.0)
    assert _tree(tmp_path) == [] and kept.log is None  # nothing written
    logged = navcli.run(ROOM, seed=2, time_limit=40.0, log=tmp_path / "r.mcap")
    assert kept.summary == logged.summary and logged.log == tmp_path / "r.mcap"
    log = read_log(logged.log)
    for topic in TOPICS:
        pd.testing.assert_frame_equal(kept[topic], log[topic], check_dtype=False, obj=topic)
        pd.testing.assert_frame_equal(logged.frames[topic], log[topic], check_dtype=False, obj=topic)
    assert (kept.bids is kept["/bids"]) and len(kept.bids) == kept.summary["ticks"]
    assert kept.events["message"].iloc[0].startswith("mission u-trap started")


def test_an_observer_sees_every_tick_and_may_stop_the_run():
    seen = []

    def watch(mission, tick):
        seen.append(tick.index)
        return tick.index < 25  # False at tick 25: stop

    r = navcli.run(SCENARIOS / "open-arena.yaml", observers=[watch])
    assert seen == list(range(1, 26))
    assert (r.summary["outcome"], r.summary["reason"], r.summary["ticks"]) == ("interrupted", "stopped by watch", 25)
    assert r.poses["time_s"].iloc[-1] == pytest.approx(2.5) and r.events["message"].iloc[-1] == "stopped by watch"


def test_spec_takes_a_file_a_scenario_or_a_spec_and_refuses_what_the_cli_refuses():
    a = navcli.spec(SCENARIOS / "open-arena.yaml", pilot="geometric", params={"pilot.K": 30})
    b = navcli.spec(a.scenario, pilot="geometric", params={"pilot.K": 30})
    assert a == b and navcli.spec(a, seed=9).seed == 9 and navcli.spec(a, params={"pilot.A_t": 40}).params.pilot.K == 30
    with pytest.raises(navcli.NavcliError, match="pilot.K must be at most 1000"):
        navcli.spec(a, params={"pilot.K": 2000})
    with pytest.raises(navcli.UnknownPlugin):
        navcli.run(a, pilot="no-such-pilot")


def test_compare_returns_a_row_per_run_and_keeps_logs_only_when_asked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    kw = dict(reruns=2, time_limit=20.0, jobs=2)
    rows = navcli.compare([SCENARIOS / "open-arena.yaml"], ["potential-field", "geometric"], **kw)
    assert _tree(tmp_path) == [] and len(rows) == 4
    assert sorted(rows["pilot"]) == ["geometric"] * 2 + ["potential-field"] * 2
    seeds = {p: sorted(g["seed"]) for p, g in rows.groupby("pilot")}
    assert seeds["geometric"] == seeds["potential-field"] and len(set(seeds["geometric"])) == 2  # the same: paired
    table = pilot_table(rows)
    assert list(table["runs"]) == [2, 2] and set(improvements(rows, "geometric")["pilot"]) == {"potential-field"}
    kept = navcli.compare([SCENARIOS / "open-arena.yaml"], ["potential-field", "geometric"], out="cmp", **kw)
    assert len(list((tmp_path / "cmp").rglob("*.mcap"))) == 4
    cols = list(rows.columns)  # one row for a run, made by one function, with or without its log
    assert set(cols) < set(kept.columns) and {"scenario_sha256", "diverting_targets", "navigation"} <= set(cols)
    pd.testing.assert_frame_equal(
        rows.sort_values("run_id")[cols].reset_index(drop=True), kept.sort_values("run_id")[cols].reset_index(drop=True)
    )


def test_sweep_takes_a_plan_as_a_dict(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    plan = {
        "version": 1,
        "scenarios": [str(SCENARIOS / "open-arena.yaml")],
        "seeds": 2,
        "time_limit": 5,
        "grid": {"pilot.K": [10, 30]},
    }
    rows = navcli.sweep(plan, jobs=2)
    assert _tree(tmp_path) == [] and sorted(rows["pilot.K"]) == [10.0, 10.0, 30.0, 30.0]
    assert rows["run_id"].nunique() == 4 and set(rows["error"]) == {""}
    with pytest.raises(
        navcli.NavcliError, match=r"<dict>: grid.pilot.k\[0\]: unknown parameter .pilot.k. \(did you mean pilot.K\?\)"
    ):
        navcli.sweep(plan | {"grid": {"pilot.k": [1]}})


def _snippets():
    text = (ROOT / "docs" / "python-api.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


@pytest.mark.parametrize("i", range(len(_snippets())))
def test_every_snippet_of_the_docs_runs_and_writes_nothing(i, tmp_path, monkeypatch):
    """Run in an empty folder (the scenarios found through a link to the repository's), with
    matplotlib drawing nowhere: the folder holds only that link afterwards."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    os.symlink(SCENARIOS, tmp_path / "scenarios")
    code = _snippets()[i].replace("reruns=3", "reruns=2")
    exec(compile(code, f"docs/python-api.md snippet {i + 1}", "exec"), {"__name__": "__docs__"})
    assert _tree(tmp_path) == ["scenarios"]
