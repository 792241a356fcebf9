"""What the robot's vision gets wrong over whole missions: phantom lines and stalls.

Runs missions without a log (in worker processes) and, every half second of simulated time,
compares the visual memory with the true room:

- **phantom lines**: a remembered linear obstacle or wall (two points) whose crisp middle, put
  in the world by the true pose, lies more than ``--off`` m (0.3) from the surface of every
  true obstacle, landmark and wall. Each memory key counts once per run, however long it lasts.
  Counted three ways: ``phantoms`` as said (the middle's place also carries the odometry's
  drift since the ends were seen, which the memory's supports allow for); ``phantoms_cut``
  beyond 0.3 m plus the middle's 70 % cut (the mean of its ends' 70 % cut radii: the papers'
  precision); ``phantoms_support`` beyond 0.3 m plus the middle's support (the mean of its
  ends' supports: a line whose ends are honest points of one straight obstacle never counts).
- **honesty**: how far outside its support the truth lies at worst (m; <= 0: always inside),
  over every remembered obstacle point (the surface of the nearest true thing) and every
  remembered landmark (its true place).
- **stalls**: the longest stretch of simulated time without progress, progress being a new
  closest approach to the target at least ``--progress`` m (0.3) closer than the last one (the
  time after the last progress counts too unless the target was reached); and ``still_s``, the
  longest stretch the robot stayed within ``--progress`` m of one place (spinning, rocking). A
  detour away from the target (round a fence, a diverting target) is a stall of the first kind,
  not of the second.

    python benchmarks/vision_audit.py --rooms paper-8x8,slanted-8x8 --seeds 6 --time-limit 300
    python benchmarks/vision_audit.py --rooms paper-8x8 --seeds 45 --pilots potential-field \\
        --perception oracle --time-limit 900

Prints one JSON line per run, then a summary per room x pilot. Seeds are those of
``navcli compare pilots`` (``rerun_seed(scenario seed, i)``), so the runs pair with its logs.
``--param NAME=VALUE`` (repeatable) overrides parameters as on the command line.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from navcli import RunSpec, load_scenario
from navcli.experiments.compare import rerun_seed
from navcli.fuzzy import CUT
from navcli.geometry import distance_to_segment
from navcli.mission import Mission

try:
    from navcli.params import parse_override
except ImportError:  # a checkout without the vision routines (the benchmark is run from older checkouts too)
    from navcli.params import parse_override  # type: ignore[no-redef,attr-defined]

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
EVERY = 5  # ticks between two checks (0.5 s)


def surfaces(sc) -> list[tuple[tuple[float, float], tuple[float, float], float]]:
    """Every physical thing of the room as (a, b, half-width): obstacles, landmarks, walls."""
    return [(o.a, o.b, o.radius) for o in sc.objects if o.kind != "target"]


def audit(job: tuple[str, str, int, str, float, tuple[tuple[str, object], ...], float, float, str]) -> dict:
    room, pilot, index, perception, limit, overrides, off, progress, folder = job
    sc = load_scenario(Path(folder) / f"{room}.yaml")
    seed = rerun_seed(sc.mission.seed, index)
    spec = RunSpec.build(sc, pilot=pilot, seed=seed, perception=perception, time_limit=limit, overrides=dict(overrides))
    m = Mission(spec, snapshots=False)
    things = surfaces(sc)
    target = sc.target.point
    phantoms: dict[str, float] = {}
    cut: dict[str, float] = {}
    support: dict[str, float] = {}
    best = math.inf
    excess = -math.inf
    landmarks = {lm.id: lm.at for lm in sc.landmarks}
    last_progress, longest = 0.0, 0.0
    anchor, anchor_t, still = (sc.robot.start[0], sc.robot.start[1]), 0.0, 0.0
    while m.outcome is None:
        m.step()
        if m.ticks % EVERY:
            continue
        pose = m.world.pose
        if math.dist((pose.x, pose.y), anchor) > progress:
            anchor, anchor_t = (pose.x, pose.y), m.time
        still = max(still, m.time - anchor_t)
        d = math.dist((pose.x, pose.y), target)
        if d <= best - progress or best == math.inf:
            best = d
            longest = max(longest, m.time - last_progress)
            last_progress = m.time
        memory = getattr(m.perception, "memory", None)
        if memory is None:
            continue
        for item in memory.items.values():
            if item.kind != "target":
                for sp in item.spots:
                    w = pose.to_world((sp.x, sp.y))
                    d = (
                        math.dist(w, landmarks[item.key])
                        if item.kind == "landmark"
                        else min(distance_to_segment(w, p, q) - r for p, q, r in things)
                    )
                    excess = max(excess, d - sp.r0)
            if len(item.spots) != 2 or item.kind not in ("obstacle", "wall") or item.key in support:
                continue
            a, b = item.spots
            mid = pose.to_world(((a.x + b.x) / 2, (a.y + b.y) / 2))
            gap = min(distance_to_segment(mid, p, q) - r for p, q, r in things)
            for found, allow in (
                (phantoms, 0.0),
                (cut, (a.radius(CUT) + b.radius(CUT)) / 2),
                (support, (a.r0 + b.r0) / 2),
            ):
                if gap > off + allow and item.key not in found:
                    found[item.key] = round(m.time, 1)
    if m.outcome != "reached":
        longest = max(longest, m.time - last_progress)
    return {
        "room": room,
        "pilot": pilot,
        "seed": seed,
        "perception": perception,
        "outcome": m.outcome,
        "time": round(m.time, 1),
        "stall_s": round(longest, 1),
        "still_s": round(still, 1),
        "phantoms": len(phantoms),
        "phantoms_cut": len(cut),
        "phantoms_support": len(support),
        "phantom_at": sorted(cut.values()),
        "phantom_keys": sorted(support),
        "honesty_excess": round(excess, 3),
        "looks": m.camera_looks,
        "contacts": m.world.bumps,
    }


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", default="paper-8x8,slanted-8x8,blocked-wall,river-bridges,u-trap,door-wall")
    ap.add_argument("--pilots", default="potential-field,geometric")
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--perception", default="vision")
    ap.add_argument("--time-limit", type=float, default=300.0)
    ap.add_argument("--off", type=float, default=0.3)
    ap.add_argument("--progress", type=float, default=0.3)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--param", action="append", default=[])
    ap.add_argument("--scenarios", default=str(SCENARIOS), help="the folder of the rooms' YAML files")
    a = ap.parse_args(argv)
    overrides = tuple(parse_override(p) for p in a.param)
    jobs = [
        (room, pilot, i, a.perception, a.time_limit, overrides, a.off, a.progress, a.scenarios)
        for room in a.rooms.split(",")
        for pilot in a.pilots.split(",")
        for i in range(a.seeds)
    ]
    rows = []
    with ProcessPoolExecutor(a.jobs) as pool:
        for row in pool.map(audit, jobs):
            rows.append(row)
            print(json.dumps(row), flush=True)
    print(
        "room pilot: runs, reached, mean time (s), phantom lines: beyond 0.3 m / beyond its 70 % cut / beyond its "
        "support (runs with one beyond its cut), longest stall (s), runs with a stall over 60 s, longest "
        "time still (s), runs still over 60 s",
        file=sys.stderr,
    )
    total = [0, 0, 0]
    for room in a.rooms.split(","):
        for pilot in a.pilots.split(","):
            rs = [r for r in rows if r["room"] == room and r["pilot"] == pilot]
            ph = [sum(r[k] for r in rs) for k in ("phantoms", "phantoms_cut", "phantoms_support")]
            total = [t + p for t, p in zip(total, ph)]
            print(
                f"{room} {pilot}: {len(rs)}, {sum(r['outcome'] == 'reached' for r in rs)}, "
                f"{statistics.mean(r['time'] for r in rs):.1f}, {' / '.join(map(str, ph))} "
                f"({sum(r['phantoms_cut'] > 0 for r in rs)}), "
                f"{max(r['stall_s'] for r in rs):.0f}, {sum(r['stall_s'] > 60 for r in rs)}, "
                f"{max(r['still_s'] for r in rs):.0f}, {sum(r['still_s'] > 60 for r in rs)}",
                file=sys.stderr,
            )
    print(
        f"phantom lines in all (beyond 0.3 m / its cut / its support): {' / '.join(map(str, total))}", file=sys.stderr
    )
    dishonest = [r for r in rows if r["honesty_excess"] > 1e-6]
    print(
        f"runs where a remembered point left its support: {len(dishonest)} of {len(rows)}"
        + (f" (worst {max(r['honesty_excess'] for r in dishonest):.3f} m)" if dishonest else ""),
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
