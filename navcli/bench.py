"""``navcli bench``: how fast a full mission runs, with logging on and off.

Each configuration runs ``repeat`` times in this process after one warm-up run; the report gives
the median real-time factor (simulated seconds per wall second) and the median wall time per
control tick, because a shared machine's noise hits single runs, not medians.
"""

from __future__ import annotations

import statistics
import tempfile
from pathlib import Path
from typing import Callable

from .runner import run_mission
from .scenario import Scenario


def benchmark(sc: Scenario, *, repeat: int = 5, pilot: str | None = None, seed: int | None = None,
              echo: Callable[[str], None] = print) -> dict[str, float]:
    """Print and return the median real-time factor with logging ``on`` and ``off``."""
    results: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "bench.mcap"
        run_mission(sc, seed=seed, pilot=pilot, out=log)  # warm-up: imports, caches
        for label, record in (("logging on", True), ("logging off", False)):
            runs = [run_mission(sc, seed=seed, pilot=pilot, out=log, record=record) for _ in range(repeat)]
            rtf = statistics.median(r.realtime_factor for r in runs)
            us = statistics.median(r.wall_s / max(r.summary["ticks"], 1) * 1e6 for r in runs)
            s = runs[0].summary
            echo(f"{label:12s} {rtf:8.0f}x real time   {us:7.0f} us/tick   "
                 f"({s['pilot']}, {s['outcome']} after {s['time_s']:.1f} s sim, {s['ticks']} ticks, median of {repeat})")
            results[label.split()[1]] = rtf
    return results


def occlusion_benchmark(sizes=(12, 18, 32, 50, 100, 200), echo: Callable[[str], None] = print) -> None:
    """Time the section 5 occlusion test (n x n) as a Python loop and with numpy, on random
    layouts of point and linear obstacles: the measurement behind ``NUMPY_FROM``."""
    import random
    import timeit

    from .perception import KnownObstacle
    from .potential_field import NUMPY_FROM, facing_loop, facing_numpy

    rnd = random.Random(1)
    echo(f"{'obstacles':>9} {'loop us':>9} {'numpy us':>9}   (best of 5 x 200 calls; numpy used from {NUMPY_FROM} on)")
    for n in sizes:
        obs = []
        for i in range(n):
            x, y = rnd.uniform(-4, 4), rnd.uniform(-4, 4)
            b = (x + rnd.uniform(-1, 1), y + rnd.uniform(-1, 1)) if i % 4 == 3 else (x, y)
            obs.append(KnownObstacle(f"o{i}", (x, y), b, 0.02 if i % 4 == 3 else 0.15))
        t = [min(timeit.repeat(lambda f=f: f(obs), number=200, repeat=5)) / 200 * 1e6 for f in (facing_loop, facing_numpy)]
        echo(f"{n:>9} {t[0]:>9.0f} {t[1]:>9.0f}")
