"""The learning paper's Table 1 from hand-made trials: every trial counted once by how it ended,
errored runs' trials too; each policy judged against the uniform random one by its 95 % intervals;
the paper's rows beside navcli's; optional rows read from a ``compare policies`` folder."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from navcli.analysis.stats import wilson_interval
from navcli.experiments import learning_paper as lp
from navcli.learning.actions import ACTIONS


def _trials(policy: str, runs: list[list[tuple[str, int, float]]]) -> pd.DataFrame:
    """Trials of ``policy``: per run, per start, (outcome, actions, reward); one MB per action."""
    rows = [
        {"policy": policy, "run": r, "start": i, "outcome": o, "success": o == "reached", "actions": a, "reward": w}
        | {x: (a if x == "MB" else 0) for x in ACTIONS}
        for r, trials in enumerate(runs)
        for i, (o, a, w) in enumerate(trials)
    ]
    return pd.DataFrame(rows)


def test_every_trial_is_counted_once_by_how_it_ended_and_an_errored_runs_trials_too():
    # 3 runs of 4 starts planned, the third ended in error: 12 trials in all
    t = _trials(
        "p",
        [
            [("reached", 10, -10.0), ("timeout", 500, -500.0), ("blocked", 30, -30.0), ("timeout", 40, -40.0)],
            [("reached", 12, -12.0), ("reached", 14, -14.0), ("reached", 16, -16.0), ("blocked", 20, -20.0)],
        ],
    )
    row = lp.policy_row(t, "p", runs=3, errored=1, starts=4, max_actions=500)  # rewards: 580 and 62 in all
    # reached 1 + 3; at the limit: the 500-action timeout; the 40-action timeout is another ending
    assert row.endings == {"reached": 4, "limit": 1, "blocked": 2, "other": 1, "errored": 4}
    assert sum(row.endings.values()) == 3 * 4 and row.finished == 8
    assert row.successes[0] == 2.0 and row.run_range == (1, 3)  # 1 and 3 successes of 4
    lo, hi = wilson_interval(2.0, 4)  # the mean rate, the starts the sample (not 8 trials)
    assert row.successes[1:] == pytest.approx((4 * lo, 4 * hi))
    assert row.means["reward"][0] == pytest.approx(-642 / 8) and row.means["MB"][0] == pytest.approx(642 / 8)
    head, rows = lp.endings_table([row], 500)
    assert head[3:8] == ["reached", "at the 500-action limit", "blocked", "other endings", "errored"]
    assert rows[0][:8] == ["p", "3 (1)", "12", "4", "1", "2", "1", "4"]
    assert lp.other_endings(t, 500) == [
        "p: 1 trial ended otherwise: timeout (1; the scenario's time limit, before the action limit)"
    ]


def _row(policy: str, reached: int, starts: int = 20, reward: float = -10.0, errored: int = 0):
    """A policy's row of one run: ``reached`` of ``starts`` reached, each trial's reward ``reward``."""
    t = _trials(policy, [[("reached" if i < reached else "blocked", 10, reward) for i in range(starts)]])
    return lp.policy_row(t, policy, runs=1 + errored, errored=errored, starts=starts, max_actions=500)


@pytest.mark.parametrize(
    "mine, theirs, want",
    [
        # Wilson of 20/20 is [16.8, 20], of 5/20 [2.2, 9.4]: apart, the policy above
        ((20, -10.0), (5, -20.0), ["beats random", "beats random"]),
        ((5, -20.0), (20, -10.0), ["random does better", "random does better"]),
        # 12/20 [7.8, 15.3] and 10/20 [5.9, 14.1] overlap; rewards alike
        ((12, -10.0), (10, -10.0), ["random does as well", "random does as well"]),
    ],
)
def test_a_policy_beats_random_only_where_the_intervals_do_not_overlap(mine, theirs, want):
    assert [round(20 * x, 1) for x in wilson_interval(20, 20)] == [16.8, 20.0]
    assert [round(20 * x, 1) for x in wilson_interval(5, 20)] == [2.2, 9.4]
    _, rows = lp.endings_table([_row("p", mine[0], reward=mine[1]), _row("random", theirs[0], reward=theirs[1])], 500)
    assert rows[0][-2:] == want and rows[1][-2:] == ["(the baseline)"] * 2


def test_touching_intervals_are_no_win_and_errors_or_no_random_give_no_verdict():
    assert lp.against_random((10.0, 12.0), (8.0, 10.0), 99) == "random does as well"  # they meet at 10
    assert lp.against_random((10.0, 12.0), (8.0, 9.99), 99) == "beats random"
    assert lp.against_random((10.0, 12.0), (8.0, 9.0), 9) == "too few starts to judge (9; 10 needed)"
    _, rows = lp.endings_table([_row("p", 20), _row("random", 5, errored=1)], 500)
    assert rows[0][-2:] == ["no verdict: 1 run ended in error"] * 2  # random's run that errored
    _, rows = lp.endings_table([_row("p", 20)], 500)
    assert rows[0][-2:] == ["no verdict: no random row"] * 2
    none = lp.policy_row(_trials("random", [[("reached", 10, -10.0)]]).iloc[0:0], "random", 1, 1, 20, 500)
    _, rows = lp.endings_table([_row("p", 20), none], 500)  # every run of random ended in error
    assert rows[0][-2:] == ["no verdict: no random row"] * 2 and rows[1][2:8] == ["20", "0", "0", "0", "0", "20"]
    assert lp.table1([none], {}, [], 20)[1] == [["random", "no trial finished (see the notes)"] + ["-"] * 7]


def test_the_papers_rows_stand_under_navclis_and_an_absent_optional_row_is_said():
    head, rows = lp.table1([_row("learned", 15), _row("random", 10)], lp.PAPER_POLICIES, ["sb3-ppo"], 20)
    assert head[-5:] == list(lp.PAPER_ACTIONS) == ["MB", "MOT", "MVT", "MVL", "MLL"]
    assert [r[0] for r in rows] == ["learned", "learned: the paper", "random", "sb3-ppo (optional)"]
    assert rows[1][1:] == ["84 of 99", "-336", "49.95", "11.41", "6.52", "5.61", "4.97", "21.43"]
    assert rows[0][1].startswith("15.0 [") and rows[0][1].endswith("(1 run)")
    assert rows[3][1] == "not run here (see the notes)"


def _spec():
    from navcli.experiments.reproduce import _scenario
    from navcli.training.task import task_spec

    return task_spec(_scenario("landmarks-12"))


def _write_run(folder: Path, name: str, policy: str, run: int, starts, sha: str) -> None:
    trials = [
        {"start": i, "x": s.x, "y": s.y, "heading": s.heading, "seed": s.seed, "outcome": "reached", "success": True}
        | {"actions": 3, "reward": -3.0, "time_s": 3.0}
        | {a: (3 if a == "MB" else 0) for a in ACTIONS}
        for i, s in enumerate(starts)
    ]
    (folder / "runs").mkdir(parents=True, exist_ok=True)
    d = {"key": name, "policy": policy, "run": run, "scenario_sha256": sha, "trials": trials}
    (folder / "runs" / f"{name}.json").write_text(json.dumps(d))


def test_an_optional_rows_trials_are_taken_only_from_the_same_room_starts_and_seeds(tmp_path):
    from navcli.training.comparison import run_starts
    from navcli.training.task import random_starts
    from navcli.training.trainer import EVAL_SEED

    spec = _spec()
    base = random_starts(spec, 3, EVAL_SEED)
    folder = tmp_path / "extra" / "mine"
    sha = spec.scenario.sha256
    _write_run(folder, "a", "mine", 0, run_starts(base, 0), sha)
    _write_run(folder, "b", "mine", 1, run_starts(base, 0), sha)  # run 1 with run 0's seeds: set aside
    _write_run(folder, "c", "other", 2, run_starts(base, 2), sha)  # another policy: not this row's
    _write_run(folder, "d", "mine", 2, run_starts(base, 2), "0" * 64)  # another room's: not this row's
    (folder / "source.json").write_text(json.dumps({"command": ["navcli", "compare", "policies", "x y"]}))
    found = lp.optional_trials(folder, "mine", spec, runs=3, starts=3)
    assert sorted(set(found.trials["run"])) == [0] and len(found.trials) == 3 and found.missing == 2
    assert found.command == "navcli compare policies 'x y'"
    assert found.set_aside == ("b.json (other starts or seeds than run 1's here)",)
    nothing = lp.optional_trials(tmp_path / "none", "mine", spec, runs=3, starts=3)
    assert nothing.trials is None and nothing.missing == 3


def test_each_training_of_figure_3_is_a_row_with_its_targets():
    curve = [{"trials": t, "successes": k} for t, k in ((100, 10), (200, 30), (300, 20), (400, 35))]
    _, rows = lp.seeds_table([{"seed": 3, "curve": curve}], 25.0, 400)
    # above 25 first at 200; after 300 trials only 400's 35: the dip at 300 is not after it
    assert rows == [["3", "35", "200", "35 (at 400)", "met", "met"]]
    _, rows = lp.seeds_table([{"seed": 4, "curve": curve}], 36.0, 400)
    assert rows == [["4", "35", "never", "35 (at 400)", "not met", "not met (35 at 400 below 36)"]]


def test_the_results_pages_summary_counts_the_verdicts_against_random(make_results):
    report = (
        "## Table 1 on a\n\n| policy | successes against random | reward against random |\n| --- | --- | --- |\n"
        "| learned | beats random | random does as well |\n| agents | random does better | n/a |\n"
        "| random | (the baseline) | (the baseline) |\n| x | no verdict: 1 run ended in error | too few starts |\n"
    )
    assert make_results.summary_table(report).splitlines()[-3:] == [
        "| against uniform random | beats random | random does as well | random does better | no verdict |",
        "| --- | ---: | ---: | ---: | ---: |",
        "| Table 1 on a | 1 | 1 | 1 | 2 |",
    ]
