"""The two builds: the hot modules compiled by mypyc (setup.py) and their pure-Python
sources (``NAVCLI_PURE=1``), which must run the same missions to the last bit; and
``navcli bench --training``'s figures."""

from __future__ import annotations

import ast
import importlib.util
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tomllib

import pytest
from typer.testing import CliRunner

import navcli
from conftest import ROOT
from navcli import builds
from navcli.cli import app
from navcli.params import PERCEPTIONS
from navcli.scenario import bundled

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
    assert f"navcli.{builds.SERVO}" in files  # the servo in C, which the pure build leaves out (above)


@compiled_only
def test_the_compiled_build_runs_every_bundled_scenario_exactly_as_pure_python():
    """benchmarks/build_matrix.py's sample: every bundled scenario once (the pilot, the perception
    and the seed in turn; at most 120 simulated s), every message of every log hashed, under both
    builds: the same digests and no run in error, or some float operation rounds otherwise in C, or
    an annotation lies where mypyc checks it. The u-trap run, in full, is one where a landmark id
    meets a variable that mypyc would hold to be a float if the map's edges were typed loosely."""
    matrix = str(ROOT / "benchmarks" / "build_matrix.py")
    crash = "u-trap/geometric/vision/917752063"
    r = subprocess.run(
        [sys.executable, matrix, "--sample", "--time-cap", "120", "--jobs", "2", "--also", crash],
        cwd=ROOT,
        env=child_env(False),
        capture_output=True,
        text=True,
    )
    lines = r.stdout.splitlines()
    assert r.returncode == 0, r.stdout[-4000:] + r.stderr[-2000:]
    missions = [line for line in lines if line.split(":")[0].count("/") == 3]
    scenarios = {line.split("/")[0] for line in missions}
    assert scenarios == set(bundled.names())
    assert {line.split("/")[2] for line in missions} == set(PERCEPTIONS)
    assert lines[-1].startswith(f"{len(bundled.names()) + 1} missions a build (pure against compiled)")
    assert lines[-1].endswith("0 differ; 0 errored")
    # the run that crashed ends as pure Python's did, with the target reached, in both builds
    (ending,) = [line for line in missions if line.startswith(crash)]
    assert ending.count("reached after") == 2, ending


def test_the_install_is_compiled_wherever_it_can_be():
    """With a C compiler and mypyc on the machine, the install has the compiled modules: a plain
    `pip install -e .` that fell back to pure Python (a build requirement missing from pip's build
    environment, say) fails here rather than passing the suite on the reference build alone.
    NAVCLI_PURE_BUILD=1 at the install is the one way to ask for pure Python on such a machine."""
    compiler = shutil.which((sysconfig.get_config_var("CC") or "cc").split()[0])
    if compiler is None or importlib.util.find_spec("mypyc") is None:
        assert navcli.BUILD in ("pure-only", "pure")  # nothing to build with: pure Python, never an error
        return
    if os.environ.get("NAVCLI_PURE_BUILD", "") not in ("", "0"):
        pytest.skip("NAVCLI_PURE_BUILD is set: pure Python asked for")
    assert LIBRARY is not None, (
        f"a C compiler ({compiler}) and mypyc are here, but the install is pure Python: "
        "`python -m pip install -v -e .` says why (look for 'navcli:')"
    )


def test_navcli_version_names_the_build():
    r = CliRunner().invoke(app, ["--version"])
    assert r.exit_code == 0
    assert r.output.strip() == f"navcli {navcli.__version__}, {builds.describe(navcli.BUILD)}"
    assert builds.describe("pure-only").startswith("pure-only (pure Python")
    env = {"NAVCLI_PURE": "1"}
    named = subprocess.run(
        [sys.executable, "-m", "navcli", "--version"], env={**os.environ, **env}, capture_output=True, text=True
    ).stdout
    assert ", pure" in named and "NAVCLI_PURE is set" in named or "pure-only" in named, named


def test_mypy_holds_the_compiled_modules_to_the_stricter_rules():
    """pyproject.toml's stricter mypy section names exactly the compiled modules."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]["overrides"]
    (strict,) = [o for o in config if o.get("disallow_any_generics")]
    assert sorted(strict["module"]) == sorted(f"navcli.{m}" for m in builds.MODULES)
    assert strict["warn_return_any"] and strict["disallow_untyped_calls"] and strict["disallow_untyped_defs"]


def _requirement(spec: str) -> tuple[str, str]:
    name = re.match(r"[A-Za-z0-9_.-]+", spec)
    assert name is not None, spec
    return name[0].lower().replace("_", "-"), spec[name.end() :].split(";")[0].strip()


def test_the_build_environment_has_every_typed_package_the_compiled_modules_use():
    """pip builds in an environment of the build requirements alone. A typed package that a
    compiled module imports must be one of them, with the same range as at run time, or the first
    install types it as Any (and compiles other code than a second install would)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    needs = dict(map(_requirement, project["build-system"]["requires"]))
    runtime = dict(map(_requirement, project["project"]["dependencies"]))
    for name in set(needs) - {"setuptools", "mypy"}:
        assert needs[name] == runtime[name], f"{name}: {needs[name]!r} to build, {runtime[name]!r} to run"
    imported = set()
    for m in builds.MODULES:
        tree = ast.parse((ROOT / "navcli" / (m.replace(".", "/") + ".py")).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                imported |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                imported.add(node.module.split(".")[0])
    typed = set()
    for top in imported - set(sys.stdlib_module_names) - {"navcli"}:
        spec = importlib.util.find_spec(top)
        assert spec is not None and spec.origin is not None, top
        if os.path.isfile(os.path.join(os.path.dirname(spec.origin), "py.typed")):
            typed.add(top)
    assert typed == {"numpy", "pymunk"}  # worked out by hand from the compiled modules' imports
    assert {"numpy", "pymunk", "msgspec"} <= set(needs)  # msgspec: log.format's Struct classes, type-checked too


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
