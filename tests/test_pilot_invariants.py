"""The potential-field pilot's equations at their edges (navcli/pilot/potential_field.py): the occlusion
test's two forms agree on layouts drawn from a grid (where sight lines pass exactly through ends,
centres coincide and a body touches a line: the ties a float draw never meets), the linear force of
section 3.2 and the passable gap of eq. 8 against numbers worked out by hand, and the Pilot's turn
averaged with the previous one in the frame the robot has turned to."""

from __future__ import annotations

import math

import msgspec
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from navcli.beliefs import Beliefs, KnownObstacle
from navcli.geometry import Pose
from navcli.log.format import Pilot as PilotMessage
from navcli.log.format import encode, pilot_message
from navcli.params import PILOT, ROBOT
from navcli.pilot.potential_field import PotentialFieldPilot, facing_loop, facing_numpy, linear_force, passable_gap

K, R = 18.0, 0.40
grid = st.integers(-4, 4).map(lambda k: k * 0.5)  # metres, 0 included: exact ties


@st.composite
def grid_layouts(draw):
    obs = []
    for i in range(draw(st.integers(0, 9))):
        a = (draw(grid), draw(grid))
        if draw(st.booleans()):
            obs.append(KnownObstacle(f"p{i}", a, a, draw(st.sampled_from([0.0, 0.25, 0.5, 1.0]))))
        else:
            b = (draw(grid), draw(grid))
            if a != b:
                obs.append(KnownObstacle(f"s{i}", a, b, 0.025))
    return obs


@given(grid_layouts())
def test_the_array_and_loop_occlusion_tests_agree_on_every_tie(obstacles):
    assert facing_numpy(obstacles) == facing_loop(obstacles)


def test_an_obstacle_on_the_robot_or_behind_a_twin_is_not_hidden():
    on_robot = KnownObstacle("here", (0.0, 0.0), (0.0, 0.0), 0.2)
    twins = [KnownObstacle("a", (1.0, 0.0), (1.0, 0.0), 0.2), KnownObstacle("b", (1.0, 0.0), (1.0, 0.0), 0.2)]
    touching = [
        KnownObstacle("post", (2.0, 0.0), (2.0, 0.0), 0.1),
        KnownObstacle("fence", (1.0, -1.0), (1.0, 0.0), 0.025),
    ]
    behind = [KnownObstacle("far", (1.0, 0.0), (1.0, 0.0), 0.1), KnownObstacle("near", (0.5, 0.0), (0.5, 0.0), 0.25)]
    for f in (facing_loop, facing_numpy):
        assert f([on_robot, *twins]) == [True, True, True]  # no sight line; each twin's ends on the other's centre
        assert f(behind) == [False, True]  # 1 m away, behind a post on its sight line
        assert f(touching) == [True, True]  # a fence ending on a sight line does not cross it


def test_section_3_2_the_magnitude_from_the_nearest_point_the_direction_from_the_centre():
    """Segment (1, 0)-(1, 2): nearest point (1, 0), 1 m away: |F| = 18 / 1^2 (eq. 2); its centre
    (1, 1) gives the direction -(1, 1)/sqrt 2: (-12.728, -12.728). Half-width 0.2: d = 0.8, |F| =
    18 / 0.64 = 28.125 the same way."""
    fx, fy, mag, distress = linear_force((1.0, 0.0), (1.0, 2.0), K, R)
    assert (fx, fy, mag, distress) == pytest.approx((-18 / math.sqrt(2), -18 / math.sqrt(2), 18.0, False))
    fx, fy, mag, _ = linear_force((1.0, 0.0), (1.0, 2.0), K, R, radius=0.2)
    assert (fx, fy, mag) == pytest.approx((-28.125 / math.sqrt(2), -28.125 / math.sqrt(2), 28.125))
    # in distress (0.3 m <= R_min): F_max = 18 / 0.16 = 112.5, still from the centre (0.3, 1.5) ...
    fx, fy, mag, distress = linear_force((0.3, 0.0), (0.3, 3.0), K, R)
    c = math.hypot(0.3, 1.5)
    assert (fx, fy, mag, distress) == pytest.approx((-0.3 / c * 112.5, -1.5 / c * 112.5, 112.5, True))
    # ... unless told to push from the nearest point, which it does only in distress
    assert linear_force((1.0, 0.0), (1.0, 2.0), K, R, distress_from_nearest=True)[:2] == pytest.approx(
        (-18 / math.sqrt(2), -18 / math.sqrt(2))
    )


def test_section_3_2_a_robot_on_the_centre_flees_along_the_normal():
    """The segment (-2, -1)-(2, 1) centred on the robot: no direction from the centre; its normal
    (-2, 4)/sqrt 20 at F_max (the robot is on it: in the prohibited area)."""
    fx, fy, mag, distress = linear_force((-2.0, -1.0), (2.0, 1.0), K, R)
    n = math.sqrt(20)
    assert (fx, fy, mag, distress) == pytest.approx((-2 / n * 112.5, 4 / n * 112.5, 112.5, True))


def test_section_3_2_a_near_centre_still_gives_the_direction():
    """Segment (0.5, 0)-(0.5, 1): its centre (0.5, 0.5) 0.71 m away gives the direction, its
    nearest point (0.5, 0) the magnitude 18 / 0.25 = 72: (-50.91, -50.91), not the normal's (-72, 0)."""
    fx, fy, mag, _ = linear_force((0.5, 0.0), (0.5, 1.0), K, R)
    assert (fx, fy, mag) == pytest.approx((-72 / math.sqrt(2), -72 / math.sqrt(2), 72.0))


def test_section_3_2_the_prohibited_area_includes_its_edge():
    """A face exactly R_min = 0.4 m away is in distress (eq. 3: d <= R_min)."""
    assert linear_force((0.4, -1.0), (0.4, 1.0), K, R)[2:] == pytest.approx((112.5, True))


@pytest.mark.parametrize("radius", [0.0, 0.15])
def test_eq8_at_the_passable_gap_the_largest_push_back_is_the_targets_pull(radius):
    """Half the gap is the d where max_x 2 K x / (s (s - radius)^2), s = hypot(x, d), equals A_t:
    computed here on a grid of x of its own, just above and below that d."""
    d = passable_gap(PILOT.K, PILOT.A_t, radius) / 2

    def push(d: float) -> float:
        x = np.linspace(0.0, 3.0, 300_001)
        s = np.hypot(x, d)
        return float((2 * PILOT.K * x / (s * (s - radius) ** 2)).max())

    assert push(d) == pytest.approx(PILOT.A_t, rel=1e-4)
    assert push(d * 0.999) > PILOT.A_t > push(d * 1.001)
    if radius == 0.0:  # the closed form of the module docstring: 2 sqrt(0.7698 K / A_t)
        c = 2 / math.sqrt(2) / 1.5**1.5
        assert 2 * d == pytest.approx(2 * math.sqrt(c * PILOT.K / PILOT.A_t), rel=1e-6)


@pytest.mark.parametrize("k, a_t", [(18.0, 50.0), (18.0, 1000.0), (18.0, 0.5), (5.0, 50.0)])
def test_eq8_the_closed_form_holds_for_any_K_and_A_t(k, a_t):
    """Point obstacles: the half-gap d where 0.7698 K / d^2 = A_t, from 0.13 m to 5.3 m here."""
    c = 2 / math.sqrt(2) / 1.5**1.5
    assert passable_gap(k, a_t) == pytest.approx(2 * math.sqrt(c * k / a_t), rel=1e-6)


def test_section_5_the_previous_angle_is_carried_into_the_frame_the_robot_turned_to():
    """A target fixed in the world, 90 deg to the left; the robot then turns 30 deg toward it (by
    odometry), so it sees it at 60 deg: the previous heading, 90 deg in the odometry frame, is 60
    deg in the new one, and the mean of 60 and 60 is 60 (carried the wrong way, 120, it would be 90)."""
    p = PotentialFieldPilot(PILOT, ROBOT)
    p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), (0.0, 5.0), None, ()))
    b = (5 * math.cos(math.radians(60)), 5 * math.sin(math.radians(60)))
    out = p.decide(Beliefs(0.1, Pose(0.0, 0.0, math.radians(30)), b, None, ()))
    assert out.info["raw_turn_deg"] == pytest.approx(60.0) and out.info["turn_deg"] == pytest.approx(60.0)


def test_a_diverting_line_alone_steers_the_pilot():
    """No target point, a diverting line x = 2 from y = 1 to y = 3: outside its corridor the pull
    is toward the line's centre (2, 2), 45 deg to the left."""
    p = PotentialFieldPilot(PILOT, ROBOT)
    out = p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), None, ((2.0, 1.0), (2.0, 3.0)), ()))
    assert out.info["turn_deg"] == pytest.approx(45.0) and out.info["in_corridor"] is False


def test_its_message_with_each_obstacles_force_is_the_published_pilot_record():
    p = PotentialFieldPilot(PILOT, ROBOT)
    post = KnownObstacle("post", (1.0, 0.2), (1.0, 0.2), 0.15)
    out = p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), (5.0, 0.0), None, (post,)))
    msg = msgspec.json.decode(encode(pilot_message(out.info, 0.3, 0.0)), type=PilotMessage)
    force = msg.obstacles["post"]
    c = math.hypot(1.0, 0.2)
    mag = K / (c - 0.15) ** 2  # eq. 2 from its surface
    assert (force.x, force.y, force.mag) == pytest.approx((-1.0 / c * mag, -0.2 / c * mag, mag), abs=1e-4)
    assert force.facing and all(v == round(v, 4) for v in (force.x, force.y, force.mag))  # to 1e-4 force units
