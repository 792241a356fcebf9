"""``navcli plot map LOG``: the Map Manager's final map over the true arena, from a log alone.

The log's ``/map/scene`` holds the map as the robot knew it, in ``base_link`` (egocentric): each
mapped landmark's estimate (a disc the size of its 70 % cut, named ``A'``), blocked edges, the
diverting line, and the diverting lines ended so far, each named by how it ended; ``/map/regions``
its regions' triangles and beta-units. The last message is placed in the arena with
the robot's true pose at that time, so the drawing shows belief (purple) over truth (blue), and
how far the map had drifted. Reads logs only; never imports the simulator.
"""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

from ..log.format import MAP_REGIONS_TOPIC, MAP_SCENE_TOPIC, POSE_TOPIC
from .logs import LogError, read_log, require, scene_messages
from .plots import draw_arena, save_figure

LOOP, LIST = 1, 2  # foxglove.LinePrimitive's types (0 is a strip)


def last_map(path: Path):
    """(log time ns, entities) of the last ``/map/scene`` message, with those of the last
    ``/map/regions`` (the regions and beta-units, a topic of their own) at or before it (only
    those two decoded), or None."""
    last = next(iter(deque(scene_messages(path, MAP_SCENE_TOPIC, decode=False), maxlen=1)), None)
    if last is None:
        return None
    ns, (decode, data) = last
    entities = list(decode(data).entities)
    regions = None
    for at, found in scene_messages(path, MAP_REGIONS_TOPIC, decode=False):
        if at <= ns:
            regions = found
    if regions is not None:
        decode_regions, raw = regions
        entities += decode_regions(raw).entities
    return ns, entities


def plot_map(log_path: str | Path, out: str | Path) -> Path:
    """Draw the final map of the run in ``log_path`` over its arena into the PNG ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.patches as mp
    import matplotlib.pyplot as plt

    path = Path(log_path)
    log = require(read_log(path, topics=[POSE_TOPIC]), POSE_TOPIC, scenario=True)
    found = last_map(path)
    if found is None:
        raise LogError(f"{path}: no /map/scene in this log (written by navcli runs with the Navigation system)")
    ns, entities = found
    poses = log[POSE_TOPIC]
    at = poses[poses["log_time_ns"] <= ns].iloc[-1]
    c, s = math.cos(at["theta"]), math.sin(at["theta"])

    def world(p) -> tuple[float, float]:
        return at["x"] + c * p.x - s * p.y, at["y"] + s * p.x + c * p.y

    fig, ax = plt.subplots(figsize=(7, 7))
    ax.plot(poses["x"], poses["y"], lw=0.8, color="0.5", label="path")
    for e in entities:
        for ln in e.lines:
            pts = [world(p) for p in ln.points]
            if ln.type == LOOP:  # a region
                pts.append(pts[0])
            colour = (ln.color.r, ln.color.g, ln.color.b)
            if ln.type == LIST:  # beta-unit spokes, in pairs
                for a, b in zip(pts[::2], pts[1::2]):
                    ax.plot([a[0], b[0]], [a[1], b[1]], color=colour, alpha=0.35, lw=0.6)
                continue
            ax.plot(
                [p[0] for p in pts],
                [p[1] for p in pts],
                color=colour,
                alpha=max(ln.color.a, 0.3),
                lw=3 if ln.thickness >= 0.04 else 0.8,
            )
        for cyl in e.cylinders:
            x, y = world(cyl.pose.position)
            ax.add_patch(mp.Circle((x, y), cyl.size.x / 2, color="tab:purple", alpha=0.35, zorder=5))
        for t in e.texts:
            x, y = world(t.pose.position)
            ax.annotate(t.text, (x, y), xytext=(4, -10), textcoords="offset points", color="tab:purple", zorder=6)
    sc = log.scenario
    if sc:
        draw_arena(ax, sc)
    summary = log.summary
    ax.set_title(
        f"{summary.get('scenario', path.stem)}: the map at {ns / 1e9:.0f} s "
        f"({summary.get('outcome', '?')}, diverting targets: {summary.get('diverting_targets', 0)})\n"
        "the map (purple): landmarks (70 % cut), regions, blocked edges (thick, pink),\n"
        "the diverting line (green), those ended (thin green, named by how they ended);\n"
        "the truth: obstacles (red), landmarks (blue), the path (grey)",
        fontsize=8,
    )
    return save_figure(fig, out, dpi=110)
