"""Instructions per tick of a bundled mission with its log, counted by valgrind (not timed: the
count is the same on a busy machine), for speed comparisons between checkouts.

Runs the mission twice, for ``--short`` and ``--long`` simulated seconds, each under
``valgrind --tool=callgrind``, and prints the difference of their instruction counts per tick
between them (start-up, imports and the first ticks cancel out):

    python benchmarks/tick_instructions.py                       # this checkout
    (cd /tmp/old && PYTHONPATH=/tmp/old python $PWD/benchmarks/tick_instructions.py)   # another

The child runs ``navcli.runner.run_mission`` on ``scenarios/<room>.yaml`` of the checkout whose
navcli is imported, with the seed and pilot given, its log to a temporary file.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = """
import sys, pathlib, navcli
from navcli import RunSpec, load_scenario, run_mission
room, pilot, seed, limit, out = sys.argv[1:6]
sc = load_scenario(pathlib.Path(navcli.__file__).parent / "data" / "scenarios" / f"{room}.yaml")
run_mission(RunSpec.build(sc, pilot=pilot, seed=int(seed), time_limit=float(limit)), out=pathlib.Path(out))
"""


def instructions(args: list[str]) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            "valgrind",
            "--tool=callgrind",
            f"--callgrind-out-file={tmp}/cg.out",
            sys.executable,
            "-c",
            CHILD,
            *args,
            str(Path(tmp) / "run.mcap"),
        ]
        r = subprocess.run(cmd, capture_output=True, text=True, env=os.environ)
        m = re.search(r"Collected : (\d+)", r.stderr)
        if r.returncode != 0 or m is None:
            raise SystemExit(r.stderr[-2000:])
        return int(m.group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--room", default="paper-8x8")
    ap.add_argument("--pilot", default="potential-field")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--short", type=float, default=10.0)
    ap.add_argument("--long", type=float, default=60.0)
    a = ap.parse_args()
    short = instructions([a.room, a.pilot, a.seed, str(a.short)])
    long = instructions([a.room, a.pilot, a.seed, str(a.long)])
    ticks = round((a.long - a.short) / 0.1)
    print(
        f"{a.room} {a.pilot} seed {a.seed}: {(long - short) / ticks / 1e3:.0f} thousand instructions a tick "
        f"(ticks {a.short:g}-{a.long:g} s, with the log)"
    )


if __name__ == "__main__":
    main()
