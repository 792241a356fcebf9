"""The two builds against each other: every bundled scenario x both pilots x both perceptions x
seeds, each mission run to its end under the compiled build and under pure Python, every message
of every log hashed (``trace_digest.digest``). The builds must give the same digests and neither
may end a run in an error.

    python benchmarks/build_matrix.py                 # the whole matrix: 15 x 2 x 2 x 3 = 180 missions a build
    python benchmarks/build_matrix.py --sample --time-cap 120   # each scenario once (tests/test_builds.py)

``--sample`` runs every scenario once, the pilot, the perception and the seed turning over from one
scenario to the next so that each pilot and each perception meet several rooms; ``--also
SCENARIO/PILOT/PERCEPTION/SEED`` adds one mission, run to its end (a run known to tell the builds
apart when an annotation lies). ``--time-cap`` shortens every other mission to at most that many simulated seconds (the
default: each scenario's own time limit, the run to its end).

It prints one line a mission with its outcome under each build, then the verdict, and exits 1 when
a mission's digests differ or a mission errored under either build, 0 otherwise. The missions
run on ``--jobs`` worker processes a build (default: the cores, shared by the two builds, which run
one after the other). It needs the compiled build installed (``python -m pip install -e .``).
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import subprocess
import sys
import tempfile
import traceback
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
PILOTS = ("potential-field", "geometric")


def configurations(sample: bool, seeds: int, also: list[str]) -> list[str]:
    """The missions, as ``scenario/pilot/perception/seed`` keys."""
    from navcli.params import PERCEPTIONS
    from navcli.scenario import bundled

    names = bundled.names()
    if sample:
        turns = itertools.cycle(itertools.product(PILOTS, PERCEPTIONS, range(1, seeds + 1)))
        keys = [f"{n}/{p}/{q}/{s}" for n, (p, q, s) in zip(names, turns)]
    else:
        keys = [f"{n}/{p}/{q}/{s}" for n in names for p in PILOTS for q in PERCEPTIONS for s in range(1, seeds + 1)]
    return keys + [k for k in also if k not in keys]


def one(key: str, cap: float | None) -> dict[str, str]:
    """Run one mission in this process's build: its outcome and its log's digest, or its error."""
    from navcli import RunSpec, load_scenario, run_mission
    from navcli.scenario import bundled
    from trace_digest import digest

    name, pilot, perception, seed = key.split("/")
    try:
        sc = load_scenario(bundled.path(name))
        limit = sc.mission.time_limit if cap is None else min(sc.mission.time_limit, cap)
        spec = RunSpec.build(sc, pilot=pilot, perception=perception, seed=int(seed), time_limit=limit)
        with tempfile.TemporaryDirectory() as tmp:
            log = Path(tmp) / "run.mcap"
            r = run_mission(spec, out=log)
            topics = digest(log)
        outcome = f"{r.summary['outcome']} after {r.summary['time_s']:.1f} s"
        return {"key": key, "outcome": outcome, "digest": json.dumps(topics, sort_keys=True)}
    except Exception as e:  # a crash is a result here: the other build may not have it
        where = traceback.extract_tb(e.__traceback__)[-1]
        error = f"error: {type(e).__name__}: {e} ({Path(where.filename).name}:{where.lineno})"
        return {"key": key, "outcome": error, "digest": ""}


def child(missions: list[tuple[str, float | None]], jobs: int) -> None:
    """In one build's process: run the missions, print a JSON line each, the build first."""
    import navcli

    print(json.dumps({"build": navcli.BUILD}), flush=True)
    with ProcessPoolExecutor(jobs) as pool:
        for result in pool.map(one, *zip(*missions)):
            print(json.dumps(result), flush=True)


def run_build(pure: bool, jobs: int, missions: list[tuple[str, float | None]]) -> tuple[str, dict[str, dict[str, str]]]:
    env = {k: v for k, v in os.environ.items() if k != "NAVCLI_PURE"}
    if pure:
        env["NAVCLI_PURE"] = "1"
    cmd = [sys.executable, __file__, "--child", json.dumps(missions), "--jobs", str(jobs)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        sys.exit(f"the {'pure' if pure else 'compiled'} build's missions failed to run:\n{out.stderr[-3000:]}")
    lines = [json.loads(line) for line in out.stdout.splitlines()]
    return lines[0]["build"], {r["key"]: r for r in lines[1:]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--child", help=argparse.SUPPRESS)  # the missions as JSON, for one build's process
    ap.add_argument("--sample", action="store_true", help="each scenario once, pilot, perception and seed in turn")
    ap.add_argument("--seeds", type=int, default=3, help="seeds 1..N (default 3)")
    ap.add_argument("--time-cap", type=float, default=None, help="at most this many simulated seconds a mission")
    ap.add_argument("--also", action="append", default=[], metavar="SCENARIO/PILOT/PERCEPTION/SEED")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes a build")
    args = ap.parse_args()
    if args.child:
        child([(k, cap) for k, cap in json.loads(args.child)], args.jobs)
        return 0
    keys = configurations(args.sample, args.seeds, args.also)
    missions = [(k, None if k in args.also else args.time_cap) for k in keys]
    (pure_build, pure), (compiled_build, compiled) = (run_build(p, args.jobs, missions) for p in (True, False))
    if compiled_build != "compiled":
        sys.exit(f"the compiled build does not run here (navcli.BUILD is {compiled_build!r}): nothing to compare")
    differ = [k for k in keys if pure[k]["digest"] != compiled[k]["digest"]]
    errored = [k for k in keys if pure[k]["outcome"].startswith("error") or compiled[k]["outcome"].startswith("error")]
    for k in keys:
        mark = "DIFFERS " if k in differ else ""
        print(f"{mark}{k}: pure {pure[k]['outcome']}; compiled {compiled[k]['outcome']}")
    print(
        f"{len(keys)} missions a build ({pure_build} against {compiled_build}): "
        f"{len(keys) - len(differ)} trace-identical, {len(differ)} differ; {len(errored)} errored"
    )
    return 1 if differ or errored else 0


if __name__ == "__main__":
    sys.exit(main())
