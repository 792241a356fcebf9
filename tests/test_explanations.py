"""What only a log or an observer reads is built only for them: a mission that nobody records
explains nothing (``Mission(explain=False)``: no ``/pilot`` fields, force arrows or Navigation
``info``) and builds no :class:`~navcli.mission.Tick` (``advance`` without observers), and does
exactly what the recorded mission does."""

from __future__ import annotations

import pytest

from conftest import SCENARIOS
from navcli.config import RunSpec
from navcli.mission import Mission
from navcli.navigation import NO_INFO
from navcli.runner import advance, run_mission
from navcli.scenario import load_scenario


def spec(name: str, pilot: str, seconds: float, **overrides: float) -> RunSpec:
    return RunSpec.build(
        load_scenario(SCENARIOS / f"{name}.yaml"), pilot=pilot, seed=3, time_limit=seconds, overrides=overrides
    )


@pytest.mark.parametrize("pilot", ["potential-field", "geometric"])
def test_an_unexplained_mission_decides_as_the_explained_one_tick_by_tick(pilot):
    """blocked-wall with the Pilot's report of a long obstacle on (``blocked_report_m``, the one
    explanation a decision reads: it reaches the Rescuer as ``pilot_blocked``): every bid, winner,
    wheel command, report and pose is the same, while the unexplained Pilot's ``info`` holds only
    that report and the Navigation system's none."""
    s = spec("blocked-wall", pilot, 60.0, **{"pilot.blocked_report_m": 0.3})
    told, silent = Mission(s, snapshots=False), Mission(s, snapshots=False, explain=False)
    reports = 0
    while told.outcome is None:
        a, b = told.step(), silent.step()
        assert (a.pose, a.command, a.bids, a.agent_bids, a.winners) == (
            b.pose,
            b.command,
            b.bids,
            b.agent_bids,
            b.winners,
        )
        assert a.pilot.blocked_by == b.pilot.blocked_by and a.pilot.events == b.pilot.events
        reports += a.pilot.info.get("blocked_by") is not None
        assert a.navigation is not None and b.navigation is not None and a.navigation.info
        assert b.navigation.info is NO_INFO and not b.pilot.arrows
        assert "mode" in a.pilot.info
        if pilot == "potential-field" or a.pilot.info["mode"] == "reflex":  # the geometric pilot's avoid explains
            assert a.pilot.info["mode"] == "reflex" or "obstacles" in a.pilot.info
            assert b.pilot.info.keys() <= {"blocked_by"}
            assert b.pilot.info.get("blocked_by") == a.pilot.info.get("blocked_by")
    assert silent.outcome == told.outcome and silent.ticks == told.ticks
    if pilot == "potential-field":
        assert reports > 0  # the report was exercised


def test_a_mission_nobody_observes_runs_as_a_recorded_one(tmp_path):
    """``advance`` without observers steps without a record (``Mission.step_unrecorded``); the run
    ends the same as one written to a log, whose explanations are built."""
    s = spec("paper-8x8", "potential-field", 40.0)
    recorded = run_mission(s, out=tmp_path / "run.mcap").summary
    m = Mission(s, snapshots=False, explain=False)
    assert m.step_unrecorded() is None and m.ticks == 1
    advance(m)
    assert m.summary() | {"run_id": None} == recorded | {"run_id": None}
    assert run_mission(s, record=False).summary == m.summary()
