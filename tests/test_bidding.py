"""The arbiter gives each resource to its highest bid, with a deterministic tie rule."""

from __future__ import annotations

import pytest

from navcli.bidding import Bid, Look, Move, arbitrate


def test_highest_bid_wins_each_resource():
    bids = [
        Bid("pilot", "motion", Move(0.5, 0.2), 0.3),
        Bid("navigation", "motion", Move(0.0, 0.3), 0.6),
        Bid("pilot", "camera", Look(0.0, "obstacles"), 0.7),
        Bid("navigation", "camera", Look(1.0, "target"), 0.2),
    ]
    w = arbitrate(bids)
    assert w["motion"].bidder == "navigation" and w["camera"].bidder == "pilot"


def test_ties_go_to_the_bid_offered_first():
    a, b = Bid("pilot", "motion", Move(0.1, 0.1), 0.5), Bid("navigation", "motion", Move(0.0, 0.3), 0.5)
    assert arbitrate([a, b])["motion"] is a
    assert arbitrate([b, a])["motion"] is b


def test_a_resource_nobody_bids_for_has_no_winner():
    assert arbitrate([Bid("navigation", "motion", Move(0, 0), 0.0)])["camera"] is None


@pytest.mark.parametrize("value", [-0.01, 1.01, float("nan")])
def test_bids_outside_unit_interval_are_refused(value):
    with pytest.raises(ValueError):
        Bid("pilot", "motion", Move(0, 0), value)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_moves_and_looks_are_refused(bad):
    """A NaN heading must never reach the wheels (it would make the world's pose NaN a tick later)."""
    for make in (lambda: Move(bad, 0.3), lambda: Move(0.0, bad), lambda: Look(bad, "search")):
        with pytest.raises(ValueError, match="finite"):
            make()


def test_an_agent_that_computes_nan_is_stopped_at_its_bid():
    """An agent's arithmetic going wrong (0/0) surfaces as an error at the bid, not in the world."""
    from navcli.beliefs import Beliefs
    from navcli.fuzzy import FuzzyPoint
    from navcli.geometry import Pose
    from navcli.navigation import Situation, TargetTracker

    b = Beliefs(0.0, Pose(0, 0, 0), (float("nan"), 1.0), None, ())
    broken = Situation(b, FuzzyPoint(float("nan"), 1.0, (0.0,) * 4), None, "memory", 0.0)
    with pytest.raises(ValueError, match="finite heading"):
        TargetTracker().bid(broken)
