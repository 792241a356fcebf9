"""Mutation testing of the modules whose equations the tests must pin down: each mutant (an operator,
a constant, a comparison of the module changed) should make some test fail.

    pip install -e '.[mutation]'
    python benchmarks/mutation.py                       # the three modules, one at a time
    python benchmarks/mutation.py --module navcli.learning.prioritized_sweeping
    python benchmarks/mutation.py --score               # the scores of what has run, nothing run

mutmut (its configuration: ``[tool.mutmut]`` in pyproject.toml) copies the tree to ``mutants/``
(ignored by git), and runs each mutant against the tests listed there that call the function it
mutates. The modules run one after another (each run uses ``--jobs`` processes), and a rerun only
tests the mutants without a result (delete ``mutants/`` to start again, as after editing a
mutated module). The table gives per module the mutants killed (a test failed), timed out
(counted as killed: the mutant made a test loop), survived, and the score (killed and timed out
over those checked); ``--survivors`` lists each survivor, for ``python -m mutmut show NAME``.
Some 30 mutants a minute on two cores: the three modules take the best part of an hour.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections import Counter
from pathlib import Path

MODULES = ("navcli.pilot.potential_field", "navcli.learning.prioritized_sweeping", "navcli.vision.visual_memory")
ROOT = Path(__file__).resolve().parent.parent
KILLED, SURVIVED, TIMEOUT = {1, 3}, {0}, {36, -24, 24, 152, 255}


def results(module: str) -> dict[str, int | None]:
    """Mutant name -> mutmut's exit code (None: not checked yet) of ``module``'s mutants."""
    meta = ROOT / "mutants" / (module.replace(".", "/") + ".py.meta")
    if not meta.exists():
        return {}
    return json.loads(meta.read_text())["exit_code_by_key"]


def score_line(module: str) -> tuple[str, list[str]]:
    """The module's row of the table and its survivors' names."""
    codes = results(module)
    counts = Counter(
        "killed"
        if c in KILLED
        else "timeout"
        if c in TIMEOUT
        else "survived"
        if c in SURVIVED
        else "unchecked"
        if c is None
        else "other"
        for c in codes.values()
    )
    checked = len(codes) - counts["unchecked"]
    detected = counts["killed"] + counts["timeout"]
    score = f"{100 * detected / checked:5.1f} %" if checked else "    -"
    row = (
        f"{module:40} {len(codes):6} {counts['killed']:7} {counts['timeout']:8} {counts['survived']:9} "
        f"{counts['other']:6} {counts['unchecked']:10}  {score}"
    )
    return row, sorted(n for n, c in codes.items() if c in SURVIVED)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--module", action="append", choices=MODULES, help="only this module (repeatable)")
    ap.add_argument("--jobs", type=int, default=2, help="mutants tested at once")
    ap.add_argument("--score", action="store_true", help="print the scores of what has run; run nothing")
    ap.add_argument("--survivors", action="store_true", help="list the surviving mutants")
    args = ap.parse_args()
    modules = args.module or list(MODULES)
    if not args.score:
        for m in modules:
            cmd = [sys.executable, "-m", "mutmut", "run", "--max-children", str(args.jobs), f"{m}.*"]
            if subprocess.run(cmd, cwd=ROOT).returncode not in (0, 1):
                print(f"mutmut failed on {m}", file=sys.stderr)
                return 2
    print(
        f"{'module':40} {'total':>6} {'killed':>7} {'timeout':>8} {'survived':>9} {'other':>6} {'unchecked':>10}  score"
    )
    for m in modules:
        row, survivors = score_line(m)
        print(row)
        if args.survivors:
            print("".join(f"    {n}\n" for n in survivors), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
