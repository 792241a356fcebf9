"""The two builds (issue 39): the hot modules compiled by mypyc (setup.py) and their pure-Python
sources (``NAVCLI_PURE=1``), which must run the same missions to the last bit; and
``navcli bench --training``'s figures."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest
from typer.testing import CliRunner

import navcli
from conftest import ROOT
from navcli import builds
from navcli.cli import app

LIBRARY = builds.library(os.path.dirname(navcli.__file__))
compiled_only = pytest.mark.skipif(
    LIBRARY is None, reason="no compiled build installed (pure Python only): nothing to compare"
)

# in a child process: which build runs, and where every navcli module came from
WHERE = """
import sys, navcli, navcli.runner, navcli.mission
from navcli import builds
for m in builds.MODULES:
    __import__("navcli." + m)
print(navcli.BUILD)
for name, mod in sorted(sys.modules.items()):
    if name.startswith("navcli.") and getattr(mod, "__file__", None):
        print(name, mod.__file__)
"""


def child_env(pure: bool) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "NAVCLI_PURE"}
    if pure:
        env["NAVCLI_PURE"] = "1"
    return env


def run_child(code: list[str], pure: bool) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, *code],
        cwd=ROOT,
        env=child_env(pure),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


@compiled_only
def test_navcli_pure_runs_every_module_from_its_source_and_the_default_the_compiled_ones():
    pure, compiled = (run_child(["-c", WHERE], p).communicate()[0].splitlines() for p in (True, False))
    assert pure[0] == "pure"
    assert compiled[0] == "compiled", "the compiled modules are older than their sources: `pip install -e .` rebuilds"
    assert all(line.endswith(".py") for line in pure[1:])
    files = dict(line.split(" ", 1) for line in compiled[1:])
    for m in builds.MODULES:
        assert not files[f"navcli.{m}"].endswith(".py"), m
    assert files["navcli.runner"].endswith(".py")  # a module not compiled is its source in both


@compiled_only
def test_the_compiled_build_runs_20_missions_exactly_as_pure_python():
    """benchmarks/trace_digest.py (10 bundled rooms x both pilots, every message of every log
    hashed) under both builds at once: the same digests, or some float operation rounds otherwise
    in C."""
    digest = str(ROOT / "benchmarks" / "trace_digest.py")
    children = [run_child([digest], pure) for pure in (True, False)]
    (pure, err1), (compiled, err2) = (c.communicate() for c in children)
    assert children[0].returncode == 0 and children[1].returncode == 0, err1[-2000:] + err2[-2000:]
    assert pure.count('"paper-8x8/potential-field"') == 1 and len(pure.splitlines()) > 40  # 20 missions' digests
    assert pure == compiled


@compiled_only
def test_the_compiled_modules_worked_examples_hold_in_their_pure_python_sources():
    """The doctests of the compiled modules' sources (which pytest cannot collect from a compiled
    build: conftest.py at the root leaves them to this test), run under NAVCLI_PURE=1."""
    files = [str(ROOT / "navcli" / (m.replace(".", "/") + ".py")) for m in builds.MODULES]
    r = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--doctest-modules", *files],
        cwd=ROOT,
        env=child_env(True),
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-2000:]
    assert " passed" in r.stdout


def test_bench_training_gives_the_learning_tasks_throughput_and_a_whole_trainings_time():
    args = ["bench", "--training", "--trials", "3", "--eval-starts", "2", "--actions", "5", "--jobs", "1"]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    lines = {line.split()[0]: line for line in r.output.splitlines() if line.strip()}
    assert "actions/s" in lines["env.step"] and "5 actions" in lines["env.step"]
    training = lines["training"]
    assert "3 trials in" in training and "evaluation every 3 trials on 2 starts" in training
    # evaluated: the untrained policy, the one after 3 trials, the hand-coded and the random one, 2 starts each
    m = re.search(r"8 evaluation trials: (\d+) run in .* (\d+) taken over", training)
    assert m is not None, training
    run, taken_over = int(m[1]), int(m[2])
    assert run + taken_over == 8 and run >= 6  # the hand-coded and random policies' 4, and the untrained one's 2
    assert "extrapolated" not in r.output
