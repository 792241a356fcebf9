"""``navcli reproduce`` on tiny settings: the report's numbers are those of the logs and trial
records it names (recomputed here from the logs' summaries, not from navcli's tables)."""

from __future__ import annotations

import csv
import json
import re
import statistics
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import ROOT
from navcli.analysis import read_log
from navcli.analysis.files import MARK
from navcli.cli import app
from navcli.experiments import learning_paper
from navcli.experiments.reproduce import FULL, QUICK, REPORT_FILES, reproduce
from navcli.learning.actions import ACTIONS

TINY = replace(
    QUICK,
    reruns=2,
    sensitivity_seeds=2,
    trap_seeds=1,
    trap_rooms=("blocked-wall",),
    policy_runs=2,
    policy_starts=3,
    train_trials=4,
    eval_every=2,
    eval_starts=3,
)
VFH = "vfh_pilot:VFHPilot"
"""The example plugin (examples/vfh-pilot), beside the paper's two pilots, as reproduce --pilot runs it."""
PILOTS = ("geometric", "potential-field", VFH)


OPTIONAL = "all-MB"
"""An optional row of the learning paper's Table 1 in these tests (MB in every state: needs nothing
more), made by its own ``compare policies`` command with one run of TINY's two: the other is missing."""


def _optional_row(out: Path) -> str:
    """The optional row's trials, by the command the report names, where the report reads them."""
    folder = out / "policies" / "landmarks-12" / learning_paper.EXTRA / OPTIONAL
    if not folder.exists():
        args = ["compare", "policies", "landmarks-12", "--policy", OPTIONAL, "--runs", "1", "--starts", "3"]
        r = CliRunner().invoke(app, [*args, "--jobs", "1", "--out", str(folder)])
        assert r.exit_code == 0, r.output
    return str(folder.resolve())


def _reproduce(out: Path) -> str:
    """``navcli reproduce all --pilot vfh_pilot:VFHPilot`` on TINY settings, with :data:`OPTIONAL` an
    optional row of Table 1 beside the declared ones: the report's Markdown."""
    import sys

    _optional_row(out)
    declared = learning_paper.OPTIONAL_POLICIES
    learning_paper.OPTIONAL_POLICIES = (learning_paper.OptionalRow(OPTIONAL, "nothing more"), *declared)
    sys.path.insert(0, str(ROOT / "examples" / "vfh-pilot"))  # the plugin's folder, as if installed
    try:
        return reproduce("all", out, settings=TINY, jobs=2, echo=lambda s: None, pilots=(VFH,))["markdown"].read_text()
    finally:
        sys.path.remove(str(ROOT / "examples" / "vfh-pilot"))
        learning_paper.OPTIONAL_POLICIES = declared


@pytest.fixture(scope="module")
def done(tmp_path_factory) -> tuple[Path, str]:
    out = tmp_path_factory.mktemp("rp")
    return out, _reproduce(out)


def _rows(md: str, heading: str, table: int = 0) -> list[list[str]]:
    """The rows of the ``table``-th table (from 0) of the section whose heading starts with ``heading``."""
    part = md.split(f"## {heading}", 1)[1].split("\n## ", 1)[0]
    tables: list[list[str]] = []
    last = False
    for ln in part.splitlines():
        if ln.startswith("| ") and not last:
            tables.append([])
        if ln.startswith("| "):
            tables[-1].append(ln)
        last = ln.startswith("| ")
    return [[c.strip() for c in ln.strip("|").split("|")] for ln in tables[table][2:]]


def _mean(cell: str) -> float:
    return float(cell.split(" ")[0])


def _identity(summary: dict) -> tuple:
    """What makes two runs' results the same: every number of their summaries."""
    keys = ("outcome", "time_s", "path_length_m", "collisions", "camera_looks", "ticks", "diverting_targets")
    return tuple(summary[k] for k in keys)


def test_the_pilots_table_is_the_mean_of_the_logs_it_names(done):
    out, md = done
    assert md.startswith(MARK) and "QUICK RUN" in md  # marked as a quick run, at the top
    rows = _rows(md, "Pilot paper, Table 1:")
    for perception in ("vision", "oracle"):
        with (out / "table1" / perception / "runs.csv").open() as f:
            logs = [r["log"] for r in csv.DictReader(f)]
        assert len(logs) == len(PILOTS) * TINY.reruns
        summaries = [read_log(p, topics=[]).summary for p in logs]
        for pilot in PILOTS:
            mine = [s for s in summaries if s["pilot"] == pilot]
            reached = list({_identity(s): s for s in mine if s["outcome"] == "reached"}.values())  # identical: once
            time_row = next(r for r in rows if r[:3] == [perception, pilot, "time_s"])
            path_row = next(r for r in rows if r[:3] == [perception, pilot, "path_cm"])
            assert _mean(time_row[4]) == pytest.approx(statistics.mean(s["time_s"] for s in reached), abs=0.05 + 1e-9)
            assert _mean(path_row[4]) == pytest.approx(
                statistics.mean(100 * s["path_length_m"] for s in reached), abs=0.05 + 1e-9
            )
            assert time_row[6] == f"{sum(s['outcome'] == 'reached' for s in mine)}/{len(mine)}"
            times = [s["time_s"] for s in mine if s["outcome"] == "reached"]  # the SD: every reached run
            assert float(time_row[5]) == pytest.approx(statistics.stdev(times), abs=0.05 + 1e-9)


def test_the_trap_table_counts_the_logs_outcomes_and_diverting_targets(done):
    out, md = done
    rows = _rows(md, "Trap rooms")
    with (out / "traps" / "runs.csv").open() as f:
        summaries = [read_log(r["log"], topics=[]).summary for r in csv.DictReader(f)]
    for pilot in PILOTS:
        mine = [s for s in summaries if s["pilot"] == pilot]
        got = {r[1]: r[3].split(" ")[0] for r in rows if r[0] == pilot}
        assert got["reached"] == f"{sum(s['outcome'] == 'reached' for s in mine)}/{len(mine)}"
        assert got["needed 1 diverting target"] == f"{sum(s['diverting_targets'] == 1 for s in mine)}/{len(mine)}"


def test_the_policy_table_is_the_trials_it_names(done):
    out, md = done
    rows = {r[0]: r for r in _rows(md, "Learning paper, Table 1 on landmarks-12")}
    ends = {r[0]: r for r in _rows(md, "Learning paper, Table 1 on landmarks-12", 1)}
    with (out / "policies" / "landmarks-12" / "trials.csv").open() as f:
        trials = list(csv.DictReader(f))
    for policy, runs in (("learned", 2), ("hand-coded", 2), ("random", 2), (OPTIONAL, 1)):
        mine = [t for t in trials if t["policy"] == policy]
        assert sorted({t["run"] for t in mine}) == [str(r) for r in range(runs)]
        per_run = [sum(t["success"] == "True" for t in mine if t["run"] == str(r)) for r in range(runs)]
        row = rows[policy]
        assert _mean(row[1]) == pytest.approx(statistics.mean(per_run), abs=0.05 + 1e-9)  # successes of 3
        assert row[1].endswith(f"({min(per_run)}-{max(per_run)})" if runs > 1 else "(1 run)")
        per_run_reward = [statistics.mean(float(t["reward"]) for t in mine if t["run"] == str(r)) for r in range(runs)]
        assert _mean(row[2]) == pytest.approx(statistics.mean(per_run_reward), abs=0.05 + 1e-9)
        assert [_mean(row[4 + k]) for k in range(5)] == [
            pytest.approx(statistics.mean(float(t[a]) for t in mine), abs=0.005 + 1e-9)
            for a in ("MB", "MOT", "MVT", "MVL", "MLL")
        ]  # the paper's order of the actions
        # every trial counted once, by how it ended; the missing run's trials as errored
        end = ends[policy]
        limit = [t for t in mine if t["outcome"] != "reached" and float(t["actions"]) >= 500]
        blocked = [t for t in mine if t["outcome"] == "blocked" and t not in limit]
        reached = [t for t in mine if t["outcome"] == "reached"]
        errored = (TINY.policy_runs - runs) * TINY.policy_starts
        assert end[1:8] == [
            f"{TINY.policy_runs} ({TINY.policy_runs - runs})",
            str(TINY.policy_runs * TINY.policy_starts),
            str(len(reached)),
            str(len(limit)),
            str(len(blocked)),
            str(len(mine) - len(reached) - len(limit) - len(blocked)),
            str(errored),
        ]
        assert sum(int(c) for c in end[3:8]) == int(end[2])


def test_an_optional_row_is_read_with_its_command_and_a_missing_one_is_said(done):
    out, md = done
    section = md.split("## Learning paper, Table 1 on landmarks-12", 1)[1].split("\n## ", 1)[0]
    made = f"navcli compare policies landmarks-12 --policy {OPTIONAL} --runs 1 --starts 3 --out {_optional_row(out)}"
    assert "its trials read from" in section and f"made by `{made}`" in section
    assert "1 of its 2 runs not found (not run, or ended in error), counted as errored" in section
    ends = {r[0]: r for r in _rows(md, "Learning paper, Table 1 on landmarks-12", 1)}
    assert ends[OPTIONAL][-2:] == ["no verdict: 1 run ended in error"] * 2  # its missing run: not judged
    rows = {r[0]: r for r in _rows(md, "Learning paper, Table 1 on landmarks-12")}
    assert rows["sb3-ppo (optional)"][1] == "not run here (see the notes)"
    assert (
        "sb3-ppo (optional, needs" in section
        and "not run here, so no row; to add it run `navcli compare policies landmarks-12 --policy sb3-ppo --runs 2 --starts 3 --out"
        in section
    )


def test_the_papers_rows_stand_under_navclis_with_every_action_in_its_order(done):
    _, md = done
    rows = _rows(md, "Learning paper, Table 1 on landmarks-12")
    names = [r[0] for r in rows]
    assert names.index("learned: the paper") == names.index("learned") + 1
    assert names.index("hand-coded: the paper") == names.index("hand-coded") + 1
    paper = next(r for r in rows if r[0] == "hand-coded: the paper")
    assert paper[1:] == ["24 of 99", "-858", "153.33", "4.94", "18.59", "0.52", "121.96", "7.32"]  # the paper's Table 1
    head = md.split("## Learning paper, Table 1 on landmarks-12", 1)[1].split("| policy |", 1)[1].split("\n", 1)[0]
    assert head.strip(" |").split(" | ")[-5:] == ["MB", "MOT", "MVT", "MVL", "MLL"]


def test_the_figure_is_written_and_named_and_the_html_holds_the_same_tables(done):
    out, md = done
    img = re.search(r"!\[[^]]*\]\(([^)]+)\)", md).group(1)
    assert (out / img).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = (out / "report.html").read_text()
    assert (
        html.count("<table>") == sum(ln.startswith("| ---") for ln in md.splitlines()) == 12
    )  # every table, once (two each for the rooms, the sensitivity and the trap rooms, three for the
    # policies' Table 1, one for Figure 3's trainings)
    took = {r[0]: int(r[1].removesuffix(" s")) for r in _rows(md, "How long it took")}
    assert len(took) == 7 and took["all"] >= max(v for k, v in took.items() if k != "all")  # six sections, then all


def test_a_second_run_resumes_what_the_first_left(done):
    """Nothing is run again: every log, every policy run's trials and the model stay as they were."""
    out, md = done
    kept = [p for p in out.rglob("*") if p.suffix in (".mcap", ".npz") or p.parent.name == "runs"]
    before = {p: p.stat().st_mtime_ns for p in kept}
    again = _reproduce(out)
    assert len(kept) > 10 and {p: p.stat().st_mtime_ns for p in kept} == before
    assert _rows(again, "Pilot paper, Table 1:") == _rows(md, "Pilot paper, Table 1:")


def test_the_command_refuses_an_unknown_section():
    r = CliRunner().invoke(app, ["reproduce", "everything"])
    assert r.exit_code == 2 and "expected pilots, learning or all" in r.output


@pytest.mark.parametrize(
    "args, want",
    [
        (["--quick", "--train-seeds", "3"], replace(QUICK, train_seeds=3)),
        (["--train-seeds", "1"], replace(FULL, train_seeds=1)),
        ([], FULL),
    ],
)
def test_train_seeds_sets_figure_3s_trainings_and_nothing_else(args, want, monkeypatch, tmp_path):
    seen = []
    monkeypatch.setattr(
        "navcli.experiments.reproduce.reproduce",
        lambda which, out, settings, **kw: seen.append(settings) or _written(out),
    )
    r = CliRunner().invoke(app, ["reproduce", "learning", "--out", str(tmp_path / "r"), *args])
    assert r.exit_code == 0, r.output
    assert seen == [want]


def _written(out: Path, errored_runs: int = 0) -> dict[str, Path]:
    out.mkdir(parents=True, exist_ok=True)
    (out / "report.md").write_text("# report\n")
    (out / "source.json").write_text(json.dumps({"errored_runs": errored_runs}))
    return {"markdown": out / "report.md", "html": out / "report.html", "source": out / "source.json"}


def test_train_seeds_below_one_is_refused():
    r = CliRunner().invoke(app, ["reproduce", "learning", "--train-seeds", "0"])
    assert r.exit_code == 2 and "--train-seeds" in r.output


def test_the_reports_own_files_are_recognised_so_the_command_can_run_again(done):
    """The CLI checks its folder before the work: report.md and report.html of an earlier run are
    navcli's (their mark), so the same command resumes instead of being refused."""
    from navcli.outputs import check_folder, navcli_wrote

    out, _ = done
    check_folder(out, REPORT_FILES, overwrite=True)  # raises if one were taken for a user's file
    assert navcli_wrote(out / "table1" / "conditions.json")
    (out / "mine.html").write_text("<html>mine</html>")
    assert not navcli_wrote(out / "mine.html")


def test_a_users_pilot_runs_beside_the_papers_two_without_the_papers_numbers(done):
    _, md = done
    rows = _rows(md, "Pilot paper, Table 1:")
    mine = [r for r in rows if r[1] == VFH]
    assert len(mine) == 4 and all(r[3] == "-" and r[7] == "" for r in mine)  # no paper number, no verdict
    gains = [r for r in rows if r[1] == f"{VFH} gain %"]
    assert [r[0] for r in gains] == ["vision", "vision", "oracle", "oracle"] and all(r[3] == "-" for r in gains)
    r = CliRunner().invoke(app, ["reproduce", "pilots", "--pilot", "geometric"])
    assert r.exit_code == 2 and "one of the paper's two pilots" in r.output


RANGES = {
    "time_s": (0.0, float("inf")),
    "path_cm": (0.0, float("inf")),
    "successes": (0.0, 99.0),
    "reward": (-float("inf"), 0.0),
    "actions": (0.0, float("inf")),
    "contacts per run": (0.0, float("inf")),
    **{a: (0.0, float("inf")) for a in ACTIONS},
}
"""Where each quantity of the report lives: times, paths, actions (and each action's count) and contacts
are not negative, rewards not positive (every action costs), successes of 99 starts between 0 and 99."""


def _bounds(cell: str) -> tuple[float, float]:
    lo, hi = re.search(r"\[([-+\d.]+)%?, ([-+\d.]+)%?\]", cell).groups()
    return float(lo), float(hi)


def test_no_interval_leaves_its_range_and_no_verdict_stands_without_a_paper_number(done):
    _, md = done
    checked = 0
    for heading, quantity, paper, navcli, agreement in (
        ("Pilot paper, Table 1:", 2, 3, 4, 7),
        ("Trap rooms", 1, 2, 3, 4),
        ("Learning paper, Table 1", 1, 2, 3, 4),
    ):
        for row in _rows(md, heading, 2 if heading.startswith("Learning") else 0):
            q = row[quantity]
            if row[paper] == "-":  # the paper has no number: no verdict
                assert row[agreement] == "", row
            else:
                assert row[agreement], row
            if "[" not in row[navcli]:
                continue
            lo, hi = _bounds(row[navcli])
            if row[navcli].endswith("%]") or "/" in row[navcli]:
                low, high = 0.0, 100.0  # a rate, in %
            elif "gain" in row[1]:
                low, high = -float("inf"), 100.0  # a gain in % is at most 100 (the time or path gone)
            else:
                low, high = RANGES[q]
            assert low <= lo <= hi <= high, row
            checked += 1
    assert checked >= 20
    for row in _rows(md, "Pilot paper, Table 1's sensitivity"):
        assert len(row) == 4  # condition, metric, gain, pairs: the paper has no numbers here, so no verdict


def test_too_few_runs_give_no_verdict_and_the_notes_say_so(done):
    """TINY has 2 reruns, 2 pairs, 3 starts: every verdict of Table 1 and of the policies says too few."""
    from navcli.analysis.stats import MIN_SAMPLE

    _, md = done
    for heading, table, agreement in (("Pilot paper, Table 1:", 0, 7), ("Learning paper, Table 1", 2, 4)):
        verdicts = {r[agreement] for r in _rows(md, heading, table) if r[agreement]}
        assert verdicts and all(v.startswith("too few ") and f"{MIN_SAMPLE} needed" in v for v in verdicts)
    assert (
        "the policies on landmarks-12: only 3 starts; with fewer than 10 its 95 % intervals are too uncertain to trust"
        in md
    )


def test_the_report_records_its_provenance_and_that_no_run_errored(done):
    import navcli
    from navcli.experiments import provenance

    out, md = done
    source = json.loads((out / "source.json").read_text())
    assert source["command"] is None  # TINY: settings no command line gives
    assert source["build"] == navcli.BUILD and source["errored_runs"] == 0
    assert source["libraries"] == provenance.libraries() and source["dir"] == str(out.resolve())
    if provenance.checkout(ROOT):
        assert len(source["commit"]) == 40 and isinstance(source["dirty"], bool)
    lines = md.splitlines()
    assert lines[3].startswith("Made from Python") and f"the {navcli.BUILD} build" in lines[3]
    assert "No run ended in error." in md.split("\n## ", 1)[0]  # at the top


def _swing(scan: range = range(0)) -> tuple:
    """A hand-made run, a pose a second for 200 s: 0.1 m/s along x for 50 s (to x = 5 m), then 100 s
    swinging between x = 5 m (even seconds) and 5.5 m (odd), then 1 m/s on; ``scan``: the seconds
    of a deliberate scan."""
    t = np.arange(201, dtype=float)
    x = np.where(t <= 50, 0.1 * t, np.where(t <= 150, 5.0 + 0.5 * (t % 2), 5.0 + (t - 150)))
    counted = np.array([int(s) not in scan for s in t])
    return t, np.column_stack([x, np.zeros_like(x)]), counted


def test_the_stall_metric_on_a_hand_made_trace():
    """Worked out: at 110 s the robot is at 5 m, where it was at 50 s; from then to 150 s, every
    pose lies 0 m from the one 60 s before it (the same parity of seconds): one stall from 50 s to
    150 s, 100 s (108 s alone: 5 m against 4.8 m at 48 s, a stall of 60 s; the others of the swing's
    first minute are 0.4 m or more from theirs). With the seconds 60-109 a deliberate scan, the
    clock loses 50 s: the swing's poses after it are 110 s of clock from where the robot drove
    (x at most 4 m), and no 60 s of clock lies within the swing: no stall."""
    from navcli.analysis.stall import STALL_M, STALL_S, longest_stall

    assert (STALL_S, STALL_M) == (60.0, 0.3)
    t, xy, _ = _swing()
    assert longest_stall(t, xy) == pytest.approx(100.0)
    t, xy, counted = _swing(range(60, 110))
    assert longest_stall(t, xy, counted) == 0.0
    assert longest_stall(np.arange(601.0), np.zeros((601, 2))) == pytest.approx(600.0)  # standing: all of it
    drive = np.column_stack([0.05 * np.arange(601.0), np.zeros(601)])  # the paper's pace: 3 m a minute
    assert longest_stall(np.arange(601.0), drive) == 0.0


def test_a_deliberate_scan_is_the_rescuer_holding_the_stopped_wheels():
    import pandas as pd

    from navcli.analysis.stall import scanning

    ns = [100, 200, 300, 400, 500]
    bids = pd.DataFrame(
        {
            "log_time_ns": ns,
            "motion.winner": ["navigation", "navigation", "pilot", "navigation", "navigation"],
            "motion.actions.navigation.speed": [0.0, 0.0, 0.0, 0.05, 0.0],
        }
    )
    nav = pd.DataFrame(
        {"log_time_ns": ns, "forwarded.motion_agent": ["rescuer", "target-tracker", "rescuer", "rescuer", "rescuer"]}
    )
    poses = pd.DataFrame({"log_time_ns": [0, 100, 200, 300, 400, 500]})
    # before any tick: no scan; then: stopped by the rescuer; the tracker's stop; the pilot holds
    # the wheels; the rescuer drives; stopped by the rescuer
    assert scanning(poses, bids, nav).tolist() == [False, True, False, False, False, True]
    assert scanning(poses, bids, None).tolist() == [False] * 6  # no Navigation system's topic: no scan


def test_the_rooms_are_every_bundled_room_of_the_papers_size():
    from navcli.experiments.rooms import ROOM_SIZE, square_rooms
    from navcli.scenario import bundled, load_scenario

    sizes = {n: load_scenario(bundled.path(n)).arena for n in bundled.names()}
    assert square_rooms() == tuple(n for n, a in sorted(sizes.items()) if (a.width, a.height) == ROOM_SIZE)
    assert {"paper-8x8", "slanted-8x8", "drawn-8x8-a", "drawn-8x8-b"} <= set(square_rooms())
    assert "u-trap" not in square_rooms() and "drawn-door" in FULL.trap_rooms


def test_the_rooms_tables_are_the_logs_they_name(done):
    """Per room, perception and pilot: reached, the mean and SD of time, the runs with a stall (the
    stall recomputed from each log); per room and perception: the ratio of the mean times."""
    from navcli.analysis.stall import STALL_S, run_stall
    from navcli.experiments.rooms import TIME_RATIO_TARGET

    out, md = done
    heading = "Pilots on every 8 m x 8 m room"
    rows, targets = _rows(md, heading), _rows(md, heading, 1)
    with (out / "rooms" / "runs.csv").open() as f:
        logs = [r["log"] for r in csv.DictReader(f)]
    runs = [(log.summary, log.config["perception"], p) for p, log in ((p, read_log(p, topics=[])) for p in logs)]
    assert len(runs) == 2 * len(PILOTS) * (TINY.reruns + TINY.room_reruns)  # paper-8x8 and slanted-8x8
    assert len(rows) == 2 * 2 * len(PILOTS) and len(targets) == 4
    means, reached_of, stalled_of = {}, {}, {}
    for room, perception, pilot, reached, time_cell, _, longest, stalled in rows:
        mine = [(s, p) for s, per, p in runs if s["scenario"] == room and per == perception and s["pilot"] == pilot]
        times = [s["time_s"] for s, _ in mine if s["outcome"] == "reached"]
        assert reached.split(" ")[0] == f"{len(times)}/{len(mine)}"
        assert _mean(time_cell) == pytest.approx(statistics.mean(times), abs=0.05 + 1e-9)
        assert time_cell.split(" ")[2] == f"{statistics.stdev(times):.1f}"
        stall = [run_stall(p) for _, p in mine]
        assert int(longest) == round(max(stall)) and stalled == f"{sum(x >= STALL_S for x in stall)}/{len(mine)}"
        means[room, perception, pilot] = statistics.mean(times)
        reached_of[room, perception, pilot], stalled_of[room, perception, pilot] = len(times), stalled
    for room, perception, ratio, verdict, pf_stalled, stall_verdict in targets:
        want = means[room, perception, "potential-field"] / means[room, perception, "geometric"]
        assert float(ratio) == pytest.approx(want, abs=0.005 + 1e-9)
        pf, gp = (reached_of[room, perception, pilot] for pilot in ("potential-field", "geometric"))
        if pf < gp:
            assert verdict == f"not met: PF reached {pf} run{'s' if pf != 1 else ''}, GP {gp}"
        else:
            assert verdict == ("met" if want <= TIME_RATIO_TARGET else "not met")
        assert pf_stalled == stalled_of[room, perception, "potential-field"]
        assert stall_verdict == ("met" if pf_stalled.startswith("0/") else "not met")


def test_the_trap_rooms_table_counts_each_rooms_endings(done):
    out, md = done
    rows = _rows(md, "Trap rooms", 1)
    with (out / "traps" / "runs.csv").open() as f:
        summaries = [read_log(r["log"], topics=[]).summary for r in csv.DictReader(f)]
    order = ("potential-field", "geometric", VFH)  # the paper's two, then the user's
    assert [r[:2] for r in rows] == [[room, p] for room in TINY.trap_rooms for p in order]
    for room, pilot, reached, target, blocked, blocked_target, timeout, contacts, thesis in rows:
        mine = [s for s in summaries if s["scenario"] == room and s["pilot"] == pilot]
        k = sum(s["outcome"] == "reached" for s in mine)
        assert reached.split(" ")[0] == f"{k}/{len(mine)}"
        assert target == ("met" if k >= 0.95 * len(mine) else "not met")
        ended = sum(s["outcome"] == "blocked" for s in mine)
        assert blocked == f"{ended}/{len(mine)}" and blocked_target == ("met" if ended == 0 else "not met")
        assert timeout == f"{sum(s['outcome'] == 'timeout' for s in mine)}/{len(mine)}"
        assert _mean(contacts) == pytest.approx(statistics.mean(s["collisions"] for s in mine), abs=0.05 + 1e-9)
        assert thesis == "no figure"  # the thesis gives no contacts figure


def test_every_declared_sensitivity_row_is_in_the_report(done):
    from navcli.experiments.switches import SENSITIVITY_ROWS

    _, md = done
    rows = _rows(md, "Pilot paper, Table 1's sensitivity", 1)
    want = [
        f"{r.label}: {room} ({p} perception)"
        for r in SENSITIVITY_ROWS
        for room in TINY.sensitivity_rooms
        for p in r.perceptions
    ]
    assert [r[0] for r in rows[::2]] == want and [r[1] for r in rows[:2]] == ["time_s", "path_cm"]


def test_a_sensitivity_row_sets_scenario_fields_as_a_file_would():
    from navcli.experiments.switches import scenario_with
    from navcli.scenario import ScenarioError

    base = scenario_with("paper-8x8", {})
    changed = scenario_with("paper-8x8", {"noise.odometry": 0.0, "mission.time_limit": 100})
    assert base.noise.odometry > 0 and changed.noise.odometry == 0.0 and changed.mission.time_limit == 100
    assert changed.sha256 != base.sha256 and changed.obstacles == base.obstacles
    with pytest.raises(ScenarioError, match="noise.no_such_field"):
        scenario_with("paper-8x8", {"noise.no_such_field": 1})


def test_the_results_pages_summary_counts_the_targets_beside_the_verdicts(make_results):
    report = (
        "## Rooms\n\n| room | ratio | target (at most 1.3) | stalls | target (none) |\n| --- | --- | --- | --- | --- |\n"
        "| a | 1.0 | met | 1/2 | not met |\n| b | - | no verdict: 1 run ended in error | 0/2 | not met: x |\n\n"
        "## Table 1\n\n| pilot | agreement |\n| --- | --- |\n| GP | agrees |\n| PF | does not agree (above) |\n"
    )
    assert make_results.summary_table(report).splitlines()[2:] == [
        "| Table 1 | 1 | 1 | 0 |",
        "",
        "| targets of | met | not met | no verdict |",
        "| --- | ---: | ---: | ---: |",
        "| Rooms | 1 | 2 | 1 |",
    ]
    assert "targets of" not in make_results.summary_table(report.split("## Table 1")[1])  # none: no such table


def test_a_room_with_an_errored_run_counts_it_and_gets_no_verdict():
    import pandas as pd

    from navcli.experiments.rooms import compare_rows, pilot_rows

    runs = pd.DataFrame(
        {
            "pilot": ["geometric"] * 3 + ["potential-field"] * 3,
            "outcome": ["reached", "reached", "reached", "reached", "reached", "error"],
            "time_s": [100.0, 200.0, 300.0, 150.0, 250.0, 0.0],
            "path_cm": [500.0, 1000.0, 1500.0, 700.0, 900.0, 0.0],
            "stall_s": [0.0, 0.0, 61.0, 0.0, 90.0, 0.0],
            "scenario": ["r"] * 6,
            "perception": ["vision"] * 6,
            "collisions": [0] * 6,
            "camera_looks": [0] * 6,
            "ticks": [1, 2, 3, 4, 5, 6],
            "diverting_targets": [0] * 6,
        }
    )
    gp = pilot_rows("r", "vision", "geometric", runs[runs["pilot"] == "geometric"])
    # times 100, 200, 300: mean 200, SD 100; one run of three stalled, for 61 s
    assert gp[3] == "3/3" and gp[4].startswith("200.0 ± 100.0 [") and gp[6:] == ["61", "1/3"]
    pf = pilot_rows("r", "vision", "potential-field", runs[runs["pilot"] == "potential-field"])
    assert pf[3] == "2/3, 1 errored" and pf[4].startswith("200.0 ± 70.7 [")  # 150 and 250: SD 50 * sqrt(2)
    row = compare_rows("r", "vision", runs)
    assert row[2] == "1.00" and row[3] == "no verdict: 1 run ended in error"  # 200 / 200
    assert row[4] == "1/3" and row[5] == "no verdict: 1 run ended in error"
