"""Parameters declared once (navcli.params.declare): checked wherever a value is made, with a unit
and a description each, switches as booleans, and the same declaration read by the overrides, the
scenario format's JSON Schema and `navcli params`."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

from navcli.params import (
    LEARNING,
    NAVIGATION_C2,
    Declared,
    NavigationParams,
    ParamError,
    Params,
    ParamSet,
    PilotParams,
    RobotParams,
    param,
    parse_override,
)


def test_a_value_out_of_range_is_refused_when_the_set_is_made():
    with pytest.raises(ParamError, match="robot.max_speed must be above 0, got -1"):
        Params(robot=RobotParams(max_speed=-1.0))
    with pytest.raises(ParamError, match="pilot.bid_cap must be at most 0.9, got 1.5"):
        PilotParams(bid_cap=1.5)
    with pytest.raises(ParamError, match="navigation.blocked_bumps expects a whole number"):
        NavigationParams(blocked_bumps=2.5)
    with pytest.raises(ParamError, match="learning.distance_bounds must be 4 increasing numbers"):
        dataclasses.replace(LEARNING, distance_bounds=(1.0, 0.5, 3.0, 5.0))


def test_values_are_held_in_their_declared_type():
    p = PilotParams(K=20, looks=0, reflex_look_pans_deg=[-30, 30])
    assert (type(p.K), p.K) == (float, 20.0)
    assert p.looks is False and p.reflex_look_pans_deg == (-30.0, 30.0)
    assert type(NavigationParams(blocked_bumps=4.0).blocked_bumps) is int
    assert NAVIGATION_C2.alpha == 1.231  # dataclasses.replace goes through the same checks


@pytest.mark.parametrize("value", [0.5, 2, "yes", None])
def test_a_switch_takes_true_false_1_and_0_only(value):
    assert Params().override({"pilot.looks": 1}).pilot.looks is True
    assert Params().override({"pilot.looks": False}).pilot.looks is False
    with pytest.raises(ParamError, match="pilot.looks is a switch"):
        Params().override({"pilot.looks": value})


def test_every_parameter_is_declared_with_a_unit_field_and_a_description():
    names = set()
    for name, d, value in Params().declarations():
        names.add(name)
        assert isinstance(d, Declared) and len(d.description) >= 10, name
        assert d.check(name, value) == value  # the default lies in its own range
        if d.kind == "switch":
            assert isinstance(value, bool), name
    assert names == set(Params().flat())
    switches = [n for n, d, _ in Params().declarations() if d.kind == "switch"]
    assert len(switches) >= 15 and "pilot.drive_while_turning" in switches


def test_a_bad_declaration_is_refused_when_its_class_is_made():
    with pytest.raises(ParamError, match="the default must be at most 1"):
        param(2.0, "", "a bid", at_most=1.0)
    with pytest.raises(TypeError):
        param("fast", "", "a word is no parameter")

    @dataclasses.dataclass(frozen=True)
    class Undeclared(ParamSet):
        gain: float = 1.0

    with pytest.raises(TypeError, match="Undeclared.gain is not declared"):
        Undeclared()


def test_a_plugins_set_is_declared_and_overridden_like_navclis():
    @dataclasses.dataclass(frozen=True)
    class Gains(ParamSet):
        gain: float = param(1.5, "1/s", "turn rate per radian of heading error", above=0.0)
        smooth: bool = param(True, "", "average each turn with the one before")

    p = Params().with_plugin("mine", Gains())
    assert p.flat()["mine.gain"] == 1.5 and "mine.gain" not in json.dumps(p.to_json())
    q = p.override({"mine.gain": 3, "mine.smooth": 0, "pilot.K": 30})
    assert q.plugin("mine") == Gains(gain=3.0, smooth=False) and q.pilot.K == 30.0
    with pytest.raises(ParamError, match="mine.gain must be above 0"):
        p.override({"mine.gain": 0})
    with pytest.raises(ParamError, match="unknown parameter 'mine.gian' \\(did you mean mine.gain\\?\\)"):
        p.override({"mine.gian": 1})
    with pytest.raises(ParamError, match="cannot name a plugin's parameters"):
        Params().with_plugin("pilot", Gains())


def test_the_json_schema_and_the_checks_read_one_declaration():
    import jsonschema

    for name, d, value in Params().declarations():
        schema = d.json_schema(value)
        jsonschema.Draft7Validator.check_schema(schema)
        v = jsonschema.Draft7Validator(schema)
        assert v.is_valid(list(value) if isinstance(value, tuple) else value), name
        lo, lo_open = d.lower
        hi, hi_open = d.upper
        for bound, open_, step in ((lo, lo_open, -1.0), (hi, hi_open, 1.0)):
            if bound is None or d.kind != "number":
                continue
            past = bound + step * max(1e-6, abs(bound) * 1e-6)
            assert not v.is_valid(past), name  # the schema refuses what the check refuses
            with pytest.raises(ParamError):
                d.check(name, past)
            assert v.is_valid(bound) is (not open_), name
        if d.kind == "switch":
            assert v.is_valid(True) and not v.is_valid(1.5)


def test_parse_override_reads_switches_lists_and_numbers():
    assert parse_override("pilot.looks=true") == ("pilot.looks", True)
    assert parse_override("pilot.looks=FALSE") == ("pilot.looks", False)
    assert parse_override("pilot.K=1e1") == ("pilot.K", 10.0)
    assert parse_override("navigation.scan_pans_deg=[]") == ("navigation.scan_pans_deg", [])
    assert math.isnan(parse_override("pilot.K=nan")[1])  # parsed; refused by the override's check
    with pytest.raises(ParamError):
        Params().override(dict([parse_override("pilot.K=nan")]))
