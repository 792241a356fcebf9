"""``navcli reproduce``: both papers' experiments under their conditions, and a report beside the
papers' numbers (``report.md``, its PNGs, and ``report.html``).

Sections (each resumes from what an earlier run of the same command left in its folder):

- ``pilots``: the pilot paper's Table 1 on ``paper-8x8`` with vision and with ground truth
  (:func:`table1`), its sensitivity to what the paper leaves unstated (:func:`sensitivity`), and the
  trap rooms' diverting targets beside the thesis' real-robot figures (:func:`traps`);
- ``learning``: the learning paper's Table 1 (:func:`policies`) and Figure 3 (:func:`figure3`).

Agreement is decided one way throughout (our design): a paper's number *agrees* when it lies in
navcli's 95 % interval of the same quantity, else it *does not agree*, and the report says which
side it lies on. ``--quick`` runs every section with few reruns (:data:`QUICK`) to check the
machinery in minutes; its intervals are wide and the report says so at the top.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable

from .. import __version__
from ..scenario import bundled

SCENARIOS = bundled.FOLDER
SECTIONS = ("pilots", "learning")
TRAP_ROOMS = ("river-bridges", "u-trap", "door-wall", "hidden-fence", "blocked-wall")

# The papers' numbers (pilot paper, Table 1; learning paper, Table 1 and section 6; the thesis' robot)
PAPER_TABLE1: dict[str, dict[str, tuple[float, float]]] = {
    "geometric": {"time_s": (297.3, 81.9), "path_cm": (1532, 429)},  # mean, standard deviation
    "potential-field": {"time_s": (243.4, 99.1), "path_cm": (1195, 198)}}
PAPER_GAINS = {"time_s": 18.1, "path_cm": 22.0}  # %: the potential field against the geometric pilot
PAPER_POLICIES: dict[str, dict[str, float]] = {"learned": {"successes": 84, "reward": -336, "actions": 49.95},
                  "hand-coded": {"successes": 24, "reward": -858, "actions": 153.33}}
THESIS_TRAPS = {"reached": 0.85, "diverting_1": 0.58, "diverting_2": 0.18}
PAPER_FIGURE3 = "the learned policy ahead of the hand-coded one from 99 trials on; 84 of 99 after 2,000"


@dataclass(frozen=True)
class Settings:
    """How much of each experiment is run (the full sizes are the papers')."""

    reruns: int = 45  # Table 1: seeds per pilot and perception
    sensitivity_seeds: int = 10
    sensitivity_speeds: tuple[float, ...] = (0.05, 0.1, 0.3)
    sensitivity_rooms: tuple[str, ...] = ("paper-8x8", "slanted-8x8")
    trap_seeds: int = 10
    trap_rooms: tuple[str, ...] = TRAP_ROOMS
    policy_runs: int = 5
    policy_starts: int = 99
    train_trials: int = 2000
    eval_every: int = 100
    eval_starts: int = 99
    quick: bool = False


FULL = Settings()
QUICK = Settings(reruns=3, sensitivity_seeds=3, sensitivity_speeds=(0.05, 0.3), sensitivity_rooms=("paper-8x8",),
                 trap_seeds=2, policy_runs=2, policy_starts=10, train_trials=20, eval_every=10, eval_starts=10,
                 quick=True)


class Report:
    """The report as blocks, written once as Markdown and once as HTML (no converter needed)."""

    def __init__(self) -> None:
        self.blocks: list[tuple[str, Any]] = []

    def heading(self, text: str, level: int = 2) -> None:
        self.blocks.append(("h", (level, text)))

    def text(self, text: str) -> None:
        self.blocks.append(("p", text))

    def table(self, header: list[str], rows: list[list[Any]]) -> None:
        self.blocks.append(("table", (header, [[str(c) for c in r] for r in rows])))

    def image(self, path: str, caption: str) -> None:
        self.blocks.append(("img", (path, caption)))

    def markdown(self) -> str:
        out = []
        for kind, b in self.blocks:
            if kind == "h":
                out.append(f"{'#' * b[0]} {b[1]}")
            elif kind == "p":
                out.append(b)
            elif kind == "table":
                header, rows = b
                out += ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
                out += ["| " + " | ".join(r) + " |" for r in rows]
            else:
                out.append(f"![{b[1]}]({b[0]})")
            out.append("")
        return "\n".join(out)

    def html(self) -> str:
        import html

        e = html.escape
        from ..analysis.files import MARK

        out = [f"<!doctype html>{MARK}<html><head><meta charset='utf-8'><title>navcli reproduce</title><style>"
               "body{font-family:sans-serif;max-width:70em;margin:2em auto}table{border-collapse:collapse}"
               "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}img{max-width:100%}</style></head><body>"]
        for kind, b in self.blocks:
            if kind == "h":
                out.append(f"<h{b[0]}>{e(b[1])}</h{b[0]}>")
            elif kind == "p":
                out.append(f"<p>{e(b)}</p>")
            elif kind == "table":
                header, rows = b
                out.append("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in header) + "</tr>"
                           + "".join("<tr>" + "".join(f"<td>{e(c)}</td>" for c in r) + "</tr>" for r in rows)
                           + "</table>")
            else:
                out.append(f"<figure><img src='{e(b[0])}' alt='{e(b[1])}'><figcaption>{e(b[1])}</figcaption></figure>")
        return "\n".join(out + ["</body></html>\n"])


def verdict(paper: float, lo: float, hi: float) -> str:
    """Does the paper's number lie in navcli's 95 % interval ``[lo, hi]``?"""
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return "no interval (too few runs)"
    if lo <= paper <= hi:
        return "agrees"
    return f"does not agree (the paper's is {'above' if paper > hi else 'below'})"


def t_mean(values: list[float]) -> tuple[float, float, float]:
    """Mean and its 95 % Student-t interval (NaNs for none; a point for one value)."""
    from ..training.comparison import t_interval

    import numpy as np

    return t_interval(np.asarray(values, dtype=float))


def _conditions(report: Report, out: Path, specs: list) -> None:
    """Every parameter of the section's configurations, with their run ids, in ``conditions.json``."""
    from ..outputs import write_text

    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "conditions.json", json.dumps({"navcli_version": __version__, "configurations": [
        {"run_id": s.run_id, **s.to_json()} for s in specs]}, indent=1) + "\n")
    report.text(f"Every parameter of these runs, with their configurations' run ids: {out / 'conditions.json'}.")


def _scenario(name: str):
    from ..scenario import load_scenario

    return load_scenario(SCENARIOS / f"{name}.yaml")


def _compare(names: tuple[str, ...], reruns: int, out: Path, ex, perception: str | None = None,
             overrides: dict | None = None):
    """Every pilot on each room with the same seeds (``navcli compare pilots``): the runs frame."""
    from ..analysis.tables import load_runs
    from ..config import RunSpec
    from .compare import plan, run_on

    specs = [RunSpec.build(_scenario(n), perception=perception, overrides=overrides or {}) for n in names]
    work = plan(specs, ["potential-field", "geometric"], reruns, out)
    run_on(work, ex)
    return load_runs(out, paths=[j.log for j in work]), specs


def table1(report: Report, s: Settings, out: Path, ex) -> None:
    """The pilot paper's Table 1, with vision and with ground truth."""
    from ..analysis.tables import improvements, pilot_table

    report.heading("Pilot paper, Table 1: the potential-field pilot against the geometric one")
    report.text(f"paper-8x8 (our room in the paper's spirit; its coordinates are not given), {s.reruns} reruns per "
                "pilot and perception, the same seeds for both pilots; the paper's pace (5 cm/s, the scenario's "
                "robot.max_speed). Means over the reached runs with 95 % t-intervals; gains paired over the seeds "
                "both reached, with bootstrap 95 % intervals. Logs: " + str(out))
    rows: list[list[Any]] = []
    bases: list = []
    for perception in ("vision", "oracle"):
        runs, specs = _compare(("paper-8x8",), s.reruns, out / perception, ex, perception)
        _write_runs(runs, out / perception / "runs.csv")
        bases += specs
        table = pilot_table(runs).set_index("pilot")
        imps = improvements(runs, "geometric").set_index("metric")
        for pilot in ("geometric", "potential-field"):
            ok = runs[(runs["pilot"] == pilot) & (runs["outcome"] == "reached")]
            for metric in ("time_s", "path_cm"):
                m, lo, hi = t_mean(list(ok[metric]))
                paper, sd = PAPER_TABLE1[pilot][metric]
                rows.append([perception, pilot, metric, f"{paper:g} ± {sd:g}", f"{m:.1f} [{lo:.1f}, {hi:.1f}]",
                             f"{int(table.loc[pilot, 'reached'])}/{int(table.loc[pilot, 'runs'])}",
                             verdict(paper, lo, hi), "yes" if abs(m - paper) <= sd else "no"])
        for metric in ("time_s", "path_cm"):
            g = imps.loc[metric]
            rows.append([perception, "PF gain %", metric, f"+{PAPER_GAINS[metric]:g}",
                         f"{g['improvement_pct']:+.1f} [{g['ci95_low']:+.1f}, {g['ci95_high']:+.1f}] ({int(g['pairs'])} pairs)",
                         "", verdict(PAPER_GAINS[metric], g["ci95_low"], g["ci95_high"]), ""])
    report.table(["perception", "pilot", "quantity", "the paper", "navcli [95 % CI]", "reached", "agreement",
                  "navcli's mean within the paper's ± 1 SD"], rows)
    report.text("Run ids and every run's numbers: " + ", ".join(str(out / p / "runs.csv") for p in ("vision", "oracle")))
    _conditions(report, out, bases)


def _write_runs(runs, path: Path) -> None:
    from ..analysis.files import write_csv

    write_csv(path, runs.drop(columns=["xy"], errors="ignore"))


def sensitivity(report: Report, s: Settings, out: Path, ex) -> None:
    """Table 1's dependence on the unstated: speed and how a turn is executed, both perceptions."""
    from ..analysis.tables import improvements, load_sweep
    from .sweep import load_plan, plan_runs, run_sweep

    out.mkdir(parents=True, exist_ok=True)
    plan_file = out / "plan.yaml"
    rooms = ", ".join(json.dumps(str(SCENARIOS / f"{r}.yaml")) for r in s.sensitivity_rooms)  # quoted: any path
    plan_file.write_text(f"# navcli reproduce: the sensitivity's plan\nversion: 1\nscenarios: [{rooms}]\n"
                         f"seeds: {s.sensitivity_seeds}\n"
                         "pilots: [potential-field, geometric]\nperception: [vision, oracle]\ngrid:\n"
                         f"  robot.max_speed: [{', '.join(map(str, s.sensitivity_speeds))}]\n"
                         "  pilot.drive_while_turning: [1, 0]\n")
    table = out / "results.parquet"
    planned = plan_runs(load_plan(plan_file), None)
    run_sweep(planned, table, ex)
    runs = load_sweep(table)
    runs = runs[runs["run_id"].isin({r.spec.run_id for r in planned})]  # the table keeps other plans' rows
    imps = improvements(runs, "geometric")
    report.heading("Pilot paper, Table 1's sensitivity (the paper states one condition)")
    report.text(f"{s.sensitivity_seeds} seed(s) a point; the plan: {plan_file}; every run: {table}. The paper has "
                "no numbers here: the column says how the potential field's gain moves with what it leaves unstated.")
    rows = [[r["condition"], r["metric"], f"{r['improvement_pct']:+.1f} [{r['ci95_low']:+.1f}, {r['ci95_high']:+.1f}]",
             int(r["pairs"]), verdict(PAPER_GAINS[r["metric"]], r["ci95_low"], r["ci95_high"])]
            for _, r in imps.iterrows()]
    report.table(["condition", "metric", "PF gain % [95 % CI]", "pairs", "the paper's gain"], rows)


def traps(report: Report, s: Settings, out: Path, ex) -> None:
    """The trap rooms: how often each pilot gets out, with how many diverting targets."""
    from ..analysis.tables import wilson_interval

    runs, specs = _compare(s.trap_rooms, s.trap_seeds, out, ex)
    _write_runs(runs, out / "runs.csv")
    report.heading("Trap rooms: diverting targets (the thesis' real robot beside them)")
    report.text(f"{s.trap_seeds} seed(s) per room and pilot; every run: {out / 'runs.csv'}. The thesis' figures "
                "(its real robot, its rooms): 85 % reached; of runs past long obstacles 58 % needed one diverting "
                "target and 18 % two. Rates with Wilson 95 % intervals.")
    rows = []
    for pilot in ("potential-field", "geometric"):
        g = runs[(runs["pilot"] == pilot) & runs["outcome"].isin(("reached", "blocked", "timeout"))]  # not interrupted
        n = len(g)
        for key, k, paper in (("reached", int((g["outcome"] == "reached").sum()), THESIS_TRAPS["reached"]),
                              ("needed 1 diverting target", int((g["diverting_targets"] == 1).sum()),
                               THESIS_TRAPS["diverting_1"]),
                              ("needed 2", int((g["diverting_targets"] == 2).sum()), THESIS_TRAPS["diverting_2"])):
            lo, hi = wilson_interval(k, n)
            rows.append([pilot, key, f"{paper:.0%}", f"{k}/{n} [{lo:.0%}, {hi:.0%}]", verdict(paper, lo, hi)])
        m, lo, hi = t_mean(list(g["collisions"]))
        rows.append([pilot, "contacts per run", "-", f"{m:.1f} [{lo:.1f}, {hi:.1f}]", ""])
    report.table(["pilot", "quantity", "the thesis", "navcli", "agreement"], rows)
    _conditions(report, out, specs)


def policies(report: Report, s: Settings, out: Path, ex) -> None:
    """The learning paper's Table 1: the bundled model, the hand-coded policy, the bidding agents."""
    from ..config import RunSpec
    from ..training.comparison import parse_policy, plan, policy_table, run_all, trials_frame

    spec = RunSpec.build(_scenario("landmarks-12"))
    chosen = [parse_policy(p) for p in ("learned", "hand-coded", "agents")]
    (out / "runs").mkdir(parents=True, exist_ok=True)
    results = run_all(plan(spec, chosen, s.policy_runs, s.policy_starts, out), ex)
    trials = trials_frame([r for r in results if r.trials is not None])
    _write_runs(trials, out / "trials.csv")
    table = policy_table(trials).set_index("policy")
    report.heading("Learning paper, Table 1: policies on the paper's task")
    report.text(f"landmarks-12, {s.policy_runs} run(s) of {s.policy_starts} fixed starts (the paper: 99); learned = "
                "the model bundled with navcli (2,000 trials of Prioritized Sweeping). Means over the runs with 95 % "
                f"t-intervals; successes scaled to 99 starts. Every trial: {out / 'trials.csv'}")
    rows = []
    for policy in ("learned", "hand-coded", "agents"):
        if policy not in table.index:  # every run of it failed: said, not hidden
            rows.append([policy, "-", "-", "no trial finished (see the runs' errors)", ""])
            continue
        for metric, paper in (PAPER_POLICIES.get(policy) or {"successes": math.nan}).items():
            scale = 99 / s.policy_starts if metric == "successes" else 1.0
            m, lo, hi = (table.loc[policy, k] * scale for k in (metric, f"{metric}_lo", f"{metric}_hi"))
            rows.append([policy, metric, "-" if math.isnan(paper) else f"{paper:g}", f"{m:.1f} [{lo:.1f}, {hi:.1f}]",
                         "" if math.isnan(paper) else verdict(paper, lo, hi)])
    report.table(["policy", "quantity", "the paper", "navcli [95 % CI]", "agreement"], rows)
    _conditions(report, out, [spec])


def figure3(report: Report, s: Settings, out: Path, jobs: int) -> None:
    """The learning paper's Figure 3: a training's learning curve."""
    from ..config import RunSpec
    from ..learning import model_file
    from ..learning.model_file import curve_paths
    from ..training.trainer import train

    model = out / f"model-{s.train_trials}-every{s.eval_every}-on{s.eval_starts}.npz"  # one per size: resumed only by it
    spec = RunSpec.build(_scenario("landmarks-12"))
    have = int(model_file.load(model)[1].get("trials", 0)) if model.exists() else 0
    if have < s.train_trials:
        res = train(spec, trials=s.train_trials, eval_every=s.eval_every, eval_starts=s.eval_starts, out=model,
                    resume=model if have else None, workers=max(1, jobs))
        curve, hand = [(p.trials, p.successes) for p in res.curve], res.hand_coded
    else:
        meta = model_file.load(model)[1]
        curve, hand = [(p["trials"], p["successes"]) for p in meta["curve"]], meta["hand_coded"]
    ahead = next((n for n, k in curve if hand is not None and k > hand), None)
    report.heading("Learning paper, Figure 3: the learning curve")
    report.text(f"{s.train_trials} training trials on landmarks-12, the greedy policy evaluated every {s.eval_every} "
                f"on {s.eval_starts} fixed starts. The paper: {PAPER_FIGURE3}. navcli: {curve[-1][1]} of "
                f"{s.eval_starts} after {curve[-1][0]}, the hand-coded policy {hand}; the learned policy "
                + (f"first ahead of it at {ahead} trials." if ahead is not None else "never ahead of it."))
    _conditions(report, out, [spec])
    png = curve_paths(model)[1]
    report.image(str(png.relative_to(out.parent)), "successes of the test starts against training trials")
    report.text(f"The model, its curve and every training trial: {model}, {curve_paths(model)[0]}.")


def reproduce(which: str, out: Path, *, settings: Settings = FULL, jobs: int = 2, scheduler: str | None = None,
              echo: Callable[[str], None] = print) -> dict[str, Path]:
    """Run the sections of ``which`` (``pilots``, ``learning`` or ``all``) into ``out`` and write
    ``report.md`` and ``report.html`` there; returns the files written."""
    from ..analysis.files import write_markdown
    from ..outputs import write_text
    from .executor import executor

    report = Report()
    report.heading("navcli reproduce: both papers' experiments beside their numbers", 1)
    if settings.quick:
        report.text("QUICK RUN (--quick): few reruns, to check the machinery; the intervals are wide and the "
                    "verdicts are not the reproduction's. Run without --quick for the papers' sizes.")
    report.text(f"navcli {__version__}; settings: {json.dumps(asdict(settings))}. A paper's number agrees when it "
                "lies in navcli's 95 % interval of the same quantity.")
    durations = []
    t_all = time.perf_counter()
    with executor(jobs, scheduler) as ex:
        steps: list[tuple[str, Callable[[], None]]] = []
        if which in ("pilots", "all"):
            steps += [("Table 1 (pilots)", lambda: table1(report, settings, out / "table1", ex)),
                      ("sensitivity", lambda: sensitivity(report, settings, out / "sensitivity", ex)),
                      ("trap rooms", lambda: traps(report, settings, out / "traps", ex))]
        if which in ("learning", "all"):
            steps += [("Table 1 (policies)", lambda: policies(report, settings, out / "policies", ex)),
                      ("Figure 3", lambda: figure3(report, settings, out / "figure3", jobs))]
        for name, step in steps:
            t0 = time.perf_counter()
            echo(f"reproduce: {name} ...")
            step()
            durations.append([name, f"{time.perf_counter() - t0:.0f} s"])
    report.heading("How long it took")
    report.table(["section", "wall time"], durations + [["all", f"{time.perf_counter() - t_all:.0f} s"]])
    files = {"markdown": out / "report.md", "html": out / "report.html"}
    write_markdown(files["markdown"], report.markdown())
    write_text(files["html"], report.html())
    return files


__all__ = ["FULL", "QUICK", "Settings", "reproduce"]
