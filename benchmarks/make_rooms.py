"""How the held-out rooms ``scattered-8x8``, ``crossed-8x8`` and ``landmarks-drawn`` were made:
drawn at random, once, from fixed seeds, before any run in them, and never reshaped ("check every
result on a room you did not design the feature on").

``landmarks-drawn`` (the learning paper's kind of room, for its Table 1 on a room training never
saw): 9 m x 7 m, walled, 12 landmarks and nothing else, each at least 1.2 m from the others, the
target one of them drawn at random.

Each is 8 m x 8 m at the paper's pace (5 cm/s), start and target in opposite corners (the other
diagonal from paper-8x8's), six point obstacles, two fences of 2-3 m at random angles whose
middles lie near the diagonal, six landmarks; every object keeps 0.6 m from the start, the target
and each other (the robot's body fits between any two).

    python benchmarks/make_rooms.py   # rewrites the three rooms' files in scenarios/
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1] / "scenarios"
START, TARGET = (0.8, 7.2), (7.2, 0.8)
GAP = 0.6


def _dist_to_segment(p, a, b) -> float:
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)


def _clear(p, things) -> bool:
    return all((_dist_to_segment(p, a, b) if b else math.dist(p, a)) > GAP for a, b in things)


def room(seed: int) -> dict:
    rng = np.random.default_rng(seed)
    things: list = [(START, None), (TARGET, None)]
    fences = []
    while len(fences) < 2:
        s = rng.uniform(0.25, 0.75)
        mid = (
            START[0] + s * (TARGET[0] - START[0]) + rng.normal(0, 0.5),
            START[1] + s * (TARGET[1] - START[1]) + rng.normal(0, 0.5),
        )
        length, angle = rng.uniform(2.0, 3.0), rng.uniform(0, math.pi)
        a = (mid[0] - length / 2 * math.cos(angle), mid[1] - length / 2 * math.sin(angle))
        b = (mid[0] + length / 2 * math.cos(angle), mid[1] + length / 2 * math.sin(angle))
        if (
            all(0.6 < c < 7.4 for c in (*a, *b))
            and all(_dist_to_segment(p, a, b) > GAP for p, q in things if q is None)
            and all(min(_dist_to_segment(e, *f) for e in (a, b)) > 1.0 for f in fences)
        ):
            fences.append((a, b))
            things.append((a, b))
    points = {"circles": [], "landmarks": []}
    for kind in ("circles", "landmarks"):
        while len(points[kind]) < 6:
            p = (float(rng.uniform(0.6, 7.4)), float(rng.uniform(0.6, 7.4)))
            if _clear(p, things):
                points[kind].append(p)
                things.append((p, None))
    return {"fences": fences, **points}


def write(name: str, seed: int, description: str) -> None:
    r = room(seed)
    f = lambda v: f"{v:.2f}"  # noqa: E731
    lines = [
        f"# A held-out room, drawn at random (benchmarks/make_rooms.py, seed {seed}) before any run in it,",
        "# and never reshaped: results here check what was designed on paper-8x8 and slanted-8x8.",
        "version: 1",
        f"name: {name}",
        f"description: >\n  {description}",
        "arena: {width: 8.0, height: 8.0}",
        "robot:",
        f"  start: [{START[0]}, {START[1]}]",
        "  heading_deg: -45",
        "  radius: 0.25",
        "  max_speed: 0.05   # m/s: the paper's pace, as in paper-8x8",
        "target:",
        f"  at: [{TARGET[0]}, {TARGET[1]}]",
        "  tolerance: 0.3",
        "obstacles:",
    ]
    lines += [f"  - circle: {{center: [{f(x)}, {f(y)}], radius: 0.15}}" for x, y in r["circles"]]
    lines += [f"  - segment: {{from: [{f(a[0])}, {f(a[1])}], to: [{f(b[0])}, {f(b[1])}]}}" for a, b in r["fences"]]
    lines += ["landmarks:"] + [
        f"  - {{id: {chr(65 + i)}, at: [{f(x)}, {f(y)}]}}" for i, (x, y) in enumerate(r["landmarks"])
    ]
    lines += [
        "mission:",
        "  pilot: potential-field",
        "  time_limit: 900",
        "  seed: 1",
        "noise:",
        "  odometry: 0.02",
        "  vision_heading_deg: 2",
        "  vision_distance: 0.05",
        "camera:",
        "  fov_deg: 60",
        "  range: 6.0",
    ]
    (ROOT / f"{name}.yaml").write_text("\n".join(lines) + "\n")


def landmarks(name: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    W, H = 9.0, 7.0
    pts: list[tuple[float, float]] = []
    while len(pts) < 12:
        p = (float(rng.uniform(0.8, W - 0.8)), float(rng.uniform(0.8, H - 0.8)))
        if all(math.dist(p, q) >= 1.2 for q in pts):
            pts.append(p)
    target = int(rng.integers(12))
    ids = [chr(65 + i) if i != target else "T" for i in range(12)]
    f = lambda v: f"{v:.2f}"  # noqa: E731
    lines = [
        f"# A held-out landmarks room, drawn at random (benchmarks/make_rooms.py, seed {seed}) before any run",
        "# in it, and never reshaped: the learning paper's Table 1 on a room training never saw.",
        "version: 1",
        f"name: {name}",
        "description: >",
        f"  Held-out walled {W:g} m x {H:g} m area with 12 landmarks drawn at random (seed {seed}) and nothing",
        "  else; the target is landmark T.",
        f"arena: {{width: {W}, height: {H}}}",
        "robot:",
        "  start: [0.6, 0.6]",
        "  heading_deg: 45",
        "target:",
        "  landmark: T",
        "  tolerance: 0.3",
        "landmarks:",
    ]
    lines += [f"  - {{id: {i}, at: [{f(x)}, {f(y)}]}}" for i, (x, y) in zip(ids, pts)]
    lines += ["noise:", "  odometry_drift_deg_per_m: 0.9", "mission:", "  time_limit: 600", "  seed: 1"]
    (ROOT / f"{name}.yaml").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    write(
        "scattered-8x8",
        35,
        "Held-out pilot comparison room (random, seed 35): opposite corners, six point obstacles, "
        "two fences at random angles near the diagonal, six landmarks, the paper's pace.",
    )
    write(
        "crossed-8x8",
        3535,
        "Held-out pilot comparison room (random, seed 3535): opposite corners, six point "
        "obstacles, two fences at random angles near the diagonal, six landmarks, the paper's pace.",
    )
    landmarks("landmarks-drawn", 36)
