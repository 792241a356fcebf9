"""Comparison plots from logs: every trajectory of each pilot on its arena, and box plots.

The arena is drawn from the scenario YAML attached to each log (the README's "The log"), read
as plain YAML: analysis needs nothing of navcli to draw it.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import yaml

from .logs import read_log


def _arena(ax, sc: dict) -> None:
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
    att = read_log(log_path, topics=[]).attachments
    return yaml.safe_load(next(iter(att.values())).decode()) if att else {}


def comparison_plots(runs: pd.DataFrame, out: Path) -> dict[str, Path]:
    """``trajectories-<scenario>-<pilot>.png`` and ``boxplots-<scenario>.png`` into ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files: dict[str, Path] = {}
    for scenario, g in runs.groupby("scenario", sort=True):
        sc = _scenario_of(g["log"].iloc[0])
        for pilot, gp in g.groupby("pilot", sort=True):
            fig, ax = plt.subplots(figsize=(6.5, 6.5))
            for r in gp.itertuples():
                xy = r.xy if "xy" in gp else read_log(r.log, topics=["/robot/pose"])["/robot/pose"][["x", "y"]].to_numpy()
                ax.plot(xy[:, 0], xy[:, 1], lw=0.8, alpha=0.6, color="tab:purple" if r.reached else "tab:orange")
            if sc:
                _arena(ax, sc)
            ax.set_title(f"{scenario}: {pilot}, {int(gp['reached'].sum())}/{len(gp)} reached "
                         f"(orange: failed)")
            path = out / f"trajectories-{scenario}-{pilot}.png"
            fig.tight_layout()
            fig.savefig(path, dpi=100)
            plt.close(fig)
            files[f"trajectories-{scenario}-{pilot}"] = path
        ok = g[g["reached"]]
        pilots = sorted(g["pilot"].unique())
        fig, axes = plt.subplots(1, 2, figsize=(9, 4.5))
        for ax, (col, label) in zip(axes, (("time_s", "time to target (s)"), ("path_cm", "path length (cm)"))):
            ax.boxplot([ok.loc[ok["pilot"] == p, col].to_numpy() for p in pilots], tick_labels=pilots)
            ax.set_ylabel(label)
            ax.grid(axis="y", alpha=0.3)
        fig.suptitle(f"{scenario}: reached runs per pilot")
        fig.tight_layout()
        path = out / f"boxplots-{scenario}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        files[f"boxplots-{scenario}"] = path
    return files
