"""The pilot paper's Table 1 from a folder of logs: per pilot, success, time and path length,
and each pilot's improvement over the baseline with a confidence interval and a paired test.

Everything here reads logs only (through :func:`analysis.read_log`). Every log's summary is
checked against its poses first: a log whose summary disagrees is refused, by name.

Statistics, chosen to need nothing beyond numpy:
- the improvement of a pilot over the baseline is ``100 * (mean_baseline - mean_pilot) /
  mean_baseline`` (positive: the pilot takes less time / a shorter path), over the seeds both
  pilots completed (the comparison is paired: the same seeds for every pilot);
- its 95 % confidence interval is a paired bootstrap (seeds resampled with replacement, 10 000
  resamples, percentile interval);
- its p-value is a paired sign-flip permutation test of the mean difference (two-sided, 10 000
  random sign assignments, with the observed one counted), exact in the limit and free of the
  normality a t-test assumes.
The random draws are seeded, so the same logs always give the same table.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from .logs import LogError, config_columns, path_length, read_log

METRICS = {"time_s": "time (s)", "path_cm": "path length (cm)"}
RESAMPLES = 10_000
PATH_TOLERANCE = 0.01  # the summary's path length must match the poses' within 1 %


def load_runs(logdir: str | Path) -> pd.DataFrame:
    """One row per ``.mcap`` under ``logdir`` (recursively): the summary, the run's configuration
    (perception, time limit and every parameter as ``params.<group>.<name>`` columns, so runs can
    be grouped by them), plus the path length and time recomputed from ``/robot/pose``, whose x,
    y are kept in ``xy`` for plots. Raises :class:`LogError` naming a log whose
    summary disagrees with its poses, or that has no summary."""
    rows = []
    for path in sorted(Path(logdir).rglob("*.mcap")):
        log = read_log(path, topics=["/robot/pose"])
        s = log.summary
        if not s:
            raise LogError(f"{path}: no /mission/summary (the run was killed before it could close its log)")
        poses = log["/robot/pose"]
        walked = path_length(poses)
        last = float(poses["time_s"].iloc[-1])
        if abs(walked - s["path_length_m"]) > PATH_TOLERANCE * max(walked, 0.01):
            raise LogError(f"{path}: summary path length {s['path_length_m']:.3f} m disagrees with "
                           f"its poses ({walked:.3f} m)")
        if abs(last - s["time_s"]) > 1e-6:
            raise LogError(f"{path}: summary time {s['time_s']} s disagrees with its last pose ({last} s)")
        config = log.config
        rows.append({"log": str(path), "run_id": s.get("run_id"), "scenario": s["scenario"], "pilot": s["pilot"],
                     "seed": s["seed"], "perception": config.get("perception"),
                     "time_limit_s": config.get("time_limit_s"),
                     "outcome": s["outcome"], "reached": s["outcome"] == "reached", "time_s": s["time_s"],
                     "path_m": s["path_length_m"], "path_cm": 100.0 * s["path_length_m"],
                     "collisions": s["collisions"], "camera_looks": s["camera_looks"], "ticks": s["ticks"],
                     "poses_path_m": walked, "xy": poses[["x", "y"]].to_numpy()} | config_columns(config))
    if not rows:
        raise LogError(f"{logdir}: no .mcap logs found")
    return pd.DataFrame(rows)


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score 95 % interval of a success rate (sound at 0/n and n/n, unlike the normal
    approximation).

    >>> [round(x, 3) for x in wilson_interval(45, 45)]
    [0.921, 1.0]
    """
    if n == 0:
        return math.nan, math.nan
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


CONDITION = ["scenario", "perception", "pilot"]
"""What a row of the table is: one pilot on one scenario with one perception."""


def _conditions(runs: pd.DataFrame) -> pd.DataFrame:
    runs = runs.copy()
    runs["perception"] = runs["perception"].fillna("?") if "perception" in runs else "?"
    return runs


def pilot_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Per scenario, perception and pilot: runs, successes with the success rate and its Wilson
    95 % interval; the mean and standard deviation over the *reached* runs of time, path length
    (cm, as the paper prints it), collisions and camera looks; and, so that failures are not
    hidden by leaving them out, the mean time with every failed run counted at its time limit
    (``time_fail_at_limit_mean``)."""
    out = []
    for (scenario, perception, pilot), g in _conditions(runs).groupby(CONDITION, sort=True):
        ok = g[g["reached"]]
        n, k = len(g), int(g["reached"].sum())
        lo, hi = wilson_interval(k, n)
        row = {"scenario": scenario, "perception": perception, "pilot": pilot, "runs": n, "reached": k,
               "failed": n - k, "success_rate": k / n, "success_ci_low": lo, "success_ci_high": hi}
        for col in ("time_s", "path_cm", "collisions", "camera_looks"):
            row[f"{col}_mean"] = float(ok[col].mean()) if len(ok) else math.nan
            row[f"{col}_std"] = float(ok[col].std(ddof=1)) if len(ok) > 1 else math.nan
        limit = g["time_limit_s"].fillna(g["time_s"]) if "time_limit_s" in g else g["time_s"]
        row["time_fail_at_limit_mean"] = float(g["time_s"].where(g["reached"], limit).mean())
        row["collisions_all_mean"] = float(g["collisions"].mean())
        out.append(row)
    return pd.DataFrame(out)


def improvements(runs: pd.DataFrame, baseline: str) -> pd.DataFrame:
    """Per scenario, pilot (other than ``baseline``) and metric: the paired improvement over the
    baseline in %, its bootstrap 95 % CI, the permutation p-value, and the number of pairs."""
    out = []
    for (scenario, perception), g in _conditions(runs).groupby(["scenario", "perception"], sort=True):
        base = g[(g["pilot"] == baseline) & g["reached"]].set_index("seed")
        for pilot in sorted(set(g["pilot"]) - {baseline}):
            other = g[(g["pilot"] == pilot) & g["reached"]].set_index("seed")
            seeds = base.index.intersection(other.index)
            for metric in METRICS:
                b = base.loc[seeds, metric].to_numpy(float)
                p = other.loc[seeds, metric].to_numpy(float)
                imp, lo, hi, pval = paired_improvement(b, p)
                out.append({"scenario": scenario, "perception": perception, "pilot": pilot, "baseline": baseline,
                            "metric": metric,
                            "pairs": len(seeds), "improvement_pct": imp, "ci95_low": lo, "ci95_high": hi,
                            "p_value": pval})
    return pd.DataFrame(out)


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
    signs = rng.choice([-1.0, 1.0], size=(RESAMPLES, n))
    null = np.abs((signs * d).mean(axis=1))
    pval = (1 + np.count_nonzero(null >= abs(d.mean()) - 1e-12)) / (RESAMPLES + 1)
    return float(imp), float(lo), float(hi), float(pval)


def _fmt(mean: float, std: float, digits: int = 2) -> tuple[str, str]:
    f = lambda x: "-" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}f}"  # noqa: E731
    return f(mean), f(std)


def markdown(table: pd.DataFrame, imps: pd.DataFrame) -> str:
    """The comparison as Markdown: Table 1's layout (times and paths over the reached runs), the
    success rate with its interval and the time with failures counted at the limit beside it;
    then the improvements."""
    lines = []
    for (scenario, perception), g in table.groupby(["scenario", "perception"], sort=True):
        lines += [f"### {scenario} ({perception} perception)", "",
                  "| pilot | reached | success (95 % CI) | time avg (s) | time std | path avg (cm) | path std "
                  "| time, failures at the limit (s) | collisions avg (all runs) | camera looks avg |",
                  "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
        for r in g.itertuples():
            t, ts = _fmt(r.time_s_mean, r.time_s_std)
            p, ps = _fmt(r.path_cm_mean, r.path_cm_std)
            tl, _ = _fmt(r.time_fail_at_limit_mean, 0.0)
            c, _ = _fmt(r.collisions_all_mean, 0.0)
            k, _ = _fmt(r.camera_looks_mean, 0.0, 1)
            rate = f"{100 * r.success_rate:.0f} % [{100 * r.success_ci_low:.0f}, {100 * r.success_ci_high:.0f}]"
            lines.append(f"| {r.pilot} | {r.reached}/{r.runs} | {rate} | {t} | {ts} | {p} | {ps} | {tl} | {c} | {k} |")
        lines.append("")
        gi = imps[(imps["scenario"] == scenario) & (imps["perception"] == perception)] if len(imps) else imps
        if len(gi):
            lines += ["| pilot vs baseline | metric | pairs (both reached) | improvement | 95 % CI | p (paired) |",
                      "| --- | --- | ---: | ---: | --- | ---: |"]
            for r in gi.itertuples():
                if math.isnan(r.improvement_pct):
                    lines.append(f"| {r.pilot} vs {r.baseline} | {METRICS[r.metric]} | {r.pairs} | - | - | - |")
                else:
                    lines.append(f"| {r.pilot} vs {r.baseline} | {METRICS[r.metric]} | {r.pairs} | "
                                 f"{r.improvement_pct:+.1f} % | [{r.ci95_low:+.1f}, {r.ci95_high:+.1f}] % | "
                                 f"{r.p_value:.4f} |")
            lines.append("")
    return "\n".join(lines)


def write_report(runs: pd.DataFrame, out: str | Path, baseline: str = "geometric") -> dict[str, Path]:
    """Table (CSV, Markdown), trajectories and box plots into ``out``; returns what was written."""
    from . import plots

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    table = pilot_table(runs)
    imps = improvements(runs, baseline) if baseline in set(runs["pilot"]) else \
        pd.DataFrame(columns=["scenario", "perception"])
    files = {"runs": out / "runs.csv", "table": out / "table.csv", "improvements": out / "improvements.csv",
             "markdown": out / "table.md"}
    runs.drop(columns=["xy"]).to_csv(files["runs"], index=False)
    table.to_csv(files["table"], index=False)
    imps.to_csv(files["improvements"], index=False)
    files["markdown"].write_text(markdown(table, imps))
    files.update(plots.comparison_plots(runs, out))
    return files
