"""The run configuration: one value, from the command line to the log and back, named by its hash."""

from __future__ import annotations

import pickle

import pytest

from navcli.analysis import read_log
from conftest import SCENARIOS
from navcli import NavcliError
from navcli.config import RunSpec
from navcli.params import Params, ParamError
from navcli.runner import run_mission
from navcli.scenario import load_scenario


@pytest.fixture(scope="module")
def base():
    return RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"))


def test_build_takes_the_scenarios_choices_unless_told_otherwise(base):
    sc = base.scenario
    assert (base.seed, base.pilot, base.perception, base.time_limit) == (
        sc.mission.seed,
        sc.mission.pilot,
        sc.mission.perception,
        sc.mission.time_limit,
    )
    other = RunSpec.build(
        sc,
        seed=9,
        pilot="geometric",
        perception="oracle",
        time_limit=5,
        overrides={"pilot.K": 30, "vision.forget_above": 0.3},
    )
    assert (other.seed, other.pilot, other.perception, other.time_limit) == (9, "geometric", "oracle", 5.0)
    assert other.params.pilot.K == 30.0 and other.params.vision.forget_above == 0.3
    assert other.params.pilot.A_t == sc.params.pilot.A_t  # everything else as the scenario has it


def test_the_run_id_changes_with_anything_that_decides_the_run(base):
    ids = {base.run_id}
    for changed in (
        base.replace(seed=2),
        base.replace(pilot="geometric"),
        base.replace(perception="oracle"),
        base.replace(time_limit=base.time_limit + 1),
        base.replace(params=base.params.override({"navigation.kappa2": 0.5})),
    ):
        ids.add(changed.run_id)
    assert len(ids) == 6
    again = RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"))
    assert again.run_id == base.run_id and again == base  # the same configuration, the same name


def test_a_moved_scenario_file_is_the_same_run_but_an_edited_one_is_not(base, tmp_path):
    moved = tmp_path / "elsewhere.yaml"
    moved.write_text(base.scenario.text)
    assert RunSpec.build(load_scenario(moved)).run_id == base.run_id
    moved.write_text(base.scenario.text + "\n# a comment changes the file\n")
    assert RunSpec.build(load_scenario(moved)).run_id != base.run_id


def test_json_round_trip_and_pickle_keep_the_configuration(base):
    spec = base.replace(seed=5, params=base.params.override({"pilot.R_min": 0.5}))
    back = RunSpec.from_json(spec.to_json(), spec.scenario.text)
    assert back.to_json() == spec.to_json() and back.run_id == spec.run_id
    assert pickle.loads(pickle.dumps(spec)) == spec  # what a worker process receives


def test_the_log_records_the_configuration_it_was_run_with(base, tmp_path):
    spec = base.replace(time_limit=2.0, params=base.params.override({"pilot.K": 25}))
    res = run_mission(spec, out=tmp_path / "r.mcap")
    log = read_log(res.log, topics=[])
    assert log.metadata["run"]["run_id"] == spec.run_id == log.summary["run_id"]
    assert log.config == spec.to_json()
    rebuilt = RunSpec.from_json(log.config, next(iter(log.attachments.values())).decode())
    assert rebuilt == spec  # a log is enough to reproduce its run


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(pilot="autopilot"), "unknown pilot"),
        (dict(perception="sonar"), "unknown perception"),
        (dict(seed=-1), "seed"),
        (dict(seed=2**64), "seed"),
        (dict(time_limit=float("inf")), "time limit"),
        (dict(time_limit=0.0), "time limit"),
    ],
)
def test_impossible_configurations_are_refused(base, change, words):
    with pytest.raises(NavcliError, match=words):  # a ConfigError, or for a name, the registry's UnknownPlugin
        base.replace(**change)


def test_every_parameter_round_trips_by_its_dotted_name():
    p = Params()
    flat = p.flat()
    assert Params.from_json(p.to_json()) == p
    assert len(flat) == sum(len(v) for v in p.to_json().values()) and "navigation.I_a_bar" in flat
    with pytest.raises(ParamError, match="navigation.I_a_bar must be below 1"):
        p.override({"navigation.I_a_bar": 1.0})  # the look bid divides by 1 - I_a_bar


def test_the_wall_clock_guard_is_no_part_of_a_runs_identity():
    """robot.decision_limit_s (declared course=False) never changes what a run does: two runs that
    differ in it alone are one run, with one id; a parameter of the run's course changes the id."""
    from navcli import RunSpec, load_scenario
    from navcli.scenario import bundled

    sc = load_scenario(bundled.path("open-arena"))
    base = RunSpec.build(sc, seed=1)
    assert RunSpec.build(sc, seed=1, overrides={"robot.decision_limit_s": 9.0}).run_id == base.run_id
    assert RunSpec.build(sc, seed=1, overrides={"robot.max_speed": 0.2}).run_id != base.run_id
    assert [n for n, d, _ in base.params.declarations() if not d.course] == ["robot.decision_limit_s"]
