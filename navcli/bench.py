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
