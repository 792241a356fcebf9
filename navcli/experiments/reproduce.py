"""``navcli reproduce``: both papers' experiments under their conditions, and a report beside the
papers' numbers (``report.md``, its PNGs, and ``report.html``).

Sections (each resumes from what an earlier run of the same command left in its folder):

- ``pilots``: the pilot paper's Table 1 on ``paper-8x8`` with vision and with ground truth
  (:func:`table1`), the two pilots on every bundled room of the paper's size
  (:mod:`~navcli.experiments.rooms`), its sensitivity to what the paper leaves unstated (:func:`sensitivity`), and the
  trap rooms' diverting targets beside the thesis' real-robot figures, and each room's endings
  (:func:`traps`, :mod:`~navcli.experiments.trap_rooms`);
- ``learning``: the learning paper's Table 1 (:func:`policies`) and Figure 3 (:func:`figure3`).

Agreement is decided one way throughout (our design, :func:`verdict`): a paper's number *agrees*
when navcli's 95 % interval of the same quantity meets the paper's own range of it, else it *does
not agree*, and the report says on which side the paper's lies. The paper's range is its spread
where it gives one, not the zero-width point a deterministic run would be held to: the mean +- 1
SD of its runs (the pilot paper's Table 1), the 95 % interval its Table 1 gives a gain (its means'
standard errors over its 45 runs a pilot, :func:`paper_gain_interval`), the Wilson interval of a
count (successes of 99); the number itself where the paper gives nothing more. navcli's intervals
stay in their quantity's range (:mod:`navcli.analysis.stats`: Wilson for rates, a bootstrap for
means). Where the paper has no number there is no verdict; where navcli has fewer than
:data:`~navcli.analysis.stats.MIN_SAMPLE` runs (pairs, starts), the verdict says it has too few to
judge. Identical reruns count once (:func:`navcli.analysis.tables.distinct_runs`: ground-truth
runs repeat one run whatever the seed), in a verdict's interval and its count. A set that holds a
run that ended in ``error`` gets no verdict (our choice: judging the rest would judge a set the
errors chose); every table counts such runs as not reached, its notes say why, the top of the
report lists them all, and ``source.json`` counts them (``navcli reproduce`` then exits 4).
The report's first paragraph and ``source.json`` say where it comes from
(:mod:`~navcli.experiments.provenance`: the command line, commit, build and libraries). ``--quick`` runs every section with few reruns (:data:`QUICK`) to check the machinery in
minutes; its intervals are wide and the report says so at the top.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable

from .. import __version__
from ..analysis.stats import MIN_SAMPLE, bootstrap_mean, small_sample, wilson_interval
from ..params import Params
from ..scenario import bundled
from . import learning_paper, rooms, trap_rooms
from .document import Report, interval_text

SCENARIOS = bundled.FOLDER
SECTIONS = ("pilots", "learning")
TRAP_ROOMS = ("river-bridges", "u-trap", "door-wall", "hidden-fence", "blocked-wall", "drawn-door")

# The papers' numbers (pilot paper, Table 1; learning paper, Table 1 and section 6; the thesis' robot)
PAPER_TABLE1: dict[str, dict[str, tuple[float, float]]] = {
    "geometric": {"time_s": (297.3, 81.9), "path_cm": (1532, 429)},  # mean, standard deviation
    "potential-field": {"time_s": (243.4, 99.1), "path_cm": (1195, 198)},
}
PAPER_PILOTS = ("potential-field", "geometric")
"""The pilot paper's two pilots (``--pilot`` adds a user's beside them)."""
PAPER_GAINS = {"time_s": 18.1, "path_cm": 22.0}  # %: the potential field against the geometric pilot
PAPER_RUNS = 45  # runs per pilot behind the pilot paper's Table 1
THESIS_TRAPS = {"reached": 0.85, "diverting_1": 0.58, "diverting_2": 0.18}


@dataclass(frozen=True)
class Settings:
    """How much of each experiment is run (the full sizes are the papers')."""

    reruns: int = 45  # Table 1: seeds per pilot and perception
    room_reruns: int = 10  # the other rooms of the paper's size: seeds per room, pilot and perception
    rooms: tuple[str, ...] | None = None  # those rooms; None: every bundled one (rooms.square_rooms)
    sensitivity_seeds: int = 10
    sensitivity_speeds: tuple[float, ...] = (0.05, 0.1, 0.3)
    sensitivity_rooms: tuple[str, ...] = ("paper-8x8", "slanted-8x8")
    trap_seeds: int = 10
    trap_rooms: tuple[str, ...] = TRAP_ROOMS
    policy_runs: int = 5
    policy_starts: int = 99
    policy_rooms: tuple[str, ...] = learning_paper.POLICY_ROOMS
    train_seeds: int = 5
    train_trials: int = 2000
    eval_every: int = 100
    eval_starts: int = 99
    quick: bool = False


FULL = Settings()
QUICK = Settings(
    reruns=3,
    room_reruns=2,
    rooms=("paper-8x8", "slanted-8x8"),
    sensitivity_seeds=3,
    sensitivity_speeds=(0.05, 0.3),
    sensitivity_rooms=("paper-8x8",),
    trap_seeds=2,
    policy_runs=2,
    policy_starts=10,
    policy_rooms=("landmarks-12",),
    train_seeds=2,
    train_trials=20,
    eval_every=10,
    eval_starts=10,
    quick=True,
)


def verdict(
    navcli: tuple[float, float], paper: tuple[float, float], n: int, unit: str = "runs", errored: int = 0
) -> str:
    """The report's one rule (module docstring): does navcli's 95 % interval ``navcli`` (low, high),
    from ``n`` ``unit`` (distinct: identical reruns count once), meet the paper's range ``paper``
    (low, high; a point when they are equal)? None when ``errored`` of the runs behind it ended in
    error: a set that lost runs to errors is not judged.

    >>> verdict((250.1, 250.4), (297.3 - 81.9, 297.3 + 81.9), 45)  # 45 distinct runs, within the spread
    'agrees'
    >>> verdict((140.0, 150.0), (215.4, 379.2), 45)
    "does not agree (the paper's is above)"
    >>> verdict((140.0, 150.0), (215.4, 379.2), 3)
    'too few runs to judge (3; 10 needed)'
    >>> verdict((250.1, 250.4), (215.4, 379.2), 44, errored=1)
    'no verdict: 1 run ended in error'
    """
    from ..analysis.tables import errored_verdict

    lo, hi = navcli
    if errored:
        return errored_verdict(errored)
    if n < MIN_SAMPLE:
        return f"too few {unit} to judge ({n}; {MIN_SAMPLE} needed)"
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return "no interval"
    if hi < paper[0]:
        return "does not agree (the paper's is above)"
    if lo > paper[1]:
        return "does not agree (the paper's is below)"
    return "agrees"


def paper_gain_interval(metric: str) -> tuple[float, float]:
    """The 95 % interval of the potential field's gain over the geometric pilot (%) that the pilot
    paper's Table 1 itself allows: its two means with their standard errors over
    :data:`PAPER_RUNS` runs each (SD / sqrt(45)), carried to the gain 100 (1 - pf / geo) by the delta
    method, the pilots' runs taken as independent (the paper does not say they were paired).

    >>> [round(x, 1) for x in paper_gain_interval("time_s")], [round(x, 1) for x in paper_gain_interval("path_cm")]
    ([6.4, 29.9], [14.6, 29.4])
    """
    (g, sd_g), (p, sd_p) = PAPER_TABLE1["geometric"][metric], PAPER_TABLE1["potential-field"][metric]
    se_g, se_p = sd_g / math.sqrt(PAPER_RUNS), sd_p / math.sqrt(PAPER_RUNS)
    gain = 100 * (1 - p / g)
    se = 100 * math.hypot(se_p / g, p * se_g / g**2)
    return gain - 1.96 * se, gain + 1.96 * se


def _conditions(report: Report, out: Path, specs: list) -> None:
    """Every parameter of the section's configurations, with their run ids, in ``conditions.json``."""
    from ..outputs import write_text

    out.mkdir(parents=True, exist_ok=True)
    write_text(
        out / "conditions.json",
        json.dumps(
            {"navcli_version": __version__, "configurations": [{"run_id": s.run_id, **s.to_json()} for s in specs]},
            indent=1,
        )
        + "\n",
    )
    report.text(f"Every parameter of these runs, with their configurations' run ids: {out / 'conditions.json'}.")


def _scenario(name: str):
    from ..scenario import load_scenario

    return load_scenario(SCENARIOS / f"{name}.yaml")


def _compare(
    names: tuple[str, ...],
    reruns: int,
    out: Path,
    ex,
    perception: str | None = None,
    overrides: dict | None = None,
    pilots: tuple[str, ...] = (),
):
    """The paper's two pilots and ``pilots`` on each room with the same seeds (``navcli compare
    pilots``): the runs frame."""
    from ..analysis.tables import load_runs
    from ..config import RunSpec
    from .compare import plan, run_on

    specs = [RunSpec.build(_scenario(n), perception=perception, overrides=overrides or {}) for n in names]
    work = plan(specs, list(PAPER_PILOTS + pilots), reruns, out)
    run_on(work, ex)
    return load_runs(out, paths=[j.log for j in work]), specs


def table1(report: Report, s: Settings, out: Path, ex, pilots: tuple[str, ...] = ()) -> None:
    """The pilot paper's Table 1, with vision and with ground truth (and ``pilots`` beside the
    paper's two, which the paper has no numbers for)."""
    from ..analysis.tables import error_notes, errored, improvements, notes, pilot_table

    report.heading("Pilot paper, Table 1: the potential-field pilot against the geometric one")
    report.text(
        f"paper-8x8 (our room in the paper's spirit; its coordinates are not given), {s.reruns} reruns per "
        "pilot and perception, the same seeds for both pilots; the paper's pace (5 cm/s, the scenario's "
        "robot.max_speed). Means over the distinct reached runs (identical reruns count once) with bootstrap "
        "95 % intervals, against the paper's mean ± 1 SD (the spread of its runs); gains paired over the seeds "
        "both reached (identical pairs once), with bootstrap 95 % intervals, against the 95 % interval the "
        f"paper's Table 1 gives its gain ({PAPER_RUNS} runs a pilot). navcli's SD is over every reached run "
        "(n - 1; 0 when the reruns repeat one run), beside the paper's SD. A pilot with runs that ended in error "
        "gets no verdict. Logs: " + str(out)
    )
    rows: list[list[Any]] = []
    bases: list = []
    remarks: list[str | None] = []
    for perception in ("vision", "oracle"):
        runs, specs = _compare(("paper-8x8",), s.reruns, out / perception, ex, perception, pilots=pilots)
        _write_runs(runs, out / perception / "runs.csv")
        report.errored([f"Table 1: {e}" for e in error_notes(runs)], errored(runs))
        bases += specs
        table = pilot_table(runs).set_index("pilot")
        imps = improvements(runs, "geometric")
        once = improvements(runs, "geometric", once=True).set_index("metric")
        for pilot in ("geometric", "potential-field") + pilots:
            rows += _table1_rows(perception, pilot, runs, table)
            mine = runs[runs["pilot"] == pilot]
            remarks.append(small_sample(f"{perception}, {pilot}", _distinct_reached(mine)[0], "distinct reached runs"))
        for pilot in ("potential-field",) + pilots:
            bad = int((runs["pilot"].isin((pilot, "geometric")) & (runs["outcome"] == "error")).sum())
            all_pairs = imps[imps["pilot"] == pilot].set_index("metric")
            for metric in ("time_s", "path_cm"):
                g = once[once["pilot"] == pilot].loc[metric]
                pairs, every = int(g["pairs"]), int(all_pairs.loc[metric, "pairs"])
                cells = interval_text(g["improvement_pct"], g["ci95_low"], g["ci95_high"], sign=True) + (
                    f" ({every} pairs{f', {pairs} distinct' if pairs < every else ''})"
                )
                if pilot != "potential-field":
                    rows.append([perception, f"{pilot} gain %", metric, "-", cells, "", "", ""])
                    continue
                p_lo, p_hi = paper_gain_interval(metric)
                unit = "distinct pairs" if pairs < every else "pairs"
                rows.append(
                    [
                        perception,
                        "PF gain %",
                        metric,
                        f"+{PAPER_GAINS[metric]:g} [{p_lo:+.1f}, {p_hi:+.1f}]",
                        cells,
                        "",
                        "",
                        verdict((g["ci95_low"], g["ci95_high"]), (p_lo, p_hi), pairs, unit, errored=bad),
                    ]
                )
        remarks += notes(runs, table.reset_index(), imps, "geometric")
    report.table(
        ["perception", "pilot", "quantity", "the paper", "navcli [95 % CI]", "navcli SD", "reached", "agreement"], rows
    )
    report.notes(remarks)
    report.text(
        "Run ids and every run's numbers: " + ", ".join(str(out / p / "runs.csv") for p in ("vision", "oracle"))
    )
    _conditions(report, out, bases)


def _distinct_reached(runs) -> tuple[int, Any]:
    """How many distinct runs of ``runs`` (one pilot's) reached the target, and those runs."""
    from ..analysis.tables import distinct_runs

    ok = distinct_runs(runs[runs["outcome"] == "reached"])
    return len(ok), ok


def _table1_rows(perception: str, pilot: str, runs, table) -> list[list[Any]]:
    """A pilot's time and path rows of Table 1: its mean over the distinct reached runs against
    the paper's (none for a pilot the paper does not have)."""
    mine = runs[runs["pilot"] == pilot]
    n, ok = _distinct_reached(mine)
    reached, bad = int((mine["outcome"] == "reached").sum()), int((mine["outcome"] == "error").sum())
    count = f"{int(table.loc[pilot, 'reached'])}/{int(table.loc[pilot, 'runs'])}" + (f", {bad} errored" if bad else "")
    distinct = f" ({n} distinct of {reached})" if n < reached else ""
    rows = []
    every = mine[mine["outcome"] == "reached"]
    for metric in ("time_s", "path_cm"):
        m, lo, hi = bootstrap_mean(ok[metric].to_numpy(dtype=float))
        cell = interval_text(m, lo, hi) + distinct
        sd = f"{every[metric].std(ddof=1):.1f}" if len(every) > 1 else "-"
        if pilot not in PAPER_TABLE1:  # a user's pilot: the paper has no number for it
            rows.append([perception, pilot, metric, "-", cell, sd, count, ""])
            continue
        paper, paper_sd = PAPER_TABLE1[pilot][metric]
        unit = "distinct reached runs" if distinct else "reached runs"
        rows.append(
            [
                perception,
                pilot,
                metric,
                f"{paper:g} ± {paper_sd:g} (SD)",
                cell,
                sd,
                count,
                verdict((lo, hi), (paper - paper_sd, paper + paper_sd), n, unit, errored=bad),
            ]
        )
    return rows


def _write_runs(runs, path: Path) -> None:
    from ..analysis.files import write_csv

    write_csv(path, runs.drop(columns=["xy"], errors="ignore"))


@dataclass(frozen=True)
class Row:
    """A row of the sensitivity's table of switches: ``label`` and what it changes from the
    defaults, ``overrides``: a parameter by its ``--param`` name (its group one of
    :attr:`~navcli.params.Params.GROUPS`: ``pilot.look_cap``) or a field of the scenario by its
    dotted place in the file (``noise.odometry``); run with each of ``perceptions``."""

    label: str
    overrides: dict[str, Any]
    perceptions: tuple[str, ...] = ("vision", "oracle")


VISION = ("vision",)
SENSITIVITY_ROWS: tuple[Row, ...] = (
    Row("navcli's defaults", {}),
    Row("no wheel slip (the command driven exactly)", {"robot.slip_noise": 0.0}),
    Row("no stall rule (only the long blocked window)", {"navigation.stall_rule": False}),
    Row(
        "no progress is not blocked (only bumps and the Pilot's report)",
        {"navigation.blocked_no_progress": False},
        VISION,
    ),
    Row("gives up when the map shows no way out", {"navigation.gives_up": True}, VISION),
    Row("ways seen closed block for good", {"navigation.seen_closed_cost": 0.0}, VISION),
    Row("dead ends matched by their ends only", {"navigation.dead_end_radius": 0.0}, VISION),
    Row("diverting edges handed over only when seen whole", {"navigation.diverting_seen_whole": True}, VISION),
    Row("every look sees all", {"vision.routines": 0}, VISION),
    Row("lines joined by geometry", {"vision.line_objects": 0}, VISION),
    Row("walls known", {"vision.walls": "known"}, VISION),
    Row("walls felt", {"vision.walls": "felt"}, VISION),
    Row("eq. 1's look capped at 0.9", {"pilot.look_cap": 0.9}, VISION),
    Row("bumps joined by nearness alone", {"vision.bump_lines": "near"}, VISION),
    Row("a fence corrected at one end moves whole", {"vision.fence_rigid": True}, VISION),
    Row(
        "the three alternatives together",
        {"vision.routines": 0, "vision.line_objects": 0, "pilot.look_cap": 0.9},
        VISION,
    ),
)
"""The sensitivity's switches, one row each: navcli's choices where the papers are silent, one at a
time from the defaults (and the three alternative sensing choices together). A switch gets its
row here, and nowhere else: ``Row("label", {"group.name": value})``."""


def sensitivity(report: Report, s: Settings, out: Path, ex) -> None:
    """Table 1's dependence on the unstated: speed and how a turn is executed (both perceptions),
    and navcli's switches (:data:`SENSITIVITY_ROWS`)."""
    from ..analysis.tables import load_sweep
    from .sweep import load_plan, plan_runs, run_sweep

    out.mkdir(parents=True, exist_ok=True)
    rooms = ", ".join(json.dumps(str(SCENARIOS / f"{r}.yaml")) for r in s.sensitivity_rooms)  # quoted: any path
    plan_file = out / "plan.yaml"
    plan_file.write_text(
        f"# navcli reproduce: the sensitivity's plan\nversion: 1\nscenarios: [{rooms}]\n"
        f"seeds: {s.sensitivity_seeds}\npilots: [potential-field, geometric]\n"
        "perception: [vision, oracle]\ngrid:\n"
        f"  robot.max_speed: [{', '.join(map(str, s.sensitivity_speeds))}]\n"
        "  pilot.drive_while_turning: [true, false]\n"
    )
    report.heading("Pilot paper, Table 1's sensitivity (the paper states one condition)")
    report.text(
        f"{s.sensitivity_seeds} seed(s) a point. The paper has no numbers here: the column says how the potential "
        "field's gain moves with what it leaves unstated: the robot's pace and how a turn is executed (both "
        f"perceptions; the plan: {plan_file}), then each of navcli's switches from the defaults."
    )
    table = out / "results.parquet"
    planned = plan_runs(load_plan(plan_file), None)
    run_sweep(planned, table, ex)
    runs = load_sweep(table)
    runs = runs[runs["run_id"].isin({r.spec.run_id for r in planned})]  # the table keeps other plans' rows
    report.text(f"Every run: {table}.")
    _gain_table(report, [(None, runs)])
    _switch_rows(report, s, out / "switches", ex)


def _gain_table(report: Report, groups: list[tuple[str | None, Any]]) -> None:
    """The potential field's gain per condition of each group of runs (named by the group's label,
    or by the condition where it has none), their errors and a small sample said in the notes; no
    verdict: the paper has no number for these conditions."""
    import pandas as pd

    from ..analysis.tables import error_notes, errored, improvements

    rows, pairs = [], []
    for label, runs in groups:
        imps = improvements(runs, "geometric")
        pairs += [int(p) for p in imps["pairs"]]
        rows += [
            [
                label or r["condition"],
                r["metric"],
                interval_text(r["improvement_pct"], r["ci95_low"], r["ci95_high"], sign=True),
                int(r["pairs"]),
            ]
            for _, r in imps.iterrows()
        ]
    runs = pd.concat([g for _, g in groups], ignore_index=True)
    errors = error_notes(runs)
    report.errored([f"Sensitivity: {e}" for e in errors], errored(runs))
    report.table(["condition", "metric", "PF gain % [95 % CI]", "pairs"], rows)
    few = small_sample("every condition", min(pairs), "pairs at the fewest") if pairs else None
    report.notes([few, *errors])


def _switch_rows(report: Report, s: Settings, out: Path, ex) -> None:
    """A row per switch of :data:`SENSITIVITY_ROWS`, per sensitivity room and perception: run as a
    sweep's rows (no logs), into one results table."""
    from ..analysis.tables import load_sweep
    from ..config import RunSpec
    from .compare import reruns
    from .sweep import SweepRun, run_sweep

    work, specs, label = [], [], {}
    for i, row in enumerate(SENSITIVITY_ROWS):
        params = {k: v for k, v in row.overrides.items() if k.split(".", 1)[0] in Params.GROUPS}
        fields = {k: v for k, v in row.overrides.items() if k not in params}
        for room in s.sensitivity_rooms:
            sc = _scenario_with(room, fields)
            for perception in row.perceptions:
                spec = RunSpec.build(sc, perception=perception, overrides=params)
                runs = [
                    SweepRun(seeded.replace(pilot=pilot), i, params, None)
                    for seeded in reruns(spec, {}, s.sensitivity_seeds)
                    for pilot in PAPER_PILOTS
                ]
                work += runs
                specs.append(spec)
                label[f"{row.label}: {room} ({perception} perception)"] = {r.spec.run_id for r in runs}
    out.mkdir(parents=True, exist_ok=True)
    table = out / "results.parquet"
    run_sweep(work, table, ex)
    every = load_sweep(table)
    report.text(
        "Each switch alone from the defaults (its row of navcli.experiments.reproduce.SENSITIVITY_ROWS, with the "
        f"parameters or scenario fields it changes), {s.sensitivity_seeds} seed(s) a room, pilot and perception: "
        + "; ".join(f"{r.label}: {_overrides_text(r.overrides)}" for r in SENSITIVITY_ROWS)
        + f". Every run: {table}."
    )
    _gain_table(report, [(name, every[every["run_id"].isin(ids)]) for name, ids in label.items()])
    _conditions(report, out, specs)


def _overrides_text(overrides: dict[str, Any]) -> str:
    """``a=1, b=x`` (``the defaults`` for none)."""
    return ", ".join(f"{k}={v}" for k, v in overrides.items()) or "the defaults"


def _scenario_with(room: str, fields: dict[str, Any]):
    """The bundled ``room`` with the scenario ``fields`` (dotted places in its file) set: its YAML
    edited and read again, so every field is checked as a scenario file's is."""
    if not fields:
        return _scenario(room)
    import yaml

    from ..scenario import parse_scenario

    doc = yaml.safe_load((SCENARIOS / f"{room}.yaml").read_text())
    for name, value in fields.items():
        *parents, leaf = name.split(".")
        node = doc
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = value
    where = f"{room} with {_overrides_text(fields)}"
    return parse_scenario(yaml.safe_dump(doc, sort_keys=False), where)


def traps(report: Report, s: Settings, out: Path, ex, pilots: tuple[str, ...] = ()) -> None:
    """The trap rooms: how often each pilot gets out, with how many diverting targets."""
    from ..analysis.tables import error_notes, errored

    runs, specs = _compare(s.trap_rooms, s.trap_seeds, out, ex, pilots=pilots)
    _write_runs(runs, out / "runs.csv")
    report.heading("Trap rooms: diverting targets (the thesis' real robot beside them)")
    report.text(
        f"{s.trap_seeds} seed(s) per room and pilot; every run: {out / 'runs.csv'}. The thesis' figures "
        "(its real robot, its rooms): 85 % reached; of runs past long obstacles 58 % needed one diverting "
        "target and 18 % two, given without a count of runs (so each is taken as the number itself). Rates "
        "over every run but the interrupted (a run that ended in error counts as not reached, and its pilot "
        "gets no verdict), with Wilson 95 % intervals over the distinct runs (identical reruns count once); "
        "contacts with a bootstrap 95 % interval."
    )
    errors = error_notes(runs)
    report.errored([f"Trap rooms: {e}" for e in errors], errored(runs))
    rows = []
    remarks: list[str | None] = []
    for pilot in PAPER_PILOTS + pilots:
        rows += _trap_rows(pilot, runs[(runs["pilot"] == pilot) & (runs["outcome"] != "interrupted")])
        remarks.append(small_sample(pilot, _distinct(runs[runs["pilot"] == pilot]), "distinct runs"))
    report.table(["pilot", "quantity", "the thesis", "navcli", "agreement"], rows)
    report.notes([*remarks, *errors])
    trap_rooms.table(report, s.trap_rooms, runs, PAPER_PILOTS + pilots)
    _conditions(report, out, specs)


def _distinct(runs) -> int:
    from ..analysis.tables import distinct_runs

    return len(distinct_runs(runs[runs["outcome"] != "interrupted"]))


def _trap_rows(pilot: str, g) -> list[list[Any]]:
    """A pilot's rows of the trap rooms' table from its runs ``g`` (errors among them): each count
    over every run, its interval and verdict over the distinct runs."""
    from ..analysis.tables import distinct_runs, errored

    d = distinct_runs(g)
    n_all, n, bad = len(g), len(d), errored(g)
    tail = (f"; {n} distinct" if n < n_all else "") + (f", {bad} errored" if bad else "")
    rows = []
    for key, test, paper in (
        ("reached", lambda r: r["outcome"] == "reached", THESIS_TRAPS["reached"]),
        ("needed 1 diverting target", lambda r: r["diverting_targets"] == 1, THESIS_TRAPS["diverting_1"]),
        ("needed 2", lambda r: r["diverting_targets"] == 2, THESIS_TRAPS["diverting_2"]),
    ):
        k_all, k = int(test(g).sum()), int(test(d).sum())
        lo, hi = wilson_interval(k, n)
        rows.append(
            [
                pilot,
                key,
                f"{paper:.0%}",
                f"{k_all}/{n_all} [{lo:.0%}, {hi:.0%}]{tail}",
                verdict((lo, hi), (paper, paper), n, "distinct runs" if n < n_all else "runs", errored=bad),
            ]
        )
    m, lo, hi = bootstrap_mean(d["collisions"].to_numpy(dtype=float))
    rows.append([pilot, "contacts per run", "-", interval_text(m, lo, hi), ""])  # the thesis gives no number
    return rows


REPORT_FILES = ("report.md", "report.html", "source.json")
"""What :func:`reproduce` writes at the top of its folder (its sections' runs go into subfolders)."""


def command_line(
    which: str, out: Path, settings: Settings, jobs: int, scheduler: str | None, pilots: tuple[str, ...]
) -> list[str] | None:
    """The ``navcli reproduce`` command line that runs these settings, as argv, every choice
    spelled out (the folder absolute, the workers counted); None for settings no command line
    gives (:class:`Settings` changed from Python)."""
    base = QUICK if settings.quick else FULL
    if replace(base, train_seeds=settings.train_seeds) != settings:
        return None
    argv = ["navcli", "reproduce", which] + (["--quick"] if settings.quick else [])
    argv += ["--out", str(Path(out).resolve()), "--jobs", str(jobs)]
    if settings.train_seeds != base.train_seeds:
        argv += ["--train-seeds", str(settings.train_seeds)]
    if scheduler:
        argv += ["--scheduler", scheduler]
    for name in pilots:
        argv += ["--pilot", name]
    return argv


def reproduce(
    which: str,
    out: Path,
    *,
    settings: Settings = FULL,
    jobs: int = 2,
    scheduler: str | None = None,
    echo: Callable[[str], None] = print,
    pilots: tuple[str, ...] = (),
) -> dict[str, Path]:
    """Run the sections of ``which`` (``pilots``, ``learning`` or ``all``) into ``out`` and write
    ``report.md``, ``report.html`` and ``source.json`` (:func:`provenance.record`, with the count
    of runs that ended in error) there; returns the files written. ``pilots`` (plugins' names) run
    beside the paper's two in Table 1, the rooms of its size and the trap rooms."""
    from ..analysis.files import write_markdown
    from ..outputs import write_text
    from . import provenance
    from .executor import executor

    source = provenance.record(command_line(which, out, settings, jobs, scheduler, pilots))
    source["dir"] = str(Path(out).resolve())
    report = Report()
    report.heading("navcli reproduce: both papers' experiments beside their numbers", 1)
    report.text(provenance.describe(source))
    if settings.quick:
        report.text(
            "QUICK RUN (--quick): few reruns, to check the machinery; the intervals are wide and the "
            "verdicts are not the reproduction's. Run without --quick for the papers' sizes."
        )
    if not settings.quick and settings.train_seeds != FULL.train_seeds:
        report.text(
            f"Figure 3 from {settings.train_seeds} training(s) (--train-seeds), where the full reproduction "
            f"runs {FULL.train_seeds}."
        )
    report.text(
        f"navcli {__version__}; settings: {json.dumps(asdict(settings))}. A paper's number agrees when "
        "navcli's 95 % interval of the same quantity meets the paper's own range of it: the mean ± 1 SD of "
        "its runs where it gives an SD, the 95 % interval its Table 1 gives a gain, the Wilson interval of a "
        "count, else the number itself. No verdict where the paper has no number; none either from fewer "
        f"than {MIN_SAMPLE} runs (pairs, starts): too few to judge (identical reruns count as one), nor on a "
        "set that holds a run that ended in error."
    )
    durations = []
    t_all, cpu_here, cpu_workers = time.perf_counter(), time.process_time(), _children_cpu()
    with executor(jobs, scheduler) as ex:
        steps: list[tuple[str, Callable[[], None]]] = []
        if which in ("learning", "all"):  # the longest runs first: Figure 3's trainings, then the rest behind
            trainings = learning_paper.start_figure3(settings, out / "figure3", ex, _scenario)
        if which in ("pilots", "all"):
            steps += [
                ("Table 1 (pilots)", lambda: table1(report, settings, out / "table1", ex, pilots)),
                (
                    "rooms",
                    lambda: rooms.section(
                        report, settings, out / "rooms", out / "table1", ex, pilots, _scenario, _write_runs
                    ),
                ),
                ("sensitivity", lambda: sensitivity(report, settings, out / "sensitivity", ex)),
                ("trap rooms", lambda: traps(report, settings, out / "traps", ex, pilots)),
            ]
        if which in ("learning", "all"):
            steps += [
                (
                    "Table 1 (policies)",
                    lambda: learning_paper.policies(
                        report, settings, out / "policies", ex, verdict, _scenario, _conditions
                    ),
                ),
                (
                    "Figure 3",
                    lambda: learning_paper.figure3(
                        report, settings, out / "figure3", ex, trainings, _scenario, _conditions
                    ),
                ),
            ]
        for name, step in steps:
            t0 = time.perf_counter()
            echo(f"reproduce: {name} ...")
            step()
            durations.append([name, f"{time.perf_counter() - t0:.0f} s"])
    wall = time.perf_counter() - t_all
    here, workers = time.process_time() - cpu_here, _children_cpu() - cpu_workers
    report.heading("How long it took")
    report.text(
        f"{jobs} worker(s){' on ' + scheduler if scheduler else ''}. Each section from its start to its end "
        "in this process; Figure 3's trainings, the longest runs, start before every other section and run "
        "beside them, so its row is only what was left of them."
    )
    report.table(["section", "wall time"], durations + [["all", f"{wall:.0f} s"]])
    if workers > 0:  # local workers (a cluster's CPU is not seen from here)
        serial = here / (here + workers)
        report.text(
            f"CPU: {here:.0f} s in this process (planning, reading logs, tables, figures: the serial "
            f"part), {workers:.0f} s in the workers; serial share {serial:.1%}, so by Amdahl's law no "
            f"number of workers makes this reproduction more than {1 / serial:.0f}x faster than one."
        )
    _say_errors(report)
    source["errored_runs"] = report.error_count
    files = dict(zip(("markdown", "html", "source"), (out / f for f in REPORT_FILES)))
    write_markdown(files["markdown"], report.markdown())
    write_text(files["html"], report.html())
    write_text(files["source"], json.dumps(source, indent=1) + "\n")
    return files


def _say_errors(report: Report) -> None:
    """Runs that ended in error, said at the top of the report (under its provenance), or that none did."""
    if report.errors:
        blocks = [
            (
                "p",
                f"RUNS THAT ENDED IN ERROR: {report.error_count}; they are counted in every table, and "
                "no verdict is given on a set that holds one:",
            ),
            ("ul", list(report.errors)),
        ]
    else:
        blocks = [("p", "No run ended in error.")]
    report.blocks[2:2] = blocks


def _children_cpu() -> float:
    """CPU seconds (user + system) of this process's finished children: the local pool's workers,
    once it is closed."""
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


__all__ = ["FULL", "QUICK", "Settings", "reproduce"]
