"""A plugin named by its user: ``NAME=module:Class`` and ``NAME=path/to/file.py:Class`` wherever a
pilot is named (the command line, scenario files, sweep plans, the API), the name used in tables,
summaries, log file names and parameters; the name's rules (navcli.plugins.names) refused with
exit 2; the help texts that name a plugin saying every form, in the same words."""

from __future__ import annotations

import re

import jsonschema
import pytest
from typer.testing import CliRunner

import navcli
from conftest import SCENARIOS, module_in_folder
from navcli.analysis import read_log
from navcli.analysis.tables import load_runs
from navcli.cli import app
from navcli.config import RunSpec
from navcli.plugins import UnknownPlugin, registry
from navcli.plugins.names import PLUGIN_FORMS, label, named
from navcli.scenario import json_schema, load_scenario

STILL = '''
from dataclasses import dataclass

from navcli.params import ParamSet, param
from navcli.pilot import Avoidance, Pilot


@dataclass(frozen=True)
class StillParams(ParamSet):
    gain: float = param(1.0, "", "a parameter to address by the plugin's name")


class Still(Pilot):
    """Never avoids: the Navigation system's request goes through."""

    Params = StillParams

    def avoid(self, beliefs, obstacles, request):
        return Avoidance(None, 0.0, {})


class Raises(Still):
    def avoid(self, beliefs, obstacles, request):
        raise RuntimeError("no")
'''


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A folder holding ``still.py`` (a pilot plugin), made the current folder."""
    yield from module_in_folder(tmp_path, monkeypatch, "still", STILL)


def _cli(*args):
    return CliRunner().invoke(app, [str(a) for a in args], terminal_width=400)


# --- the name's rules ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "value, expected",
    [
        ("mine=still.py:Still", ("mine", "still.py:Still")),
        ("mine=still:Still", ("mine", "still:Still")),
        ("My_pilot-2=pkg.mod:Cls", ("My_pilot-2", "pkg.mod:Cls")),
        ("mine=vfh", ("mine", "vfh")),  # an installed plugin, under another name
        ("still.py:Still", ("still.py:Still", "still.py:Still")),
        ("dir/a=b.py:Cls", ("dir/a=b.py:Cls", "dir/a=b.py:Cls")),  # a '/' before the '=': a path
        ("learned:a=b.npz", ("learned:a=b.npz", "learned:a=b.npz")),  # a ':' before the '=': a reference
        ("geometric", ("geometric", "geometric")),
    ],
)
def test_a_value_is_split_into_its_name_and_its_reference(value, expected):
    assert named(value, "pilot") == expected
    assert label(value) == expected[0]


@pytest.mark.parametrize(
    "value, why",
    [
        ("my pilot=still.py:Still", "the name before '=' is 'my pilot', but a pilot's name is 1 to 64 of"),
        ("-x=still.py:Still", "the first a letter or a digit"),
        ("x" * 65 + "=still.py:Still", "1 to 64 of"),
        ("geometric=still.py:Still", "'geometric' is taken by navcli's own pilot: call the plugin another name"),
        ("mine=", "nothing after '='"),
        ("mine=potential-field", "'potential-field' is navcli's own pilot, which goes by its own name"),
    ],
)
def test_a_name_that_breaks_the_rules_is_refused_saying_why(value, why):
    with pytest.raises(UnknownPlugin, match=re.escape(why)):
        named(value, "pilot")


def test_a_policys_name_may_not_take_one_of_navclis_policies():
    with pytest.raises(UnknownPlugin, match="'agents' is taken by navcli's own navigation policy"):
        named("agents=x.py:Y", "policy")
    assert named("geometric=x.py:Y", "policy") == ("geometric", "x.py:Y")  # a pilot's name is no policy's


# --- the registry -------------------------------------------------------------------------------
def test_a_named_plugin_is_the_same_class_under_its_name(folder):
    plain = registry.pilot("still.py:Still")
    c = registry.pilot("mine=still.py:Still")
    assert c.cls is plain.cls and c.origin == plain.origin and c.version == plain.version
    assert (c.name, c.group, c.asked) == ("mine", "mine", "mine=still.py:Still")
    assert (plain.name, plain.group, plain.asked) == ("still.py:Still", "Still", "still.py:Still")
    assert registry.pilot("mod=still:Still").group == "mod"


def test_two_pilots_going_by_one_name_are_refused(folder):
    with pytest.raises(UnknownPlugin, match="'a' named twice"):
        registry.pilots(["a=still.py:Still", "a=still:Still"])
    assert [c.name for c in registry.pilots(["a=still.py:Still", "still:Still"])] == ["a", "still:Still"]


def test_a_named_plugins_faults_point_back_to_the_value_that_finds_it(folder):
    r = _cli("run", SCENARIOS / "open-arena.yaml", "--pilot", "oops=still.py:Raises", "--time-limit", 2, "--force")
    assert r.exit_code == 1, r.output
    assert "the pilot plugin 'oops'" in r.output
    assert "`navcli plugins check pilot oops=still.py:Raises`" in r.output


# --- runs, tables, files -----------------------------------------------------------------------
def test_a_named_pilot_goes_by_its_name_in_the_summary_the_log_name_and_its_parameters(folder):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    spec = RunSpec.build(sc, pilot="mine=still.py:Still", time_limit=2.0, overrides={"mine.gain": 3.0})
    assert spec.pilot_name == "mine" and spec.params.plugin("mine").gain == 3.0
    assert spec.log_name().startswith("mine-seed1-")
    plain = RunSpec.build(sc, pilot=str(folder / "still.py") + ":Still", time_limit=2.0)
    assert plain.log_name().startswith(re.sub(r"[^A-Za-z0-9_.-]+", "_", str(folder)).strip("_."))  # the path's
    assert spec.run_id != RunSpec.build(sc, pilot="other=still.py:Still", time_limit=2.0).run_id

    r = navcli.run(spec, log=folder / "run.mcap")
    assert r.summary["pilot"] == "mine"
    log = read_log(folder / "run.mcap")
    assert log.summary["pilot"] == "mine" and log.metadata["run"]["pilot"] == "mine"
    again = RunSpec.from_json(log.config, sc.text)  # a run of a named plugin is found again from its log
    assert again.pilot == "mine=still.py:Still" and again.run_id == spec.run_id


def test_compare_pilots_tables_and_files_go_by_the_names_given(folder):
    out = folder / "out"
    r = _cli(
        "compare",
        "pilots",
        SCENARIOS / "open-arena.yaml",
        "--pilots",
        f"mine={folder / 'still.py'}:Still,geometric",
        "--reruns",
        1,
        "--time-limit",
        2,
        "--jobs",
        1,
        "--out",
        out,
    )
    assert r.exit_code == 0, r.output
    assert "| mine |" in (out / "table.md").read_text()
    assert "mine vs geometric" in (out / "table.md").read_text()
    assert sorted(p.name.split("-seed")[0] for p in (out / "open-arena").glob("*.mcap")) == ["geometric", "mine"]
    assert sorted(load_runs(out)["pilot"]) == ["geometric", "mine"]
    assert (out / "trajectories-open-arena-mine.png").exists()


@pytest.mark.parametrize(
    "pilots, why",
    [
        ("geometric=still.py:Still,potential-field", "'geometric' is taken by navcli's own pilot"),
        ("a b=still.py:Still,geometric", "the name before '=' is 'a b'"),
        ("a=still.py:Still,a=still:Still", "'a' named twice"),
    ],
)
def test_compare_refuses_a_bad_name_with_exit_2(folder, pilots, why):
    r = _cli("compare", "pilots", SCENARIOS / "open-arena.yaml", "--pilots", pilots, "--out", folder / "o")
    assert r.exit_code == 2, r.output
    assert why in r.output and "--pilots" in r.output
    assert not (folder / "o").exists()


def test_the_api_compares_named_pilots_and_refuses_two_of_one_name(folder):
    df = navcli.compare(
        [SCENARIOS / "open-arena.yaml"], ["mine=still.py:Still", "geometric"], reruns=1, time_limit=2.0, jobs=1
    )
    assert sorted(df["pilot"]) == ["geometric", "mine"]
    with pytest.raises(UnknownPlugin, match="'x' named twice"):
        navcli.compare([SCENARIOS / "open-arena.yaml"], ["x=still.py:Still", "x=still:Still"], jobs=1)


def test_a_scenario_file_names_its_pilot(folder):
    text = (SCENARIOS / "open-arena.yaml").read_text()
    assert "\nmission:\n" in text
    room = folder / "room.yaml"
    room.write_text(text.replace("\nmission:\n", "\nmission:\n  pilot: mine=still.py:Still\n"))
    sc = load_scenario(room)
    assert sc.mission.pilot == "mine=still.py:Still"
    assert navcli.run(sc, time_limit=1.0).summary["pilot"] == "mine"
    pattern = json_schema()["properties"]["mission"]["properties"]["pilot"]
    for good in ("geometric", "vfh", "still.py:Still", "mine=still.py:Still", "mine=pkg.mod:Cls", "mine=vfh"):
        jsonschema.validate(good, pattern)
    for bad in ("my pilot=still.py:Still", "a=", "has space"):
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(bad, pattern)
    room.write_text(text.replace("\nmission:\n", "\nmission:\n  pilot: geometric=still.py:Still\n"))
    r = _cli("validate", room)
    assert r.exit_code == 2 and "taken by navcli's own pilot" in r.output, r.output


def test_a_sweep_plan_refuses_two_pilots_of_one_name(folder):
    from navcli.experiments.sweep import PlanError, load_plan

    plan = {"version": 1, "scenarios": [str(SCENARIOS / "open-arena.yaml")], "seeds": 1, "time_limit": 2}
    assert [b.pilot_name for b in load_plan(plan | {"pilots": ["mine=still.py:Still", "geometric"]}).bases] == [
        "mine",
        "geometric",
    ]
    with pytest.raises(PlanError, match="'a' named twice"):
        load_plan(plan | {"pilots": ["a=still.py:Still", "a=still:Still"]})


# --- the help texts ----------------------------------------------------------------------------
def _flat(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize(
    "command",
    [["plugins", "check"], ["compare", "pilots"], ["compare", "policies"], ["run"], ["reproduce"]],
)
def test_every_help_that_names_a_plugin_says_every_form_in_the_same_words(command):
    r = _cli(*command, "--help")
    assert r.exit_code == 0
    text = _flat(r.output)
    assert _flat(PLUGIN_FORMS) in text, command
    for form in ("module:Class", "path/to/file.py:Class", "NAME=module:Class", "NAME=path/to/file.py:Class"):
        assert form in text, (command, form)


AGENT = """
from navcli.bidding import Bid, Move


class Straight:
    def __init__(self, setup):
        self.name = "straight"
        self.speed = setup.params.robot.max_speed

    def bid(self, s):
        return [] if s.bearing is None else [Bid(self.name, "motion", Move(s.bearing, self.speed), 0.5)]
"""


def test_a_named_policy_goes_by_its_name_in_compare_policies(tmp_path, monkeypatch):
    from navcli.training import comparison

    for _ in module_in_folder(tmp_path, monkeypatch, "straight", AGENT):
        p = comparison.parse_policy("agents+mine=straight.py:Straight")
        assert (p.label, p.navigation) == ("agents+mine", "agents+mine=straight.py:Straight")
        sc = load_scenario(SCENARIOS / "landmarks-12.yaml")
        spec = RunSpec.build(sc, overrides={"learning.max_actions": 3})
        job = comparison.plan(spec, [p], 1, 1, tmp_path)[0]
        assert job.path.rpartition("/")[2].startswith("agents_mine-run0-")
        assert comparison.run_trials(job)[0]["actions"] is None  # run as missions, by the value that finds it
        r = _cli(
            "compare", "policies", SCENARIOS / "landmarks-12.yaml", "--policy", "a=straight.py:Straight",
            "--policy", "a=straight:Straight", "--out", tmp_path / "o",
        )  # fmt: skip
        assert r.exit_code == 2 and "a policy is named twice: a, a" in r.output, r.output
