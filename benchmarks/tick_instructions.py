"""Instructions per tick of a bundled mission with its log, counted by valgrind (not timed: the
count is the same on a busy machine), for speed comparisons between checkouts.

Runs the mission twice, for ``--short`` and ``--long`` simulated seconds, each under
``valgrind --tool=callgrind``, and prints the difference of their instruction counts per tick
between them (start-up, imports and the first ticks cancel out):

    python benchmarks/tick_instructions.py                       # this checkout
    python benchmarks/tick_instructions.py --no-log              # the same mission without its log
    python benchmarks/tick_instructions.py --env                 # a Gym env step (one action), no log
    (cd /tmp/old && PYTHONPATH=/tmp/old python $PWD/benchmarks/tick_instructions.py)   # another

The child runs ``navcli.runner.run_mission`` on ``scenarios/<room>.yaml`` of the checkout whose
navcli is imported, with the seed and pilot given, its log to a temporary file (``--no-log``: none).
``--env`` counts instead the instructions of one action of the Gymnasium environment
(:class:`navcli.envs.LandmarkNavigationEnv` in its default room, actions of a random policy drawn
from ``--seed``, a trial reset when one ends), as the difference between ``--short-actions`` and
``--long-actions`` actions.
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
room, pilot, seed, limit, record, out = sys.argv[1:7]
sc = load_scenario(pathlib.Path(navcli.__file__).parent / "data" / "scenarios" / f"{room}.yaml")
spec = RunSpec.build(sc, pilot=pilot, seed=int(seed), time_limit=float(limit))
run_mission(spec, out=pathlib.Path(out), record=record == "1")
"""

ENV_CHILD = """
import sys, numpy as np
from navcli.envs import LandmarkNavigationEnv
seed, actions = int(sys.argv[1]), int(sys.argv[2])
env = LandmarkNavigationEnv()
rng = np.random.default_rng(seed)
env.reset(seed=seed)
for _ in range(actions):
    _, _, terminated, truncated, _ = env.step(int(rng.integers(5)))
    if terminated or truncated:
        env.reset()
"""


def instructions(args: list[str], child: str = CHILD) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            "valgrind",
            "--tool=callgrind",
            f"--callgrind-out-file={tmp}/cg.out",
            sys.executable,
            "-c",
            child,
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
    ap.add_argument("--no-log", action="store_true", help="run the mission without its log")
    ap.add_argument("--env", action="store_true", help="count a Gym env step (one action) instead")
    ap.add_argument("--short-actions", type=int, default=20)
    ap.add_argument("--long-actions", type=int, default=120)
    a = ap.parse_args()
    if a.env:
        short = instructions([a.seed, str(a.short_actions)], ENV_CHILD)
        long = instructions([a.seed, str(a.long_actions)], ENV_CHILD)
        n = a.long_actions - a.short_actions
        print(
            f"LandmarkNavigationEnv seed {a.seed}: {(long - short) / n / 1e6:.2f} million instructions an action "
            f"(actions {a.short_actions}-{a.long_actions}, random policy, no log)"
        )
        return
    record = "0" if a.no_log else "1"
    short = instructions([a.room, a.pilot, a.seed, str(a.short), record])
    long = instructions([a.room, a.pilot, a.seed, str(a.long), record])
    ticks = round((a.long - a.short) / 0.1)
    print(
        f"{a.room} {a.pilot} seed {a.seed}: {(long - short) / ticks / 1e3:.0f} thousand instructions a tick "
        f"(ticks {a.short:g}-{a.long:g} s, {'without' if a.no_log else 'with'} the log)"
    )


if __name__ == "__main__":
    main()
