"""navcli compare policies on a tiny case (short trials from 3 starts, 2 runs): the table against
the per-trial records it was built from, the same starts for every policy, and resume."""

from __future__ import annotations

import csv
import json

import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.analysis.stats import wilson_interval
from navcli.cli import app
from navcli.learning import model_file
from navcli.training import comparison
from navcli.learning.actions import ACTIONS, MB, MLL, MVT, REWARDS
from navcli.learning.q_learning import QLearning
from navcli.training.task import NavigationTask, random_starts, task_spec
from navcli.training.trainer import EVAL_SEED, evaluate
from navcli.scenario import load_scenario

ROOM = SCENARIOS / "landmarks-12.yaml"
SHORT = ["--param", "learning.max_actions=4"]  # trials of at most 4 actions (4 s)


def few_starts_interval(per_start: dict) -> tuple[float, float]:
    """The bootstrap 95 % interval that resamples the starts, for 2 or 3 starts of equal trials: a
    resample is every start's mean once or one start's k times, the lowest (or highest) alone with
    probability 1/k^k (1/4 or 1/27), above 2.5 %, so the interval runs from the lowest start mean to
    the highest."""
    means = [sum(v) / len(v) for v in per_start.values()]
    assert 2 <= len(means) <= 3
    return min(means), max(means)


@pytest.fixture(scope="module")
def always_mvt(tmp_path_factory):
    """A Q-learning model file whose greedy action is MVT in every state."""
    q = QLearning(980, 5)
    q.q[:, MVT] = 1.0
    return model_file.save(
        tmp_path_factory.mktemp("q") / "q.npz", q, {"algorithm": "q-learning", "trials": 0, "scenario": "none"}
    )


@pytest.fixture(scope="module")
def parity(tmp_path_factory):
    """A model whose greedy action is MB in even states and MLL in odd ones: its actions turn on
    the state's last bit, so the runs' noise may change its actions (and rewards); whether it does
    depends on the seeds (its two runs' mean rewards differed for 13 of 20 sets of starts)."""
    q = QLearning(980, 5)
    q.q[0::2, MB] = 1.0
    q.q[1::2, MLL] = 1.0
    return model_file.save(
        tmp_path_factory.mktemp("parity") / "parity.npz",
        q,
        {"algorithm": "q-learning", "trials": 0, "scenario": "none"},
    )


@pytest.fixture(scope="module")
def compared(tmp_path_factory, always_mvt, parity):
    out = tmp_path_factory.mktemp("cmp-policies")
    args = [
        "compare",
        "policies",
        str(ROOM),
        "--policy",
        f"learned:{always_mvt}",
        "--policy",
        "learned",
        "--policy",
        f"learned:{parity}",
        "--runs",
        "2",
        "--starts",
        "3",
        "--jobs",
        "1",
        "--out",
        str(out),
        *SHORT,
    ]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    return out, args, r.output


def records(out):
    """The per-trial records of the JSON files, by (policy, run)."""
    got = {}
    for f in sorted((out / "runs").glob("*.json")):
        d = json.loads(f.read_text())
        got[d["policy"], d["run"]] = d["trials"]
    return got


def test_the_table_is_the_mean_over_runs_of_the_per_trial_records(compared, always_mvt, parity):
    out, _, output = compared
    recs = records(out)
    assert len(recs) == 6 and all(len(t) == 3 for t in recs.values())
    with (out / "policies.csv").open() as f:
        table = {row["policy"]: row for row in csv.DictReader(f)}
    assert list(table) == [f"learned:{always_mvt}", "learned", f"learned:{parity}"]
    for policy, row in table.items():
        assert row["runs"] == "2" and row["starts"] == "3"
        trials = recs[policy, 0] + recs[policy, 1]
        reached = sum(t["outcome"] == "reached" for t in trials)
        lo, hi = wilson_interval(reached, 6)  # successes: the rate over all 6 trials, in starts (of 3)
        assert (float(row["successes"]), float(row["successes_lo"]), float(row["successes_hi"])) == pytest.approx(
            (reached / 2, 3 * lo, 3 * hi)
        ), policy
        for m in ("reward", "actions", *ACTIONS):
            per_start = {i: [t[m] for t in trials if t["start"] == i] for i in range(3)}
            assert float(row[m]) == pytest.approx(sum(t[m] for t in trials) / 6, abs=1e-9), (policy, m)
            assert (float(row[f"{m}_lo"]), float(row[f"{m}_hi"])) == pytest.approx(few_starts_interval(per_start)), (
                policy,
                m,
            )
    # the always-MVT model: every action is MVT, each costing 5
    for run in (0, 1):
        for t in recs[f"learned:{always_mvt}", run]:
            assert t["MVT"] == t["actions"] > 0 and t["reward"] == -5 * t["actions"]
            assert t["MB"] == t["MLL"] == t["MOT"] == t["MVL"] == 0 and t["actions"] <= 4
    assert "| learned |" in output and "q-learning, 0 trials on none" in output
    from navcli.analysis.files import MARK, without_mark

    text = (out / "policies.md").read_text()
    assert text.startswith(MARK + "\n") and without_mark(text) in output


def test_every_policy_runs_the_evaluation_starts_and_run_0_is_the_evaluation(compared):
    out, _, _ = compared
    recs = records(out)
    spec = task_spec(load_scenario(ROOM), {"learning.max_actions": 4})
    starts = random_starts(spec, 3, EVAL_SEED)
    place = lambda trials: [(t["x"], t["y"], t["heading"]) for t in trials]  # noqa: E731
    seeds = lambda trials: [t["seed"] for t in trials]  # noqa: E731
    for trials in recs.values():
        assert place(trials) == [(s.x, s.y, s.heading) for s in starts]
    run0, run1 = ([seeds(t) for (p, r), t in recs.items() if r == run] for run in (0, 1))
    assert run0[0] == run0[1] == [s.seed for s in starts]  # run 0: the starts' own seeds
    assert run1[0] == run1[1] and not set(run1[0]) & set(run0[0])  # run 1: other seeds, the same
    evaluation = evaluate(spec, model_file.load_policy(), starts)  # what `navcli train` measures
    assert [(t["outcome"], t["actions"], t["reward"]) for t in recs["learned", 0]] == [
        (e.outcome, e.actions, e.reward) for e in evaluation
    ]


def test_a_comparison_resumes_and_reruns_only_what_is_missing_or_changed(compared):
    out, args, _ = compared
    before = (out / "policies.csv").read_text()
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0 and "(0 run now, 6 kept)" in r.output
    assert (out / "policies.csv").read_text() == before
    victim = sorted((out / "runs").glob("learned-run1-*.json"))[0]
    victim.write_text("{not json")  # a damaged file is run again, not trusted
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0 and "(1 run now, 5 kept)" in r.output
    assert (out / "policies.csv").read_text() == before  # the same configuration gives the same trials
    # another parameter is another configuration: new keys, nothing reused
    spec = task_spec(load_scenario(ROOM), {"learning.max_actions": 4})
    other = spec.replace(params=spec.params.override({"learning.max_actions": 5}))
    hc = comparison.parse_policy("hand-coded")
    assert {j.key for j in comparison.plan(spec, [hc], 2, 3, out)}.isdisjoint(
        j.key for j in comparison.plan(other, [hc], 2, 3, out)
    )


def test_the_agents_row(tmp_path):
    spec = task_spec(load_scenario(ROOM), {"learning.max_actions": 3})
    job = comparison.plan(spec, [comparison.parse_policy("agents")], 1, 1, tmp_path)[0]
    (t,) = comparison.run_trials(job)
    task = NavigationTask(spec)
    task.reset(job.starts[0])
    sweep = task.mission.time  # when the learned policies' first action starts
    assert t["outcome"] == "timeout" and t["time_s"] == pytest.approx(sweep + 3.0, abs=0.11)  # 3 actions x 1 s
    assert t["reward"] is None and t["MB"] is None
    table = comparison.policy_table(comparison.trials_frame([comparison.Result(job, [t], ran=True)]))
    assert "| agents | " in comparison.markdown(table) and "n/a" in comparison.markdown(table)


def test_the_tables_intervals_stay_in_range_and_warn_of_few_starts(tmp_path):
    """Hand-made records of 2 runs of 2 starts: successes 1 of 4 trials, their interval the Wilson
    interval of 1/4 in starts (of 2), never below 0 as a t-interval over two runs (0 and 1
    successes) would go; a mean per trial runs from the lower start's mean to the higher's; with 2
    starts the notes say the intervals are too uncertain."""
    spec = task_spec(load_scenario(ROOM), {"learning.max_actions": 4})
    hc = comparison.parse_policy("hand-coded")
    jobs = comparison.plan(spec, [hc], 2, 2, tmp_path)
    assert [j.run for j in jobs] == [0, 1]
    counts = {0: [(2, "timeout"), (4, "timeout")], 1: [(1, "reached"), (4, "timeout")]}  # MVT actions per trial
    results = []
    for j in jobs:
        trials = [
            comparison._record(
                i, st, outcome, 2.0 * n, n, REWARDS[MVT] * n, tuple(n if k == MVT else 0 for k in range(len(ACTIONS)))
            )
            for i, (st, (n, outcome)) in enumerate(zip(j.starts, counts[j.run]))
        ]
        results.append(comparison.Result(j, trials, ran=True))
    table = comparison.policy_table(comparison.trials_frame(results))
    (row,) = table.itertuples()
    lo, hi = wilson_interval(1, 4)
    assert (row.successes, row.successes_lo, row.successes_hi) == pytest.approx((0.5, 2 * lo, 2 * hi))
    assert row.successes_lo >= 0.0 and row.successes_hi <= 2.0
    start0, start1 = (2 + 1) / 2, (4 + 4) / 2  # actions per trial of each start over the two runs
    for m, scale in {"actions": 1.0, "MVT": 1.0, "reward": REWARDS[MVT], "time_s": 2.0}.items():
        assert getattr(row, m) == pytest.approx(scale * 11 / 4), m
        assert sorted((getattr(row, f"{m}_lo"), getattr(row, f"{m}_hi"))) == pytest.approx(
            sorted((scale * start0, scale * start1))
        ), m
    assert row.MB == row.MB_lo == row.MB_hi == 0.0
    md = comparison.markdown(table, "landmarks-12")
    assert (
        "the policies on landmarks-12: only 2 starts; with fewer than 10 its 95 % intervals are too uncertain "
        "to trust" in md
    )


@pytest.mark.parametrize(
    "bad, message",
    [
        (["--policy", "bogus"], "unknown policy"),
        (["--policy", "learned:"], "unknown policy"),
        (["--policy", "hand-coded", "--policy", "hand-coded"], "named twice"),
        (["--policy", "learned:/no/such.npz"], "no such model file"),
        (["--out", "/dev/null/x"], "/dev/null is a file, not a folder"),
    ],
)
def test_bad_policies_are_refused(bad, message):
    r = CliRunner().invoke(app, ["compare", "policies", str(ROOM), *bad])
    assert r.exit_code == 2 and message in r.output
