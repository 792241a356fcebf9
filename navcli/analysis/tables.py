"""The pilot paper's Table 1 from a folder of logs: per pilot, success, time and path length,
and each pilot's improvement over the baseline with a confidence interval and a paired test.

Everything here reads logs only (through :func:`analysis.read_log`). Every log's summary is
checked against its poses first: a log whose summary disagrees is refused, by name.

Statistics, chosen to need nothing beyond numpy:
- the improvement of a pilot over the baseline is ``100 * (mean_baseline - mean_pilot) /
  mean_baseline`` (positive: the pilot takes less time / a shorter path), over the seeds both
  pilots completed (the comparison is paired: the same seeds for every pilot);
- its 95 % confidence interval is a paired bootstrap (seeds resampled with replacement, 10 000
  resamples, percentile interval); with fewer than :data:`~navcli.analysis.stats.MIN_SAMPLE`
  pairs the notes say it is too uncertain to trust, in the words of every comparison;
- its p-value is a paired sign-flip permutation test of the mean difference (two-sided, 10 000
  random sign assignments, with the observed one counted), exact in the limit and free of the
  normality a t-test assumes.
The random draws are seeded, so the same logs always give the same table.

Runs are never mixed up: a row of the table is one *condition*, every run of one
configuration but the pilot and the seed (scenario text by sha256, perception, time limit, every
parameter); the same run (run id) twice is refused; interrupted runs are kept out of the success
rates and counted apart; an unreadable log is skipped by name when the caller asks for it.
Whatever the table cannot say (too few pairs for the test, an unknown baseline, no reached run)
is said in its notes.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from ..log.format import POSE_TOPIC
from .columns import IMPROVEMENTS, PILOT_TABLE
from .files import write_csv, write_markdown
from .logs import LogError, config_columns, path_length, read_log, require
from .stats import MIN_SAMPLE, RESAMPLES, small_sample, wilson_interval

METRICS = {"time_s": "time (s)", "path_cm": "path length (cm)"}
EXACT_UP_TO = 12  # pairs: up to 2^12 sign assignments the permutation test is enumerated, exact
PATH_TOLERANCE = 0.01  # the summary's path length must match the poses' within 1 %


REPORT_FILES = ("runs.csv", "table.csv", "improvements.csv", "table.md", "trajectories-*.png", "boxplots-*.png")
"""What ``compare pilots`` and ``report`` write into their folder (checked before the work: a
user's file of one of these names is never replaced)."""


def load_runs(
    logdir: str | Path | None = None,
    *,
    paths: list[str | Path] | None = None,
    skipped: list[tuple[str, str]] | None = None,
) -> pd.DataFrame:
    """The runs of a folder of logs, or of the logs given, each checked against its poses.

    Args:
        logdir: a folder: every ``.mcap`` under it, recursively.
        paths: the logs to read, in place of ``logdir``.
        skipped: if a list, a log that cannot be counted is appended to it as (path, why) and
            left out, rather than refused.

    Returns:
        One row per log: the columns of :data:`navcli.analysis.columns.RUN` and
        :data:`~navcli.analysis.columns.RUN_FROM_LOGS`, every parameter as a ``params.<group>.<name>``
        column (so runs can be grouped by them), and the poses' x, y in ``xy``, for plots.

    Raises:
        LogError: a log that cannot be read, has no summary, or whose summary disagrees with its
            poses (unless ``skipped`` is given); the same run (run id) found twice, naming both
            files.
    """
    rows = []
    seen: dict[str, str] = {}
    files = [Path(p) for p in paths] if paths is not None else sorted(Path(logdir or ".").rglob("*.mcap"))
    for path in files:
        try:
            row = _run_row(path)
        except LogError as e:
            if skipped is None:
                raise
            skipped.append((str(path), str(e).removeprefix(f"{path}: ")))
            continue
        rid = row["run_id"]
        if rid and rid in seen:
            raise LogError(
                f"{path} and {seen[rid]} are the same run (run id {rid[:8]}); a run counts once: "
                "remove one, or report on the folders separately"
            )
        if rid:
            seen[rid] = str(path)
        rows.append(row)
    if not rows:
        where = logdir if paths is None else "the runs given"
        raise LogError(f"{where}: no readable .mcap logs found")
    return pd.DataFrame(rows)


SWEEP_COLUMNS = {
    "scenario",
    "pilot",
    "perception",
    "seed",
    "point",
    "outcome",
    "time_s",
    "path_length_m",
    "collisions",
    "camera_looks",
    "ticks",
    "run_id",
}
"""What a ``navcli sweep`` results table holds besides its swept parameters' columns."""


def load_sweep(path: str | Path) -> pd.DataFrame:
    """The runs of a ``navcli sweep`` results table (Parquet, or its CSV copy) in the shape of
    :func:`load_runs`, so the same tables are built from it: a swept parameter's column ``pilot.K``
    becomes ``params.pilot.K`` (each point its own condition), and runs that raised are counted as
    ``error``. The table holds no poses, so nothing here is checked against them (a sweep with
    logs can be reported from its logs instead), and it makes no trajectory plots."""
    path = Path(path)
    try:
        df = pd.read_csv(path) if path.suffix == ".csv" else pd.read_parquet(path)
    except Exception as e:  # pyarrow's and pandas' many errors for a file that is no table
        raise LogError(f"{path}: not a sweep results table ({type(e).__name__}: {e})") from None
    missing = SWEEP_COLUMNS - set(df.columns)
    if missing:
        raise LogError(f"{path}: not a sweep results table (no column {', '.join(sorted(missing))})")
    if df.empty:
        raise LogError(f"{path}: the table holds no runs")
    swept = [c for c in df.columns if "." in c]  # parameter names are dotted (robot.max_speed)
    runs = df.rename(columns={c: f"params.{c}" for c in swept})
    for column, absent in (("log", ""), ("diverting_targets", 0), ("time_limit_s", math.nan)):
        if column not in runs:  # tables written before navcli kept these
            runs[column] = absent
    runs["reached"] = runs["outcome"] == "reached"
    runs["path_cm"] = 100.0 * runs["path_length_m"]
    if "error" in runs:  # a run that raised has no summary: its error is why it ended
        runs["reason"] = runs["error"].where(runs["outcome"] == "error", runs.get("reason", ""))
    keys = ["scenario", "scenario_sha256", "pilot", "perception", "time_limit_s", "seed"] + [
        f"params.{c}" for c in swept
    ]
    twice = runs[runs.duplicated([k for k in keys if k in runs], keep=False)]
    if len(twice):
        r = twice.iloc[0]
        raise LogError(
            f"{path}: {len(twice)} rows are the same condition, pilot and seed twice ({r['scenario']}, "
            f"{r['pilot']}, seed {r['seed']}: run ids {', '.join(str(i)[:8] for i in twice['run_id'][:2])}): "
            "the table holds runs of a scenario or plan since changed; report on a sweep with a new --out"
        )
    return runs


def _run_row(path: Path) -> dict:
    """One run's row of :func:`load_runs`; :class:`LogError` for a log it cannot count."""
    log = require(read_log(path, topics=[POSE_TOPIC]), POSE_TOPIC)
    s = log.summary
    poses = log[POSE_TOPIC]
    walked = path_length(poses)
    last = float(poses["time_s"].iloc[-1])
    if abs(walked - s["path_length_m"]) > PATH_TOLERANCE * max(walked, 0.01):
        raise LogError(
            f"{path}: summary path length {s['path_length_m']:.3f} m disagrees with its poses ({walked:.3f} m)"
        )
    if abs(last - s["time_s"]) > 1e-6:
        raise LogError(f"{path}: summary time {s['time_s']} s disagrees with its last pose ({last} s)")
    config = log.config
    run_id = s.get("run_id") or log.metadata.get("run", {}).get("run_id")
    return (
        {"log": str(path)}
        | summary_row(s, config, run_id)
        | {"poses_path_m": walked, "xy": poses[["x", "y"]].to_numpy()}
    )


def summary_row(summary: Mapping[str, Any], config: Mapping[str, Any], run_id: str | None) -> dict[str, Any]:
    """A run's row from its summary and its configuration (:meth:`navcli.config.RunSpec.to_json`):
    what :func:`load_runs` reads from a log, and what ``navcli.compare`` without logs makes in its
    workers; ``reason`` says why a run ended (an error's message)."""
    s = summary
    return {
        "run_id": run_id,
        "scenario": s["scenario"],
        "pilot": s["pilot"],
        "seed": s["seed"],
        "scenario_sha256": config.get("scenario", {}).get("sha256"),
        "perception": config.get("perception"),
        "time_limit_s": config.get("time_limit_s"),
        "outcome": s["outcome"],
        "reason": s.get("reason", ""),
        "reached": s["outcome"] == "reached",
        "time_s": s["time_s"],
        "path_m": s["path_length_m"],
        "path_cm": 100.0 * s["path_length_m"],
        "collisions": s["collisions"],
        "camera_looks": s["camera_looks"],
        "ticks": s["ticks"],
        "diverting_targets": s.get("diverting_targets", 0),
        "navigation": s.get("navigation", "agents"),
    } | config_columns(dict(config))


CONFIG = ["scenario", "scenario_sha256", "perception", "time_limit_s"]
"""With every ``params.*`` column: what makes a condition (a run's configuration but pilot and seed)."""
MIN_PAIRS = 6
"""Fewer pairs than this and the sign-flip test cannot reach p < 0.05 (its smallest two-sided
p-value is 2 / 2**pairs = 0.0625 with 5 pairs); the table says so."""


def _conditions(runs: pd.DataFrame) -> pd.DataFrame:
    """``runs`` with a ``condition`` column: the scenario and perception, and whatever else tells
    this condition from another of the same scenario (``time limit 5 s``, ``pilot.K=30``,
    ``scenario sha256 1a2b3c4d`` for an edited file)."""
    runs = runs.copy()
    runs["perception"] = runs["perception"].fillna("?") if "perception" in runs else "?"
    keys = CONFIG + sorted(c for c in runs if c.startswith("params."))
    unknown = lambda v: "?" if v is None or (isinstance(v, float) and math.isnan(v)) else v  # noqa: E731
    k = pd.DataFrame({c: runs[c].map(unknown) if c in runs else "?" for c in keys}, index=runs.index)
    labels = {}
    for scenario, g in k.groupby("scenario", sort=True):
        varying = [c for c in keys[1:] if g[c].astype(str).nunique() > 1]  # all but the scenario's name
        for key, _ in g.groupby(keys, sort=True):
            d = dict(zip(keys, key))
            extra = [
                f"scenario sha256 {str(d['scenario_sha256'])[:8]}"
                if c == "scenario_sha256"
                else f"time limit {d[c]:g} s"
                if c == "time_limit_s" and d[c] != "?"
                else f"{c.removeprefix('params.')}={d[c]:g}"
                if isinstance(d[c], float)
                else f"{c.removeprefix('params.')}={d[c]}"
                for c in varying
                if c != "perception"
            ]
            labels[key] = f"{scenario} ({d['perception']} perception{''.join(', ' + e for e in extra)})"
    runs["condition"] = [labels[tuple(r)] for r in k[keys].itertuples(index=False)]
    return runs


IDENTITY = ("outcome", "time_s", "path_cm", "collisions", "camera_looks", "ticks", "diverting_targets")
"""What makes two runs of one pilot and condition the same result: their summaries' outcome and
numbers. Runs alike in all of them are identical reruns (ground-truth perception has no noise, so
every seed gives the same run) and count as one sample in a verdict (:func:`distinct_runs`)."""


def distinct_runs(runs: pd.DataFrame) -> pd.DataFrame:
    """``runs`` with identical reruns (the same pilot, condition and :data:`IDENTITY`) kept once:
    the first of each, in order."""
    keys = [c for c in ("scenario", "scenario_sha256", "perception", "pilot", *IDENTITY) if c in runs]
    keys += sorted(c for c in runs if c.startswith("params."))
    return runs[~runs[keys].astype(str).duplicated()]


def counted(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs a success rate counts: all but the interrupted (stopped by a person or a crash, not
    by the pilot). Errors are navcli's failures in a run and stay counted as failed."""
    return runs[runs["outcome"] != "interrupted"]


def pilot_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Per scenario, perception and pilot: runs, successes with the success rate and its Wilson
    95 % interval; the mean and standard deviation over the *reached* runs of time, path length
    (cm, as the paper prints it), collisions and camera looks; and, so that failures are not
    hidden by leaving them out, the mean time with every failed run counted at its time limit
    (``time_fail_at_limit_mean``).

    Args:
        runs: one row per run (:func:`load_runs`, ``navcli.compare``).

    Returns:
        One row per condition and pilot, the columns of :data:`navcli.analysis.columns.PILOT_TABLE`.
    """
    out = []
    runs = _conditions(runs)
    for (condition, pilot), g_all in runs.groupby(["condition", "pilot"], sort=True):
        g = counted(g_all)
        ok = g[g["reached"]]
        n, k = len(g), int(g["reached"].sum())
        lo, hi = wilson_interval(k, n)
        row = {
            "condition": condition,
            "scenario": g_all["scenario"].iloc[0],
            "perception": g_all["perception"].iloc[0],
            "pilot": pilot,
            "runs": n,
            "reached": k,
            "failed": n - k,
            "interrupted": len(g_all) - n,
            "success_rate": k / n if n else math.nan,
            "success_ci_low": lo,
            "success_ci_high": hi,
        }
        for col in ("time_s", "path_cm", "collisions", "camera_looks"):
            row[f"{col}_mean"] = float(ok[col].mean()) if len(ok) else math.nan
            row[f"{col}_std"] = float(ok[col].std(ddof=1)) if len(ok) > 1 else math.nan
        # a failed run counts at its time limit; unknown limits (an old sweep table) leave this unknown
        limit = g["time_limit_s"] if "time_limit_s" in g else pd.Series(math.nan, index=g.index)
        at_limit = g["time_s"].where(g["reached"], limit)
        row["time_fail_at_limit_mean"] = float(at_limit.mean()) if n and at_limit.notna().all() else math.nan
        row["collisions_all_mean"] = float(g["collisions"].mean()) if n else math.nan
        for outcome in ("reached", "blocked", "timeout", "error"):  # how the counted runs ended
            row[f"outcome_{outcome}"] = int((g["outcome"] == outcome).sum())
        row["diverting_targets_mean"] = float(g["diverting_targets"].mean()) if n else math.nan
        for k in (0, 1, 2):  # the thesis' real-robot figures: runs that needed none, one, two diverting targets
            row[f"diverting_{k}"] = int((g["diverting_targets"] == k).sum())
        row["diverting_3_or_more"] = int((g["diverting_targets"] >= 3).sum())
        out.append(row)
    return pd.DataFrame(out, columns=list(PILOT_TABLE))


def improvements(runs: pd.DataFrame, baseline: str, once: bool = False) -> pd.DataFrame:
    """Per condition, pilot (other than ``baseline``) and metric: the paired improvement over the
    baseline in %, its bootstrap 95 % CI, the permutation p-value, and the number of pairs.
    Statistics as the module docstring says.

    Args:
        runs: one row per run (:func:`load_runs`, ``navcli.compare``).
        baseline: the pilot the others are compared with.
        once: identical pairs (both runs alike in :data:`IDENTITY` at two seeds) count as one
            pair, as a verdict counts them.

    Returns:
        One row per condition, pilot and metric (``time_s``, ``path_cm``), the columns of
        :data:`navcli.analysis.columns.IMPROVEMENTS`.
    """
    out = []
    for condition, g in _conditions(runs).groupby("condition", sort=True):
        base = g[(g["pilot"] == baseline) & g["reached"]].set_index("seed")
        for pilot in sorted(set(g["pilot"]) - {baseline}):
            other = g[(g["pilot"] == pilot) & g["reached"]].set_index("seed")
            seeds = base.index.intersection(other.index).sort_values()  # sorted: the bootstrap's draws follow it
            if once:
                cols = list(IDENTITY)
                both = pd.concat([base.loc[seeds, cols].add_prefix("base."), other.loc[seeds, cols]], axis=1)
                seeds = seeds[~both.astype(str).duplicated().to_numpy()]
            for metric in METRICS:
                b = base.loc[seeds, metric].to_numpy(float)
                p = other.loc[seeds, metric].to_numpy(float)
                imp, lo, hi, pval = paired_improvement(b, p)
                out.append(
                    {
                        "condition": condition,
                        "pilot": pilot,
                        "baseline": baseline,
                        "metric": metric,
                        "pairs": len(seeds),
                        "improvement_pct": imp,
                        "ci95_low": lo,
                        "ci95_high": hi,
                        "p_value": pval,
                    }
                )
    return pd.DataFrame(out, columns=list(IMPROVEMENTS))


def notes(
    runs: pd.DataFrame, table: pd.DataFrame, imps: pd.DataFrame, baseline: str, skipped: Sequence[tuple[str, str]] = ()
) -> list[str]:
    """What the table cannot say, in words: skipped logs, interrupted runs left out, an unknown
    baseline, a single pilot, too few pairs for the test, no reached run."""
    out = [f"skipped {path}: {why}" for path, why in skipped]
    out += error_notes(runs)
    pilots = sorted(set(runs["pilot"]))
    for r in table.itertuples():
        if r.interrupted:
            out.append(f"{r.condition}, {r.pilot}: {r.interrupted} interrupted run(s) left out of the success rate")
        if r.runs and not r.reached:
            out.append(f"{r.condition}, {r.pilot}: no run reached the target, so no time or path averages")
    if baseline not in pilots:
        out.append(
            f"baseline {baseline!r} is not among the pilots of these runs ({', '.join(pilots)}): "
            "no improvements table (--baseline names one of them)"
        )
    elif len(pilots) == 1:
        out.append(f"only one pilot ({pilots[0]}): nothing to compare it with")
    for (condition, pilot), g in imps.groupby(["condition", "pilot"], sort=True) if len(imps) else ():
        pairs = int(g["pairs"].iloc[0])
        if pairs < 2:
            out.append(
                f"{condition}, {pilot} vs {baseline}: {pairs} pair(s) where both reached the target; "
                "at least 2 are needed for an improvement with an interval"
            )
        elif pairs < MIN_SAMPLE:
            note = f"{small_sample(f'{condition}, {pilot} vs {baseline}', pairs, 'pairs')}"
            if pairs < MIN_PAIRS:
                note += f", and the paired test cannot reach p < 0.05 (its least p is 2/2^{pairs} = {2 / 2**pairs:.3g})"
            out.append(note)
    return out


def why(reasons: Sequence[str]) -> str:
    """The reasons runs ended, each once with how many runs it ended, the commonest first.

    >>> why(["TypeError: x", "ValueError: y", "TypeError: x"])
    'TypeError: x (2 runs); ValueError: y (1 run)'
    """
    counts = pd.Series([r or "no reason given" for r in reasons], dtype=object).value_counts(sort=False)
    ranked = sorted(counts.items(), key=lambda kv: (-kv[1], str(kv[0])))
    return "; ".join(f"{r} ({n} run{'s' if n != 1 else ''})" for r, n in ranked)


def error_notes(runs: pd.DataFrame) -> list[str]:
    """One note per condition and pilot with runs that ended in ``error`` (navcli's or a plugin's
    failure, not the pilot's way of failing): how many, of how many runs, and why."""
    if not (runs["outcome"] == "error").any():
        return []
    out = []
    for (condition, pilot), g in _conditions(runs).groupby(["condition", "pilot"], sort=True):
        bad = g[g["outcome"] == "error"]
        if len(bad):
            reasons = bad["reason"] if "reason" in bad else pd.Series("", index=bad.index)
            out.append(
                f"{condition}, {pilot}: {len(bad)} of {len(g)} runs ended in error (counted as not reached; "
                f"seeds {', '.join(str(x) for x in bad['seed'])}): {why([str(r) for r in reasons.fillna('')])}"
            )
    return out


def errored(runs: pd.DataFrame) -> int:
    """How many of ``runs`` ended in ``error``."""
    return int((runs["outcome"] == "error").sum())


def errored_verdict(n: int) -> str:
    """The verdict on a set holding ``n`` (at least one) runs that ended in error.

    >>> errored_verdict(1), errored_verdict(2)
    ('no verdict: 1 run ended in error', 'no verdict: 2 runs ended in error')
    """
    return f"no verdict: {n} run{'s' if n != 1 else ''} ended in error"


def paired_improvement(base: np.ndarray, pilot: np.ndarray, seed: int = 0) -> tuple[float, float, float, float]:
    """(improvement %, CI low, CI high, p-value) for paired samples; NaNs when fewer than 2 pairs."""
    n = len(base)
    if n < 2 or base.mean() == 0:
        return (math.nan,) * 4
    imp = 100.0 * (base.mean() - pilot.mean()) / base.mean()
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, n, size=(RESAMPLES, n))
    bm, pm = base[idx].mean(axis=1), pilot[idx].mean(axis=1)
    boot = 100.0 * (bm - pm) / bm
    lo, hi = np.percentile(boot, [2.5, 97.5])
    d = base - pilot
    if n <= EXACT_UP_TO:  # every one of the 2^n sign assignments: the exact p-value
        signs = 1.0 - 2.0 * ((np.arange(2**n)[:, None] >> np.arange(n)) & 1)
        null = np.abs((signs * d).mean(axis=1))
        pval = np.count_nonzero(null >= abs(d.mean()) - 1e-12) / 2**n
    else:
        signs = rng.choice([-1.0, 1.0], size=(RESAMPLES, n))
        null = np.abs((signs * d).mean(axis=1))
        pval = (1 + np.count_nonzero(null >= abs(d.mean()) - 1e-12)) / (RESAMPLES + 1)
    return float(imp), float(lo), float(hi), float(pval)


def _number(x: float | None, digits: int = 2) -> str:
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}f}"


def _fmt(mean: float, std: float, digits: int = 2) -> tuple[str, str]:
    return _number(mean, digits), _number(std, digits)


def overview(table: pd.DataFrame, imps: pd.DataFrame) -> list[str]:
    """One Markdown row per condition and pilot against the baseline: both pilots' successes and
    mean times and paths (reached runs), and the paired improvements in time and path with their
    95 % intervals and p-values: a sweep's sensitivity at a glance."""
    if not len(imps):
        return []
    lines = [
        "### Every condition: each pilot against the baseline",
        "",
        "| condition | pilot vs baseline | reached | time (s) | path (cm) | pairs | time gain, 95 % CI, p "
        "| path gain, 95 % CI, p |",
        "| --- | --- | --- | --- | --- | ---: | --- | --- |",
    ]
    rows = table.set_index(["condition", "pilot"])

    def gain(r) -> str:
        return (
            "-"
            if math.isnan(r.improvement_pct)
            else f"{r.improvement_pct:+.1f} % [{r.ci95_low:+.1f}, {r.ci95_high:+.1f}], {r.p_value:.4f}"
        )

    for (condition, pilot), g in imps.groupby(["condition", "pilot"], sort=True):
        base = g["baseline"].iloc[0]
        if (condition, pilot) not in rows.index or (condition, base) not in rows.index:
            continue  # a condition without one of the two pilots: nothing to set side by side
        a, b = rows.loc[(condition, pilot)], rows.loc[(condition, base)]
        by = g.set_index("metric")
        t = " / ".join(_number(x, 1) for x in (a.time_s_mean, b.time_s_mean))
        pth = " / ".join(_number(x, 0) for x in (a.path_cm_mean, b.path_cm_mean))
        lines.append(
            f"| {condition} | {pilot} vs {base} | {a.reached}/{a.runs} vs {b.reached}/{b.runs} | {t} | "
            f"{pth} | {int(g['pairs'].iloc[0])} | {gain(by.loc['time_s'])} | {gain(by.loc['path_cm'])} |"
        )
    return lines + [""]


def markdown(table: pd.DataFrame, imps: pd.DataFrame, remarks: Sequence[str] = ()) -> str:
    """The comparison as Markdown: Table 1's layout (times and paths over the reached runs), the
    success rate with its interval and the time with failures counted at the limit beside it;
    then the improvements."""
    lines = overview(table, imps) if table["condition"].nunique() > 1 else []
    for condition, g in table.groupby("condition", sort=True):
        lines += [
            f"### {condition}",
            "",
            "| pilot | reached | success (95 % CI) | time avg (s) | time std | path avg (cm) | path std "
            "| time, failures at the limit (s) | collisions avg (all runs) | camera looks avg |",
            "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
        ]
        for r in g.itertuples():
            t, ts = _fmt(r.time_s_mean, r.time_s_std)
            p, ps = _fmt(r.path_cm_mean, r.path_cm_std)
            tl, _ = _fmt(r.time_fail_at_limit_mean, 0.0)
            c, _ = _fmt(r.collisions_all_mean, 0.0)
            k, _ = _fmt(r.camera_looks_mean, 0.0, 1)
            rate = (
                "-"
                if not r.runs
                else f"{100 * r.success_rate:.0f} % [{100 * r.success_ci_low:.0f}, {100 * r.success_ci_high:.0f}]"
            )
            errors = f" ({r.outcome_error} errored)" if r.outcome_error else ""
            lines.append(
                f"| {r.pilot} | {r.reached}/{r.runs}{errors} | {rate} | {t} | {ts} | {p} | {ps} | {tl} | {c} | {k} |"
            )
        lines += [
            "",
            "| pilot | reached | blocked | timeout | error | diverting targets avg | runs with 0 / 1 / 2 / 3+ |",
            "| --- | ---: | ---: | ---: | ---: | ---: | --- |",
        ]
        for r in g.itertuples():
            d, _ = _fmt(r.diverting_targets_mean, 0.0)
            lines.append(
                f"| {r.pilot} | {r.outcome_reached} | {r.outcome_blocked} | {r.outcome_timeout} | "
                f"{r.outcome_error} | {d} | {r.diverting_0} / {r.diverting_1} / {r.diverting_2} / "
                f"{r.diverting_3_or_more} |"
            )
        lines.append("")
        gi = imps[imps["condition"] == condition] if len(imps) else imps
        if len(gi):
            lines += [
                "| pilot vs baseline | metric | pairs (both reached) | improvement | 95 % CI | p (paired) |",
                "| --- | --- | ---: | ---: | --- | ---: |",
            ]
            for r in gi.itertuples():
                if math.isnan(r.improvement_pct):
                    lines.append(f"| {r.pilot} vs {r.baseline} | {METRICS[r.metric]} | {r.pairs} | - | - | - |")
                else:
                    lines.append(
                        f"| {r.pilot} vs {r.baseline} | {METRICS[r.metric]} | {r.pairs} | "
                        f"{r.improvement_pct:+.1f} % | [{r.ci95_low:+.1f}, {r.ci95_high:+.1f}] % | "
                        f"{r.p_value:.4f} |"
                    )
            lines.append("")
    if remarks:
        lines += ["Notes:", ""] + [f"- {n}" for n in remarks] + [""]
    return "\n".join(lines)


def write_report(
    runs: pd.DataFrame,
    out: str | Path,
    baseline: str = "geometric",
    skipped: Sequence[tuple[str, str]] = (),
    plots: bool = True,
) -> dict[str, Path]:
    """Table (CSV, Markdown with its notes) and, with ``plots``, trajectories and box plots into
    ``out``; returns what was written."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    table = pilot_table(runs)
    imps = improvements(runs, baseline) if baseline in set(runs["pilot"]) else improvements(runs.iloc[:0], baseline)
    files = {
        "runs": out / REPORT_FILES[0],
        "table": out / REPORT_FILES[1],
        "improvements": out / REPORT_FILES[2],
        "markdown": out / REPORT_FILES[3],
    }
    for key, frame in (("runs", runs.drop(columns=["xy"], errors="ignore")), ("table", table), ("improvements", imps)):
        write_csv(files[key], frame)
    write_markdown(files["markdown"], markdown(table, imps, notes(runs, table, imps, baseline, skipped)))
    if plots:
        from . import plots as figures

        files.update(figures.comparison_plots(runs, out))
    return files
