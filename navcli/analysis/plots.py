"""Comparison plots from logs: every trajectory of each pilot on its arena, and box plots.

The arena is drawn from the scenario YAML attached to each log (the README's "The log"), read
as plain YAML: analysis needs nothing of navcli to draw it.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..log.format import POSE_TOPIC
from .files import atomic, file_name
from .logs import read_log


def draw_arena(ax, sc: dict) -> None:
    import matplotlib.patches as mp

    W, H = sc["arena"]["width"], sc["arena"]["height"]
    for o in sc.get("obstacles") or []:
        if "circle" in o:
            c = o["circle"]
            ax.add_patch(mp.Circle(c["center"], c["radius"], color="tab:red", zorder=3))
        else:
            s = o["segment"]
            ax.plot([s["from"][0], s["to"][0]], [s["from"][1], s["to"][1]], color="tab:red", lw=3, zorder=3)
    for lm in sc.get("landmarks") or []:
        ax.add_patch(mp.Circle(lm["at"], lm.get("radius", 0.15), color="tab:blue", zorder=3))
    t = sc["target"]
    if "line" in t:
        (a, b) = t["line"]
        ax.plot([a[0], b[0]], [a[1], b[1]], color="tab:green", lw=2, zorder=4)
    elif "at" in t:
        ax.plot(*t["at"], marker="*", ms=16, color="tab:green", zorder=4)
    ax.plot(*sc["robot"]["start"], marker="o", ms=8, color="k", zorder=4)
    ax.set_xlim(0, W)
    ax.set_ylim(0, H)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _scenario_of(log_path: str) -> dict:
    return read_log(log_path, topics=[]).scenario


def save_figure(fig, out: str | Path, dpi: int = 100) -> Path:
    """Write ``fig`` as a PNG to ``out`` (its folder made if need be; atomically), close it, return the path."""
    import matplotlib.pyplot as plt

    out = Path(out)
    fig.tight_layout()
    try:
        with atomic(out) as tmp:
            fig.savefig(tmp, dpi=dpi)
    finally:
        plt.close(fig)
    return out


def comparison_plots(runs: pd.DataFrame, out: Path) -> dict[str, Path]:
    """``trajectories-<scenario>[-<perception>]-<pilot>.png`` and ``boxplots-<scenario>[-<perception>].png``
    into ``out``. Failed runs are drawn in orange and end in a cross where they stopped; the box
    plots (reached runs) say how many runs each leaves out."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = runs.copy()
    runs["perception"] = runs["perception"].fillna("?") if "perception" in runs else "?"
    several = runs.groupby("scenario")["perception"].nunique().max() > 1
    files: dict[str, Path] = {}
    for (scenario, perception), g in runs.groupby(["scenario", "perception"], sort=True):
        tag = f"{scenario}-{perception}" if several else scenario
        sc = _scenario_of(g["log"].iloc[0])
        for pilot, gp in g.groupby("pilot", sort=True):
            fig, ax = plt.subplots(figsize=(6.5, 6.5))
            for r in gp.itertuples():
                xy = r.xy if "xy" in gp else read_log(r.log, topics=[POSE_TOPIC])[POSE_TOPIC][["x", "y"]].to_numpy()
                ax.plot(xy[:, 0], xy[:, 1], lw=0.8, alpha=0.6, color="tab:purple" if r.reached else "tab:orange")
                if not r.reached:
                    ax.plot(*xy[-1], marker="x", ms=9, mew=2, color="tab:orange", zorder=5)
            if sc:
                draw_arena(ax, sc)
            failed = int((~gp["reached"]).sum())
            ax.set_title(
                f"{scenario} ({perception}): {pilot}, {int(gp['reached'].sum())}/{len(gp)} reached"
                + (f"\n{failed} failed: orange, x where they stopped" if failed else "")
            )
            files[f"trajectories-{tag}-{pilot}"] = save_figure(fig, out / f"trajectories-{tag}-{file_name(pilot)}.png")
        ok = g[g["reached"]]
        pilots = sorted(g["pilot"].unique())
        labels = [f"{p}\n({int((~g.loc[g['pilot'] == p, 'reached']).sum())} failed, not shown)" for p in pilots]
        fig, axes = plt.subplots(1, 2, figsize=(9, 4.8))
        for ax, (col, label) in zip(axes, (("time_s", "time to target (s)"), ("path_cm", "path length (cm)"))):
            ax.boxplot([ok.loc[ok["pilot"] == p, col].to_numpy() for p in pilots], tick_labels=labels)
            ax.set_ylabel(label)
            ax.grid(axis="y", alpha=0.3)
        fig.suptitle(f"{scenario} ({perception} perception): reached runs per pilot")
        files[f"boxplots-{tag}"] = save_figure(fig, out / f"boxplots-{tag}.png")
    return files
