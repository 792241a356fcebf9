"""VFH+ as a navcli pilot: its stages against hand-worked numbers, and the pilot in missions.

Runs from this folder (``python -m pytest``) or from navcli's suite; the package is imported from
beside this folder when it is not installed."""

from __future__ import annotations

import math
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parents[1]
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

from navcli.beliefs import Beliefs, KnownObstacle  # noqa: E402
from navcli.bidding import Move  # noqa: E402
from navcli.geometry import Pose  # noqa: E402
from vfh_pilot import VFHParams, VFHPilot  # noqa: E402
from vfh_pilot import histogram as vfh  # noqa: E402

N = 72  # sectors of 5 degrees
ALPHA = 2 * math.pi / N


def test_a_cell_adds_its_magnitude_to_the_sectors_its_enlarged_angle_covers():
    # a cell 1.5 m ahead and one 0.5 m to the left; r_rs = 0.4: gamma = asin(0.4 / d)
    cells = np.array([[1.5, 0.0], [0.0, 0.5]])
    h = vfh.primary_histogram(cells, 0.0, N, 5.0, 1.5, 0.4)
    m_far, m_near = 5.0 - 1.5 * 1.5**2, 5.0 - 1.5 * 0.25  # a - b d^2
    g_far, g_near = math.degrees(math.asin(0.4 / 1.5)), math.degrees(math.asin(0.4 / 0.5))  # 15.5, 53.1 deg
    for k in range(N):
        deg = math.degrees(((k * ALPHA + math.pi) % (2 * math.pi)) - math.pi)
        want = (m_far if abs(deg) <= g_far else 0.0) + (m_near if abs(deg - 90.0) <= g_near else 0.0)
        assert h[k] == pytest.approx(want), k
    # the histogram's frame: the same cells seen by a robot heading 90 deg fall 18 sectors on
    turned = vfh.primary_histogram(cells, math.pi / 2, N, 5.0, 1.5, 0.4)
    assert np.allclose(turned, np.roll(h, 18))


def test_a_cell_inside_the_grown_robot_blocks_half_the_circle():
    h = vfh.primary_histogram(np.array([[0.3, 0.0]]), 0.0, N, 5.0, 1.5, 0.4)  # 0.3 m < r_rs
    assert (h > 0).sum() == 37  # every sector within 90 degrees of it, both ends included


def test_the_binary_histogram_holds_between_its_thresholds():
    prev = np.zeros(4, dtype=bool)
    steps = [np.array([5.0, 25.0, 15.0, 15.0]), np.array([15.0, 15.0, 15.0, 5.0]), np.array([25.0, 5.0, 15.0, 15.0])]
    seen = []
    for h in steps:
        prev = vfh.binary_histogram(h, prev, 10.0, 20.0)
        seen.append(prev.tolist())
    assert seen == [[False, True, False, False], [False, True, False, False], [True, False, False, False]]


def test_the_masked_histogram_closes_the_side_a_turning_circle_would_meet():
    # one cell 0.4 m to the right, slightly ahead; turning radius 0.5, r_rs 0.4: the right circle,
    # centred at (0, -0.5), meets it (0.41 m from the centre < 0.9); the left circle does not
    cells = np.array([[0.1, -0.4]])
    free = np.zeros(N, dtype=bool)
    masked = vfh.masked_histogram(free, cells, 0.0, 0.5, 0.4)
    beta = math.degrees(math.atan2(-0.4, 0.1))  # -76 deg: every direction right of it is masked
    for k in range(N):
        deg = math.degrees(((k * ALPHA + math.pi) % (2 * math.pi)) - math.pi)
        assert masked[k] == (deg < beta), k
    # with a tight turning circle (0.05 m) the same cell is 0.49 m from the right centre: masks nothing
    assert not vfh.masked_histogram(free, np.array([[0.1, -0.6]]), 0.0, 0.05, 0.4).any()


def test_openings_candidates_and_the_cost_choose_as_vfh_plus_says():
    blocked = np.ones(N, dtype=bool)
    blocked[60:72] = False  # a wide opening from -60 to -5 deg (12 sectors) ...
    blocked[0:10] = False  # ... across sector 0 up to 45 deg: 22 sectors
    blocked[30:34] = False  # and a narrow one around 150-165 deg
    runs = vfh.openings(blocked)
    assert runs == [(30, 4), (60, 22)]
    # target at 20 deg (sector 4): inside the wide opening more than s_max / 2 = 8 from both borders?
    # its borders 60 and 81 (= 9): candidates 68 and 73 (= 1), the target (4 - 60) % 72 = 16 > 13: not
    assert vfh.candidates(runs, 4, 16, N) == [31, 68, 1]
    assert vfh.candidates(runs, 70, 16, N) == [31, 68, 1, 70]
    # cost: the target's distance first (mu1 = 5), then the heading's (mu2 = 2)
    assert vfh.choose([31, 68, 1], 4, 0, None, (5.0, 2.0, 2.0), N) == 1
    assert vfh.choose([31, 68, 1], 4, 0, 68, (5.0, 2.0, 2.0), N) == 1  # 5*3+2*1+2*5 = 27 < 5*8+2*4+0 = 48


def _beliefs(obstacles, target=(3.0, 0.0), theta=0.0):
    return Beliefs(1.0, Pose(1.0, 1.0, theta), target, None, tuple(obstacles))


def test_the_pilot_steers_round_a_post_in_the_way_and_lets_a_free_request_through():
    pilot = VFHPilot(own_params=VFHParams())
    post = KnownObstacle("o0", (0.9, 0.0), (0.9, 0.0), 0.15)
    out = pilot.decide(_beliefs([post]), Move(0.0, 0.3))
    motion = [b for b in out.bids if b.resource == "motion"]
    assert out.info["target_blocked"] and len(motion) == 1 and motion[0].value == pilot.params.bid_cap
    heading = motion[0].action.heading
    # outside the post's enlarged angle: asin(r_rs / d) from its centre's direction, r_rs = 0.40
    assert abs(heading) >= math.asin(0.40 / 0.9) - ALPHA / 2
    assert out.info["chosen_sector"] == vfh.sector_of(heading, N)
    free = VFHPilot().decide(_beliefs([KnownObstacle("o1", (0.0, 1.2), (0.0, 1.2), 0.15)]), Move(0.0, 0.3))
    assert not [b for b in free.bids if b.resource == "motion"] and free.info["target_blocked"] is False
    idle = VFHPilot().decide(_beliefs([post]), None)  # no request: where to go is not the pilot's to say
    assert not [b for b in idle.bids if b.resource == "motion"] and idle.info["chosen_sector"] == -1


def test_the_pilot_slows_down_in_a_dense_direction():
    pilot = VFHPilot()
    wall = KnownObstacle("wall-e", (1.0, -2.0), (1.0, 2.0), 0.0, True)
    out = pilot.decide(_beliefs([wall], target=(0.5, 2.0)), Move(math.pi / 2 - 0.3, 0.3))
    move = next(b.action for b in out.bids if b.resource == "motion")
    h_ahead = out.info["density_ahead"]
    assert h_ahead > 0 and move.speed == pytest.approx(0.3 * vfh.speed_factor(h_ahead, 40.0, 0.25))


def test_in_missions_it_reaches_the_target_round_the_obstacles_without_a_contact():
    from navcli import RunSpec, load_scenario
    from navcli.runner import run_mission

    room = load_scenario(Path(__import__("navcli").__file__).parent / "data" / "scenarios" / "paper-8x8.yaml")
    for perception in ("oracle", "vision"):
        # the path measures the pilot's own wandering: without the stall rule, whose diverting targets
        # (the Navigation's detours, taken sooner) are not the pilot's way
        spec = RunSpec.build(
            room,
            pilot="vfh_pilot:VFHPilot",
            perception=perception,
            overrides={"robot.max_speed": 0.3, "navigation.stall_rule": False},
        )
        s = run_mission(spec, record=False).summary
        assert s["outcome"] == "reached" and s["collisions"] == 0, (perception, s)
        # no wandering: within half again the way round both fences' north-west ends (0.3 m out), the
        # way a robot of 0.25 m can take: start, (2.1, 4.7), (4.1, 6.7), target: 10.1 m
        way = math.dist((0.8, 0.8), (2.1, 4.7)) + math.dist((2.1, 4.7), (4.1, 6.7)) + math.dist((4.1, 6.7), (7.2, 7.2))
        assert s["path_length_m"] < 1.5 * way, (perception, s["path_length_m"], way)


def test_navcli_finds_it_by_its_entry_point_and_its_checks_pass():
    from navcli.plugins.checker import check

    project = tomllib.loads((HERE / "pyproject.toml").read_text())
    target = project["project"]["entry-points"]["navcli.pilots"]["vfh"]
    module, _, cls = target.partition(":")
    assert getattr(__import__(module), cls) is VFHPilot
    assert check("pilot", "vfh_pilot:VFHPilot") == []
