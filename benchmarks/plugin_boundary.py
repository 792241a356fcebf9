"""What guarding a plugin's calls costs a control tick (navcli.plugins.boundary): the same plugin
pilot (its ``avoid`` the potential-field pilot's, with its ``/pilot`` fields)
run as navcli runs a plugin, every call guarded and its result checked, against the bare class
navcli would run without the boundary, alternated, over the same mission.

    python benchmarks/plugin_boundary.py [--scenario paper-8x8] [--seconds 120] [--rounds 5]
    python benchmarks/plugin_boundary.py --instructions --seconds 40     # valgrind's count instead

Prints each variant's microseconds per tick in its fastest round (the machine's load only adds) and their difference, and the
boundary's own share measured directly (the check of one ``avoid`` result and one guarded call,
timed with ``timeit``). Runs without a log (``Mission.step`` only), so the difference is the
boundary's and not the recorder's.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from navcli.config import RunSpec  # noqa: E402
from navcli.mission import Mission  # noqa: E402
from navcli.plugins import boundary, registry  # noqa: E402
from navcli.scenario import load_scenario  # noqa: E402

PLUGIN = """
from navcli.pilot import Pilot, PotentialFieldPilot


class Paper(Pilot):
    def __init__(self, params, robot, *, own_params=None, rng=None):
        super().__init__(params, robot, own_params=own_params, rng=rng)
        self.field = PotentialFieldPilot(params, robot)

    def avoid(self, beliefs, obstacles, request):
        return self.field.avoid(beliefs, obstacles, request)
"""
"""The plugin: a plugin pilot (a subclass of ``Pilot``, as the compiled build allows) whose ``avoid``
is the paper's potential field's."""


def ticks_us(spec: RunSpec, bare: bool) -> float:
    """Microseconds per tick of ``spec``'s mission; ``bare``: its pilot made from the plugin's class
    itself, not from the guarded subclass navcli runs a plugin as."""
    m = Mission(spec, snapshots=False)
    if bare:
        c = registry.pilot(spec.pilot)
        p = spec.params
        m.pilot = c.cls(p.pilot, p.robot)
    t0 = time.perf_counter()
    while m.outcome is None:
        m.step()
    return (time.perf_counter() - t0) / m.ticks * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper-8x8")
    ap.add_argument("--seconds", type=float, default=120.0, help="simulated seconds of each mission")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument(
        "--instructions",
        action="store_true",
        help="count instructions a tick under valgrind instead (the same on a busy machine): each variant "
        "run for 10 s and for --seconds, the difference divided by the ticks between",
    )
    ap.add_argument("--only", choices=("bare", "guarded"), help=argparse.SUPPRESS)  # one mission, for valgrind
    a = ap.parse_args()
    sc = load_scenario(ROOT / "scenarios" / f"{a.scenario}.yaml")
    folder = Path(tempfile.mkdtemp(prefix="navcli-bench-"))
    (folder / "paper.py").write_text(PLUGIN)
    spec = RunSpec.build(sc, pilot=f"{folder / 'paper.py'}:Paper", time_limit=a.seconds, perception="vision")
    if a.only:
        ticks_us(spec, bare=a.only == "bare")
        return
    if a.instructions:
        counted(a)
        return
    runs: dict[str, list[float]] = {"bare": [], "guarded": []}
    ticks_us(spec, bare=False)  # warm-up: imports, caches
    for _ in range(a.rounds):
        for name in runs:
            runs[name].append(ticks_us(spec, bare=name == "bare"))
    bare, guarded = (min(runs[n]) for n in ("bare", "guarded"))
    print(f"{a.scenario}, {a.seconds:g} s, {a.rounds} rounds: the fastest round's us per tick (the least disturbed)")
    print(f"  bare     {bare:8.1f}")
    print(f"  guarded  {guarded:8.1f}  ({guarded - bare:+.1f} us, {100 * (guarded / bare - 1):+.1f} %)")
    direct(spec)


def counted(a: argparse.Namespace) -> None:
    """Instructions a tick of each variant, by valgrind's callgrind (start-up cancels out between a
    10 s mission and a --seconds one)."""
    import os
    import re
    import subprocess

    def count(variant: str, seconds: float) -> int:
        with tempfile.TemporaryDirectory() as tmp:
            cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={tmp}/cg.out", sys.executable, __file__]
            cmd += ["--scenario", a.scenario, "--seconds", str(seconds), "--only", variant]
            r = subprocess.run(cmd, capture_output=True, text=True, env=os.environ)
            m = re.search(r"Collected : (\d+)", r.stderr)
            if r.returncode != 0 or m is None:
                raise SystemExit(r.stderr[-2000:])
            return int(m.group(1))

    ticks = round((a.seconds - 10.0) / 0.1)
    per = {v: (count(v, a.seconds) - count(v, 10.0)) / ticks for v in ("bare", "guarded")}
    print(f"{a.scenario}, ticks 10-{a.seconds:g} s: instructions a tick")
    print(f"  bare     {per['bare']:10.0f}")
    print(
        f"  guarded  {per['guarded']:10.0f}  ({per['guarded'] - per['bare']:+.0f}, {100 * (per['guarded'] / per['bare'] - 1):+.1f} %)"
    )


def direct(spec: RunSpec) -> None:
    """The boundary's own cost, timed alone: one ``avoid`` result checked, one call guarded."""
    from navcli.pilot import Avoidance
    from navcli.bidding import Move

    c = registry.pilot(spec.pilot)
    schemas = boundary.info_type(c)
    a = Avoidance(Move(0.1, 0.3), 0.5, {"turn_deg": 3.0, "in_distress": False, "net": {"x": 1.0, "y": 0.5}})
    n = 200_000
    check = timeit.timeit(lambda: boundary.avoidance_problem(a, 0.9, 0.3, schemas), number=n) / n * 1e6
    deadline = boundary.Deadline(c, 5.0)
    call = timeit.timeit(lambda: deadline.call(int), number=n) / n * 1e6
    bare = timeit.timeit(lambda: int(), number=n) / n * 1e6
    print(f"  one avoid result checked: {check:.2f} us; one call guarded: {call - bare:.2f} us over the bare call")


if __name__ == "__main__":
    main()
