"""navcli sweep: plan files, the results table, resume, and the same table from a Dask cluster."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pandas as pd
import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.cli import app
from navcli.experiments import sweep
from navcli.experiments.compare import rerun_seed
from navcli.experiments.executor import SerialExecutor, executor

try:
    import distributed
except ModuleNotFoundError:
    distributed = None
requires_cluster = pytest.mark.skipif(
    distributed is None, reason="needs dask.distributed (pip install 'navcli[cluster]')"
)
"""For the tests that run on a Dask cluster: the plan's parsing and the local workers need none."""

ARENA = SCENARIOS / "open-arena.yaml"


def _plan(tmp_path: Path, body: str, name: str = "plan.yaml") -> Path:
    p = tmp_path / name
    p.write_text(f"version: 1\nscenarios: [{ARENA}]\n" + body)
    return p


GRID = "seeds: 2\ntime_limit: 3\ngrid:\n  robot.max_speed: [0.2, 0.4, 0.6]\n  pilot.K: [10, 30]\n"
NO_SWEEP = "params: {navigation.initial_sweep: 0}\n"  # 3 s runs: drive at once, no initial look around


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A real two-worker Dask cluster of processes on 127.0.0.1, with a client to inspect it; its
    workers' scratch space in the test's temporary folder, not /tmp/dask-scratch-space."""
    import dask

    scratch = tmp_path_factory.mktemp("dask")
    with (
        dask.config.set({"temporary-directory": str(scratch)}),
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            local_directory=scratch,
        ) as c,
        distributed.Client(c) as client,
    ):
        yield c, client


def _sweep(args: list[str]) -> None:
    res = CliRunner().invoke(app, ["sweep", *args])
    assert res.exit_code == 0, res.output


def test_a_grid_plan_is_every_combination_with_paired_seeds(tmp_path):
    p = sweep.load_plan(_plan(tmp_path, GRID + "params: {pilot.A_t: 40, navigation.initial_sweep: 0}\n"))
    runs = sweep.plan_runs(p, None)
    assert p.size == len(runs) == 3 * 2 * 2
    combos = {(r.overrides["robot.max_speed"], r.overrides["pilot.K"]) for r in runs}
    assert combos == {(v, k) for v in (0.2, 0.4, 0.6) for k in (10.0, 30.0)}
    assert {r.seed for r in (r.spec for r in runs)} == {rerun_seed(1, 0), rerun_seed(1, 1)}
    spec = runs[-1].spec
    assert (spec.params.robot.max_speed, spec.params.pilot.K, spec.params.pilot.A_t, spec.time_limit) == (
        0.6,
        30,
        40,
        3,
    )
    assert len({r.spec.run_id for r in runs}) == len(runs)


def test_a_random_plan_is_a_seeded_sample_within_its_ranges(tmp_path):
    body = "seeds: 1\nrandom: {samples: 7, seed: 4, ranges: {pilot.K: [5, 9], navigation.kappa1: [0.2, 0.3]}}\n"
    a, b = (sweep.load_plan(_plan(tmp_path, body)).points for _ in range(2))
    assert a == b and len(a) == 7 and len({pt["pilot.K"] for pt in a}) == 7
    assert all(5 <= pt["pilot.K"] <= 9 and 0.2 <= pt["navigation.kappa1"] <= 0.3 for pt in a)
    other = sweep.load_plan(_plan(tmp_path, body.replace("seed: 4", "seed: 5"))).points
    assert other != a


def test_a_plan_of_points_gives_each_point_whole_with_the_defaults_filling_in(tmp_path):
    body = "seeds: 1\npoints:\n  - {}\n  - {vision.routines: 0}\n  - {vision.walls: felt, pilot.look_cap: 0.9}\n"
    points = sweep.load_plan(_plan(tmp_path, body)).points
    assert points == (
        {"vision.routines": 1, "vision.walls": "seen", "pilot.look_cap": 1.0},
        {"vision.routines": 0, "vision.walls": "seen", "pilot.look_cap": 1.0},
        {"vision.routines": 1, "vision.walls": "felt", "pilot.look_cap": 0.9},
    )


@pytest.mark.parametrize(
    "body, where, message",
    [
        ("seeds: 1\npoints:\n  - {}\n  - {vision.routines: 1}\n", ":6: points[1]", "the point of points[0] again"),
        (
            "seeds: 1\npoints:\n  - {vision.walls: seen-ish}\n",
            ":5: points[0].vision.walls",
            "vision.walls is one of seen, known, felt",
        ),
        ("seeds: 1\ngrid: {pilot.K: [1]}\npoints: [{}]\n", ":5: points", "not more than one"),
        (
            "seeds: 1\ngrid:\n  pilot.k: [1, 2]\n",
            ":5: grid.pilot.k",
            "unknown parameter 'pilot.k' (did you mean pilot.K?)",
        ),
        (
            "seeds: 1\ngrid:\n  pilot.R_min: [0.3, 0]\n",
            ":5: grid.pilot.R_min[1]",
            "pilot.R_min must be at least 0.01, got 0",
        ),
        (
            "seeds: 1\ngrid: {pilot.K: [1]}\nrandom: {samples: 2, ranges: {pilot.K: [1, 2]}}\n",
            ":5: random",
            "a grid, a random sample or a list of points, not more than one",
        ),
        (
            "seeds: 1\nrandom: {samples: 2, ranges: {pilot.K: [3, 2]}}\n",
            ":4: random.ranges.pilot.K",
            "low 3 is above high 2",
        ),
        ("seeds: two\n", ":3: seeds", "expected a whole number"),
        ("seeds: 1\nseed: 3\n", ":4: seed", "unknown field 'seed'"),
        (
            "seeds: 1\npilots: [potential-field, wall-follower]\n",
            ":4: pilots[1]",
            "unknown pilot 'wall-follower': not one of navcli's (potential-field, geometric), not an entry point navcli.pilots",
        ),
        ("seeds: 1\ngrid: {pilot.K: [1, 2}\n", ":4", "not valid YAML"),
    ],
)
def test_bad_plans_are_refused_with_file_line_and_field(tmp_path, body, where, message):
    plan = _plan(tmp_path, body)
    res = CliRunner().invoke(app, ["sweep", str(plan), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2
    assert f"{plan}{where}" in res.output and message in res.output and "Traceback" not in res.output
    assert not (tmp_path / "out").exists()


def test_a_missing_scenario_and_a_huge_file_are_refused(tmp_path):
    plan = tmp_path / "plan.yaml"
    plan.write_text("version: 1\nseeds: 1\nscenarios: [nope.yaml]\n")
    res = CliRunner().invoke(app, ["sweep", str(plan)])
    assert res.exit_code == 2 and f"{plan}:3: scenarios[0]: scenario nope.yaml refused" in res.output
    assert f"{tmp_path / 'nope.yaml'}: no such file" in res.output
    plan.write_text("#" * (sweep.MAX_PLAN_BYTES + 1))
    res = CliRunner().invoke(app, ["sweep", str(plan)])
    assert res.exit_code == 2 and f"larger than {sweep.MAX_PLAN_BYTES:,} bytes" in res.output


def test_the_table_holds_one_row_per_run_and_resumes_after_an_interruption(tmp_path):
    p = sweep.load_plan(_plan(tmp_path, GRID + NO_SWEEP))
    runs = sweep.plan_runs(p, tmp_path / "logs")
    table = tmp_path / "results.parquet"

    def stop_after_five(row, stats):
        if stats.done == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep.run_sweep(runs, table, SerialExecutor(), on_row=stop_after_five)
    first = sweep.read_table(table)
    assert len(first) == 5  # what finished before the interruption is kept
    stats = sweep.run_sweep(runs, table, SerialExecutor())
    assert (stats.skipped, stats.done) == (5, len(runs) - 5)
    df = sweep.read_table(table)
    assert list(df["run_id"]) == [r.spec.run_id for r in runs]  # each once, in plan order
    assert df.iloc[:5].equals(first)  # not run again
    fast, slow = df[df["robot.max_speed"] == 0.6], df[df["robot.max_speed"] == 0.2]
    assert (fast["path_length_m"].to_numpy() > slow["path_length_m"].to_numpy()).all()  # the override took effect
    assert (df["outcome"] == "timeout").all() and (df["time_s"] == 3.0).all() and (df["error"] == "").all()
    for r in df.itertuples():  # the log path is the run's own, complete log
        assert Path(r.log).name.endswith(f"-{r.run_id[:8]}.mcap") and Path(r.log).exists()


@requires_cluster
def test_local_pool_and_dask_cluster_give_the_same_table(tmp_path, cluster):
    c, _ = cluster
    plan = _plan(tmp_path, GRID + NO_SWEEP)
    _sweep([str(plan), "--out", str(tmp_path / "local"), "--jobs", "2", "--no-logs", "--csv"])
    _sweep([str(plan), "--out", str(tmp_path / "dask"), "--scheduler", c.scheduler_address, "--no-logs"])
    local, remote = (pd.read_parquet(tmp_path / d / "results.parquet") for d in ("local", "dask"))
    assert len(local) == 12 and local.equals(remote)
    assert pd.read_csv(tmp_path / "local" / "results.csv")["run_id"].tolist() == local["run_id"].tolist()


@requires_cluster
def test_compare_pilots_on_the_dask_cluster_logs_the_runs_the_local_pool_does(tmp_path, cluster):
    from navcli.analysis import read_log

    c, _ = cluster
    args = [
        "compare",
        "pilots",
        str(SCENARIOS / "open-arena.yaml"),
        "--reruns",
        "2",
        "--time-limit",
        "3",
        "--param",
        "navigation.initial_sweep=0",
    ]
    for where, extra in (("local", ["--jobs", "2"]), ("dask", ["--scheduler", c.scheduler_address])):
        res = CliRunner().invoke(app, [*args, "--out", str(tmp_path / where), *extra])
        assert res.exit_code == 0, res.output
    local, remote = (sorted((tmp_path / d).rglob("*.mcap")) for d in ("local", "dask"))
    assert len(local) == 4 and [p.name for p in local] == [p.name for p in remote]  # 2 pilots x 2 seeds
    for a, b in zip(local, remote):
        sa, sb = read_log(a).summary, read_log(b).summary
        assert sa["outcome"] == sb["outcome"] == "timeout" and sa["path_length_m"] == sb["path_length_m"] > 0


@requires_cluster
def test_a_worker_killed_mid_sweep_loses_and_duplicates_nothing(tmp_path, cluster):
    c, client = cluster
    plan = sweep.load_plan(_plan(tmp_path, "seeds: 5\ntime_limit: 4\ngrid: {pilot.K: [10, 20, 30]}\n"))
    runs = sweep.plan_runs(plan, None)
    before = client.run(os.getpid)
    victim = next(iter(before.values()))
    killed = []

    def kill_one(row, stats):
        if not killed:
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    table = tmp_path / "results.parquet"
    with client.get_executor(pure=False, retries=2) as ex:
        stats = sweep.run_sweep(runs, table, ex, on_row=kill_one)
    df = sweep.read_table(table)
    assert killed and stats.done == len(runs) and stats.errors == 0
    assert sorted(df["run_id"]) == sorted(r.spec.run_id for r in runs)  # none lost, none twice
    local = tmp_path / "local.parquet"
    with executor(2) as ex:
        sweep.run_sweep(runs, local, ex)
    assert df.equals(sweep.read_table(local))  # and the runs retried elsewhere gave the same rows


def test_a_plan_may_list_perceptions_each_a_base_of_its_own(tmp_path):
    p = sweep.load_plan(
        _plan(
            tmp_path,
            "seeds: 2\npilots: [potential-field, geometric]\n"
            "perception: [vision, oracle]\ngrid:\n  pilot.K: [10, 30]\n",
        )
    )
    assert [(b.pilot, b.perception) for b in p.bases] == [
        (pi, pe) for pi in ("potential-field", "geometric") for pe in ("vision", "oracle")
    ]
    assert p.size == 2 * 2 * 2 * 2
    bad = _plan(tmp_path, "seeds: 1\nperception: [vision, sonar]\n", "bad.yaml")
    res = CliRunner().invoke(app, ["sweep", str(bad)])
    assert res.exit_code == 2 and "perception[1]" in res.output and "sonar" in res.output


def test_report_reads_a_sweep_table_and_pairs_the_pilots_per_point(tmp_path):
    """A hand-made results table: at K = 10 the potential field takes 9, 18, 27 s where the
    geometric pilot takes 10, 20, 30 s (paths likewise, in metres), so it is 10 % faster on every
    seed: the bootstrap interval is [10, 10] and the exact sign-flip p-value is 2/8 (only the
    all-plus and all-minus signs reach the observed mean). At K = 30 they are equal: 0 %."""
    rows = []
    for k, ratio in ((10.0, 0.9), (30.0, 1.0)):
        for seed, base in zip((1, 2, 3), (10.0, 20.0, 30.0)):
            for pilot, t in (("geometric", base), ("potential-field", ratio * base)):
                rows.append(
                    {
                        "scenario": "room",
                        "pilot": pilot,
                        "perception": "vision",
                        "seed": seed,
                        "point": int(k),
                        "pilot.K": k,
                        "outcome": "reached",
                        "reason": "",
                        "time_s": t,
                        "path_length_m": t / 10,
                        "collisions": 0,
                        "camera_looks": 1,
                        "ticks": int(t * 10),
                        "diverting_targets": 0,
                        "log": "",
                        "run_id": f"{pilot}-{k}-{seed}",
                        "error": "",
                    }
                )
    table = tmp_path / "results.parquet"
    pd.DataFrame(rows).to_parquet(table, index=False)
    res = CliRunner().invoke(app, ["report", str(table)])
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    over = [ln for ln in lines if ln.startswith("| room (vision perception, pilot.K=")]
    k10 = next(ln for ln in over if "pilot.K=10)" in ln and "vs geometric" in ln)
    k30 = next(ln for ln in over if "pilot.K=30)" in ln and "vs geometric" in ln)
    assert k10.count("+10.0 % [+10.0, +10.0], 0.2500") == 2  # time and path
    assert "| 18.0 / 20.0 |" in k10 and "3/3 vs 3/3" in k10
    assert k30.count("+0.0 % [+0.0, +0.0], 1.0000") == 2
    assert (tmp_path / "table.md").exists() and not list(tmp_path.glob("*.png"))  # no poses: no plots
    bad = tmp_path / "other.csv"
    bad.write_text("a,b\n1,2\n")
    res = CliRunner().invoke(app, ["report", str(bad), "--out", str(tmp_path / "other")])  # (table.md is there)
    assert res.exit_code == 2 and "not a sweep results table" in res.output


@pytest.mark.parametrize(
    "body, words",
    [
        ("seeds: 1\nrandom: {samples: 100000000, ranges: {pilot.K: [1, 2]}}\n", "100000000 samples: more than"),
        (
            "seeds: 1\ngrid: {pilot.K: "
            + str(list(range(1, 1001)))
            + ", robot.max_speed: "
            + str([0.1 + i / 1000 for i in range(1001)])
            + "}\n",
            "points; split the plan",
        ),
        ("seeds: 1\nparams: {pilot.K: 20}\ngrid: {pilot.K: [10, 30]}\n", "pilot.K set here and in grid"),
        (
            "seeds: 1\nparams: {pilot.K: 20}\nrandom: {samples: 2, ranges: {pilot.K: [1, 2]}}\n",
            "set here and in random",
        ),
        (
            "seeds: 1\nrandom: {samples: 2, ranges: {pilot.reflex_look_pans_deg: [[0], [1]]}}\n",
            "give its values in a grid",
        ),
        (
            "seeds: 1\ngrid: {pilot.reflex_look_pans_deg: [[0, 1], nope]}\n",
            "expects a list of at most 64 finite numbers",
        ),
        ("seeds: 1\ngrid: {learning.distance_bounds: [[1, 2]]}\n", "must be 4 increasing numbers"),
    ],
)
def test_a_plan_that_would_mislead_or_hang_is_refused_at_once(tmp_path, body, words):
    """Counts bounded before anything is drawn; a value given twice (params and a grid) refused
    instead of one silently winning."""
    res = CliRunner().invoke(app, ["sweep", str(_plan(tmp_path, body)), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and words in res.output and "Traceback" not in res.output, res.output
    assert not (tmp_path / "o").exists()


def test_a_scenario_named_twice_is_refused(tmp_path):
    copy = tmp_path / "copy.yaml"
    copy.write_bytes(ARENA.read_bytes())
    p = tmp_path / "plan.yaml"
    p.write_text(f"version: 1\nseeds: 1\nscenarios: [{ARENA}, {copy}]\n")
    with pytest.raises(sweep.PlanError) as e:
        sweep.load_plan(p)
    assert "is the scenario of scenarios[0] again" in str(e.value)


def test_a_list_valued_parameter_is_a_grid_axis_and_a_column(tmp_path):
    plan = sweep.load_plan(
        _plan(tmp_path, "seeds: 1\ntime_limit: 2\ngrid: {pilot.reflex_look_pans_deg: [[], [-30, 30]]}\n")
    )
    runs = sweep.plan_runs(plan, None)
    assert [r.spec.params.pilot.reflex_look_pans_deg for r in runs] == [(), (-30.0, 30.0)]
    table = tmp_path / "t.parquet"
    sweep.run_sweep(runs, table, SerialExecutor())
    assert list(sweep.read_table(table)["pilot.reflex_look_pans_deg"]) == ["[]", "[-30.0, 30.0]"]


def test_param_takes_a_list(tmp_path):
    from navcli.params import parse_override
    from navcli.params import ParamError

    assert parse_override("pilot.reflex_look_pans_deg=[]") == ("pilot.reflex_look_pans_deg", [])
    assert parse_override("pilot.reflex_look_pans_deg=[ -1.5 ,2]") == ("pilot.reflex_look_pans_deg", [-1.5, 2.0])
    for bad in ("pilot.reflex_look_pans_deg=[1,,2]", "pilot.reflex_look_pans_deg=1,2", "pilot.K=[1"):
        with pytest.raises(ParamError):
            parse_override(bad)
    r = CliRunner().invoke(app, ["params", "--param", "pilot.reflex_look_pans_deg=[-45, 45]"])
    assert r.exit_code == 0 and "-45" in r.output, r.output


def test_the_bundled_plans_load():
    """Every plan in plans/ (the README's and reproduce's sensitivity plans) is a valid plan."""
    from conftest import ROOT

    plans = sorted((ROOT / "plans").glob("*.yaml"))
    assert len(plans) >= 2
    for p in plans:
        assert sweep.load_plan(p).size > 0
