"""Batch commands never mix runs up: report groups by configuration, refuses the same run twice,
keeps interrupted runs out of success rates, says what it cannot compute, skips an unreadable
log by name; compare reports the runs it planned."""

from __future__ import annotations

import shutil

import pytest
import yaml
from typer.testing import CliRunner

from navcli.analysis.stats import MIN_SAMPLE
from navcli.analysis.tables import MIN_PAIRS, load_runs, pilot_table
from conftest import scenario_dict
from navcli.cli import app
from navcli.config import RunSpec
from navcli.experiments import compare
from navcli.runner import run_mission
from navcli.scenario import load_scenario

PILOTS = ["potential-field", "geometric"]
cli = CliRunner()


@pytest.fixture(scope="module")
def near(tmp_path_factory):
    """A target 1.5 m ahead in an empty room (oracle): every run reaches it in a few seconds."""
    d = tmp_path_factory.mktemp("near")
    f = d / "near.yaml"
    f.write_text(
        yaml.safe_dump(
            scenario_dict(
                name="near", target={"at": [2.5, 2.0]}, mission={"time_limit": 30, "seed": 7, "perception": "oracle"}
            )
        )
    )
    return load_scenario(f)


@pytest.fixture(scope="module")
def three_pairs(near, tmp_path_factory):
    out = tmp_path_factory.mktemp("runs")
    compare.run_all(compare.plan([RunSpec.build(near)], PILOTS, 3, out), 1)
    return out


def report(*args):
    r = cli.invoke(app, ["report", *map(str, args)])
    assert "Traceback" not in r.output
    return r


def test_a_small_sample_is_reported_with_a_warning(three_pairs, tmp_path):
    r = report(three_pairs, "--out", tmp_path)
    assert r.exit_code == 0, r.output
    assert "| potential-field | 3/3 |" in r.output and "| geometric | 3/3 |" in r.output
    assert f"only 3 pairs; with fewer than {MIN_SAMPLE} its 95 % intervals are too uncertain to trust" in r.output
    assert 3 < MIN_PAIRS and "the paired test cannot reach p < 0.05 (its least p is 2/2^3 = 0.25)" in r.output


def test_the_same_runs_twice_are_refused(three_pairs, tmp_path):
    for sub in ("a", "b"):
        shutil.copytree(three_pairs, tmp_path / sub)
    r = report(tmp_path)
    assert r.exit_code == 2 and "are the same run" in r.output


def test_other_time_limits_are_other_conditions_and_an_interrupted_run_is_left_out(near, three_pairs, tmp_path):
    shutil.copytree(three_pairs, tmp_path / "a")
    other = RunSpec.build(near, time_limit=20.0)  # another configuration of the same scenario
    run_mission(other.replace(pilot="geometric"), out=tmp_path / "b" / "g.mcap")

    def stop(mission, tick):
        if tick.index == 7:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_mission(other, out=tmp_path / "b" / "pf.mcap", on_tick=stop)
    table = pilot_table(load_runs(tmp_path)).set_index(["condition", "pilot"])
    assert table["runs"].to_dict() == {
        ("near (oracle perception, time limit 20 s)", "geometric"): 1,
        ("near (oracle perception, time limit 20 s)", "potential-field"): 0,
        ("near (oracle perception, time limit 30 s)", "geometric"): 3,
        ("near (oracle perception, time limit 30 s)", "potential-field"): 3,
    }
    assert table.loc[("near (oracle perception, time limit 20 s)", "potential-field"), "interrupted"] == 1
    r = report(tmp_path, "--out", tmp_path / "rep")
    assert r.exit_code == 0 and "1 interrupted run(s) left out of the success rate" in r.output


def test_unknown_baseline_unreadable_log_and_one_pilot_are_said(three_pairs, tmp_path):
    shutil.copytree(three_pairs, tmp_path / "runs", ignore=shutil.ignore_patterns("geometric-*"))
    (tmp_path / "runs" / "broken.mcap").write_bytes(b"not an mcap")
    r = report(tmp_path / "runs", "--out", tmp_path / "rep", "--baseline", "geometrc")
    assert r.exit_code == 2 and "'geometrc' is not a pilot" in r.output and not (tmp_path / "rep").exists()
    assert "none of these runs' (potential-field)" in r.output
    r = report(tmp_path / "runs", "--out", tmp_path / "rep", "--baseline", "geometric")
    assert r.exit_code == 0, r.output
    assert f"skipped {tmp_path / 'runs' / 'broken.mcap'}: not an MCAP file" in r.output
    assert "baseline 'geometric' is not among the pilots of these runs (potential-field)" in r.output


def test_an_empty_folder_says_what_is_missing(tmp_path):
    r = report(tmp_path)
    assert r.exit_code == 2 and "no readable .mcap logs found" in r.output


def test_compare_reports_only_the_runs_it_planned(near, tmp_path):
    out = tmp_path / "cmp"
    scenario = near.source
    r = cli.invoke(app, ["compare", "pilots", scenario, "--reruns", "1", "--jobs", "1", "--out", str(out)])
    assert r.exit_code == 0, r.output
    r = cli.invoke(
        app, ["compare", "pilots", scenario, "--reruns", "1", "--jobs", "1", "--out", str(out), "--pilots", "geometric"]
    )
    assert r.exit_code == 0 and "Traceback" not in r.output, r.output
    assert "| geometric | 1/1 |" in r.output and "| potential-field |" not in r.output
    assert "only one pilot (geometric)" in r.output


def test_the_table_breaks_outcomes_and_diverting_targets_down_per_pilot():
    import pandas as pd

    from navcli.analysis.tables import markdown

    rows = []
    for seed, (outcome, diverting) in enumerate(
        [("reached", 0), ("reached", 1), ("reached", 2), ("blocked", 3), ("timeout", 1), ("interrupted", 0)]
    ):
        rows.append(
            {
                "log": f"l{seed}",
                "run_id": f"r{seed}",
                "scenario": "s",
                "perception": "vision",
                "pilot": "pf",
                "seed": seed,
                "time_limit_s": 100.0,
                "outcome": outcome,
                "reached": outcome == "reached",
                "time_s": 50.0 if outcome == "reached" else 100.0,
                "path_m": 5.0,
                "path_cm": 500.0,
                "collisions": 0,
                "camera_looks": 3,
                "ticks": 500,
                "diverting_targets": diverting,
                "poses_path_m": 5.0,
                "xy": None,
            }
        )
    t = pilot_table(pd.DataFrame(rows)).iloc[0]
    assert (t.outcome_reached, t.outcome_blocked, t.outcome_timeout, t.interrupted) == (3, 1, 1, 1)
    assert (t.diverting_0, t.diverting_1, t.diverting_2, t.diverting_3_or_more) == (1, 2, 1, 1)  # the 5 counted
    assert t.diverting_targets_mean == pytest.approx((0 + 1 + 2 + 3 + 1) / 5)
    md = markdown(pilot_table(pd.DataFrame(rows)), pd.DataFrame(columns=["condition"]))
    assert "| pf | 3 | 1 | 1 | 0 | 1.40 | 1 / 2 / 1 / 1 |" in md
