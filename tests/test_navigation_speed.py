"""The Navigation system's per-tick shortcuts give what the plain definitions give, to the bit.

Each test here would fail if a shortcut taken for speed changed an answer: the sector
search, the memory's points, the Communicator's auction, the NamedTuple bids, the network's size."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from navcli.beliefs import Beliefs, KnownLandmark
from navcli.bidding import RESOURCES, Bid, Look, Move, arbitrate
from navcli.fuzzy import TWO_PI, FuzzyPoint
from navcli.geometry import Pose
from navcli.navigation import Communicator
from navcli.navigation.beta_map import BetaNetwork
from navcli.navigation.map_manager import TARGET, MapManager
from navcli.navigation.risk_manager import SECTORS, sector_of


def plain_sector_of(x: float, y: float) -> int:
    """The definition: the nearest centre, the first of equals."""
    h = math.atan2(y, x)
    best, off = 0, math.inf
    for i, c in enumerate(SECTORS):
        d = abs(math.remainder(h - c, TWO_PI))
        if d < off:
            best, off = i, d
    return best


def test_sector_of_is_the_nearest_centre_first_of_equals_at_every_boundary():
    angles = [math.radians(a) + e for a in range(-180, 181, 30) for e in (-1e-12, 0.0, 1e-12)]
    angles += list(np.random.default_rng(0).uniform(-math.pi, math.pi, 500))
    for h in angles:
        x, y = math.cos(h), math.sin(h)
        assert sector_of(x, y) == plain_sector_of(x, y), h
    assert sector_of(0.0, 0.0) == plain_sector_of(0.0, 0.0)


def fp(x: float, y: float, r: float = 0.3) -> FuzzyPoint:
    return FuzzyPoint(x, y, (r, 0.7 * r, 0.3 * r, 0.0))


@pytest.mark.parametrize("target_key", [TARGET, "B", "Z"])
@pytest.mark.parametrize("told", [True, False])
def test_memory_points_are_the_memorys_landmarks_and_marker_in_its_order(target_key, told):
    lms = tuple(KnownLandmark(k, fp(i, 1.0), 0.1 * i) for i, k in enumerate("CAB"))
    b = Beliefs(
        1.0, Pose(0, 0, 0), None, None, (), landmarks=lms, target_at=fp(5.0, 5.0) if told else None, target_seen=0.5
    )
    m = MapManager(target_key=target_key)
    got = m.memory_points(b)
    want = {lm.key: lm.where for lm in lms}  # the memory's landmarks, in its order, then the marker:
    if told and target_key != "B":  # it stands for a point target, or a landmark the memory lacks
        want[target_key] = b.target_at
    assert list(got.items()) == list(want.items())
    assert m.memory_points(b) is got  # once per tick


def plain_forward(held: dict, agent_bids, time: float, window: float, name: str):
    """The Communicator's rule as first written: fresh bids first, then those held in the window."""
    fresh = {(b.bidder, b.resource): (time, b) for b in agent_bids}
    held = fresh | {k: (t, b) for k, (t, b) in held.items() if k not in fresh and t >= time - window - 1e-9}
    winners = arbitrate(b for _, b in held.values())
    by = {r: b.bidder for r, b in winners.items() if b is not None}
    return held, by, [Bid(name, r, b.action, b.value) for r, b in winners.items() if b is not None]


def test_the_communicator_forwards_what_the_plain_rule_forwards():
    rng = np.random.default_rng(3)
    c, held = Communicator(window=0.2), {}
    for tick in range(400):
        time = tick * 0.1
        bids = [
            Bid(
                str(rng.integers(4)),
                RESOURCES[rng.integers(2)],
                Move(float(rng.uniform(-1, 1)), 0.3),
                float(rng.choice([0.0, 0.5, 1.0, rng.uniform()])),
            )
            for _ in range(rng.integers(0, 5))
        ]
        held, by, want = plain_forward(held, bids, time, 0.2, "navigation")
        assert c.forward(bids, time) == want
        assert c.forwarded_by == by and list(c._held.items()) == list(held.items())


def test_bids_moves_and_looks_are_immutable_values_with_the_dataclass_repr():
    b = Bid("pilot", "motion", Move(0.0, 0.3), 0.9)
    assert repr(b) == "Bid(bidder='pilot', resource='motion', action=Move(heading=0.0, speed=0.3), value=0.9)"
    assert repr(Look(0.5, "search")) == "Look(pan=0.5, purpose='search')"
    assert b == Bid("pilot", "motion", Move(0.0, 0.3), 0.9) and hash(b) == hash(
        Bid("pilot", "motion", Move(0.0, 0.3), 0.9)
    )
    assert pickle.loads(pickle.dumps(b)) == b
    with pytest.raises(AttributeError):
        b.value = 0.1
    with pytest.raises(ValueError, match="unknown resource"):
        Bid("pilot", "wheels", Move(0.0, 0.3), 0.5)
    assert isinstance(b.action, Move) and not isinstance(b.action, Look)


def test_the_networks_size_counts_its_units():
    net = BetaNetwork()
    pts = {k: fp(x, y, 0.05) for k, (x, y) in zip("ABCDEF", [(0, 0), (4, 0), (0, 4), (3, 3), (5, 2), (1, 5)])}
    net.learn(pts)
    assert len(net) == sum(len(per) for per in net.units.values()) > 0
