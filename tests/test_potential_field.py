"""The potential-field pilot, equation by equation, against numbers worked out by hand."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navcli.params import PILOT
from navcli.beliefs import KnownObstacle
from navcli.pilot.potential_field import (
    facing,
    facing_loop,
    facing_numpy,
    field,
    line_target_force,
    linear_force,
    pilot_bid,
    point_force,
    target_force,
)

K, A_t, R = 18.0, 50.0, 0.40
F_MAX = K / R**2  # 112.5, eq. 3


def pt(key, x, y, r=0.15):
    return KnownObstacle(key, (x, y), (x, y), r)


def seg(key, a, b):
    return KnownObstacle(key, a, b, 0.025)


def test_eq2_point_force_falls_with_the_square_of_distance_away_from_the_obstacle():
    fx, fy, mag, distress = point_force((1.0, 0.0), K, R)
    assert (fx, fy, mag, distress) == pytest.approx((-18.0, 0.0, 18.0, False))
    fx, fy, mag, distress = point_force((0.3, 0.4), K, R)  # d = 0.5: 18 / 0.25 = 72, along -(0.6, 0.8)
    assert (fx, fy, mag) == pytest.approx((-43.2, -57.6, 72.0)) and not distress


def test_eq2_4_distances_count_from_the_obstacles_surface():
    """A 0.15 m obstacle whose centre is 0.65 m away is 0.5 m away: 18 / 0.25 = 72 (eq. 2); the
    prohibited area ends R_min = 0.40 m from its surface, i.e. 0.55 m from its centre, 0.15 m
    before a 0.25 m robot would touch it (contact at 0.40 m between centres)."""
    fx, fy, mag, distress = point_force((0.65, 0.0), K, R, radius=0.15)
    assert (fx, fy, mag, distress) == pytest.approx((-72.0, 0.0, 72.0, False))
    assert point_force((0.56, 0.0), K, R, radius=0.15)[3] is False
    assert point_force((0.54, 0.0), K, R, radius=0.15)[2:] == pytest.approx((F_MAX, True))
    # a linear obstacle 0.05 m thick: from its face
    _, _, mag, distress = linear_force((1.025, -1.0), (1.025, 1.0), K, R, radius=0.025)
    assert mag == pytest.approx(18.0) and not distress


def test_eq3_4_inside_the_grown_circle_the_force_is_the_constant_f_max():
    for o in ((0.2, 0.0), (0.0, -0.4), (0.1, 0.1)):
        fx, fy, mag, distress = point_force(o, K, R)
        assert mag == pytest.approx(F_MAX) and distress
        assert math.hypot(fx, fy) == pytest.approx(F_MAX)
        assert fx * o[0] + fy * o[1] < 0  # pointing away from the obstacle


def test_section_3_2_linear_force_magnitude_from_nearest_point_direction_from_centre():
    fx, fy, mag, distress = linear_force((1.0, -1.0), (1.0, 3.0), K, R)
    # nearest point (1, 0): |F| = 18 / 1**2; centre (1, 1): direction -(1, 1)/sqrt(2)
    assert mag == pytest.approx(18.0) and not distress
    assert (fx, fy) == pytest.approx((-18 / math.sqrt(2), -18 / math.sqrt(2)))


def test_eq5_target_force_is_constant_whatever_the_distance():
    assert target_force((3.0, 4.0), A_t) == pytest.approx((30.0, 40.0))
    assert target_force((300.0, 400.0), A_t) == pytest.approx((30.0, 40.0))


def test_section_3_3_corridor_pull_is_perpendicular_inside_and_to_the_centre_outside():
    fx, fy, inside = line_target_force((2.0, -3.0), (2.0, 3.0), A_t, 0.4)
    assert inside and (fx, fy) == pytest.approx((50.0, 0.0))  # straight at the line
    fx, fy, inside = line_target_force((2.0, -0.5), (2.0, 5.0), A_t, 0.4)  # projects 0.5 m from an end
    assert inside and (fx, fy) == pytest.approx((50.0, 0.0))
    fx, fy, inside = line_target_force((2.0, 1.0), (2.0, 5.0), A_t, 0.4)  # projects beyond the end
    assert not inside and (fx, fy) == pytest.approx((2 / math.sqrt(13) * 50, 3 / math.sqrt(13) * 50))
    fx, fy, inside = line_target_force((2.0, -0.3), (2.0, 5.0), A_t, 0.4)  # within the margin of an end
    assert not inside and fy > 0


def test_eq6_7_net_force_and_turn_angle():
    f = field((5.0, 0.0), None, [pt("o", 1.0, 0.5, r=0.0)], PILOT)  # a point, as in the paper
    # d^2 = 1.25: |F| = 14.4 along -(1, 0.5)/sqrt(1.25)
    fo = (-14.4 / math.sqrt(1.25), -7.2 / math.sqrt(1.25))
    assert f.net == pytest.approx((50 + fo[0], fo[1]))
    assert f.turn == pytest.approx(math.atan2(fo[1], 50 + fo[0]))
    assert not f.in_distress and not f.passed


def test_eq9_bid_is_0_9_times_the_strongest_single_repulsion_over_f_max():
    f = field((5.0, 0.0), None, [pt("near", 1.0, 0.5, r=0.0), pt("far", 2.0, -1.5, r=0.0)], PILOT)
    assert f.g_max == pytest.approx(14.4)
    assert f.bid == pytest.approx(0.9 * 14.4 / 112.5)
    assert pilot_bid(F_MAX, PILOT) == pytest.approx(0.9) and pilot_bid(2 * F_MAX, PILOT) == pytest.approx(0.9)
    assert field((5.0, 0.0), None, [], PILOT).bid == 0.0
    no_repulsion = replace(PILOT, K=0.0)  # K = 0 is accepted: nothing repels, and nothing is bid
    assert field((5.0, 0.0), None, [pt("near", 0.3, 0.0)], no_repulsion).bid == 0.0


def test_section_5_in_distress_each_offender_weighs_1_5_and_the_target_is_ignored():
    f = field((5.0, 1.0), None, [pt("hit", 0.2, 0.2, r=0.0), pt("other", 0.0, 2.0, r=0.0)], PILOT)
    assert f.in_distress
    u = -1 / math.sqrt(2)
    hit = (1.5 * F_MAX * u, 1.5 * F_MAX * u)
    other = (0.0, -18 / 4)
    assert f.net == pytest.approx((hit[0] + other[0], hit[1] + other[1]))
    assert f.bid == pytest.approx(0.9)
    # two obstacles in distress, left and right ahead: both weigh 1.5 (their sideways pushes cancel)
    f = field(
        (5.0, 0.0), None, [pt("l", 0.3, 0.2, r=0.0), pt("r", 0.3, -0.1, r=0.0), pt("far", -2.0, 0.0, r=0.0)], PILOT
    )
    ul, ur = (0.3, 0.2), (0.3, -0.1)
    nl, nr = math.hypot(*ul), math.hypot(*ur)
    want = (-1.5 * F_MAX * (ul[0] / nl + ur[0] / nr) + 18 / 4, -1.5 * F_MAX * (ul[1] / nl + ur[1] / nr))
    assert f.net == pytest.approx(want) and f.target == pytest.approx((50.0, 0.0))


def test_in_the_corner_of_two_fences_distress_pushes_out_from_their_nearest_points():
    """Inside the corner of a U: a fence 0.3 m to the left, running ahead from the corner
    (-0.3, 0.3) to (2.7, 0.3), and one 0.3 m behind, running from the corner to (-0.3, -2.7). Both are IN_DISTRESS (0.3 - 0.025 <= R_min), so the target is
    ignored and each weighs 1.5. Section 3.2 pushes from their centres (1.2, 0.3) and
    (-0.3, -1.2): (-0.970, -0.243) and (0.243, 0.970), each along the other fence, which sum to
    (-0.728, 0.728): straight into the corner, at 135 degrees, a sink. From the nearest points
    (0, 0.3) and (-0.3, 0) (``distress_from_nearest``, our design): (0, -1) and (1, 0), out
    of the corner at -45 degrees."""
    corner = [seg("left", (-0.3, 0.3), (2.7, 0.3)), seg("behind", (-0.3, 0.3), (-0.3, -2.7))]
    centre = field((0.0, 5.0), None, corner, replace(PILOT, distress_from_nearest=0))
    assert centre.in_distress
    assert math.degrees(math.atan2(centre.net[1], centre.net[0])) == pytest.approx(135.0)
    u = 1.2 / math.hypot(1.2, 0.3) - 0.3 / math.hypot(1.2, 0.3)  # |each component| of the sum
    assert centre.net == pytest.approx((-1.5 * F_MAX * u, 1.5 * F_MAX * u))
    nearest = field((0.0, 5.0), None, corner, PILOT)
    assert nearest.net == pytest.approx((1.5 * F_MAX, -1.5 * F_MAX))


def test_section_5_repulsion_from_passed_obstacles_is_dropped():
    f = field((5.0, 0.0), None, [pt("behind", -1.0, 0.2, r=0.0)], PILOT)  # repulsion points at the target
    assert f.passed and f.repulsion == (0.0, 0.0) and f.net == pytest.approx((50.0, 0.0)) and f.turn == 0.0
    assert f.bid > 0  # the bid still says an obstacle is near
    f = field((5.0, 0.0), None, [pt("ahead", 1.0, 0.2)], PILOT)
    assert not f.passed and f.repulsion != (0.0, 0.0)


def test_section_5_only_obstacles_directly_facing_the_robot_contribute():
    wall = seg("A", (1.0, -1.0), (1.0, 1.0))
    hidden, beside = pt("B", 2.0, 0.3), pt("C", 2.0, 3.0)
    assert facing([wall, hidden, beside]) == [True, False, True]
    # Figure 13: points behind a linear obstacle are hidden; one behind another point obstacle too
    assert facing([pt("near", 1.0, 0.0), pt("far", 2.0, 0.05)]) == [True, False]
    assert facing([pt("near", 1.0, 0.0), pt("far", 2.0, 0.6)]) == [True, True]
    f = field((5.0, 0.0), None, [wall, hidden], PILOT)
    assert [o.facing for o in f.forces] == [True, False]
    only_wall = field((5.0, 0.0), None, [wall], PILOT)
    assert f.net == pytest.approx(only_wall.net)


def test_a_segment_crossing_the_sight_line_of_its_own_neighbour_hides_it_but_not_itself():
    a = seg("A", (1.0, -1.0), (1.0, 1.0))
    b = seg("B", (3.0, -1.0), (3.0, 1.0))
    assert facing([a, b]) == [True, False]


coords = st.integers(-6000, 6000).map(lambda v: v / 1000)  # a millimetre grid: physical layouts


@st.composite
def layouts(draw):
    n = draw(st.integers(0, 12))
    obs = []
    for i in range(n):
        x, y = draw(coords), draw(coords)
        if draw(st.booleans()):
            obs.append(pt(f"p{i}", x, y, draw(st.floats(0.01, 0.3))))
        else:
            x2, y2 = draw(coords), draw(coords)
            if math.hypot(x2 - x, y2 - y) > 1e-3:
                obs.append(seg(f"s{i}", (x, y), (x2, y2)))
    return obs


@settings(deadline=None)
@given(layouts(), coords, coords)
def test_bid_stays_in_0_0_9_and_forces_stay_bounded_for_any_layout(obstacles, tx, ty):
    f = field((tx, ty), None, obstacles, PILOT)
    assert 0.0 <= f.bid <= 0.9
    for o in f.forces:
        assert 0.0 <= o.magnitude <= F_MAX + 1e-9
        assert math.hypot(o.fx, o.fy) <= F_MAX + 1e-9
    bound = 1.5 * F_MAX + len(obstacles) * F_MAX + A_t
    assert math.hypot(*f.net) <= bound
    assert -math.pi <= f.turn <= math.pi and math.isfinite(f.turn)


@settings(deadline=None)
@given(layouts())
def test_numpy_and_loop_occlusion_agree(obstacles):
    assert facing_numpy(obstacles) == facing_loop(obstacles)


@settings(deadline=None)
@given(layouts())
def test_the_inlined_occlusion_is_the_geometry_of_lines_of_sight(obstacles):
    from navcli.geometry import blocks_sight, crosses_sight

    def hides(q, c):
        return blocks_sight((0.0, 0.0), c, q.a, q.radius) if q.is_point else crosses_sight((0.0, 0.0), c, q.a, q.b)

    ref = [not any(j != i and hides(q, o.centre) for j, q in enumerate(obstacles)) for i, o in enumerate(obstacles)]
    assert facing_loop(obstacles) == ref


# -- section 5, as worded ----------------------------------------------------------------------
def test_section_5_the_turn_is_the_mean_of_this_angle_and_the_previous_one():
    """Raw angles 0, 90, 90, 90 degrees give 0, 45, 90, 90: the mean of the new and the previous
    computed angle, not a running filter (which would give 0, 45, 67.5, 78.75)."""
    from navcli.beliefs import Beliefs
    from navcli.geometry import Pose
    from navcli.params import ROBOT
    from navcli.pilot.potential_field import PotentialFieldPilot

    p = PotentialFieldPilot(PILOT, ROBOT)
    turns = []
    for target in ((5.0, 0.0), (0.0, 5.0), (0.0, 5.0), (0.0, 5.0)):  # no obstacles: raw = target bearing
        out = p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), target, None, ()))
        turns.append(out.info["turn_deg"])
    assert turns == pytest.approx([0.0, 45.0, 90.0, 90.0])


def test_section_5_no_averaging_in_distress():
    from navcli.beliefs import Beliefs
    from navcli.geometry import Pose
    from navcli.params import ROBOT
    from navcli.pilot.potential_field import PotentialFieldPilot

    p = PotentialFieldPilot(PILOT, ROBOT)
    p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), (5.0, 0.0), None, ()))  # previous angle: 0
    near = pt("near", 0.25, 0.25, r=0.0)  # 0.35 m: inside R_min, the repulsion alone, straight away
    out = p.decide(Beliefs(0.0, Pose(0.0, 0.0, 0.0), (5.0, 0.0), None, (near,)))
    assert out.info["in_distress"] and out.info["turn_deg"] == pytest.approx(-135.0)
    assert out.info["raw_turn_deg"] == out.info["turn_deg"]


def test_occlusion_never_hides_an_obstacle_in_distress():
    """A long linear obstacle whose nearest point is 0.325 m away but whose centre lies behind a
    small obstacle: section 5's sight line to the centre is blocked, yet it still pushes."""
    wall = seg("long", (0.35, -3.0), (0.35, 0.5))  # centre (0.35, -1.25); face 0.325 m away
    pole = pt("pole", 0.2, -0.714, r=0.15)  # on the sight line from that centre to the robot
    assert facing([wall, pole]) == [False, True]  # the plain occlusion test would hide it
    f = field((5.0, 0.0), None, [wall, pole], PILOT)
    forces = {o.key: o for o in f.forces}
    assert forces["long"].facing and forces["long"].in_distress and f.in_distress


def test_a_rooms_corner_is_no_sink():
    """At 0.45 m from two walls, section 3.2 on whole 8 m walls (direction from their centres)
    pushes the robot along both walls into the corner; a wall as the 1 m stretch nearest the robot
    pushes it out."""
    south = ((-0.45, -0.45), (7.55, -0.45))  # the robot at (0.45, 0.45) of an 8 m room, facing +x
    west = ((-0.45, 7.55), (-0.45, -0.45))
    whole = [KnownObstacle(k, a, b, 0.0) for k, (a, b) in (("s", south), ("w", west))]
    rx, ry = field(None, None, whole, PILOT).repulsion
    assert rx < 0 and ry < 0  # both walls push toward the corner
    walls = [KnownObstacle(k, a, b, 0.0, wall=True) for k, (a, b) in (("s", south), ("w", west))]
    rx, ry = field(None, None, walls, PILOT).repulsion
    assert rx > 0 and ry > 0 and rx == pytest.approx(ry)  # out of it, along the diagonal
    f = field((5.0, 5.0), None, walls, PILOT)
    assert 0 < f.turn < math.pi / 2


def test_a_fence_longer_than_the_line_window_pushes_away_from_its_near_stretch_not_along_it():
    """Section 3.2 takes the direction from a linear obstacle's centre: beside one end of a 9 m
    fence 0.6 m to the left, the centre is 4 m ahead, and the push points back along the fence
    (atan2(-0.6, -4), -171 degrees). Longer than ``line_window`` (3 m), the fence acts as its
    3 m stretch nearest the robot, clipped at the fence's end 0.5 m behind: from -0.5 to 2.5 m,
    centred 1 m ahead, so the push turns away from the fence (atan2(-0.6, -1), -149 degrees).
    A 2.8 m obstacle, the paper's kind, is unchanged."""
    long = KnownObstacle("fence", (-0.5, 0.6), (8.5, 0.6), 0.0)
    f = field((5.0, 0.0), None, [long], PILOT)
    ((fx, fy),) = [(o.fx, o.fy) for o in f.forces]
    assert math.degrees(math.atan2(fy, fx)) == pytest.approx(math.degrees(math.atan2(-0.6, -1.0)))
    paper = replace(PILOT, line_window=100.0)
    ((gx, gy),) = [(o.fx, o.fy) for o in field((5.0, 0.0), None, [long], paper).forces]
    assert math.degrees(math.atan2(gy, gx)) == pytest.approx(math.degrees(math.atan2(-0.6, -4.0)))
    short = KnownObstacle("post-row", (-0.5, 0.6), (2.3, 0.6), 0.0)
    assert field((5.0, 0.0), None, [short], PILOT).forces == field((5.0, 0.0), None, [short], paper).forces
