"""How large a run's log is, per simulated second, and what writing it costs: for comparing two
commits (or two writer settings) on one machine.

Runs each mission once with its log and once without (``--repeat`` times, alternating), and prints
per mission: the log's bytes, its simulated seconds, bytes per simulated second, the median wall
CPU time of writing it per simulated second (with the log minus without: the recorder's whole
cost, building the messages included; CPU time of this process, so that other work on a shared
machine counts less), and per topic the messages and their uncompressed bytes. It
imports ``navcli`` from the current directory, so run it from each checkout in turn:

    git worktree add /tmp/old <commit>
    (cd /tmp/old && python $PWD/benchmarks/log_size.py); python benchmarks/log_size.py

The missions (``NAME:PILOT:SECONDS``, default ``paper-8x8:potential-field:300``
``trap-box:potential-field:1200``) are bundled scenarios, run with their own seed.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, ".")  # the checkout this is run from, not the installed package

from navcli.config import RunSpec  # noqa: E402
from navcli.runner import run_mission  # noqa: E402
from navcli.scenario import load_scenario  # noqa: E402

MISSIONS = ("paper-8x8:potential-field:300", "trap-box:potential-field:1200")


def topic_bytes(path: Path) -> tuple[Counter, Counter]:
    """Per topic: messages, and their bytes before compression."""
    from mcap.reader import make_reader

    count: Counter = Counter()
    size: Counter = Counter()
    with path.open("rb") as f:
        for _, channel, message in make_reader(f).iter_messages():
            count[channel.topic] += 1
            size[channel.topic] += len(message.data)
    return count, size


def measure(mission: str, repeat: int, folder: Path) -> None:
    name, pilot, seconds = mission.split(":")
    spec = RunSpec.build(load_scenario(f"scenarios/{name}.yaml"), pilot=pilot, time_limit=float(seconds))
    log = folder / f"{name}.mcap"
    walls: dict[bool, list[float]] = {True: [], False: []}
    for _ in range(repeat):
        for record in (True, False):
            t = time.process_time()  # this process's CPU time (the writer compresses in this thread): what other
            res = run_mission(
                spec, out=log, record=record, overwrite=True
            )  # processes on the machine take is not counted
            walls[record].append(time.process_time() - t)
    sim = res.summary["time_s"]
    write = (statistics.median(walls[True]) - statistics.median(walls[False])) / sim
    total = log.stat().st_size
    print(
        f"{name} ({pilot}, {res.summary['outcome']} at {sim:.1f} s): {total:,} bytes, {total / sim:,.0f} bytes "
        f"per simulated s; writing {write * 1e3:.2f} ms per simulated s (median of {repeat}: "
        f"{statistics.median(walls[True]):.2f} s of CPU with the log, {statistics.median(walls[False]):.2f} s without)"
    )
    count, size = topic_bytes(log)
    raw = sum(size.values())
    print(f"  {'topic':20s} {'messages':>9s} {'bytes (uncompressed)':>21s} {'per sim s':>10s}  share")
    for topic, b in size.most_common():
        print(f"  {topic:20s} {count[topic]:9,d} {b:21,d} {b / sim:10,.0f}  {b / raw:5.1%}")
    print(f"  {'all':20s} {sum(count.values()):9,d} {raw:21,d} {raw / sim:10,.0f}  compressed to {total / raw:.1%}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("missions", nargs="*", default=list(MISSIONS), metavar="NAME:PILOT:SECONDS")
    ap.add_argument("--repeat", type=int, default=3, help="runs with and without the log, alternating")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        for mission in args.missions:
            measure(mission, args.repeat, Path(d))


if __name__ == "__main__":
    main()
