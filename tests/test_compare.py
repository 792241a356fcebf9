"""navcli compare pilots / navcli report on a small comparison, checked against the logs themselves."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from navcli.analysis import LogError, path_length, read_log
from navcli.analysis.tables import load_runs, paired_improvement, pilot_table
from conftest import SCENARIOS
from navcli.config import RunSpec
from navcli.experiments import compare
from navcli.cli import app
from navcli.mission import Mission
from navcli.log.writer import Recorder
from navcli.scenario import load_scenario

PILOTS = ["potential-field", "geometric"]


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """Two reruns of the Figure 9 room with both pilots, run in this process."""
    out = tmp_path_factory.mktemp("cmp")
    sc = load_scenario(SCENARIOS / "paper-fig9.yaml")
    jobs = compare.plan([RunSpec.build(sc)], PILOTS, 2, out)
    results = compare.run_all(jobs, 1)
    return out, jobs, results


def test_the_same_seeds_serve_every_pilot(small):
    _, jobs, _ = small
    seeds = {p: [j.spec.seed for j in jobs if j.spec.pilot == p] for p in PILOTS}
    assert seeds["potential-field"] == seeds["geometric"] and len(set(seeds["geometric"])) == 2
    assert seeds["geometric"] == [compare.rerun_seed(1, 0), compare.rerun_seed(1, 1)]


def test_table_agrees_with_the_poses_of_the_logs(small):
    out, jobs, results = small
    runs = load_runs(out)
    assert len(runs) == len(jobs) and all(r.ran for r in results)
    table = pilot_table(runs).set_index("pilot")
    for pilot in PILOTS:
        times, paths = [], []
        for j in (j for j in jobs if j.spec.pilot == pilot):
            log = read_log(j.log)
            if log.summary["outcome"] != "reached":
                continue
            poses = log["/robot/pose"]
            times.append(poses["time_s"].iloc[-1])
            paths.append(100 * path_length(poses))
        assert table.loc[pilot, "reached"] == len(times)
        assert table.loc[pilot, "time_s_mean"] == pytest.approx(np.mean(times), abs=1e-9)
        assert table.loc[pilot, "path_cm_mean"] == pytest.approx(np.mean(paths), rel=0.01)
        assert table.loc[pilot, "path_cm_std"] == pytest.approx(np.std(paths, ddof=1), rel=0.05, abs=1.0)


def test_resume_runs_only_what_is_missing(small):
    out, jobs, _ = small
    gone = jobs[1]
    Path(gone.log).unlink()
    again = compare.run_all(jobs, 1)
    assert [r.job for r in again if r.ran] == [gone]
    assert all(r.outcome == compare.complete(r.job.log, r.job.spec.run_id) for r in again)


def test_parallel_and_serial_give_the_same_table(small, tmp_path):
    serial, jobs, _ = small  # the same plan, run in this process
    base = RunSpec.build(load_scenario(SCENARIOS / "paper-fig9.yaml"))
    parallel = compare.run_all(compare.plan([base], PILOTS, 2, tmp_path), 2)
    assert all(r.ran for r in parallel)
    columns = ["scenario", "pilot", "seed", "run_id", "outcome", "time_s", "path_m", "collisions", "camera_looks"]
    a, b = (load_runs(d).sort_values("log").reset_index(drop=True)[columns] for d in (serial, tmp_path))
    assert a.equals(b) and pilot_table(load_runs(serial)).equals(pilot_table(load_runs(tmp_path)))


def test_failed_runs_stay_in_the_table_as_failures(tmp_path, monkeypatch):
    import navcli.runner

    sc = load_scenario(SCENARIOS / "paper-fig9.yaml")
    jobs = compare.plan([RunSpec.build(sc, time_limit=3.0)], PILOTS, 2, tmp_path)  # too short to arrive: timeouts
    real = navcli.runner.run_mission

    def boom(mission, tick):
        if tick.index == 3:
            raise RuntimeError("wheel fell off")

    def one_breaks(spec, **kw):  # one run raises: an error, its log closed and marked
        if spec.pilot == "geometric" and spec.seed == jobs[0].spec.seed:
            kw["on_tick"] = boom
        return real(spec, **kw)

    monkeypatch.setattr(navcli.runner, "run_mission", one_breaks)
    results = compare.run_all(jobs, 1)
    assert sorted(r.outcome for r in results) == ["error", "timeout", "timeout", "timeout"]
    broken = next(r for r in results if r.outcome == "error")
    assert "wheel fell off" in broken.message
    table = pilot_table(load_runs(tmp_path)).set_index("pilot")
    assert table["runs"].to_dict() == {"geometric": 2, "potential-field": 2}
    assert table["reached"].sum() == 0 and table["failed"].sum() == 4
    assert compare.complete(broken.job.log, broken.job.spec.run_id) is None  # a resumed comparison runs it again


def test_a_log_whose_summary_disagrees_with_its_poses_is_refused_by_name(tmp_path):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    m = Mission(RunSpec.build(sc))
    path = tmp_path / "liar.mcap"
    rec = Recorder(path)
    rec.start(m.spec, m.world.pose, m.world.odometry.pose)
    for _ in range(30):
        rec.tick(m.step())
    rec.finish(m.summary() | {"path_length_m": 42.0}, m.world.time_ns)
    with pytest.raises(LogError, match="liar.mcap.*disagrees"):
        load_runs(tmp_path)


def test_a_parameter_reaches_every_worker_and_the_log_and_never_reuses_other_runs(tmp_path):
    """The whole configuration travels with the job: --param pilot.K=30 is what the workers run
    and what every log records; resume never takes a K = 18 log for a K = 30 run."""
    sc = load_scenario(SCENARIOS / "paper-fig9.yaml")
    base = RunSpec.build(sc, time_limit=5.0)
    k18 = compare.plan([base], PILOTS, 2, tmp_path)
    compare.run_all(k18, 2)
    k30 = compare.plan([RunSpec.build(sc, time_limit=5.0, overrides={"pilot.K": 30})], PILOTS, 2, tmp_path)
    assert {j.log for j in k30}.isdisjoint(j.log for j in k18)  # the run id is part of the path
    results = compare.run_all(k30, 2)
    assert all(r.ran for r in results)  # nothing reused from the K = 18 runs
    for r in results:
        config = read_log(r.job.log, topics=[]).config
        assert config["params"]["pilot"]["K"] == 30.0 and config["seed"] == r.job.spec.seed
    runs = load_runs(tmp_path)
    assert sorted(runs["params.pilot.K"]) == [18.0] * 4 + [30.0] * 4
    # a log of another configuration at the expected path is not taken as done
    Path(k18[0].log).replace(k30[0].log)
    assert compare.complete(k30[0].log, k30[0].spec.run_id) is None


def test_paired_statistics_on_a_known_case():
    base = np.array([10.0, 12.0, 11.0, 13.0, 9.0, 10.0, 12.0, 11.0])
    better = base * 0.8  # 20 % less, every pair
    imp, lo, hi, p = paired_improvement(base, better)
    assert imp == pytest.approx(20.0) and lo == pytest.approx(20.0) and hi == pytest.approx(20.0)
    assert p < 0.01  # all eight differences the same sign: 2 / 2**8 exactly, estimated
    imp, lo, hi, p = paired_improvement(base, base[::-1].copy())  # the same values shuffled: no effect
    assert lo < 0 < hi and p > 0.2


def test_cli_compare_and_report(tmp_path):
    runner = CliRunner()
    out = tmp_path / "cli"
    r = runner.invoke(
        app,
        ["compare", "pilots", str(SCENARIOS / "paper-fig9.yaml"), "--reruns", "1", "--jobs", "1", "--out", str(out)],
    )
    assert r.exit_code == 0, r.output
    assert "2 runs (2 run now, 0 already complete)" in r.output and "| potential-field |" in r.output
    for f in (
        "table.csv",
        "table.md",
        "improvements.csv",
        "runs.csv",
        "boxplots-paper-fig9.png",
        "trajectories-paper-fig9-geometric.png",
        "trajectories-paper-fig9-potential-field.png",
    ):
        assert (out / f).exists(), f
    r = runner.invoke(
        app,
        ["compare", "pilots", str(SCENARIOS / "paper-fig9.yaml"), "--reruns", "1", "--jobs", "1", "--out", str(out)],
    )
    assert "0 run now, 2 already complete" in r.output
    r = runner.invoke(app, ["report", str(out / "paper-fig9"), "--out", str(tmp_path / "rep")])
    assert r.exit_code == 0 and (tmp_path / "rep" / "table.md").read_text() == (out / "table.md").read_text()
    assert runner.invoke(app, ["report", str(tmp_path / "nope")]).exit_code == 2
    r = runner.invoke(app, ["compare", "pilots", str(SCENARIOS / "paper-fig9.yaml"), "--pilots", "autopilot"])
    assert r.exit_code == 2 and "unknown pilot" in r.output


def test_few_pairs_get_the_exact_permutation_p_value():
    """With n pairs the sign-flip test has 2^n equally likely assignments: all differences of one
    sign give the two extreme ones, p = 2 / 2^n exactly (no Monte Carlo below that floor)."""
    for n in (2, 3, 5):
        base = np.arange(10.0, 10.0 + n)
        _, _, _, p = paired_improvement(base, base - 1.0)
        assert p == 2 / 2**n
    _, _, _, p = paired_improvement(np.array([10.0, 12.0, 11.0]), np.array([9.0, 12.5, 10.0]))
    # d = (1, -0.5, 1), |mean| = 0.5; of the 8 sign assignments |mean| >= 0.5 for (+,-,+), (-,+,-),
    # (+,+,+) and (-,-,-): p = 4 / 8
    assert p == 0.5
