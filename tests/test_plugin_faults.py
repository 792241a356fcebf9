"""A plugin's faults are the plugin's (navcli.plugins.boundary): whatever its code raises, a call
its signature refuses, what it returns that navcli does not take, and a decision that overruns
robot.decision_limit_s end the run as ``error`` with its log closed, and the command with exit 1
and a line naming the plugin and the file and line in it, never "internal error"; a plugin's own
names cannot break the log's schema, and ``plugins check`` checks a short run's log against its
schemas; file plugins are loaded under a private module name, and again when edited."""

from __future__ import annotations

import json
import math
import signal
import sys
import threading
import time

import jsonschema
import pytest

import navcli
from typer.testing import CliRunner

from navcli import NavcliError
from navcli.analysis.logs import read_log
from navcli.analysis.schemas import log_problems, schema_problems
from navcli.cli import app
from navcli.config import RunSpec
from navcli.plugins import PluginError, boundary, registry
from navcli.plugins.checker import check
from navcli.runner import run_mission
from navcli.scenario import load_scenario
from conftest import SCENARIOS

HEAD = """\
import math
import time

import numpy as np

from navcli.bidding import Bid, Move
from navcli.pilot import Avoidance, Pilot


def helper(t):
    return Move(math.nan, 0.1)  # the line navcli's Move refuses: the fault is here, not in bidding.py
"""

PILOTS = {
    "Signature": "    def avoid(self, beliefs):\n        return Avoidance(None, 0.0, {})\n",
    "ReturnsNone": "    def avoid(self, beliefs, obstacles, request):\n        return None\n",
    "NanMove": "    def avoid(self, beliefs, obstacles, request):\n"
    "        return Avoidance(Move._make((math.nan, math.nan)), 0.5, {})\n",
    "TextBid": "    def avoid(self, beliefs, obstacles, request):\n        return Avoidance(Move(0.0, 0.2), '0.5', {})\n",
    "NumpyInfo": "    def avoid(self, beliefs, obstacles, request):\n"
    "        return Avoidance(None, 0.0, {'turn_deg': np.float64(1.0)})\n",
    "ArrayInfo": "    def avoid(self, beliefs, obstacles, request):\n"
    "        return Avoidance(None, 0.0, {'turn_deg': np.zeros(2)})\n",
    "SneakyMode": "    def avoid(self, beliefs, obstacles, request):\n        return Avoidance(None, 0.0, {'mode': 'sneaky'})\n",
    "Deep": "    def avoid(self, beliefs, obstacles, request):\n        return Avoidance(helper(beliefs.time), 0.5, {})\n",
    "BadExecute": "    def avoid(self, beliefs, obstacles, request):\n        return Avoidance(None, 0.0, {})\n\n"
    "    def execute(self, winner):\n        return (float('inf'), 0.0)\n",
    "Sleeper": "    def avoid(self, beliefs, obstacles, request):\n"
    "        try:\n            time.sleep(30)\n        except Exception:  # a timeout is not an Exception it can swallow\n"
    "            pass\n        return Avoidance(None, 0.0, {})\n",
    "Named": "    name = 'my pilot!'  # its own name: the log's /bids must not see it\n\n"
    "    def avoid(self, beliefs, obstacles, request):\n        return Avoidance(Move(0.3, 0.2), 0.5, {})\n",
}

POLICIES = """

class BidsNone:
    name = "bids-none"

    def __init__(self, setup):
        pass

    def bid(self, s):
        return None


class Impostor:
    name = "impostor"

    def __init__(self, setup):
        pass

    def bid(self, s):
        return [Bid("target-tracker", "motion", Move(0.0, 0.2), 0.5)]


class BadName:
    name = "target tracker"

    def __init__(self, setup):
        pass

    def bid(self, s):
        return []
"""


def plugin_source() -> str:
    return HEAD + "".join(f"\n\nclass {n}(Pilot):\n{body}" for n, body in PILOTS.items()) + POLICIES


def line_of(text: str, source: str, after: str = "") -> int:
    """The 1-based line of ``text`` in ``source``, the first after the line holding ``after``."""
    lines = source.splitlines()
    start = next(i for i, x in enumerate(lines) if after in x) if after else 0
    return next(i for i, x in enumerate(lines) if i >= start and text in x) + 1


@pytest.fixture
def plugin(tmp_path, monkeypatch):
    """The test plugins, in a file named by its path (``faulty.py``)."""
    source = plugin_source()
    (tmp_path / "faulty.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    registry.clear_caches()
    yield tmp_path, source
    registry.clear_caches()


def _room():
    return load_scenario(SCENARIOS / "open-arena.yaml")


def _run_cli(*args):
    return CliRunner().invoke(app, ["run", "open-arena", "--seed", "1", "--time-limit", "3", *args])


COMPILED = {"TextBid": ("raised: TypeError: float object expected; got str", "return Avoidance(Move(0.0, 0.2), '0.5'")}
"""What the compiled build says instead (its Avoidance checks its fields' types when it is made: in the
plugin's own line), where the pure build's boundary finds the fault in what avoid returned."""


@pytest.mark.parametrize(
    "cls, words, at",
    [
        ("Signature", "TypeError: Signature.avoid() takes 2 positional arguments but 4 were given", "def avoid"),
        ("ReturnsNone", "returned None, not a navcli.pilot.Avoidance", "def avoid"),
        ("NanMove", "returned a move that is not two finite numbers: Move(heading=nan, speed=nan)", "def avoid"),
        ("TextBid", "returned a bid of \"'0.5'\", not a finite number".replace('"', ""), "def avoid"),
        ("NumpyInfo", "Expected `float`, got `numpy.float64` - at `$.turn_deg`", "def avoid"),
        ("SneakyMode", "Invalid enum value 'sneaky' - at `$.mode`", "def avoid"),
        ("ArrayInfo", "Expected `float`, got `numpy.ndarray` - at `$.turn_deg`", "def avoid"),
        ("BadExecute", "returned (inf, 0.0), not a wheel command (v, omega) of finite numbers", "def execute"),
    ],
)
def test_a_wrong_return_or_call_is_the_plugins_fault_at_its_method(plugin, cls, words, at):
    folder, source = plugin
    if cls in COMPILED and navcli.BUILD == "compiled":  # mypyc's Avoidance refuses it where it is made
        words, at = COMPILED[cls]
    r = _run_cli("--pilot", f"faulty.py:{cls}", "--out", "x.mcap")
    assert r.exit_code == 1, r.output
    line = r.output.strip().splitlines()[-1]
    assert line.startswith(f"error: the pilot plugin 'faulty.py:{cls}' (module faulty.py, version sha256:"), line
    assert words in line, line
    assert f"faulty.py:{line_of(at, source, f'class {cls}(')}" in line, line  # where its method is defined
    assert "The fault is the plugin's, not navcli's" in line
    assert "internal error" not in r.output and "a bug in navcli" not in r.output
    log = read_log(folder / "x.mcap")  # closed, readable, ended by the plugin's fault
    assert log.summary["outcome"] == "error" and f"'faulty.py:{cls}'" in log.summary["reason"]


def test_a_fault_raised_inside_navcli_from_the_plugins_call_is_placed_at_the_plugins_line(plugin):
    folder, source = plugin
    r = _run_cli("--pilot", "faulty.py:Deep", "--out", "deep.mcap")
    assert r.exit_code == 1, r.output
    # Move's own check (bidding.py) raised it; the innermost frame in the plugin's file is helper's line
    want = f"ValueError: a move needs a finite heading and speed, got nan, 0.1 at faulty.py:{line_of('return Move(math.nan', source)} in helper"
    assert want in r.output and "bidding.py" not in r.output, r.output


def test_a_policy_plugins_wrong_bids_and_names_are_its_faults(plugin):
    folder, source = plugin
    sc = _room()
    with pytest.raises(PluginError, match=r"its bid\(\) \(defined at faulty.py:(\d+)\) returned None, not a list") as e:
        run_mission(RunSpec.build(sc, navigation="agents+faulty.py:BidsNone", time_limit=3.0), out=folder / "p.mcap")
    assert f"faulty.py:{line_of('def bid', source, 'class BidsNone')}" in str(e.value)
    assert read_log(folder / "p.mcap").summary["outcome"] == "error"
    with pytest.raises(PluginError, match="a bid under the name 'target-tracker', not its own 'impostor'"):
        run_mission(RunSpec.build(sc, navigation="faulty.py:Impostor", time_limit=3.0), record=False)
    with pytest.raises(PluginError, match="its agent's name is 'target tracker', not 1 to 64 of"):
        run_mission(RunSpec.build(sc, navigation="faulty.py:BadName", time_limit=3.0), record=False)


def test_a_plugins_own_name_never_reaches_the_logs_bids(plugin):
    folder, _ = plugin
    spec = RunSpec.build(_room(), pilot="faulty.py:Named", time_limit=5.0)
    run_mission(spec, out=folder / "named.mcap")
    bids = 0
    for topic, _, schema, message in _json(folder / "named.mcap"):
        if topic == "/bids":
            bids += 1
            jsonschema.validate(message, schema)  # the schema allows the systems "pilot" and "navigation" only
            assert "my pilot!" not in json.dumps(message)
    assert bids == 50  # 5 s at 10 ticks a second, every one checked
    assert check("pilot", "faulty.py:Named") == []


def _json(path):
    from navcli.analysis.schemas import json_messages

    return json_messages(path)


def test_plugins_check_validates_a_short_runs_log_against_its_schemas(plugin, monkeypatch):
    # Were the boundary to miss a field that breaks /pilot's schema, the checker's run would still see it
    monkeypatch.setattr(boundary, "info_problem", lambda info, kind: None)
    problems = check("pilot", "faulty.py:SneakyMode")
    log = [p for p in problems if "breaks of the log's schemas" in p]
    assert len(log) == 2, problems  # both perceptions' runs
    assert '/pilot at 0.1 s: mode is "sneaky", not one of avoid, idle, reflex' in log[0]
    assert "200 breaks of the log's schemas" in log[0]  # every tick of the 20 s run (10 ticks a second)


def test_the_log_validator_agrees_with_jsonschema(tmp_path):
    log = tmp_path / "a.mcap"
    run_mission(RunSpec.build(_room(), time_limit=3.0), out=log)
    count, problems = log_problems(log)
    assert count > 0 and problems == []
    seen = set()
    for topic, _, schema, message in _json(log):
        if topic in seen:
            continue
        seen.add(topic)
        assert schema_problems(schema, message) == [] and jsonschema.Draft202012Validator(schema).is_valid(message)
        for broken in _breakages(message):
            assert schema_problems(schema, broken) != [], (topic, broken)
            assert not jsonschema.Draft202012Validator(schema).is_valid(broken), (topic, broken)
    assert {"/bids", "/pilot", "/navigation", "/vision", "/mission/summary"} <= seen


def _breakages(message: dict) -> list[dict]:
    """Copies of ``message`` each broken one way: an unknown key, a required key dropped, a number
    made text."""
    out = [message | {"no_such_field": 1}]
    first = next(iter(message))
    out.append({k: v for k, v in message.items() if k != first})
    number = next((k for k, v in message.items() if isinstance(v, float)), None)
    if number is not None:
        out.append(message | {number: "text"})
    return out


def test_a_hung_plugin_is_stopped_by_the_decision_limit_and_its_log_closed(plugin):
    folder, _ = plugin
    spec = RunSpec.build(_room(), pilot="faulty.py:Sleeper", time_limit=3.0, overrides={"robot.decision_limit_s": 0.3})
    t0 = time.monotonic()
    with pytest.raises(PluginError, match=r"took more than robot.decision_limit_s = 0.3 s of wall-clock time"):
        run_mission(spec, out=folder / "hung.mcap")
    assert time.monotonic() - t0 < 10.0  # not the 30 s it sleeps (its except Exception did not swallow the stop)
    log = read_log(folder / "hung.mcap")
    assert log.summary["outcome"] == "error" and "decision_limit_s" in log.summary["reason"]
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # no timer left running


def test_outside_the_main_thread_a_late_decision_is_caught_when_it_returns(plugin):
    # no signal reaches another thread: a call that returns late is caught then
    c = registry.pilot("faulty.py:Named")
    deadline = boundary.Deadline(c, 0.05)
    caught: list[BaseException] = []

    def late():
        try:
            deadline.call(time.sleep, 0.2)
        except PluginError as e:
            caught.append(e)

    t = threading.Thread(target=late)
    t.start()
    t.join()
    assert len(caught) == 1 and isinstance(caught[0], boundary.Overran)
    assert deadline.call(math.sqrt, 4.0) == 2.0  # a quick call passes


def test_another_alarm_pending_is_left_to_come(plugin):
    c = registry.pilot("faulty.py:Named")
    heard = []
    old = signal.signal(signal.SIGALRM, lambda *_: heard.append("theirs"))
    try:
        deadline = boundary.Deadline(c, 5.0)  # puts its handler in front of theirs
        signal.setitimer(signal.ITIMER_REAL, 0.05)
        deadline.call(time.sleep, 0.2)  # theirs pending: the call is timed when it returns instead
        assert heard == ["theirs"]
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)


def test_the_guard_leaves_a_normal_run_as_it_was(plugin, monkeypatch):
    """A well-behaved plugin's run is the same guarded (at any limit) as with the plugin's own class
    made directly, no boundary between it and navcli."""
    from navcli.plugins import boundary

    def trace(limit):
        spec = RunSpec.build(
            _room(), pilot="faulty.py:Named", time_limit=10.0, overrides={"robot.decision_limit_s": limit}
        )
        m = __import__("navcli.mission", fromlist=["Mission"]).Mission(spec, snapshots=False)
        poses = []
        while m.outcome is None:
            t = m.step()
            poses.append((t.pose.x, t.pose.y, t.pose.theta, t.command))
        return poses, type(m.pilot)

    (guarded, cls), (longer, _) = trace(5.0), trace(3600.0)
    monkeypatch.setattr(boundary, "make_pilot", lambda c, limit_s, *args, **kw: c.cls(*args, **kw))
    bare, bare_cls = trace(5.0)
    assert cls is not bare_cls and bare_cls.__name__ == "Named"  # the guarded subclass, then the plugin's own
    assert guarded == longer == bare and len(bare) == 100


def test_a_file_plugin_is_loaded_under_a_private_name(tmp_path, monkeypatch):
    import numpy

    (tmp_path / "numpy.py").write_text("from navcli.pilot import Pilot\n\nclass Shadow(Pilot):\n    pass\n")
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "numpy.py").write_text("from navcli.pilot import Pilot\n\nclass Shadow(Pilot):\n    pass\n")
    monkeypatch.chdir(tmp_path)
    registry.clear_caches()
    a = registry.pilot("numpy.py:Shadow").cls
    b = registry.pilot("other/numpy.py:Shadow").cls
    assert sys.modules["numpy"] is numpy and numpy.zeros(2).shape == (2,)  # the real numpy, untouched
    assert a is not b and a.__module__.startswith("navcli_plugin_") and a.__module__ != b.__module__
    assert sys.modules[a.__module__].__file__ == str((tmp_path / "numpy.py").resolve())


def test_worker_processes_load_a_file_plugin(plugin):
    folder, _ = plugin
    r = CliRunner().invoke(
        app,
        ["compare", "pilots", "open-arena", "--reruns", "2", "--pilots", "faulty.py:Named,geometric"]
        + ["--jobs", "2", "--time-limit", "3", "--out", "cmp"],
    )
    assert r.exit_code == 0, r.output
    rows = (folder / "cmp" / "runs.csv").read_text().splitlines()[1:]
    mine = [row for row in rows if ",faulty.py:Named," in row]
    assert len(mine) == 2 and all(",timeout," in row for row in mine), rows  # run to their end, none errored


def test_the_registry_sees_an_edited_file_plugin(plugin):
    folder, source = plugin
    first = registry.pilot("faulty.py:Named")
    assert registry.pilot("faulty.py:Named") is first  # unchanged: found once
    (folder / "faulty.py").write_text(source.replace("name = 'my pilot!'", "name = 'edited'\n    version = '2.0'"))
    again = registry.pilot("faulty.py:Named")
    assert again.version == "2.0" and again.cls is not first.cls and again.cls.name == "edited"
    assert again.cls.__module__ == first.cls.__module__  # the same private name, holding the new module


def test_an_edited_module_plugin_is_refused_where_it_cannot_be_reloaded(plugin, monkeypatch):
    folder, source = plugin
    monkeypatch.setattr(sys, "path", list(sys.path))
    (folder / "faultymod.py").write_text(source)
    sys.modules.pop("faultymod", None)
    try:
        c = registry.pilot("faultymod:Named")
        assert registry.pilot("faultymod:Named") is c
        (folder / "faultymod.py").write_text(source + "\n# edited\n")
        with pytest.raises(PluginError, match="has changed since this process loaded it"):
            registry.pilot("faultymod:Named")
    finally:
        sys.modules.pop("faultymod", None)


def test_plugins_check_runs_a_policy_through_the_same_boundary(plugin):
    folder, source = plugin
    problems = check("policy", "faulty.py:BidsNone")
    at = line_of("def bid", source, "class BidsNone")
    assert problems and all(f"its bid() (defined at faulty.py:{at}) returned None, not a list" in p for p in problems)
    assert check("policy", "faulty.py:BadName")[0].startswith("cannot be made as navcli makes it")


def test_a_subclass_of_a_compiled_pilot_is_refused_saying_why_in_the_compiled_build(tmp_path, monkeypatch):
    # the potential-field pilot's module is compiled (navcli.builds.MODULES); the geometric pilot's is not
    (tmp_path / "geo.py").write_text(
        "from navcli.pilot import PotentialFieldPilot\n\nclass Geo(PotentialFieldPilot):\n    pass\n"
    )
    monkeypatch.chdir(tmp_path)
    registry.clear_caches()
    if navcli.BUILD != "compiled":  # pure Python: any pilot may be subclassed
        assert registry.pilot("geo.py:Geo").cls.__mro__[1].__name__ == "PotentialFieldPilot"
        return
    with pytest.raises(
        NavcliError, match="it subclasses navcli.pilot.potential_field.PotentialFieldPilot, which this build"
    ):
        registry.pilot("geo.py:Geo")
