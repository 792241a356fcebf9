"""Each log compression against the log's size and the instructions a tick, for the choice of the
default (docs/howto/speed.md, "How a log is compressed", holds the table this prints).

Every compression of ``navcli.log.compression.COMPRESSIONS`` with a chunk finished every simulated
second (the writer's ``FLUSH_EVERY_NS``, what a hard kill can lose), and the default also with a
chunk every 5 s. Sizes: bundled missions run with their log (at most ``--seconds`` simulated s),
bytes and kB a simulated second. Instructions: ``valgrind --tool=callgrind`` counts a mission of
``--short`` and of ``--long`` simulated seconds, as ``benchmarks/tick_instructions.py`` does, and the
difference per tick is printed (start-up and imports cancel out; the machine's load does not change
the count):

    python benchmarks/log_compression.py                      # paper-8x8 and trap-box, seed 1
    python benchmarks/log_compression.py --no-instructions    # sizes alone, in seconds
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

CHILD = """
import sys, pathlib, navcli
import navcli.log.writer as writer
from navcli import RunSpec, load_scenario, run_mission
room, pilot, seed, limit, compression, flush, out = sys.argv[1:8]
writer.FLUSH_EVERY_NS = int(flush)
sc = load_scenario(pathlib.Path(navcli.__file__).parent / "data" / "scenarios" / f"{room}.yaml")
spec = RunSpec.build(sc, pilot=pilot, seed=int(seed), time_limit=float(limit))
run_mission(spec, out=pathlib.Path(out), log_compression=compression)
print(pathlib.Path(out).stat().st_size)
"""

SECOND = 1_000_000_000


def configurations() -> list[tuple[str, int]]:
    """(compression, ns between finished chunks): every compression at a second, the default at 5 s."""
    from navcli.log.compression import COMPRESSIONS, DEFAULT

    return [(c, SECOND) for c in COMPRESSIONS] + [(DEFAULT, 5 * SECOND)]


def run(args: list[str], callgrind: bool) -> tuple[int, int]:
    """The log's bytes and, under callgrind, the instructions of the child run with ``args``."""
    with tempfile.TemporaryDirectory() as tmp:
        grind = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={tmp}/cg.out"] if callgrind else []
        cmd = [*grind, sys.executable, "-c", CHILD, *args, str(Path(tmp) / "run.mcap")]
        r = subprocess.run(cmd, capture_output=True, text=True, env=os.environ)
        m = re.search(r"Collected : (\d+)", r.stderr)
        if r.returncode != 0 or (callgrind and m is None):
            raise SystemExit(r.stderr[-2000:])
        return int(r.stdout.split()[-1]), int(m.group(1)) if m else 0


def sizes(room: str, pilot: str, seed: str, seconds: float, config: tuple[str, int]) -> str:
    from navcli import load_scenario

    limit = min(seconds, load_scenario(room).mission.time_limit)
    size, _ = run([room, pilot, seed, str(limit), config[0], str(config[1])], callgrind=False)
    return f"{size:,} ({size / limit / 1e3:.1f})"


def instructions(a: argparse.Namespace, config: tuple[str, int]) -> float:
    """Thousands of instructions a tick between the short and the long run."""
    counts = [run([a.room, a.pilot, a.seed, str(s), config[0], str(config[1])], True)[1] for s in (a.short, a.long)]
    return (counts[1] - counts[0]) / round((a.long - a.short) / 0.1) / 1e3


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", nargs="+", default=["paper-8x8", "trap-box"], help="the missions whose logs are sized")
    ap.add_argument("--seconds", type=float, default=120.0, help="simulated seconds of each sized mission, at most")
    ap.add_argument("--room", default="paper-8x8", help="the mission whose instructions are counted")
    ap.add_argument("--pilot", default="potential-field")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--short", type=float, default=10.0)
    ap.add_argument("--long", type=float, default=40.0)
    ap.add_argument("--jobs", type=int, default=2, help="valgrind runs at once")
    ap.add_argument("--no-instructions", action="store_true", help="sizes alone (no valgrind)")
    a = ap.parse_args()
    configs = configurations()
    with ThreadPoolExecutor(a.jobs) as pool:
        counted = None if a.no_instructions else [pool.submit(instructions, a, c) for c in configs]
        sized = {room: [sizes(room, a.pilot, a.seed, a.seconds, c) for c in configs] for room in a.rooms}
        per_tick = [f.result() for f in counted] if counted else None
    rooms = " | ".join(f"{room}: bytes (kB a simulated s)" for room in a.rooms)
    head = f"| compression | chunk every | {rooms} |" + (f" instructions a tick ({a.room}) |" if per_tick else "")
    print(head)
    print("|" + " --- |" * head.count(" |"))
    for i, (compression, flush) in enumerate(configs):
        row = f"| {compression} | {flush // SECOND} s | " + " | ".join(sized[room][i] for room in a.rooms) + " |"
        if per_tick:
            row += f" {per_tick[i]:,.0f}k ({per_tick[i] - per_tick[0]:+,.0f}k) |"
        print(row)
    print(
        f"(sizes: seed {a.seed}, {a.pilot}, at most {a.seconds:g} simulated s; instructions: ticks "
        f"{a.short:g}-{a.long:g} s, against the first row)"
    )


if __name__ == "__main__":
    main()
