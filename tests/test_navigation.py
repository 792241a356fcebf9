"""The Navigation system's agents against hand-worked bids."""

from __future__ import annotations

import math

import pytest

from navcli.beliefs import Beliefs
from navcli.geometry import Pose
from navcli.navigation import NavigationSystem, TargetTracker
from navcli.params import NAVIGATION, PILOT

P = NAVIGATION  # kappa1 0.314, alpha 1.731, kappa2 0.493, beta 2.03, I_a_bar 0.386


def seen(target=(3.0, 4.0), spread=0.0, line=None):
    return Beliefs(0.0, Pose(0.0, 0.0, 0.0), target, line, (), spread)


def bids_of(beliefs):
    return {b.resource: b for b in TargetTracker(P, 0.3).bid(beliefs)}


def test_a_precisely_known_target_gets_kappa1_to_move_toward_it_and_no_look():
    b = bids_of(seen())
    assert b["motion"].value == pytest.approx(0.314)  # I_a = 0: kappa1 (1 - 0)^alpha
    assert b["motion"].action.heading == pytest.approx(math.atan2(4.0, 3.0)) and b["motion"].action.speed == 0.3
    assert "camera" not in b  # the look bid kappa2 * 0 / I_a_bar is 0: not offered


def test_bids_from_the_target_imprecision():
    spread = math.pi  # half a turn: I_a = 0.5 ** 2.03 = 0.2449
    i_a = 0.5 ** 2.03
    b = bids_of(seen(spread=spread))
    assert b["motion"].value == pytest.approx(0.314 * (1 - i_a) ** 1.731)  # 0.1931
    assert b["motion"].value == pytest.approx(0.1931, abs=1e-4)
    assert b["camera"].value == pytest.approx(0.493 * i_a / 0.386)  # rising: 0.3128
    assert b["camera"].action.pan == pytest.approx(math.atan2(4.0, 3.0))
    wide = bids_of(seen(spread=0.8 * 2 * math.pi))  # I_a = 0.8 ** 2.03 = 0.6357 > I_a_bar: falling again
    i_a = 0.8 ** 2.03
    assert wide["camera"].value == pytest.approx(0.493 * (1 - i_a) / (1 - 0.386))


def test_a_lost_target_gets_no_motion_bid_at_all():
    b = bids_of(seen(spread=2 * math.pi))  # heading unknown: I_a = 1
    assert "motion" not in b and "camera" not in b
    assert TargetTracker().bid(seen(target=None)) == []


def test_a_line_target_is_headed_for_through_the_pilots_corridor():
    line = ((2.0, -3.0), (2.0, 3.0))  # in front, the robot inside the corridor: straight across
    b = bids_of(seen(target=(2.0, 0.0), line=line))
    assert b["motion"].action.heading == pytest.approx(0.0)
    line = ((2.0, 0.2), (2.0, 4.0))  # beside the end: for the line's centre (2, 2.1)
    b = TargetTracker(P, 0.3, PILOT.corridor_margin).bid(seen(target=(2.0, 2.1), line=line))
    assert b[0].action.heading == pytest.approx(math.atan2(2.1, 2.0))


def test_the_communicator_forwards_the_winning_agent_bids_as_the_systems():
    nav = NavigationSystem()
    out = nav.bid(seen(spread=math.pi))
    assert [a.name for a in nav.agents] == ["target-tracker"]
    assert {b.bidder for b in out.bids} == {"navigation"} and {b.bidder for b in out.agent_bids} == {"target-tracker"}
    assert sorted((b.resource, b.value) for b in out.bids) == sorted((b.resource, b.value) for b in out.agent_bids)
