"""Bundled scenarios by name, from any folder: ``navcli run paper-8x8``; ``navcli scenarios`` lists
them; a path wins over a name; a name that is neither is refused (exit 2) with the names it could
have meant, by every command that takes a scenario."""

from __future__ import annotations

import hashlib

import pytest
import yaml
from typer.testing import CliRunner

from conftest import SCENARIOS, scenario_dict
from navcli.cli import app
from navcli.scenario import bundled, load_scenario

runner = CliRunner()


@pytest.fixture
def elsewhere(tmp_path, monkeypatch):
    """An empty folder outside the repository, as the working directory."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_every_file_of_the_repositorys_scenarios_folder_is_bundled_by_its_name():
    files = sorted(p.name.removesuffix(".yaml") for p in SCENARIOS.glob("*.yaml"))
    assert list(bundled.names()) == files and len(files) >= 12
    for name in files:
        assert bundled.path(name).read_bytes() == (SCENARIOS / f"{name}.yaml").read_bytes()


@pytest.mark.parametrize("written", ["paper-8x8", "paper-8x8.yaml", "scenarios/paper-8x8.yaml"])
def test_a_bundled_scenario_loads_by_its_name_from_any_folder(elsewhere, written):
    sc = load_scenario(written)
    assert sc.name == "paper-8x8" and sc.source == str(bundled.path("paper-8x8"))


def test_run_takes_a_bundled_name_in_an_empty_folder(elsewhere):
    r = runner.invoke(app, ["run", "open-arena", "--time-limit", "1", "--out", "run.mcap"])
    assert r.exit_code == 3, r.output  # 1 s is too short to reach the target: a timeout, exit 3
    assert "outcome      timeout" in r.output and (elsewhere / "run.mcap").is_file()


def test_a_path_wins_over_a_name(elsewhere):
    (elsewhere / "paper-8x8.yaml").write_text(yaml.safe_dump(scenario_dict(name="my-room")))
    assert load_scenario("paper-8x8.yaml").name == "my-room"  # the file in this folder
    assert load_scenario("./paper-8x8.yaml").name == "my-room"
    assert load_scenario("paper-8x8").name == "paper-8x8"  # no file of that name here: the bundled one
    (elsewhere / "scenarios").mkdir()
    (elsewhere / "scenarios" / "open-arena.yaml").write_text(yaml.safe_dump(scenario_dict(name="mine")))
    assert load_scenario("scenarios/open-arena.yaml").name == "mine"


def test_a_name_that_is_neither_is_refused_with_the_names_it_could_have_meant(elsewhere):
    r = runner.invoke(app, ["run", "paper-8x9"])
    assert r.exit_code == 2 and "Traceback" not in r.output
    assert "paper-8x9: no such file, nor a bundled scenario of that name" in r.output
    assert "did you mean paper-8x8 or paper-fig9?" in r.output
    r = runner.invoke(app, ["validate", "u-trapp.yaml", "scenarios/landmark-12.yaml", "nothing-like-it"])
    assert r.exit_code == 2
    assert "did you mean u-trap?" in r.output and "did you mean landmarks-12" in r.output
    assert (
        "nothing-like-it: no such file, nor a bundled scenario of that name (`navcli scenarios` lists them)" in r.output
    )
    # a path to a folder elsewhere is not a name: no bundled scenario is taken for it
    r = runner.invoke(app, ["validate", "rooms/paper-8x8.yaml"])
    assert r.exit_code == 2 and "rooms/paper-8x8.yaml: no such file" in r.output


@pytest.mark.parametrize(
    "command",
    [
        ["run"],
        ["validate"],
        ["bench"],
        ["params"],
        ["plot", "field"],
        ["plot", "bids"],
        ["compare", "pilots"],
        ["compare", "policies"],
        ["train"],
        ["tune", "--param", "pilot.K=1:10"],
    ],
)
def test_every_command_that_takes_a_scenario_resolves_names_the_same_way(elsewhere, command):
    """Each command reads its scenario through the one resolver: a misspelt name is refused with
    the same suggestion (before any work: nothing is written)."""
    r = runner.invoke(app, [*command, "paper-8x9"])
    assert r.exit_code == 2 and "did you mean paper-8x8 or paper-fig9?" in r.output, r.output
    assert list(elsewhere.iterdir()) == []


def test_a_sweep_plan_names_bundled_scenarios(elsewhere):
    from navcli.experiments.sweep import PlanError, load_plan

    (elsewhere / "plan.yaml").write_text("version: 1\nscenarios: [open-arena, paper-fig9.yaml]\nseeds: 2\n")
    plan = load_plan(elsewhere / "plan.yaml")
    assert [b.scenario.name for b in plan.bases] == ["open-arena", "paper-fig9"] and plan.size == 4
    (elsewhere / "bad.yaml").write_text("version: 1\nscenarios: [open-arenna]\nseeds: 2\n")
    with pytest.raises(PlanError, match="did you mean open-arena"):
        load_plan(elsewhere / "bad.yaml")


def test_the_scenarios_command_lists_each_with_its_description():
    r = runner.invoke(app, ["scenarios"])
    assert r.exit_code == 0
    lines = r.output.splitlines()
    for name in bundled.names():
        line = next(ln for ln in lines if ln.startswith(name + " "))
        first_words = " ".join(load_scenario(name).description.split()[:3])
        assert first_words in line, (name, line)
    assert f"{len(bundled.names())} scenarios, in {bundled.FOLDER}" in r.output


def test_the_scenarios_command_prints_one_to_copy(elsewhere):
    r = runner.invoke(app, ["scenarios", "paper-8x8"])
    assert r.exit_code == 0
    assert hashlib.sha256(r.output.encode()).hexdigest() == load_scenario("paper-8x8").sha256
    r = runner.invoke(app, ["scenarios", "paper-8x9"])
    assert r.exit_code == 2 and "'paper-8x9' is not a bundled scenario (did you mean paper-8x8" in r.output
