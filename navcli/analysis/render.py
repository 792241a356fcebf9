"""A video of a run from its log alone (``navcli render``): no simulator, no viewer.

Each frame shows, top-down on the true arena (drawn from the scenario YAML attached to the log):
the path driven so far and the robot (ground truth, ``/robot/pose``); the robot's beliefs, the
visual memory of ``/memory/scene`` (per remembered point its 70 % cut as a disc and its support as
a faint ring, placed in the world with the true pose at the time it was drawn, as the log's 3D
view places them); the
pilot's force arrows from ``/pilot`` (net, target, repulsive; 100 force units = 1 m as in the 3D
view) or, for a pilot without forces, the turn it asks for; under it a strip of the bids per
resource (``/bids``) with a cursor at the frame's time.

Frames are taken every ``speed / fps`` simulated seconds from ``start`` to ``end`` inclusive.
matplotlib's animation writers encode: Pillow for GIF, ffmpeg for MP4 when installed. The drawing
itself is :class:`RunFigure`, which the Gymnasium environment's ``render_mode="rgb_array"`` draws
too, from the trial as it runs (:mod:`navcli.envs.landmark_navigation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

from .. import NavcliError
from ..log.format import BIDS_TOPIC, MEMORY_SCENE_TOPIC, MEMORY_SUPPORTS_TOPIC, PILOT_TOPIC, POSE_TOPIC
from .files import atomic
from .logs import read_log, require, scene_messages
from .plots import draw_arena

FORCE_SCALE = 100.0  # force units per metre of arrow, as in the log's /robot/scene
BID_SERIES = ("motion.pilot", "motion.navigation", "camera.pilot", "camera.navigation")
FORCES = (
    ("net", "m"),
    ("target", "tab:green"),
    ("repulsive", "tab:red"),
)  # the pilot's forces drawn, and their colours
_MEMORY_COLOURS = {"landmark": "tab:blue", "obstacle": "tab:red", "bump": "red", "target": "tab:green"}


class RenderError(NavcliError):
    """A render that cannot be made as asked (bad time range, a format without its encoder)."""


@dataclass(frozen=True)
class Rendered:
    path: Path
    frames: int
    size: tuple[int, int]  # pixels (width, height)


def frame_times(start: float, end: float, speed: float, fps: float) -> np.ndarray:
    """Simulated times (s) of the frames: every ``speed / fps`` s from ``start`` to ``end``.

    >>> frame_times(0.0, 3.0, 10.0, 10.0).tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    step = speed / fps
    return start + step * np.arange(math.floor((end - start) / step + 1e-9) + 1)


def _memory(path: Path) -> list[tuple[float, list[tuple[str, float, float, float, float]]]]:
    """``/memory/scene`` as (time s, [(kind, x, y, r70, r0)]) in ``base_link``: the disc of a
    70 % cut is a cylinder, the support a ring around the same centre in ``/memory/supports``
    (the entity of the same id, at the same time; logs before it kept the rings with the discs)."""
    supports = {
        (log_time, e.id): [ln for ln in e.lines if len(ln.points) > 2]
        for log_time, m in scene_messages(path, MEMORY_SUPPORTS_TOPIC)
        for e in m.entities
    }
    out = []
    for log_time, m in scene_messages(path, MEMORY_SCENE_TOPIC):
        spots = []
        for e in m.entities:
            rings = supports.get((log_time, e.id)) or [ln for ln in e.lines if len(ln.points) > 2]
            for i, c in enumerate(e.cylinders):
                x, y, r70 = c.pose.position.x, c.pose.position.y, c.size.x / 2
                r0 = r70
                if i < len(rings):
                    p = rings[i].points[0]
                    r0 = math.hypot(p.x - x, p.y - y)
                spots.append((_kind(c.color), x, y, r70, r0))
        out.append((log_time / 1e9, spots))
    return out


def memory_in_world(memory: list, mem_t: np.ndarray, poses: tuple[np.ndarray, ...], t: float) -> list[tuple]:
    """The spots of the last ``memory`` drawing at or before ``t`` (s) in the world: each drawing
    is egocentric, so it is placed with the true pose at the time it was drawn (``poses``: x, y,
    theta, time arrays), where the log's 3D view keeps it until the next one."""
    j = int(np.searchsorted(mem_t, t, side="right")) - 1
    if j < 0:
        return []
    px, py, pth, pt = poses
    i = max(int(np.searchsorted(pt, mem_t[j], side="right")) - 1, 0)
    x, y, c, s = px[i], py[i], math.cos(pth[i]), math.sin(pth[i])
    return [(kind, x + c * mx - s * my, y + s * mx + c * my, r70, r0) for kind, mx, my, r70, r0 in memory[j][1]]


def _kind(colour) -> str:
    """What a remembered point is, from the colour the log draws it in (blue a landmark, green the
    target, bright red a bump, red an obstacle)."""
    r, g, b = colour.r, colour.g, colour.b
    if b > max(r, g):
        return "landmark"
    if g > max(r, b):
        return "target"
    return "bump" if g < 0.2 else "obstacle"


class RunFigure:
    """The drawing of a run at one moment, as ``navcli render`` writes each frame of its video and
    the Gymnasium environment returns each ``render()`` of ``render_mode="rgb_array"``: top-down on
    the true arena (``scenario``: the scenario as plain YAML values) the path driven so far and the
    robot, the remembered points in the world (each a disc of its 70 % cut and a ring of its
    support), the pilot's force arrows, and under it a strip of the bids per resource with a
    cursor at the moment drawn. A figure of 5 x 6.4 inches at ``dpi``: its frames all one size."""

    def __init__(self, scenario: dict, title: str, radius: float, dpi: int = 80):
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.collections import PatchCollection
        from matplotlib.patches import Circle

        self._circle = Circle
        self.radius = radius
        self.fig = fig = plt.figure(figsize=(5.0, 6.4), dpi=dpi)
        grid = fig.add_gridspec(2, 1, height_ratios=(4.2, 1.0), hspace=0.3)
        self.ax, self.strip = ax, strip = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
        draw_arena(ax, scenario)
        ax.set_title(title, fontsize=9)
        self.bid_lines = {series: strip.plot([], [], lw=0.8, label=series)[0] for series in BID_SERIES}
        strip.set_ylim(0, 1)
        strip.set_ylabel("bid")
        strip.set_xlabel("simulated time (s)")
        strip.legend(fontsize=6, ncol=2, loc="upper right")
        self.cursor = strip.axvline(0.0, color="k", lw=0.8)
        (self.path_line,) = ax.plot([], [], color="k", lw=1.0, zorder=5)
        self.body = Circle((0, 0), radius, facecolor="gold", edgecolor="k", zorder=6)
        ax.add_patch(self.body)
        (self.heading,) = ax.plot([], [], color="k", lw=1.5, zorder=7)
        self.supports = PatchCollection([], facecolor="none", lw=0.5, alpha=0.5, zorder=2)
        self.cuts = PatchCollection([], alpha=0.45, zorder=2)
        ax.add_collection(self.supports)
        ax.add_collection(self.cuts)
        self.arrows: list = []
        self.clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, zorder=8)

    def bids(self, times, series: dict, span: tuple[float, float]) -> None:
        """The strip: each of :data:`BID_SERIES` in ``series`` against ``times`` (s), over ``span``."""
        for name, line in self.bid_lines.items():
            if name in series:
                line.set_data(times, series[name])
        self.strip.set_xlim(*span)

    def draw(self, t: float, path_x, path_y, theta: float, spots: list[tuple], forces: list[tuple]) -> None:
        """The moment ``t`` (s): the path so far (its last point the robot, heading ``theta``),
        ``spots`` (kind, x, y, r70, r0) in the world, and ``forces`` (fx, fy, colour) egocentric in
        force units (:data:`FORCE_SCALE` to a metre), each from the robot."""
        Circle = self._circle
        x, y = path_x[-1], path_y[-1]
        c, s = math.cos(theta), math.sin(theta)
        self.path_line.set_data(path_x, path_y)
        self.body.center = (x, y)
        self.heading.set_data([x, x + self.radius * c], [y, y + self.radius * s])
        colours = [_MEMORY_COLOURS.get(k, _MEMORY_COLOURS["obstacle"]) for k, *_ in spots]  # walls as obstacles
        self.supports.set_paths([Circle((wx, wy), r0) for _, wx, wy, _, r0 in spots])
        self.supports.set_edgecolor(colours)
        self.cuts.set_paths([Circle((wx, wy), max(r70, 0.03)) for _, wx, wy, r70, _ in spots])
        self.cuts.set_facecolor(colours)
        for a in self.arrows:
            a.remove()
        self.arrows.clear()
        for fx, fy, colour in forces:
            dx, dy = (c * fx - s * fy) / FORCE_SCALE, (s * fx + c * fy) / FORCE_SCALE
            self.arrows.append(
                self.ax.arrow(
                    x, y, dx, dy, width=0.02, head_width=0.12, length_includes_head=True, color=colour, zorder=7
                )
            )
        self.cursor.set_xdata([t, t])
        self.clock.set_text(f"t = {t:5.1f} s")

    def rgb(self):
        """The figure as drawn now: an array of height x width x 3 bytes (RGB)."""
        self.fig.canvas.draw()
        return np.asarray(self.fig.canvas.buffer_rgba())[..., :3].copy()

    @property
    def size(self) -> tuple[int, int]:
        """Pixels (width, height)."""
        width, height = self.fig.canvas.get_width_height()
        return int(width), int(height)

    def close(self) -> None:
        import matplotlib.pyplot as plt

        plt.close(self.fig)


def force_vectors(get: Callable[[str], float | None]) -> list[tuple[float, float, str]]:
    """The pilot's forces to draw, (fx, fy, colour), from ``get`` of a ``/pilot`` field by its
    dotted name (``net.x`` ...; None when absent): net, target and repulsive, or for a pilot without
    forces the turn it asks for; each of at least one force unit.

    >>> force_vectors({"net.x": 30.0, "net.y": 40.0, "target.x": 0.5, "target.y": 0.0}.get)
    [(30.0, 40.0, 'm')]
    >>> [(round(fx), round(fy), c) for fx, fy, c in force_vectors({"turn_deg": 90.0}.get)]
    [(0, 50, 'm')]
    """
    vectors = [(get(f"{name}.x"), get(f"{name}.y"), colour) for name, colour in FORCES]
    if all(fx is None for fx, _, _ in vectors) and get("turn_deg") is not None:
        turn = math.radians(float(get("turn_deg")))  # type: ignore[arg-type]
        vectors = [(50 * math.cos(turn), 50 * math.sin(turn), "m")]
    return [
        (float(fx), float(fy), colour)
        for fx, fy, colour in vectors
        if fx is not None and fy is not None and math.hypot(fx, fy) >= 1.0
    ]


def render(
    log_path: str | Path,
    out: str | Path,
    *,
    speed: float = 10.0,
    start: float | None = None,
    end: float | None = None,
    fps: float = 10.0,
    dpi: int = 80,
    progress: Callable[[int, int], None] | None = None,
) -> Rendered:
    """Write a video of the run in ``log_path`` to ``out`` (``.gif``, or ``.mp4`` with ffmpeg):
    a :class:`RunFigure` per frame.

    ``speed`` is simulated seconds per second of video; ``start``/``end`` (s) clip the run;
    ``progress(i, n)`` is called after each frame. Raises :class:`RenderError` (or
    :class:`~analysis.logs.LogError`) on a request it cannot serve."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import animation

    log_path, out = Path(log_path), Path(out)
    suffix = out.suffix.lower()
    if suffix == ".mp4":
        if not animation.writers.is_available("ffmpeg"):
            raise RenderError("MP4 needs ffmpeg, which is not installed here; a GIF works without it (--out run.gif)")
        writer: animation.AbstractMovieWriter = animation.FFMpegWriter(fps=fps)  # type: ignore[arg-type]
    elif suffix == ".gif":  # (matplotlib's stubs say int; both writers take a float rate)
        writer = animation.PillowWriter(fps=fps)  # type: ignore[arg-type]
    else:
        raise RenderError(f"{out}: the video must end in .gif or .mp4")
    if speed <= 0 or fps <= 0:
        raise RenderError("--speed and the frame rate must be positive")
    topics = (POSE_TOPIC, PILOT_TOPIC, BIDS_TOPIC)
    log = require(read_log(log_path, topics=topics), *topics, scenario=True)
    sc = log.scenario
    poses, pilot, bids = log[POSE_TOPIC], log[PILOT_TOPIC], log[BIDS_TOPIC]
    t_end = float(poses["time_s"].iloc[-1])
    start = 0.0 if start is None else start
    end = t_end if end is None else min(end, t_end)
    if not 0.0 <= start < end:
        raise RenderError(f"empty time range: from {start:g} s to {end:g} s (the run lasts {t_end:g} s)")
    times = frame_times(start, end, speed, fps)
    memory = _memory(log_path)
    mem_t = np.array([t for t, _ in memory])
    radius = log.config.get("params", {}).get("robot", {}).get("radius", 0.25)
    figure = RunFigure(sc, f"{sc.get('name', '')}  {log.summary.get('pilot', '')}", radius, dpi)
    figure.bids(bids["time_s"], {s: bids[s] for s in BID_SERIES if s in bids}, (start, end))
    px, py, pth, pt = (poses[c].to_numpy() for c in ("x", "y", "theta", "time_s"))
    pilot_t = pilot["time_s"].to_numpy()

    def draw(t: float) -> None:
        i = max(int(np.searchsorted(pt, t, side="right")) - 1, 0)
        row = pilot.iloc[max(int(np.searchsorted(pilot_t, t, side="right")) - 1, 0)]
        forces = force_vectors(lambda k: None if pd.isna(row.get(k, np.nan)) else row[k])
        figure.draw(t, px[: i + 1], py[: i + 1], pth[i], memory_in_world(memory, mem_t, (px, py, pth, pt), t), forces)

    try:
        with atomic(out) as tmp, writer.saving(figure.fig, str(tmp), dpi):  # one draw per frame (FuncAnimation.save
            for k in range(len(times)):  # draws each twice)
                draw(times[k])
                writer.grab_frame()
                if progress:
                    progress(k + 1, len(times))
        return Rendered(out, len(times), figure.size)
    finally:
        figure.close()
