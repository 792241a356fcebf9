"""No run lost from a result: runs that end in ``error`` are counted by every table, report and
verdict, which say how many and why; ``compare``, ``sweep`` and ``reproduce`` exit 4 when some
did; a verdict over a set holding one is "no verdict"; identical reruns are one sample of a
verdict. The errors here are made on purpose (a plugin pilot that raises, a runner patched to
raise on one seed), never borrowed from a bug of navcli's."""

from __future__ import annotations


import pandas as pd
import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS, module_in_folder
from navcli.analysis.tables import distinct_runs, improvements, markdown, notes, pilot_table
from navcli.cli import app
from navcli.cli.errors import EXIT_BAD_INPUT, EXIT_FAILED_MISSION, EXIT_RUNS_ERRORED
from navcli.experiments import reproduce as rp
from navcli.experiments.document import Report

FAILING = '''
"""A pilot that raises after its first simulated second: a deliberate failure."""

from navcli.pilot.geometric import GeometricPilot


class Failing(GeometricPilot):
    def avoid(self, beliefs, obstacles, request):
        if beliefs.time > 1.0:
            raise RuntimeError("deliberate failure of the test pilot")
        return super().avoid(beliefs, obstacles, request)
'''


def _runs(pilot: str, outcomes: list[str], *, scenario: str = "room", perception: str = "vision", **same) -> list:
    """Rows of ``load_runs``' shape, one per outcome; run k takes k s and k m unless ``same``
    gives every run the same numbers (identical reruns)."""
    rows = []
    for k, outcome in enumerate(outcomes):
        rows.append(
            {
                "scenario": scenario,
                "scenario_sha256": "ab" * 32,
                "perception": perception,
                "time_limit_s": 100.0,
                "pilot": pilot,
                "seed": 1000 + k,
                "run_id": f"{pilot}-{k}",
                "outcome": outcome,
                "reason": "TypeError: boom" if outcome == "error" else "",
                "reached": outcome == "reached",
                "time_s": same.get("time_s", 10.0 + k),
                "path_cm": same.get("path_cm", 100.0 * (1 + k)),
                "collisions": 0,
                "camera_looks": 3,
                "ticks": 100 + k if not same else 100,
                "diverting_targets": same.get("diverting_targets", 0 if same else k % 3),
            }
        )
    return rows


def test_the_exit_code_of_errored_runs_is_its_own():
    assert EXIT_RUNS_ERRORED not in (0, 1, EXIT_BAD_INPUT, EXIT_FAILED_MISSION, 130, 141, 143)
    from navcli.cli.errors import __doc__ as table

    assert f"\n{EXIT_RUNS_ERRORED}     ``compare``, ``sweep``, ``reproduce``" in table


def test_the_table_counts_an_errored_run_as_not_reached_and_its_notes_say_why():
    runs = pd.DataFrame(_runs("a", ["reached"] * 9 + ["error"]) + _runs("b", ["reached"] * 10))
    table = pilot_table(runs).set_index("pilot")
    assert (table.loc["a", "runs"], table.loc["a", "reached"], table.loc["a", "outcome_error"]) == (10, 9, 1)
    said = notes(runs, table.reset_index(), improvements(runs, "b"), "b")
    assert [n for n in said if "error" in n] == [
        "room (vision perception), a: 1 of 10 runs ended in error (counted as not reached; seeds 1009): "
        "TypeError: boom (1 run)"
    ]
    md = markdown(table.reset_index(), improvements(runs, "b"), said)
    assert "| a | 9/10 (1 errored) |" in md and "| b | 10/10 |" in md


def test_a_sweep_tables_errors_are_its_runs_reasons(tmp_path):
    from navcli.analysis.tables import load_sweep

    rows = _runs("a", ["reached", "error"])
    for r in rows:
        r.pop("reason")
        r["point"], r["path_length_m"] = 0, r["path_cm"] / 100
        r["error"] = "ValueError: no way" if r["outcome"] == "error" else ""
    path = tmp_path / "results.csv"
    pd.DataFrame(rows).to_csv(path, index=False)
    runs = load_sweep(path)
    assert notes(runs, pilot_table(runs), improvements(runs.iloc[:0], "a"), "a")[0].endswith(
        "ValueError: no way (1 run)"
    )


@pytest.fixture
def failing(tmp_path, monkeypatch):
    """The failing pilot's module (``failing.py``) in the current folder, found as failing:Failing."""
    yield from module_in_folder(tmp_path, monkeypatch, "failing", FAILING)


def test_compare_pilots_exits_4_when_every_run_of_a_pilot_errored_and_its_table_says_so(failing):
    scenario = str(SCENARIOS / "open-arena.yaml")
    args = ["compare", "pilots", scenario, "--pilots", "failing:Failing,geometric", "--reruns", "2"]
    r = CliRunner().invoke(app, [*args, "--jobs", "1", "--time-limit", "5", "--out", "cmp"])
    assert r.exit_code == EXIT_RUNS_ERRORED, r.output
    assert "2 of 4 runs ended in error" in r.output
    table = (failing / "cmp" / "table.md").read_text()
    assert "| failing:Failing | 0/2 (2 errored) |" in table
    assert "failing:Failing: 2 of 2 runs ended in error" in table and "deliberate failure of the test pilot" in table
    good = CliRunner().invoke(
        app, ["compare", "pilots", scenario, "--pilots", "geometric", "--reruns", "1", "--jobs", "1", "--out", "ok"]
    )
    assert good.exit_code == 0, good.output  # no error: exit 0, whatever the outcomes


def _raising_on(seed: int):
    """``run_mission`` that raises on the run of ``seed`` (as a crash inside navcli would)."""
    from navcli import runner

    real = runner.run_mission

    def run_mission(spec, *a, **kw):
        if spec.seed == seed:
            raise TypeError("float object expected; got str")
        return real(spec, *a, **kw)

    return run_mission


def test_sweep_exits_4_when_one_run_errored_and_keeps_the_rest(tmp_path, monkeypatch):
    from navcli.config import RunSpec
    from navcli.experiments.compare import rerun_seed
    from navcli.scenario import load_scenario

    base = RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml")).seed
    monkeypatch.setattr("navcli.runner.run_mission", _raising_on(rerun_seed(base, 1)))
    plan = tmp_path / "plan.yaml"
    plan.write_text(f"version: 1\nscenarios: [{SCENARIOS / 'open-arena.yaml'}]\nseeds: 2\ntime_limit: 5\n")
    r = CliRunner().invoke(app, ["sweep", str(plan), "--jobs", "1", "--no-logs", "--csv", "--out", str(tmp_path / "s")])
    assert r.exit_code == EXIT_RUNS_ERRORED, r.output
    assert "1 raised an error" in r.output
    table = pd.read_csv(tmp_path / "s" / "results.csv")
    assert sorted(table["outcome"] == "error") == [False, True]
    assert table.loc[table["outcome"] == "error", "error"].item() == "TypeError: float object expected; got str"


def _frame(*groups: list) -> pd.DataFrame:
    return pd.DataFrame([row for g in groups for row in g])


def test_the_trap_rooms_count_every_run_and_judge_no_set_with_an_error(tmp_path, monkeypatch):
    runs = _frame(
        _runs("potential-field", ["reached"] * 9 + ["error"], scenario="u-trap"),
        _runs("geometric", ["reached"] * 8 + ["blocked"] * 2, scenario="u-trap"),
    )
    monkeypatch.setattr(rp, "_compare", lambda *a, **kw: (runs, []))
    report = Report()
    rp.traps(report, rp.QUICK, tmp_path, None)
    md = report.markdown()
    rows = {(r[0], r[1]): r for r in _table(md)}
    assert rows["potential-field", "reached"][3].startswith("9/10 [") and rows["potential-field", "reached"][
        3
    ].endswith(", 1 errored")
    assert {rows["potential-field", q][4] for q in ("reached", "needed 1 diverting target", "needed 2")} == {
        "no verdict: 1 run ended in error"
    }
    assert rows["geometric", "reached"][3].startswith("8/10 [") and "errored" not in rows["geometric", "reached"][3]
    assert not rows["geometric", "reached"][4].startswith("no verdict")  # 10 distinct runs, no error: judged
    assert "u-trap (vision perception), potential-field: 1 of 10 runs ended in error" in md
    assert "TypeError: boom (1 run)" in md
    assert report.error_count == 1 and report.errors[0].startswith("Trap rooms: u-trap")


def test_identical_reruns_are_one_sample_of_a_verdict(tmp_path, monkeypatch):
    same = {"time_s": 250.0, "path_cm": 1300.0, "diverting_targets": 1}
    runs = _frame(
        _runs("potential-field", ["reached"] * 12, scenario="u-trap", **same),
        _runs("geometric", ["reached"] * 12, scenario="u-trap"),
    )
    assert len(distinct_runs(runs)) == 1 + 12
    monkeypatch.setattr(rp, "_compare", lambda *a, **kw: (runs, []))
    report = Report()
    rp.traps(report, rp.QUICK, tmp_path, None)
    rows = {(r[0], r[1]): r for r in _table(report.markdown())}
    assert rows["potential-field", "reached"][3] == "12/12 [21%, 100%]; 1 distinct"  # Wilson of 1/1
    assert rows["potential-field", "reached"][4] == "too few distinct runs to judge (1; 10 needed)"
    assert rows["geometric", "reached"][3] == "12/12 [76%, 100%]"  # Wilson of 12/12, every run distinct


def test_table_1s_verdicts_count_identical_reruns_once_and_judge_no_pilot_with_an_error():
    same = {"time_s": 277.1, "path_cm": 1362.7}
    runs = _frame(
        _runs("geometric", ["reached"] * 45, **same),
        _runs("potential-field", ["reached"] * 44 + ["error"]),
    )
    table = pilot_table(runs).set_index("pilot")
    geo = rp._table1_rows("oracle", "geometric", runs, table)
    assert geo[0][4] == "277.1 (no interval) (1 distinct of 45)" and geo[0][6] == "45/45"
    assert geo[0][5] == "0.0"  # the SD of every reached run: the reruns repeat one run
    assert geo[0][7] == "too few distinct reached runs to judge (1; 10 needed)"
    pf = rp._table1_rows("oracle", "potential-field", runs, table)
    assert pf[0][6] == "44/45, 1 errored" and pf[0][7] == "no verdict: 1 run ended in error"


def test_identical_pairs_count_once_in_a_verdicts_gain():
    runs = _frame(
        _runs("geometric", ["reached"] * 12, time_s=300.0, path_cm=1500.0),
        _runs("potential-field", ["reached"] * 12, time_s=250.0, path_cm=1300.0),
        _runs("varied", ["reached"] * 12),
    )
    every, once = improvements(runs, "geometric"), improvements(runs, "geometric", once=True)
    assert set(every["pairs"]) == {12}
    assert dict(zip(once["pilot"], once["pairs"])) == {"potential-field": 1, "varied": 12}


def test_the_report_says_its_errored_runs_at_the_top():
    report = Report()
    report.heading("navcli reproduce", 1)
    report.text("provenance")
    report.heading("Trap rooms")
    report.errored(["Trap rooms: u-trap, geometric: 2 of 10 runs ended in error"], 2)
    rp._say_errors(report)
    md = report.markdown()
    assert md.index("RUNS THAT ENDED IN ERROR: 2") < md.index("## Trap rooms")
    assert "- Trap rooms: u-trap, geometric: 2 of 10 runs ended in error" in md
    clean = Report()
    clean.heading("navcli reproduce", 1)
    clean.text("provenance")
    rp._say_errors(clean)
    assert "No run ended in error." in clean.markdown()


@pytest.mark.parametrize("errored, code", [(0, 0), (3, EXIT_RUNS_ERRORED)])
def test_reproduce_exits_4_when_its_report_counts_errored_runs(errored, code, monkeypatch, tmp_path):
    import json

    def fake(which, out, settings, **kw):
        out.mkdir(parents=True, exist_ok=True)
        (out / "report.md").write_text("# report\n")
        (out / "source.json").write_text(json.dumps({"errored_runs": errored}))
        return {"markdown": out / "report.md", "source": out / "source.json"}

    monkeypatch.setattr("navcli.experiments.reproduce.reproduce", fake)
    r = CliRunner().invoke(app, ["reproduce", "pilots", "--quick", "--out", str(tmp_path / "r")])
    assert r.exit_code == code, r.output
    assert ("3 runs ended in error" in r.output) == bool(errored)


def test_a_policy_whose_runs_errored_is_counted_and_not_judged():
    from types import SimpleNamespace as NS

    from navcli.training.comparison import failures

    def result(policy: str, error: str | None):
        return NS(job=NS(policy=NS(label=policy)), trials=None if error else [{}], error=error or "")

    failed = failures([result("learned", None), result("learned", "KeyError: x"), result("random", None)], "room")
    assert failed == {"learned": "room, learned: 1 of 2 runs ended in error: KeyError: x (1 run)"}


def test_every_batch_commands_help_states_the_exit_code():
    for args in (["compare", "pilots"], ["compare", "policies"], ["sweep"], ["reproduce"]):
        r = CliRunner().invoke(app, [*args, "--help"], terminal_width=400)
        assert f"Exits {EXIT_RUNS_ERRORED} when some runs ended in error" in r.output, args


def _table(md: str) -> list[list[str]]:
    lines = [ln for ln in md.splitlines() if ln.startswith("| ") and not ln.startswith("| ---")]
    return [[c.strip() for c in ln.strip("|").split("|")] for ln in lines[1:]]


def test_a_policys_successes_interval_takes_the_starts_as_its_sample_and_holds_its_mean():
    """Runs repeat the same starts: two runs alike give the interval of one run, not of twice the trials."""
    from navcli.analysis.stats import wilson_interval
    from navcli.experiments.learning_paper import policy_row
    from navcli.learning.actions import ACTIONS

    trial = {"outcome": "reached", "success": True, "actions": 5, "reward": -5.0} | {a: 1 for a in ACTIONS}
    same = [
        trial | {"start": s, "run": r} | ({"outcome": "blocked", "success": False} if s == 0 else {})
        for r in range(2)
        for s in range(3)
    ]  # 2 of 3 starts reached, in both runs
    row = policy_row(pd.DataFrame(same), "p", runs=2, errored=0, starts=3, max_actions=500)
    lo, hi = wilson_interval(2, 3)
    assert row.successes == pytest.approx((2.0, 3 * lo, 3 * hi)) and 3 * lo < 2.0 < 3 * hi


def test_compare_policies_exits_4_and_its_table_says_which_runs_errored_and_why(tmp_path, monkeypatch):
    from navcli.training import comparison

    real = comparison.run_trials

    def run_trials(job):
        if job.run == 1:
            raise KeyError("deliberate")
        return real(job)

    monkeypatch.setattr(comparison, "run_trials", run_trials)
    args = ["compare", "policies", "landmarks-12", "--policy", "random", "--runs", "2", "--starts", "2"]
    r = CliRunner().invoke(app, [*args, "--jobs", "1", "--out", str(tmp_path / "p")])
    assert r.exit_code == EXIT_RUNS_ERRORED, r.output
    assert "1 of 2 runs ended in error" in r.output
    md = (tmp_path / "p" / "policies.md").read_text()
    assert "- random: 1 of 2 runs ended in error: KeyError: 'deliberate' (1 run)" in md


def test_figure_3_draws_the_trainings_that_finished_and_counts_one_that_raised(tmp_path):
    from concurrent.futures import Future

    from navcli.experiments.executor import SerialExecutor
    from navcli.experiments.learning_paper import figure3

    curve = [{"trials": t, "successes": s, "reward": -10.0 * t} for t, s in ((10, 1), (20, 3))]
    good, bad = Future(), Future()
    good.set_result({"seed": 1, "curve": curve, "hand_coded": 2, "random": 0})
    bad.set_exception(RuntimeError("deliberate"))
    report = Report()
    out = tmp_path / "figure3"
    out.mkdir()
    figure3(
        report,
        rp.QUICK,
        out,
        SerialExecutor(),
        ([out / "m1.npz", out / "m2.npz"], {good: 0, bad: 1}),
        rp._scenario,
        rp._conditions,
    )
    md = report.markdown()
    assert "1 of 2 trainings ended in error (seeds 2): RuntimeError: deliberate" in md
    assert "1 training of" in md and "(seeds 1, in parallel" in md and (out / "figure3.png").exists()
    assert report.error_count == 1
