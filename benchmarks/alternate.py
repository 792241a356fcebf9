"""Wall time of one navcli command in several checkouts or builds, alternated, with medians and
ratios, and a check that the file each run writes is the same byte for byte in all of them.

    python benchmarks/alternate.py --build base=/tmp/old:pure --build pure=.:pure --build compiled=. \\
        --repeat 3 --same .npz -- train landmarks-12 --trials 60 --eval-every 60 --eval-starts 10 \\
        --seed 1 --jobs 1 --out {out}.npz

Each ``--build NAME=DIR[:pure]`` runs ``python -m navcli`` from checkout ``DIR`` (on
``PYTHONPATH``; ``:pure`` sets ``NAVCLI_PURE=1``, so a compiled checkout runs its pure-Python
modules). The rounds run every build once, in the order given, ``--repeat`` times, so all the
builds see the same drift of the machine's load. ``{out}`` in the command is replaced by a
per-run path (without extension) under a temporary folder; with ``--same SUFFIX`` the files of
that suffix the runs write there are compared across builds and rounds by their SHA-256, and a
difference is reported (exit 1): a model file, not the notes beside it that name the version.
OpenBLAS is held to one thread, as the benchmark does. The first build is the reference of the
ratios (its median over each other build's).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def parse_build(text: str) -> tuple[str, Path, bool]:
    name, sep, where = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=DIR[:pure], got {text!r}")
    folder, _, mode = where.partition(":")
    if mode not in ("", "pure"):
        raise argparse.ArgumentTypeError(f"the build's mode is 'pure' or nothing, got {mode!r}")
    path = Path(folder or ".").resolve()
    if not (path / "navcli" / "__init__.py").is_file():
        raise argparse.ArgumentTypeError(f"{path} holds no navcli checkout")
    return name, path, mode == "pure"


def run(folder: Path, pure: bool, command: list[str]) -> float:
    env = dict(os.environ, PYTHONPATH=str(folder), OPENBLAS_NUM_THREADS="1")
    env.pop("NAVCLI_PURE", None)
    if pure:
        env["NAVCLI_PURE"] = "1"
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "navcli", *command], cwd=folder, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit(f"navcli {' '.join(command)} failed in {folder}:\n{r.stderr[-2000:]}")
    return wall


def digest(files: list[Path]) -> str:
    h = hashlib.sha256()
    for f in sorted(files):
        h.update(f.suffix.encode() + b"\0" + f.read_bytes())
    return h.hexdigest()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", action="append", type=parse_build, required=True, help="NAME=DIR[:pure]")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--same", action="append", default=[], help="a suffix of {out}'s files to hold identical")
    ap.add_argument("command", nargs=argparse.REMAINDER, help="after --: navcli's arguments, {out} for the output")
    a = ap.parse_args()
    command = a.command[1:] if a.command[:1] == ["--"] else a.command
    if not command:
        ap.error("give navcli's arguments after --")
    walls: dict[str, list[float]] = {name: [] for name, _, _ in a.build}
    digests: dict[str, set[str]] = {name: set() for name, _, _ in a.build}
    with tempfile.TemporaryDirectory() as tmp:
        for rnd in range(a.repeat):
            for name, folder, pure in a.build:
                stem = Path(tmp) / f"{name}-{rnd}"
                walls[name].append(run(folder, pure, [c.replace("{out}", str(stem)) for c in command]))
                written = [p for p in Path(tmp).iterdir() if p.name.startswith(stem.name + ".") and p.suffix in a.same]
                if written:
                    digests[name].add(digest(written))
                print(f"round {rnd + 1} {name}: {walls[name][-1]:.2f} s", flush=True)
    ref = a.build[0][0]
    base = statistics.median(walls[ref])
    for name, _, _ in a.build:
        m = statistics.median(walls[name])
        print(f"{name:>12}: median {m:.2f} s of {len(walls[name])}, {base / m:.2f}x {ref}'s speed")
    seen = set().union(*digests.values())
    if len(seen) > 1:
        print(f"the runs' files differ: {len(seen)} different contents ({digests})")
        raise SystemExit(1)
    if seen:
        print(f"every run wrote the same files (sha256 {next(iter(seen))[:16]})")


if __name__ == "__main__":
    main()
