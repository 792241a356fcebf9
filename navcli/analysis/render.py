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
matplotlib's animation writers encode: Pillow for GIF, ffmpeg for MP4 when installed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

from .. import NavcliError
from ..log.format import BIDS_TOPIC, MEMORY_SCENE_TOPIC, PILOT_TOPIC, POSE_TOPIC
from .files import atomic
from .logs import LogError, read_log, scene_messages
from .plots import draw_arena

FORCE_SCALE = 100.0  # force units per metre of arrow, as in the log's /robot/scene
BID_SERIES = ("motion.pilot", "motion.navigation", "camera.pilot", "camera.navigation")
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
    70 % cut is a cylinder, the support a ring around the same centre."""
    out = []
    for log_time, m in scene_messages(path, MEMORY_SCENE_TOPIC):
        spots = []
        for e in m.entities:
            rings = [ln for ln in e.lines if len(ln.points) > 2]
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


def render(log_path: str | Path, out: str | Path, *, speed: float = 10.0, start: float | None = None,
           end: float | None = None, fps: float = 10.0, dpi: int = 80,
           progress: Callable[[int, int], None] | None = None) -> Rendered:
    """Write a video of the run in ``log_path`` to ``out`` (``.gif``, or ``.mp4`` with ffmpeg).

    ``speed`` is simulated seconds per second of video; ``start``/``end`` (s) clip the run;
    ``progress(i, n)`` is called after each frame. Raises :class:`RenderError` (or
    :class:`~analysis.logs.LogError`) on a request it cannot serve."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import animation
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle

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
    log = read_log(log_path, topics=[POSE_TOPIC, PILOT_TOPIC, BIDS_TOPIC])
    if POSE_TOPIC not in log.topics or not log.attachments:
        raise LogError(f"{log_path}: no poses or no attached scenario: not a navcli run log")
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

    fig = plt.figure(figsize=(5.0, 6.4), dpi=dpi)
    grid = fig.add_gridspec(2, 1, height_ratios=(4.2, 1.0), hspace=0.3)
    ax, strip = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
    draw_arena(ax, sc)
    ax.set_title(f"{sc.get('name', '')}  {log.summary.get('pilot', '')}", fontsize=9)
    for series in BID_SERIES:
        if series in bids:
            strip.plot(bids["time_s"], bids[series], lw=0.8, label=series)
    strip.set_xlim(start, end)
    strip.set_ylim(0, 1)
    strip.set_ylabel("bid")
    strip.set_xlabel("simulated time (s)")
    strip.legend(fontsize=6, ncol=2, loc="upper right")
    cursor = strip.axvline(start, color="k", lw=0.8)
    path_line, = ax.plot([], [], color="k", lw=1.0, zorder=5)
    body = Circle((0, 0), radius, facecolor="gold", edgecolor="k", zorder=6)
    ax.add_patch(body)
    heading, = ax.plot([], [], color="k", lw=1.5, zorder=7)
    supports = PatchCollection([], facecolor="none", lw=0.5, alpha=0.5, zorder=2)
    cuts = PatchCollection([], alpha=0.45, zorder=2)
    ax.add_collection(supports)
    ax.add_collection(cuts)
    arrows: list = []
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, zorder=8)
    px, py, pth, pt = (poses[c].to_numpy() for c in ("x", "y", "theta", "time_s"))

    def draw(k: int):
        t = times[k]
        i = max(int(np.searchsorted(pt, t, side="right")) - 1, 0)
        x, y, th = px[i], py[i], pth[i]
        c, s = math.cos(th), math.sin(th)
        path_line.set_data(px[:i + 1], py[:i + 1])
        body.center = (x, y)
        heading.set_data([x, x + radius * c], [y, y + radius * s])
        world = memory_in_world(memory, mem_t, (px, py, pth, pt), t)
        supports.set_paths([Circle((wx, wy), r0) for _, wx, wy, _, r0 in world])
        supports.set_edgecolor([_MEMORY_COLOURS[k_] for k_, *_ in world])
        cuts.set_paths([Circle((wx, wy), max(r70, 0.03)) for _, wx, wy, r70, _ in world])
        cuts.set_facecolor([_MEMORY_COLOURS[k_] for k_, *_ in world])
        for a in arrows:
            a.remove()
        arrows.clear()
        row = pilot.iloc[max(int(np.searchsorted(pilot["time_s"].to_numpy(), t, side="right")) - 1, 0)]
        vectors = [(name, row.get(f"{name}.x"), row.get(f"{name}.y"), colour)
                   for name, colour in (("net", "m"), ("target", "tab:green"), ("repulsive", "tab:red"))]
        if all(pd.isna(fx) for _, fx, _, _ in vectors) and not pd.isna(row.get("turn_deg", np.nan)):
            turn = math.radians(row["turn_deg"])
            vectors = [("turn", 50 * math.cos(turn), 50 * math.sin(turn), "m")]
        for _, fx, fy, colour in vectors:
            if pd.isna(fx) or math.hypot(fx, fy) < 1.0:
                continue
            dx, dy = (c * fx - s * fy) / FORCE_SCALE, (s * fx + c * fy) / FORCE_SCALE
            arrows.append(ax.arrow(x, y, dx, dy, width=0.02, head_width=0.12, length_includes_head=True,
                                   color=colour, zorder=7))
        cursor.set_xdata([t, t])
        clock.set_text(f"t = {t:5.1f} s")

    with atomic(out) as tmp, writer.saving(fig, str(tmp), dpi):  # one draw per frame (FuncAnimation.save
        for k in range(len(times)):                                # draws each twice)
            draw(k)
            writer.grab_frame()
            if progress:
                progress(k + 1, len(times))
    width, height = fig.canvas.get_width_height()
    size = (int(width), int(height))
    plt.close(fig)
    return Rendered(out, len(times), size)
