"""The loader accepts the bundled scenarios and refuses each broken file with its own message."""

from __future__ import annotations

import math

import pytest

from conftest import SCENARIOS, scenario_dict
from navcli.scenario import Circle, ScenarioError, Segment, load_scenario


@pytest.mark.parametrize("path", sorted(SCENARIOS.glob("*.yaml")), ids=lambda p: p.name)
def test_bundled_scenarios_load(path):
    sc = load_scenario(path)
    assert sc.name == path.stem
    assert sc.text == path.read_text()


def test_values_are_converted_to_si_and_radians(make_scenario):
    sc = make_scenario(
        robot={"start": [1.0, 2.0], "heading_deg": 90},
        obstacles=[{"circle": {"center": [3, 3], "radius": 0.2}}, {"segment": {"from": [4, 1], "to": [4, 3]}}],
        camera={"fov_deg": 60},
    )
    assert sc.robot.heading == pytest.approx(math.pi / 2)
    assert sc.camera.fov == pytest.approx(math.pi / 3)
    assert sc.obstacles[0] == Circle((3.0, 3.0), 0.2)
    assert isinstance(sc.obstacles[1], Segment) and sc.obstacles[1].center == (4.0, 2.0)
    assert (
        sc.params.pilot.K == 18 and sc.params.pilot.A_t == 50 and sc.params.pilot.R_min == 0.40
    )  # the paper's defaults


def test_landmark_target_takes_the_landmark_position(make_scenario):
    sc = make_scenario(landmarks=[{"id": "T", "at": [5, 3]}], target={"landmark": "T"})
    assert sc.target.kind == "landmark" and sc.target.point == (5.0, 3.0)


def refusal(write_scenario, content) -> ScenarioError:
    path = write_scenario(content)
    with pytest.raises(ScenarioError) as e:
        load_scenario(path)
    for p in e.value.problems:
        assert p.file == str(path)
    return e.value


def line_of(text: str, needle: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), 1) if needle in ln)


# Each refusal of docs/scenario-format.md: (scenario, field named, words in the message)
CASES = {
    "unknown top-level key": (scenario_dict(obstacels=[]), "obstacels", "unknown field 'obstacels'"),
    "missing required field": (scenario_dict(target=None), "", "missing required field 'target'"),
    "wrong type": (scenario_dict(arena={"width": "wide", "height": 4}), "arena.width", "expected a number"),
    "boolean is not a number": (scenario_dict(arena={"width": True, "height": 4}), "arena.width", "boolean"),
    "zero size": (scenario_dict(arena={"width": 0, "height": 4}), "arena.width", "greater than zero"),
    "negative size": (
        scenario_dict(obstacles=[{"circle": {"center": [3, 3], "radius": -0.2}}]),
        "obstacles[0].circle.radius",
        "greater than zero",
    ),
    "point outside the arena": (scenario_dict(target={"at": [7.5, 2.0]}), "target.at", "outside the 6 m x 4 m arena"),
    "start overlaps an obstacle": (
        scenario_dict(obstacles=[{"circle": {"center": [1.3, 2.0], "radius": 0.2}}]),
        "robot.start",
        "overlaps obstacles[0]",
    ),
    "start overlaps a landmark": (
        scenario_dict(landmarks=[{"id": "A", "at": [1.2, 2.1]}]),
        "robot.start",
        "overlaps landmark 'A'",
    ),
    "start overlaps a wall": (scenario_dict(robot={"start": [0.1, 2.0]}), "robot.start", "overlaps a wall"),
    "start overlaps a segment": (
        scenario_dict(obstacles=[{"segment": {"from": [1.1, 0.5], "to": [1.1, 3.5]}}]),
        "robot.start",
        "overlaps obstacles[0]",
    ),
    "duplicate landmark id": (
        scenario_dict(landmarks=[{"id": "A", "at": [3, 1]}, {"id": "A", "at": [3, 3]}]),
        "landmarks[1].id",
        "already used by landmarks[0]",
    ),
    "unknown target landmark": (
        scenario_dict(landmarks=[{"id": "A", "at": [3, 1]}], target={"landmark": "Z"}),
        "target.landmark",
        "unknown landmark 'Z'",
    ),
    "degenerate segment": (
        scenario_dict(obstacles=[{"segment": {"from": [3, 1], "to": [3, 1]}}]),
        "obstacles[0].segment",
        "degenerate",
    ),
    "degenerate target line": (scenario_dict(target={"line": [[3, 1], [3, 1]]}), "target.line", "degenerate"),
    "two target forms": (scenario_dict(target={"at": [5, 2], "line": [[3, 1], [3, 3]]}), "target", "exactly one of"),
    "unknown pilot": (scenario_dict(mission={"pilot": "autopilot"}), "mission.pilot", "unknown pilot 'autopilot'"),
    "bad name": (scenario_dict(name="Paper 8x8"), "name", "may hold only"),
    "unsupported version": (scenario_dict(version=2), "version", "unsupported version 2"),
    "unknown nested key": (scenario_dict(noise={"odometri": 0.1}), "noise.odometri", "unknown field"),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_each_refusal_names_the_field_and_the_problem(write_scenario, case):
    content, fld, words = CASES[case]
    err = refusal(write_scenario, content)
    assert any(p.field == fld and words in p.message for p in err.problems), str(err)
    assert all(p.line is not None for p in err.problems)


def test_refusal_gives_the_line_of_the_field(write_scenario):
    text = "version: 1\nname: x\narena: {width: 6, height: 4}\nrobot:\n  start: [1, 2]\ntarget:\n  at: [9, 2]\n"
    err = refusal(write_scenario, text)
    (p,) = err.problems
    assert p.line == line_of(text, "at: [9, 2]") and p.field == "target.at"
    assert str(p).startswith(f"{p.file}:{p.line}: target.at: ")


def test_several_problems_are_reported_together(write_scenario):
    err = refusal(write_scenario, scenario_dict(arena={"width": -1, "height": 4}, mission={"pilot": "x"}))
    assert {p.field for p in err.problems} == {"arena.width", "mission.pilot"}


@pytest.mark.parametrize(
    "text, words",
    [
        ("", "empty"),
        ("# only a comment\n", "empty"),
        ("- 1\n- 2\n", "holds a list"),
        ("just a string\n", "single value"),
        ("version: 1\nname: [unclosed\n", "not valid YAML"),
        ("version: 1\nversion: 1\n", "appears twice"),
        ("!!python/object/apply:os.system ['echo hi']\n", "not valid YAML"),
    ],
)
def test_not_a_yaml_mapping_is_refused(write_scenario, text, words):
    err = refusal(write_scenario, text)
    assert words in str(err)


def test_an_unclosed_bracket_is_named_where_it_opened(write_scenario):
    text = "version: 1\nname: x\nlandmarks: [\n  {id: A, at: [1, 2]}\n"  # the [ of line 3 never closes
    err = str(refusal(write_scenario, text))
    assert ":5:" in err and "began on line 3" in err  # found at the end (line 5); opened on line 3


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(ScenarioError, match="no such file"):
        load_scenario(tmp_path / "nope.yaml")


def test_the_navigation_block_picks_a_cluster_and_overrides_parameters(make_scenario):
    from navcli.params import NAVIGATION, NAVIGATION_C2

    sc = make_scenario(navigation={"cluster": "C2", "kappa1": 0.5})
    nav = sc.params.navigation
    assert nav.kappa1 == 0.5  # the override beats the cluster's 1.0
    assert (nav.gamma_B, nav.I_a_bar) == (NAVIGATION_C2.gamma_B, NAVIGATION_C2.I_a_bar) == (4.39, 0.871)
    assert make_scenario().params.navigation == NAVIGATION  # C1 by default


@pytest.mark.parametrize(
    "block, field, words",
    [
        ({"cluster": "C3"}, "navigation.cluster", "unknown cluster 'C3'"),
        ({"kappa1": 1.5}, "navigation.kappa1", "at most 1"),
        ({"I_a_bar": 1.0}, "navigation.I_a_bar", "below 1"),
        ({"kapa1": 0.3}, "navigation.kapa1", "unknown field 'kapa1'"),
    ],
)
def test_the_navigation_block_refuses_what_cannot_be_run(write_scenario, block, field, words):
    with pytest.raises(ScenarioError) as e:
        load_scenario(write_scenario(scenario_dict(navigation=block)))
    assert any(p.field == field and words in p.message for p in e.value.problems), str(e.value)


def test_a_merge_may_be_overridden_but_a_key_written_twice_is_refused():
    """YAML's ``<<`` merge brings a mapping's keys, which the mapping's own keys override (YAML's
    rule); a key the mapping itself writes twice stays an error."""
    from navcli.scenario import ScenarioError, parse_scenario

    head = "version: 1\nname: m\nrobot: {start: [0.6, 2.0]}\ntarget: {at: [5.4, 3.0]}\n"
    merged = parse_scenario(head + "arena: {<<: {width: 6.0, height: 5.0}, height: 4.0}\n")
    assert (merged.arena.width, merged.arena.height) == (6.0, 4.0)
    with pytest.raises(ScenarioError, match="appears twice"):
        parse_scenario(head + "arena: {width: 6.0, height: 4.0, width: 5.0}\n")
