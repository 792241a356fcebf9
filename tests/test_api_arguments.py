"""The Python API checks its arguments: every wrong one refused before any work with a
NavcliError naming the function and the argument; and a command that needs an optional extra
says which to install."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

import navcli
from conftest import SCENARIOS
from navcli.cli import app

ARENA = str(SCENARIOS / "open-arena.yaml")

REFUSED = [
    ("run", (3,), {}, "scenario=3"),
    ("run", (None,), {}, "scenario=None"),
    ("run", ({"arena": {}},), {}, "scenario={'arena': {}}"),
    ("run", (ARENA,), {"params": ["pilot.K", 3]}, "params=['pilot.K', 3]"),
    ("run", (ARENA,), {"params": {3: 1}}, "a parameter name is a str"),
    ("run", (ARENA,), {"log": 123}, "log=123"),
    ("run", (ARENA,), {"log": ""}, "log='': expected a path, got an empty one"),
    ("run", (ARENA,), {"seed": True}, "seed=True: expected a seed (an int); a bool is not one"),
    ("run", (ARENA,), {"seed": 1.5}, "seed=1.5"),
    ("run", (ARENA,), {"seed": -1}, "seed=-1"),
    ("run", (ARENA,), {"time_limit": "10"}, "time_limit='10': expected a number, got str"),
    ("run", (ARENA,), {"time_limit": float("nan")}, "time_limit=nan"),
    ("run", (ARENA,), {"time_limit": 0}, "time_limit=0"),
    ("run", (ARENA,), {"pilot": 7}, "pilot=7"),
    ("run", (ARENA,), {"observers": print}, "observers=<built-in function print>"),
    ("run", (ARENA,), {"observers": [3]}, "observers=[3]: item 0 (3): expected a function"),
    ("run", (ARENA,), {"overwrite": "yes"}, "overwrite='yes'"),
    ("run", (ARENA,), {"sed": 1}, "unexpected keyword argument 'sed'"),
    ("spec", (ARENA,), {"seed": False}, "seed=False"),
    ("spec", (ARENA,), {"also": "geometric"}, "also='geometric': expected a list of pilot names, got str"),
    ("compare", ("open-arena",), {}, "scenarios='open-arena': expected a list of scenarios"),
    ("compare", (Path(ARENA),), {}, "scenarios=PosixPath"),
    (
        "compare",
        ([],),
        {},
        "scenarios=[]: expected a list of scenarios (files, bundled names or Scenarios), got an empty one",
    ),
    ("compare", ([3],), {}, "scenarios=[3]: item 0 (3)"),
    ("compare", ([ARENA], "geometric"), {}, "pilots='geometric': expected a list of pilot names, got str"),
    ("compare", ([ARENA], []), {}, "pilots=[]"),
    ("compare", ([ARENA],), {"reruns": "2"}, "reruns='2'"),
    ("compare", ([ARENA],), {"reruns": 0}, "reruns=0: expected a count of reruns of at least 1"),
    ("compare", ([ARENA],), {"reruns": -3}, "reruns=-3"),
    ("compare", ([ARENA],), {"reruns": True}, "reruns=True"),
    ("compare", ([ARENA],), {"jobs": 0}, "jobs=0: expected a count of worker processes from 1 to 256"),
    ("compare", ([ARENA],), {"jobs": -1}, "jobs=-1"),
    ("compare", ([ARENA],), {"jobs": 2.0}, "jobs=2.0"),
    ("compare", ([ARENA],), {"out": 5}, "out=5"),
    ("compare", ([ARENA],), {"params": [("pilot.K", 3)]}, "params=[('pilot.K', 3)]"),
    ("load_scenario", (3,), {}, "path=3: expected a path"),
    ("parse_scenario", (b"arena: {}",), {}, "text=b'arena: {}': expected the YAML text (a str), got bytes"),
    ("parse_scenario", ("arena: {}",), {"source": None}, "source=None"),
    ("run_mission", (ARENA,), {}, "spec='"),
    ("sweep", (3,), {}, "plan=3"),
    ("sweep", (None,), {}, "plan=None"),
    ("sweep", ("plans/x.yaml",), {"jobs": 0}, "jobs=0"),
]


@pytest.mark.parametrize("name, args, kwargs, words", REFUSED, ids=[w[:40] for *_, w in REFUSED])
def test_a_wrong_argument_is_refused_naming_it(tmp_path, monkeypatch, name, args, kwargs, words):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(navcli.NavcliError) as e:
        getattr(navcli, name)(*args, **kwargs)
    assert str(e.value).startswith(f"navcli.{name}(): "), str(e.value)
    assert words in str(e.value)
    assert isinstance(e.value, TypeError)  # what Python raises for a wrong argument, too
    assert list(tmp_path.iterdir()) == []  # refused before any work


UNCHECKED = {
    "navcli.arbitrate": "called every tick inside a mission: a check per call would cost every run",
    "navcli.param": "a declaration, run once when a plugin's parameter class is made, which checks its default",
}
"""The public functions that take their arguments unchecked, and why (docs/python-api.md says so)."""


def test_every_public_function_is_checked():
    """Every function of navcli's and navcli.analysis's public names (their ``__all__``) has the
    checking wrapper, but those UNCHECKED says why not."""
    import navcli.analysis

    functions = {
        f"{module.__name__}.{name}": getattr(module, name)
        for module in (navcli, navcli.analysis)
        for name in module.__all__
        if inspect.isfunction(getattr(module, name))
    }
    assert len(functions) >= 10 and set(UNCHECKED) <= functions.keys()
    unchecked = sorted(name for name, fn in functions.items() if not hasattr(fn, "__wrapped__"))
    assert unchecked == sorted(UNCHECKED)


def test_an_argument_without_a_declared_check_is_refused_at_definition():
    from navcli.checks.arguments import COMMON, checked

    def f(seed: int, colour: str) -> None: ...

    with pytest.raises(TypeError, match="no check declared for colour"):
        checked(COMMON)(f)


def test_good_arguments_pass_and_a_path_or_tuple_is_as_good_as_a_str_or_list(tmp_path):
    r = navcli.run(Path(ARENA), seed=3, time_limit=1, params={"pilot.K": 20}, observers=(), log=tmp_path / "a.mcap")
    assert r.summary["seed"] == 3 and r.log == tmp_path / "a.mcap" and r.log.exists()
    spec = navcli.spec(navcli.load_scenario(ARENA), seed=4, time_limit=1.0)  # a Scenario
    assert navcli.run(spec).summary["seed"] == 4  # a RunSpec
    df = navcli.compare((ARENA,), ("geometric",), reruns=1, time_limit=1.0, jobs=1)
    assert len(df) == 1 and list(df["pilot"]) == ["geometric"]


def test_run_does_not_replace_a_log_unless_asked(tmp_path):
    log = tmp_path / "run.mcap"
    first = navcli.run(ARENA, seed=1, time_limit=1.0, log=log)
    before = log.read_bytes()
    with pytest.raises(navcli.NavcliError, match=r"exists; a log is not replaced unless asked \(overwrite=True"):
        navcli.run(ARENA, seed=2, time_limit=1.0, log=log)
    assert log.read_bytes() == before
    second = navcli.run(ARENA, seed=2, time_limit=1.0, log=log, overwrite=True)
    assert second.summary["seed"] == 2 and first.summary["seed"] == 1
    assert navcli.analysis.read_log(log).summary["seed"] == 2


EXTRAS = [
    (["bench", "--training", "--trials", "1", "--actions", "1"], "gymnasium", "navcli[gym]"),
    (["tune", ARENA, "--param", "pilot.K=1:2", "--algorithm", "ga"], "deap", "navcli[cluster]"),
    (["tune", ARENA, "--param", "pilot.K=1:2"], "optuna", "navcli[cluster]"),
    (["compare", "pilots", ARENA, "--scheduler", "tcp://127.0.0.1:1"], "distributed", "navcli[cluster]"),
    (["train-rl", ARENA, "--steps", "1"], "torch", "navcli[rl]"),
]


@pytest.mark.parametrize("args, module, extra", EXTRAS, ids=[m for _, m, _ in EXTRAS])
def test_a_command_missing_an_optional_extra_says_what_to_install(tmp_path, monkeypatch, args, module, extra):
    monkeypatch.chdir(tmp_path)
    for name in [m for m in sys.modules if m == module or m.startswith(module + ".")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, module, None)  # as if not installed: importing it raises ImportError
    r = CliRunner().invoke(app, args + ["--out", str(tmp_path / "out")] if args[0] != "bench" else args)
    assert r.exit_code == 2, r.output
    assert f"needs {module}, which is not installed: pip install '{extra}'" in r.output, r.output
    assert "internal error" not in r.output


def test_the_extras_are_read_from_the_packages_metadata():
    from navcli.checks.extras import extra_of, install_hint

    assert (extra_of("gymnasium"), extra_of("optuna"), extra_of("sphinx")) == ("gym", "cluster", "docs")
    assert extra_of("numpy") is None  # a requirement of every install
    assert install_hint("distributed") == "pip install 'navcli[cluster]'"  # brought by dask[distributed]
    assert install_hint("no_such_thing.sub") == "pip install no_such_thing"
