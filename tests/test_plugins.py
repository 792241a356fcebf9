"""Plugins (navcli.plugins): a pilot or a Navigation policy of one's own, found by its installed
package's entry point or as module:Class from a plain folder, run by every command that takes a
name, its parameters declared and overridden like navcli's, its /pilot fields declared in the
log's schema, its identity in the run id, its failures reported as its own, and the checker."""

from __future__ import annotations

import json
import sys

import jsonschema
import pytest
from mcap.reader import make_reader
from typer.testing import CliRunner

from conftest import SCENARIOS, module_in_folder
from navcli import NavcliError
from navcli.analysis import read_log
from navcli.cli import app
from navcli.config import RunSpec
from navcli.plugins import PluginError, UnknownPlugin, registry
from navcli.plugins.checker import check
from navcli.scenario import load_scenario

SWERVE = '''
"""A test pilot: it turns away from what lies ahead, else lets the request through."""

import math
import random
from dataclasses import dataclass
from typing import Annotated

import msgspec

from navcli.bidding import Bid, Move
from navcli.params import ParamSet, param
from navcli.pilot import Avoidance, Pilot


@dataclass(frozen=True)
class SwerveParams(ParamSet):
    swerve_deg: float = param(40.0, "deg", "how far to turn from an obstacle ahead", at_most=90.0)
    reach_m: float = param(1.0, "m", "how far ahead an obstacle is looked for", above=0.0)


class SwerveInfo(msgspec.Struct):
    ahead: Annotated[int, msgspec.Meta(description="obstacles within reach ahead")]


class Swerve(Pilot):
    Params = SwerveParams
    Info = SwerveInfo

    def avoid(self, beliefs, obstacles, request):
        p = self.own_params
        ahead = [o for o in obstacles if 0 < o.centre[0] < p.reach_m and abs(o.centre[1]) < 0.5]
        if not ahead:
            return Avoidance(None, 0.0, {"ahead": 0})
        return Avoidance(Move(math.radians(p.swerve_deg), self.max_speed), self.params.bid_cap,
                         {"ahead": len(ahead), "turn_deg": p.swerve_deg})


class Broken(Swerve):
    def avoid(self, beliefs, obstacles, request):
        if beliefs.time > 1.0:
            return self.divide(beliefs.time)
        return super().avoid(beliefs, obstacles, request)

    def divide(self, t):
        return t / 0


class Chatty(Swerve):
    Info = None  # and yet it writes "ahead" into /pilot


class Greedy(Swerve):
    def avoid(self, beliefs, obstacles, request):
        a = super().avoid(beliefs, obstacles, request)
        return Avoidance(Move(random.uniform(-1, 1), self.max_speed), 1.0, a.info)  # above the cap, unseeded


class Unseeded(Swerve):
    def avoid(self, beliefs, obstacles, request):
        a = super().avoid(beliefs, obstacles, request)  # within the cap: only its randomness is wrong
        return Avoidance(Move(random.uniform(-1, 1), self.max_speed), self.params.bid_cap, a.info)


class NotAPilot:
    pass


class GoStraight:
    """A Navigation policy: head for the target at full speed, look nowhere."""

    def __init__(self, setup):
        self.name = "go-straight"
        self.speed = setup.params.robot.max_speed

    def bid(self, s):
        return [] if s.bearing is None else [Bid(self.name, "motion", Move(s.bearing, self.speed), 0.5)]
'''


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A plain folder holding the test plugins' module (``swerve.py``), as the current folder."""
    yield from module_in_folder(tmp_path, monkeypatch, "swerve", SWERVE)


def _room(folder):
    """A short mission with an obstacle in the way: open-arena with a post on the straight way."""
    text = (SCENARIOS / "open-arena.yaml").read_text()
    return load_scenario(
        _write(
            folder / "room.yaml",
            text.replace("\nmission:", "\nobstacles:\n  - circle: {center: [1.8, 2.25], radius: 0.15}\nmission:"),
        )
    )


def _write(path, text):
    path.write_text(text)
    return path


def _messages(path, topic):
    with open(path, "rb") as f:
        for schema, _, message in make_reader(f).iter_messages(topics=[topic]):
            yield json.loads(schema.data), json.loads(message.data)


def test_a_module_class_pilot_from_a_plain_folder_runs_with_its_parameters_and_fields(folder):
    r = CliRunner().invoke(
        app,
        [
            "run",
            "room.yaml" if _room(folder) else "",
            "--pilot",
            "swerve:Swerve",
            "--perception",
            "oracle",
            "--time-limit",
            "8",
            "--param",
            "Swerve.swerve_deg=30",
            "--out",
            "swerve.mcap",
        ],
    )
    assert r.exit_code in (0, 3), r.output
    log = read_log(folder / "swerve.mcap")
    assert log.summary["pilot"] == "swerve:Swerve"
    config = log.config
    assert config["plugins"][0] | {"version": "?"} == {
        "role": "pilot",
        "name": "swerve:Swerve",
        "version": "?",
        "origin": "module swerve",
        "params": {"swerve_deg": 30.0, "reach_m": 1.0},
    }
    assert config["plugins"][0]["version"].startswith("sha256:")  # no version declared: its source's hash
    msgs = list(_messages(folder / "swerve.mcap", "/pilot"))
    schema = msgs[0][0]
    assert schema["title"] == "navcli.Pilot+Swerve" and "ahead" in schema["properties"]
    assert "declared by the plugin (module swerve" in schema["description"]
    v = jsonschema.Draft202012Validator(schema)
    assert all(not list(v.iter_errors(m)) for _, m in msgs)
    assert any(m.get("ahead", 0) > 0 and m.get("turn_deg") == 30.0 for _, m in msgs)  # it met the post, swerved


def test_a_plugins_parameters_are_listed_checked_and_in_the_run_configuration(folder):
    r = CliRunner().invoke(app, ["params", "room.yaml" if _room(folder) else "", "--param", "Swerve.reach_m=2"])
    assert r.exit_code == 2 and "unknown parameter 'Swerve.reach_m'" in r.output  # the scenario's pilot has none
    sc = _room(folder)
    spec = RunSpec.build(sc, pilot="swerve:Swerve", overrides={"Swerve.reach_m": 2})
    assert spec.params.plugin("Swerve").reach_m == 2.0 and spec.to_json()["params"].keys() == {
        "robot",
        "pilot",
        "navigation",
        "vision",
        "learning",
    }
    with pytest.raises(NavcliError, match="Swerve.swerve_deg must be at most 90, got 95"):
        RunSpec.build(sc, pilot="swerve:Swerve", overrides={"Swerve.swerve_deg": 95})
    assert RunSpec.from_json(spec.to_json(), sc.text) == spec


def test_a_plugin_and_a_stock_pilot_never_share_a_run_id(folder):
    sc = _room(folder)
    stock = RunSpec.build(sc, pilot="potential-field")
    mine = RunSpec.build(sc, pilot="swerve:Swerve")
    assert stock.run_id != mine.run_id and "plugins" not in stock.to_json()
    assert stock.log_name() != mine.log_name()
    (folder / "swerve.py").write_text(SWERVE + "\n# edited\n")  # another version of the same plugin
    sys.modules.pop("swerve", None)
    registry.clear_caches()
    assert RunSpec.build(sc, pilot="swerve:Swerve").run_id != mine.run_id


def test_an_installed_package_is_found_by_its_entry_point(folder, monkeypatch):
    site = folder / "site"
    (site / "swerve_pkg").mkdir(parents=True)
    (site / "swerve_pkg" / "__init__.py").write_text(SWERVE)
    info = site / "swerve_pkg-1.2.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: swerve-pkg\nVersion: 1.2.0\n")
    (info / "entry_points.txt").write_text(
        "[navcli.pilots]\nswerve = swerve_pkg:Swerve\nbad = swerve_pkg:NotAPilot\n"
        "[navcli.policies]\nstraight = swerve_pkg:GoStraight\n"
    )
    monkeypatch.syspath_prepend(str(site))
    registry.entry_points.cache_clear()
    r = CliRunner().invoke(app, ["plugins", "list"])
    assert r.exit_code == 0, r.output
    assert (
        "pilot   swerve                   1.2.0        entry point swerve = swerve_pkg:Swerve of swerve-pkg 1.2.0; "
        "parameters swerve.swerve_deg, swerve.reach_m" in r.output
    )
    assert "pilot   bad                      cannot be used:" in r.output
    c = registry.pilot("swerve")
    assert (c.version, c.group) == ("1.2.0", "swerve")
    with pytest.raises(PluginError, match="is no pilot: <class 'swerve_pkg.NotAPilot'> is not a subclass"):
        registry.pilot("bad")  # an installed package that is broken: its fault, exit 1
    r = CliRunner().invoke(
        app,
        [
            "run",
            str(_room(folder).source),
            "--pilot",
            "swerve",
            "--navigation",
            "straight",
            "--time-limit",
            "3",
            "--param",
            "swerve.reach_m=1.5",
            "--out",
            "ep.mcap",
        ],
    )
    assert r.exit_code in (0, 3), r.output
    plugins = read_log(folder / "ep.mcap").config["plugins"]
    assert [(p["role"], p["name"], p["version"]) for p in plugins] == [
        ("pilot", "swerve", "1.2.0"),
        ("navigation", "straight", "1.2.0"),
    ]


def test_an_unknown_name_is_refused_saying_where_it_was_looked_for(folder):
    sc = str(_room(folder).source)
    for args, words in (
        (
            ["--pilot", "no-such-pilot"],
            "unknown pilot 'no-such-pilot': not one of navcli's "
            "(potential-field, geometric), not an entry point navcli.pilots "
            "of an installed package",
        ),
        (["--pilot", "nosuch:Pilot"], "no module 'nosuch' among the installed packages or in the current folder"),
        (["--pilot", "swerve:NotAPilot"], "is not a subclass of navcli.pilot.Pilot"),
        (["--navigation", "agents+nope"], "unknown navigation policy 'nope'"),
    ):
        r = CliRunner().invoke(app, ["run", sc, *args, "--out", "x.mcap"])
        assert r.exit_code == 2 and words in r.output and "Traceback" not in r.output, r.output
        assert not (folder / "x.mcap").exists()


def test_a_plugin_that_raises_exits_1_with_its_name_and_leaves_a_log_marked_error(folder):
    r = CliRunner().invoke(
        app, ["run", str(_room(folder).source), "--pilot", "swerve:Broken", "--time-limit", "5", "--out", "broken.mcap"]
    )
    assert r.exit_code == 1, r.output
    line = r.output.strip().splitlines()[-1]
    assert line.startswith("error: the pilot plugin 'swerve:Broken' (module swerve, version sha256:")
    assert "raised: ZeroDivisionError: float division by zero at swerve.py:" in line and "in divide" in line
    assert "not navcli's" in line and "navcli plugins check pilot swerve:Broken" in line
    assert "internal error" not in r.output and "a bug in navcli" not in r.output
    log = read_log(folder / "broken.mcap")  # closed, readable
    assert log.summary["outcome"] == "error" and "the pilot plugin 'swerve:Broken'" in log.summary["reason"]
    assert log.summary["time_s"] == pytest.approx(1.1)


def test_a_plugin_pilot_that_writes_undeclared_fields_is_stopped_as_its_fault(folder):
    with pytest.raises(PluginError, match="wrote ahead into /pilot, which its Info does not declare"):
        from navcli.runner import run_mission

        run_mission(RunSpec.build(_room(folder), pilot="swerve:Chatty", time_limit=2.0), out=folder / "c.mcap")
    assert read_log(folder / "c.mcap").summary["outcome"] == "error"


def test_the_checker_passes_a_good_plugin_and_lists_what_a_bad_one_gets_wrong(folder):
    assert check("pilot", "swerve:Swerve") == []
    assert check("policy", "swerve:GoStraight") == []
    greedy = check("pilot", "swerve:Greedy")
    assert any("a motion bid of 1, above the Pilot's cap 0.9" in p for p in greedy)
    unseeded = check("pilot", "swerve:Unseeded")  # draws from the global generator, not self.rng
    assert len(unseeded) == 1 and "two instances fed the same situations decided differently" in unseeded[0], unseeded
    chatty = check("pilot", "swerve:Chatty")
    assert any("its /pilot message breaks the schema" in p and "ahead" in p for p in chatty), chatty
    assert check("pilot", "swerve:NotAPilot")[0].startswith("<class 'swerve.NotAPilot'> is not a subclass")
    r = CliRunner().invoke(app, ["plugins", "check", "pilot", "swerve:Chatty"])
    assert r.exit_code == 1 and "problem:" in r.output
    r = CliRunner().invoke(app, ["plugins", "check", "pilot", "swerve:Swerve"])
    assert r.exit_code == 0 and "passes navcli's checks of a pilot" in r.output


def test_a_policy_plugin_drives_alone_or_beside_the_bidding_agents(folder):
    from navcli.runner import run_mission

    sc = _room(folder)
    alone = run_mission(RunSpec.build(sc, navigation="swerve:GoStraight", time_limit=4.0), record=False)
    assert alone.summary["navigation"] == "swerve:GoStraight"
    both = RunSpec.build(sc, navigation="agents+swerve:GoStraight", time_limit=4.0)
    out = folder / "both.mcap"
    run_mission(both, out=out)
    agents = set().union(*(m["agents"] for _, m in _messages(out, "/navigation")))
    assert {"go-straight", "target-tracker"} <= agents
    with pytest.raises(UnknownPlugin, match="stand alone"):
        RunSpec.build(sc, navigation="hand-coded+swerve:GoStraight")


def test_compare_sweep_and_tune_take_a_plugin_pilot_and_its_parameters(folder):
    room = str(_room(folder).source)
    r = CliRunner().invoke(
        app,
        [
            "compare",
            "pilots",
            room,
            "--pilots",
            "swerve:Swerve,geometric",
            "--reruns",
            "1",
            "--jobs",
            "1",
            "--time-limit",
            "4",
            "--param",
            "Swerve.reach_m=0.8",
            "--out",
            "cmp",
        ],
    )
    assert r.exit_code == 0, r.output
    assert "| swerve:Swerve |" in r.output and "| geometric |" in r.output
    (folder / "plan.yaml").write_text(
        "version: 1\nscenarios: [room.yaml]\nseeds: 1\ntime_limit: 3\n"
        "pilots: [swerve:Swerve, geometric]\ngrid: {Swerve.swerve_deg: [20, 60]}\n"
    )
    r = CliRunner().invoke(app, ["sweep", "plan.yaml", "--jobs", "1", "--out", "sw"])
    assert r.exit_code == 0, r.output
    import pandas as pd

    rows = pd.read_parquet(folder / "sw" / "results.parquet")
    # the plugin's own parameter varies its runs only: the geometric pilot's are one run, kept once
    assert sorted(rows["pilot"]) == ["geometric", "swerve:Swerve", "swerve:Swerve"]
    assert sorted(rows.loc[rows["pilot"] == "swerve:Swerve", "Swerve.swerve_deg"]) == [20.0, 60.0]
    r = CliRunner().invoke(
        app,
        [
            "tune",
            room,
            "--pilot",
            "swerve:Swerve",
            "--param",
            "Swerve.swerve_deg=10:80",
            "--trials",
            "2",
            "--seeds",
            "1",
            "--jobs",
            "1",
            "--time-limit",
            "3",
            "--out",
            "tn",
        ],
    )
    assert r.exit_code == 0, r.output
    assert "Swerve.swerve_deg = " in r.output


def test_compare_policies_runs_a_policy_plugin_as_missions(folder):
    from navcli.training import comparison

    p = comparison.parse_policy("swerve:GoStraight")
    assert p.kind == "plugin" and p.table is None and "module swerve" in p.about
    sc = load_scenario(SCENARIOS / "landmarks-12.yaml")
    spec = RunSpec.build(sc, overrides={"learning.max_actions": 3})
    job = comparison.plan(spec, [p], 1, 2, folder)[0]
    assert job.key != comparison.plan(spec, [comparison.parse_policy("agents")], 1, 2, folder)[0].key
    trials = comparison.run_trials(job)
    assert len(trials) == 2 and all(t["actions"] is None for t in trials)
