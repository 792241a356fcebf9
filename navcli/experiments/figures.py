"""Figures 9 and 10 of the pilot paper, for any scenario: the direction of the net virtual force
over the arena, and the pilot's bid (eq. 9) over the arena.

Each grid point is evaluated as the pilot would compute it there with every obstacle, landmark
and wall known exactly (the oracle perception): the robot placed at that point facing +x, and
the potential field computed by :func:`navcli.pilot.potential_field.field`. Points inside an obstacle's body are left blank. These
plots read the simulator's pilot, not a log, so they live here rather than in ``analysis``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

import numpy as np

from .. import NavcliError
from ..analysis.plots import save_figure

from ..config import RunSpec
from ..geometry import Pose
from ..pilot.potential_field import field
from ..scenario import Circle, Scenario
from ..vision.perception import OraclePerception


MAX_GRID_POINTS = 1_000_000
"""Most grid points of a figure (1,000 x 1,000 is finer than any screen; a 100 m room
at 2 cm would be 25 million, hours of work for a picture no one can see)."""


MAX_GRID_WORK = 2_000_000
"""Most point x body force evaluations of a figure (20,000 points of a room of 1,000
obstacles take over 5 minutes, so this bound keeps a figure to about half a minute)."""


class GridError(NavcliError):
    """A grid too fine for a figure; the message says the finest step that is drawn."""


def grid_points(sc: Scenario, step: float) -> int:
    """How many points a grid of ``step`` metres has over the arena of ``sc``."""
    return math.ceil(sc.arena.width / step - 0.5) * math.ceil(sc.arena.height / step - 0.5)


def field_grid(
    spec: RunSpec, step: float, walls: bool = False, progress: Callable[[int, int], None] | None = None
) -> tuple[np.ndarray, ...]:
    """X, Y (m), the unit net-force direction (U, V) and the bid on a grid of ``step`` metres.

    Like the paper's Figures 9 and 10, the room's walls exert no force unless ``walls`` is set
    (the paper's example has none). Blank points (inside bodies) are NaN. ``progress(rows done,
    rows)`` is called after each row of the grid (a room of a thousand obstacles takes minutes).
    A grid of more than :data:`MAX_GRID_POINTS` points raises :class:`GridError` before any work."""
    sc, pilot = spec.scenario, spec.params.pilot
    bodies = [o for o in sc.objects if o.kind in ("circle", "segment", "landmark")]
    points = grid_points(sc, step)
    budget = min(MAX_GRID_POINTS, MAX_GRID_WORK // (len(bodies) + 1))  # each point costs a force per body
    if points > budget:
        finest = math.sqrt(sc.arena.width * sc.arena.height / budget)
        raise GridError(
            f"a step of {step:g} m makes {points:,} points over the {sc.arena.width:g} m x "
            f"{sc.arena.height:g} m arena with {len(bodies)} bodies (at most {budget:,}); "
            f"use a step of at least {math.ceil(finest * 1000) / 1000:g} m"
        )
    xs = np.arange(step / 2, sc.arena.width, step)
    ys = np.arange(step / 2, sc.arena.height, step)
    X, Y = np.meshgrid(xs, ys)
    U, V, B = (np.full(X.shape, np.nan) for _ in range(3))
    perception = OraclePerception(sc, np.random.default_rng(0))  # the figure shows the field of the true layout
    rows = X.shape[0]
    for idx in np.ndindex(X.shape):
        if progress and idx[1] == 0 and idx[0]:
            progress(idx[0], rows)
        x, y = float(X[idx]), float(Y[idx])
        if any(o.clearance((x, y)) <= 0.0 for o in bodies):
            continue
        pose = Pose(x, y, 0.0)
        b = perception.observe(0.0, pose, pose)
        obstacles = b.obstacles if walls else [o for o in b.obstacles if not o.wall]
        f = field(b.target, b.target_line, obstacles, pilot)
        U[idx], V[idx] = math.cos(f.turn), math.sin(f.turn)
        B[idx] = f.bid
    if progress:
        progress(rows, rows)
    return X, Y, U, V, B


def _arena(ax, sc: Scenario, R_min: float) -> None:
    import matplotlib.patches as mp

    for o in sc.obstacles:
        if isinstance(o, Circle):
            ax.add_patch(mp.Circle(o.center, o.radius, color="tab:red", zorder=3))
            ax.add_patch(mp.Circle(o.center, o.radius + R_min, fill=False, ls="--", color="tab:red", lw=0.8, zorder=3))
        else:
            ax.plot([o.start[0], o.end[0]], [o.start[1], o.end[1]], color="tab:red", lw=3, zorder=3)
    for lm in sc.landmarks:
        ax.add_patch(mp.Circle(lm.at, lm.radius, color="tab:blue", zorder=3))
        ax.annotate(
            lm.id,
            lm.at,
            xytext=(6, 6),
            textcoords="offset points",
            color="tab:blue",
            zorder=6,
            fontweight="bold",
            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
        )
    t = sc.target
    if t.line is not None:
        ax.plot([t.line[0][0], t.line[1][0]], [t.line[0][1], t.line[1][1]], color="tab:green", lw=2, zorder=3)
    else:
        ax.plot(*t.point, marker="*", ms=16, color="tab:green", zorder=4)
    ax.plot(*sc.robot.start, marker="o", ms=8, color="k", zorder=4)
    ax.set_xlim(0, sc.arena.width)
    ax.set_ylim(0, sc.arena.height)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def plot_field(
    spec: RunSpec, out: Path, step: float = 0.2, walls: bool = False, progress: Callable[[int, int], None] | None = None
) -> Path:
    """Figure 9: arrows along the net force (eq. 6-7), over the arena."""
    sc, p = spec.scenario, spec.params.pilot
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    X, Y, U, V, _ = field_grid(spec, step, walls, progress)
    fig, ax = plt.subplots(figsize=(7, 7 * sc.arena.height / sc.arena.width + 0.5))
    ax.quiver(X, Y, U, V, angles="xy", scale_units="xy", scale=1 / (0.8 * step), width=0.003, color="0.25")
    _arena(ax, sc, p.R_min)
    ax.set_title(f"{sc.name}: direction of the net force (K={p.K:g}, A_t={p.A_t:g}, R_min={p.R_min:g} m)")
    return save_figure(fig, out, dpi=110)


def plot_bids(
    spec: RunSpec,
    out: Path,
    step: float = 0.05,
    walls: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> Path:
    """Figure 10: the pilot's motion bid (eq. 9) over the arena."""
    sc, p = spec.scenario, spec.params.pilot
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    X, Y, _, _, B = field_grid(spec, step, walls, progress)
    fig, ax = plt.subplots(figsize=(7.8, 7 * sc.arena.height / sc.arena.width + 0.5))
    im = ax.pcolormesh(X, Y, B, shading="nearest", cmap="viridis", vmin=0.0, vmax=p.bid_cap)
    fig.colorbar(im, ax=ax, label="pilot bid (eq. 9)")
    _arena(ax, sc, p.R_min)
    ax.set_title(f"{sc.name}: the pilot's bid 0.9 G_max / F_max")
    return save_figure(fig, out, dpi=110)


def learning_curves(metas: list[dict], out: str | Path) -> Path:
    """The learning paper's Figure 3 over several trainings, as a PNG: from each training's model
    metadata (``curve``: trials, successes, reward per trial at each evaluation; ``hand_coded``,
    ``random`` and their rewards), each training's curve (thin, named by its seed), their mean (thick) and range
    (shaded), with the hand-coded and random policies' levels (dashed); successes on the left,
    reward per trial on the right."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    trials = [p["trials"] for p in metas[0]["curve"]]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, level_keys, label in (
        (axes[0], "successes", ("hand_coded", "random"), "successful test trials"),
        (axes[1], "reward", ("hand_coded_reward", "random_reward"), "reward per test trial (higher is cheaper)"),
    ):
        values = np.array([[p[key] for p in m["curve"]] for m in metas], dtype=float)
        shades = plt.get_cmap("viridis")(np.linspace(0.1, 0.85, len(metas)))
        for row, m, shade in zip(values, metas, shades):  # each training, named by its seed
            ax.plot(trials, row, "-", color=shade, lw=0.9, alpha=0.7, label=f"seed {m.get('seed', '?')}")
        ax.fill_between(
            trials,
            values.min(axis=0),
            values.max(axis=0),
            color="tab:blue",
            alpha=0.15,
            label=f"range of {len(metas)} trainings",
        )
        ax.plot(trials, values.mean(axis=0), "o-", color="tab:blue", lw=2.2, label="mean")
        for k, colour, name in zip(level_keys, ("tab:orange", "tab:gray"), ("hand-coded", "random")):
            level = metas[0].get(k)
            if level is not None:
                ax.axhline(level, color=colour, ls="--", lw=2, label=f"{name} ({level:.0f})")
        ax.set_xlabel("training trials")
        ax.set_ylabel(label)
        ax.legend(loc="best", fontsize=7)
    axes[0].set_title("Successes of the test starts (Figure 3)")
    axes[1].set_title("Reward per trial of the test starts")
    fig.tight_layout()
    return save_figure(fig, Path(out), dpi=100)
