"""Hostile and odd scenario files: each is refused by the loader's own error, fast, with the line
and field, or loads and then runs; never a traceback, a hang or a crash later in the run."""

from __future__ import annotations

import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import ROOT, SCENARIOS
from navcli.config import ConfigError, RunSpec
from navcli.mission import Mission
from navcli.scenario import MAX_BYTES, MAX_PROBLEMS, ScenarioError, load_scenario, parse_scenario

BASE = "version: 1\nname: r\narena: {width: 6, height: 4}\nrobot: {start: [1, 2]}\ntarget: {at: [5, 2]}\n"
BOMB = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{c}: &{c} [{', '.join(['*' + p] * 9)}]\n" for p, c in zip("abcdefgh", "bcdefghi")
)  # 9**9 values


def refused(text: str, budget_s: float = 1.0) -> ScenarioError:
    t0 = time.perf_counter()
    with pytest.raises(ScenarioError) as e:
        parse_scenario(text, "s.yaml")
    assert time.perf_counter() - t0 < budget_s
    return e.value


# (text, line, field, words): each hostile input, BASE plus one line unless stated
HOSTILE = {
    "alias bomb": (BOMB, None, "", "values (aliases expanded)"),
    "self-referencing alias": ("a: &a [*a]\n", 1, "", "refers to the value that holds it"),
    "5000 levels deep": ("a: " + "[" * 5000 + "]" * 5000 + "\n", 1, "", "nested more than"),  # libyaml refuses too
    "40 levels deep": ("a: " + "[" * 40 + "]" * 40 + "\n", 1, "", "nested more than"),  # libyaml accepts
    "NUL byte": (BASE + 'description: "x\0y"\n', 6, "", "U+0000"),
    "400-digit seed": (BASE + "mission: {seed: " + "9" * 400 + "}\n", 6, "", "too large"),
    "seed above 64 bits": (BASE + "mission: {seed: 18446744073709551616}\n", 6, "mission.seed", "2**64 - 1"),
    "vision noise that breaks the fuzzy numbers": (
        BASE + "noise: {vision_distance: 0.4}\n",
        6,
        "noise.vision_distance",
        "at most 0.3",
    ),
    "tiny robot": (BASE.replace("{start: [1, 2]}", "{start: [1, 2], radius: 1.0e-300}"), 4, "robot.radius", "at least"),
    "tiny R_min": (BASE + "pilot: {R_min: 1.0e-300}\n", 6, "pilot.R_min", "at least 0.01"),
    "huge R_min": (BASE + "pilot: {R_min: 1.0e+308}\n", 6, "pilot.R_min", "at most 5"),
    "huge odometry noise": (BASE + "noise: {odometry: 1.0e+308}\n", 6, "noise.odometry", "at most"),
    "huge arena": (BASE.replace("height: 4", "height: 1.0e+308"), 3, "arena.height", "at most 100"),
    "lone surrogate id": (BASE + 'landmarks: [{id: "\\ud800", at: [3, 3]}]\n', 6, None, "invalid Unicode"),
    "50 m/s": (BASE.replace("{start: [1, 2]}", "{start: [1, 2], max_speed: 50}"), 4, "robot.max_speed", "at most 2"),
    "300-character name": (BASE.replace("name: r", "name: " + "r" * 300), 2, "name", "1 to 64"),
    "name ending in a newline": (BASE.replace("name: r", 'name: "r\\n"'), 2, "name", "may hold only"),
    "target inside an obstacle": (
        BASE + "obstacles: [{circle: {center: [5, 2], radius: 0.5}}]\n",
        5,
        "target.at",
        "lies inside obstacles[0]",
    ),
    "circle through a wall": (
        BASE + "obstacles: [{circle: {center: [3, 0.2], radius: 0.5}}]\n",
        6,
        "obstacles[0].circle.center",
        "through a wall",
    ),
    "YAML 1.1 exponent": (BASE + "noise: {odometry: 1e-3}\n", 6, "noise.odometry", "write it with a point"),
    "infinite time limit": (BASE + "mission: {time_limit: .inf}\n", 6, "mission.time_limit", "finite"),
}


@pytest.mark.parametrize("case", HOSTILE, ids=list(HOSTILE))
def test_hostile_files_are_refused_fast_by_line_and_field(case):
    text, line, fld, words = HOSTILE[case]
    err = refused(text)
    p = err.problems[0]
    assert (line is None or p.line == line) and (fld is None or p.field == fld) and words in p.message, str(err)


def test_a_big_file_is_refused_before_it_is_read(tmp_path):
    f = tmp_path / "big.yaml"
    f.write_text(BASE + "description: |\n" + "  x\n" * (MAX_BYTES // 4 + 1))  # one byte over the bound
    t0 = time.perf_counter()
    with pytest.raises(ScenarioError, match="larger than"):
        load_scenario(f)
    assert time.perf_counter() - t0 < 0.5


def test_the_number_of_problems_printed_is_bounded():
    text = BASE + "obstacles:\n" + "".join("  - circle: {center: [3, 3], radius: -1}\n" for _ in range(300))
    err = refused(text)
    assert len(err.problems) == 300  # all found ...
    shown = str(err).splitlines()
    assert len(shown) == MAX_PROBLEMS + 1 and shown[-1].endswith(f"and {300 - MAX_PROBLEMS} more problems in s.yaml")


def test_control_characters_in_a_name_or_text_are_refused():
    assert refused(BASE + 'description: "a\\x07b"\n').problems[0].field == "description"


def test_noise_beyond_the_noise_bound_is_refused_by_the_run_configuration():
    sc = parse_scenario(BASE + "noise: {vision_distance: 0.3}\n")
    RunSpec.build(sc)  # 0.3 x 3 deviations = 0.9: accepted
    with pytest.raises(ConfigError, match="noise.vision_distance"):
        RunSpec.build(sc, overrides={"vision.noise_bound": 4.0})  # 0.3 x 4 = 1.2


def test_validate_refuses_the_bomb_with_exit_2_and_no_traceback(tmp_path):
    f = tmp_path / "bomb.yaml"
    f.write_text(BOMB)
    r = subprocess.run(
        [sys.executable, "-m", "navcli", "validate", str(f)], capture_output=True, text=True, cwd=ROOT, timeout=30
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr and f"{f}:" in r.stderr


# --- property: random mutations of the bundled scenarios, and random bytes ------------------
BUNDLED = {p.name: p.read_text() for p in sorted(SCENARIOS.glob("*.yaml"))}
ODD = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(2**70), 2**70),
    st.booleans(),
    st.none(),
    st.text(max_size=20),
    st.lists(st.floats(-20, 20), max_size=3),
    st.sampled_from([0, -1, 1e-300, 1e308, 0.4, 2.5, 1000, "1e-3", [], {}, [[1, 2], [3, 4]]]),
)


def _leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _leaves(v, path + (i,))
    yield path


@st.composite
def mutated(draw) -> str:
    """A bundled scenario with one value replaced (structurally), or its text cut and spliced."""
    name = draw(st.sampled_from(sorted(BUNDLED)))
    text = BUNDLED[name]
    if draw(st.booleans()):
        data = yaml.safe_load(text)
        path = draw(st.sampled_from([p for p in _leaves(data) if p]))
        parent = data
        for k in path[:-1]:
            parent = parent[k]
        parent[path[-1]] = draw(ODD)
        return yaml.safe_dump(data, sort_keys=False)
    i = draw(st.integers(0, len(text)))
    j = draw(st.integers(i, min(len(text), i + 40)))
    return (
        text[:i]
        + draw(st.text(alphabet=st.sampled_from(list("[]{}:,-&*!|>'\"#\n 0123456789.e")), max_size=12))
        + text[j:]
    )


def _loads_or_refuses(text: str):
    t0 = time.perf_counter()
    try:
        sc = parse_scenario(text, "fuzz.yaml")
    except ScenarioError as e:
        assert e.problems and all(p.file == "fuzz.yaml" for p in e.problems)
        sc = None
    assert time.perf_counter() - t0 < 1.0
    return sc


@settings(max_examples=60, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_a_mutated_scenario_loads_and_runs_a_second_or_is_refused(text):
    sc = _loads_or_refuses(text)
    if sc is None:
        return
    try:
        spec = RunSpec.build(sc)
    except ConfigError:
        return
    m = Mission(spec)
    for _ in range(10):  # one simulated second
        if m.outcome is not None:
            break
        m.step()
    pose = m.world.pose
    assert m.ticks >= 1 and all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta))


@settings(max_examples=60)
@given(st.one_of(st.binary(max_size=300), st.text(max_size=300).map(str.encode)))
def test_random_bytes_load_or_are_refused(data):
    with tempfile.TemporaryDirectory() as d:
        f = Path(d) / "fuzz.yaml"
        f.write_bytes(data)
        t0 = time.perf_counter()
        try:
            load_scenario(f)
        except ScenarioError as e:
            assert e.problems and all(p.file == str(f) for p in e.problems)
        assert time.perf_counter() - t0 < 1.0


class _RefusingLoader(yaml.SafeLoader):
    """A stand-in for libyaml when it refuses a file on its own (as PyYAML 6.0.4's scanner does at
    about 1,000 levels of flow nesting, before any event): it refuses at once, at the file's end."""

    def check_event(self, *choices):
        end = len(self.buffer) - 2  # the reader appends a NUL
        raise yaml.scanner.ScannerError(
            "while scanning", None, "refused by this parser's own limit", yaml.Mark("<text>", end, 0, end, None, None)
        )


@pytest.mark.parametrize(
    "text,words",
    [
        ("a: " + "[" * 40 + "]" * 40 + "\n", "nested more than"),  # one of our bounds: ours is reported
        ("a: [1, 2\n", "refused by this parser's own limit"),  # none of ours: the parser's own refusal stands
    ],
    ids=["our bound", "its own refusal"],
)
def test_where_the_parser_refuses_on_its_own_our_bounds_still_speak_first(monkeypatch, text, words):
    import navcli.scenario.yaml_reader as scenario

    monkeypatch.setattr(scenario, "_Loader", _RefusingLoader)
    assert words in str(refused(text))
