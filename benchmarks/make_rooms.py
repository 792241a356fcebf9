"""How the held-out rooms ``scattered-8x8``, ``crossed-8x8``, ``drawn-8x8-a``, ``drawn-8x8-b``,
``drawn-door``, ``landmarks-drawn`` and ``landmarks-drawn-b`` were made:
drawn at random, once, from fixed seeds, before any run in them, and never reshaped ("check every
result on a room you did not design the feature on").

``landmarks-drawn`` (the learning paper's kind of room, for its Table 1 on a room training never
saw): 9 m x 7 m, walled, 12 landmarks and nothing else, each at least 1.2 m from the others, the
target one of them drawn at random.

Each is 8 m x 8 m at the paper's pace (5 cm/s), start and target in opposite corners (the other
diagonal from paper-8x8's), six point obstacles, two fences of 2-3 m at random angles whose
middles lie near the diagonal, six landmarks; every object keeps 0.6 m from the start, the target
and each other (the robot's body fits between any two).

``drawn-door`` (a trap room, like ``door-wall`` but drawn): 12 m x 10 m, start and target as in
the bundled trap rooms, a wall across the room at a random height and tilt with one door of
random width (1.2-1.8 m) at a random place along it, a landmark either side of the door on each
side of the wall (2 m apart along the wall, as in ``door-wall``), six more landmarks and three
point obstacles at random, each keeping 0.6 m from the others, the start, the target, the wall
and the door (the door stays open).

``landmarks-drawn-b`` is a second room of that kind, for the learning paper's Table 1 on a room
neither training nor any rule of the learning task was designed on.

The seeds of ``drawn-8x8-a``, ``drawn-8x8-b``, ``drawn-door`` and ``landmarks-drawn-b`` came from
``secrets.randbelow`` before any run in those rooms.

    python benchmarks/make_rooms.py   # rewrites the rooms' files in scenarios/ and navcli/data/scenarios/
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ROOTS = (
    Path(__file__).resolve().parents[1] / "scenarios",
    Path(__file__).resolve().parents[1] / "navcli" / "data" / "scenarios",
)
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


def _scatter(rng, things: list, kinds: tuple[tuple[str, int], ...], width: float, height: float) -> dict:
    """Points drawn uniformly 0.6 m inside a ``width`` x ``height`` room, each clear of ``things``
    (to which it is added): ``n`` of each ``kind``, kind by kind."""
    points: dict[str, list] = {kind: [] for kind, _ in kinds}
    for kind, n in kinds:
        while len(points[kind]) < n:
            p = (float(rng.uniform(0.6, width - 0.6)), float(rng.uniform(0.6, height - 0.6)))
            if _clear(p, things):
                points[kind].append(p)
                things.append((p, None))
    return points


def _f(v: float) -> str:
    return f"{v:.2f}"


def _circles(points: list) -> list[str]:
    return [f"  - circle: {{center: [{_f(x)}, {_f(y)}], radius: 0.15}}" for x, y in points]


def _segments(ends: list) -> list[str]:
    return [f"  - segment: {{from: [{_f(a[0])}, {_f(a[1])}], to: [{_f(b[0])}, {_f(b[1])}]}}" for a, b in ends]


def _landmarks(points: list) -> list[str]:
    """The ``landmarks:`` block, ids A, B, ... in order."""
    return ["landmarks:"] + [f"  - {{id: {chr(65 + i)}, at: [{_f(x)}, {_f(y)}]}}" for i, (x, y) in enumerate(points)]


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
    return {"fences": fences, **_scatter(rng, things, (("circles", 6), ("landmarks", 6)), 8.0, 8.0)}


def _save(name: str, lines: list[str]) -> None:
    for root in ROOTS:
        (root / f"{name}.yaml").write_text("\n".join(lines) + "\n")


def write(name: str, seed: int, description: str) -> None:
    r = room(seed)
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
    lines += _circles(r["circles"]) + _segments(r["fences"]) + _landmarks(r["landmarks"])
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
    _save(name, lines)


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
    lines += [f"  - {{id: {i}, at: [{_f(x)}, {_f(y)}]}}" for i, (x, y) in zip(ids, pts)]
    lines += ["noise:", "  odometry_drift_deg_per_m: 0.9", "mission:", "  time_limit: 600", "  seed: 1"]
    _save(name, lines)


def door_room(name: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    W, H, start, target = 12.0, 10.0, (6.0, 1.5), (6.0, 8.5)
    y0, tilt = float(rng.uniform(4.3, 5.7)), float(rng.uniform(-0.08, 0.08))  # the wall: y = y0 + tilt (x - 6)
    wall_y = lambda x: y0 + tilt * (x - 6.0)  # noqa: E731
    width, door = float(rng.uniform(1.2, 1.8)), float(rng.uniform(1.5, 10.5))
    lo, hi = door - width / 2, door + width / 2
    walls = [((0.1, wall_y(0.1)), (lo, wall_y(lo))), ((hi, wall_y(hi)), (11.9, wall_y(11.9)))]
    marks = [(door - 1.0, wall_y(door - 1.0) + dy) for dy in (-0.7, 0.7)]
    marks += [(door + 1.0, wall_y(door + 1.0) + dy) for dy in (-0.7, 0.7)]
    things: list = [
        (start, None),
        (target, None),
        *walls,
        ((lo, wall_y(lo)), (hi, wall_y(hi))),
        *((m, None) for m in marks),
    ]
    points = _scatter(rng, things, (("landmarks", 6), ("circles", 3)), W, H)
    lines = [
        f"# A held-out trap room, drawn at random (benchmarks/make_rooms.py, seed {seed}) before any run",
        "# in it, and never reshaped: the trap rooms' results on a room no rule was designed on.",
        "version: 1",
        f"name: {name}",
        "description: >",
        f"  Held-out 12 m x 10 m trap room (random, seed {seed}): a wall across with one {width:.2f} m door",
        "  at a random place, marked by landmarks on both sides; six more landmarks, three point obstacles.",
        f"arena: {{width: {W}, height: {H}}}",
        "robot:",
        f"  start: [{start[0]}, {start[1]}]",
        "  heading_deg: 90",
        "target:",
        f"  at: [{target[0]}, {target[1]}]",
        "obstacles:",
    ]
    lines += _segments(walls) + _circles(points["circles"]) + _landmarks(marks + points["landmarks"])
    lines += ["mission:", "  time_limit: 1200", "  seed: 1"]
    _save(name, lines)


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
    landmarks("landmarks-drawn-b", 72174)
    for name, seed in (("drawn-8x8-a", 37582), ("drawn-8x8-b", 68517)):
        write(
            name,
            seed,
            f"Held-out pilot comparison room (random, seed {seed}): opposite corners, six point "
            "obstacles, two fences at random angles near the diagonal, six landmarks, the paper's pace.",
        )
    door_room("drawn-door", 63691)
