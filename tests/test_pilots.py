"""Pilot behaviour: execution, reflexes, the look-ahead bid, the geometric baseline, and the
claims of equation 8 played out in the physics world."""

from __future__ import annotations

import math

import pytest

from analysis import read_log
from navcli.config import RunSpec
from navcli.bidding import Bid, Move
from navcli.pilot.geometric import GeometricPilot, blocked_interval
from navcli.geometry import Pose
from navcli.mission import Mission
from navcli.params import CONTROL_DT, PILOT, ROBOT
from navcli.beliefs import Beliefs, KnownObstacle
from navcli.pilot.base import Pilot
from navcli.pilot.potential_field import PotentialFieldPilot
from navcli.runner import run_mission
from navcli.beliefs import Bump


def beliefs(obstacles=(), target=(5.0, 0.0), odom=Pose(0.0, 0.0, 0.0), looked=None, bumps=()):
    return Beliefs(0.0, odom, target, None, tuple(obstacles), 0.0, looked, tuple(bumps))


def nav(move):
    return Bid("navigation", "motion", move, 0.3)


# -- execution ---------------------------------------------------------------------------------
def test_execution_turns_toward_the_heading_and_drives_when_facing_it():
    p = Pilot(PILOT, ROBOT)
    v, w = p.execute(nav(Move(0.2, 0.3)))
    assert v == pytest.approx(0.3 * math.cos(0.2)) and w == pytest.approx(PILOT.heading_gain * 0.2)
    v, w = p.execute(nav(Move(math.radians(90), 0.3)))
    assert v == 0.0 and w > 0  # turn in place first
    assert p.execute(None) == (0.0, 0.0)


def test_section_3_5_turns_over_160_degrees_are_driven_backwards_within_a_budget():
    p = Pilot(PILOT, ROBOT)
    v, w = p.execute(nav(Move(math.radians(170), 0.3)))
    assert v == pytest.approx(-0.3 * math.cos(math.radians(10)))  # backwards...
    assert w == pytest.approx(PILOT.heading_gain * math.radians(-10))  # ...turning the complement
    v, _ = p.execute(nav(Move(math.radians(150), 0.3)))
    assert v == 0.0  # under 160 degrees: an ordinary turn in place
    p.backward = PILOT.max_backward  # the backwards budget is spent
    v, w = p.execute(nav(Move(math.radians(170), 0.3)))
    assert v == 0.0 and w > 0


def test_backward_budget_counts_backward_travel_and_refills_after_a_forward_stretch():
    p = Pilot(PILOT, ROBOT)
    for x in (0.0, -0.2, -0.4):
        p.decide(beliefs(odom=Pose(x, 0.0, 0.0)))
    assert p.backward == pytest.approx(0.4)
    for x in (0.0, 0.3):
        p.decide(beliefs(odom=Pose(x, 0.0, 0.0)))
    assert p.backward == pytest.approx(0.0)  # 0.7 m forwards >= max_backward


# -- eq. 1: the look-ahead camera bid ------------------------------------------------------------
def test_eq1_look_bid_grows_with_distance_since_the_last_look_ahead():
    p = PotentialFieldPilot(PILOT, ROBOT)
    assert p.look_bid() == 0.0
    p.since_look = 0.5
    assert p.look_bid() == pytest.approx((0.5 / PILOT.look_d_max) ** PILOT.look_exponent)
    p.since_look = 5.0
    assert p.look_bid() == pytest.approx(0.9)  # capped like every Pilot bid
    out = p.decide(beliefs())
    assert any(b.resource == "camera" and b.value == pytest.approx(0.9) for b in out.bids)
    p.decide(beliefs(looked=math.radians(60)))  # Vision reports the image it took
    assert p.look_bid() == pytest.approx(0.9)  # a look to the side is not a look ahead
    p.decide(beliefs(looked=0.0))
    assert p.look_bid() == 0.0


# -- reflexes (section 3.5) --------------------------------------------------------------------
def test_reflex_stops_looks_around_backs_up_then_avoids_again():
    p = PotentialFieldPilot(PILOT, ROBOT)
    p.decide(beliefs(odom=Pose(1.0, 1.0, 0.0)))
    bumps = [Bump(3.0, "obstacle 0", (1.4, 1.0), 0.0)]  # felt during the last tick
    phases, looks = [], []
    x, looked = 1.0, None
    for _ in range(200):
        out = p.decide(beliefs(odom=Pose(x, 1.0, 0.0), looked=looked, bumps=bumps))
        bumps, looked = [], None
        phase = out.info.get("phase")
        if out.info["mode"] != "reflex" or phase == "done":
            break
        phases.append(phase)
        motion = next(b for b in out.bids if b.resource == "motion")
        assert motion.value == pytest.approx(0.9)
        if phase == "backup":
            assert motion.action.speed < 0
            x -= 0.015  # the robot backs up 1.5 cm per tick
        else:
            assert motion.action == Move(0.0, 0.0)
        if phase == "look":
            look = next(b for b in out.bids if b.resource == "camera")
            looks.append(round(math.degrees(look.action.pan)))
            looked = look.action.pan  # Vision carries the look out; the pilot hears of it next tick
    order = [ph for i, ph in enumerate(phases) if i == 0 or phases[i - 1] != ph]
    assert order == ["stop", "look", "backup"]
    assert phases.count("stop") == round(PILOT.reflex_stop_s / CONTROL_DT)
    assert looks == list(PILOT.reflex_look_pans_deg)
    assert 1.0 - x == pytest.approx(PILOT.backup_distance, abs=0.02)
    # afterwards the pilot avoids again, with what its beliefs now hold
    hit = KnownObstacle("bump-1", (0.6, 0.0), (0.6, 0.0), 0.05)
    after = p.decide(beliefs([hit], odom=Pose(x, 1.0, 0.0)))
    assert after.info["mode"] == "avoid" and "bump-1" in after.info["obstacles"]


def test_reflex_after_hitting_an_obstacle_the_pilot_did_not_know(make_scenario, tmp_path):
    """Camera range 0.3 m: the obstacle is only found by the bumper; the reflex, and the
    obstacle the bumper put in the visual memory, then take the robot around it to the target."""
    sc = make_scenario(obstacles=[{"circle": {"center": [2.5, 2.0], "radius": 0.15}}],
                       camera={"range": 0.3}, noise={"odometry": 0.0})
    out = tmp_path / "bump.mcap"
    res = run_mission(RunSpec.build(sc), out=out)
    log = read_log(out)
    ev = list(log["/events"]["message"])
    assert any("bumper contact with obstacle 0" in m for m in ev)
    assert any(m.startswith("reflex: bumper hit") for m in ev)
    assert any(m.startswith("reflex done") for m in ev)
    assert res.summary["outcome"] == "reached"
    assert 1 <= res.summary["collisions"] <= 3
    pilot = log["/pilot"]
    assert (pilot["mode"] == "reflex").any()
    assert any(c.startswith("obstacles.bump-") for c in pilot)  # the visual memory holds the obstacle hit
    backup = pilot[pilot.get("phase") == "backup"]
    assert (backup["command.v"] < 0).all() and len(backup) > 0


# -- the geometric pilot -----------------------------------------------------------------------
def test_geometric_pilot_steers_along_the_nearer_tangent_when_the_request_is_blocked():
    g = GeometricPilot(PILOT, ROBOT)
    obstacle = KnownObstacle("o", (1.2, 0.1), (1.2, 0.1), 0.15)
    a = g.avoid(beliefs([obstacle]), [obstacle], Move(0.0, 0.3))
    right, left = blocked_interval(obstacle, PILOT.R_min)
    assert a.bid == pytest.approx(0.9) and a.info["rule"] == "tangent"
    assert a.move.heading == pytest.approx(right)  # the obstacle sits left of the request
    assert right == pytest.approx(math.atan2(0.1, 1.2) - math.asin(0.4 / math.hypot(1.2, 0.1)))


def test_geometric_pilot_keeps_out_of_the_way_when_the_request_is_safe():
    g = GeometricPilot(PILOT, ROBOT)
    obstacle = KnownObstacle("o", (1.5, 1.0), (1.5, 1.0), 0.15)
    a = g.avoid(beliefs([obstacle]), [obstacle], Move(0.0, 0.3))
    assert a.move is None and a.bid == 0.0


def test_geometric_pilot_escapes_from_inside_a_grown_obstacle():
    g = GeometricPilot(PILOT, ROBOT)
    obstacle = KnownObstacle("o", (0.3, 0.0), (0.3, 0.0), 0.15)
    a = g.avoid(beliefs([obstacle]), [obstacle], Move(0.0, 0.3))
    assert a.info["rule"] == "escape" and abs(a.move.heading) == pytest.approx(math.pi)


def test_geometric_pilot_passes_a_long_obstacle_around_its_nearer_end():
    g = GeometricPilot(PILOT, ROBOT)
    wall = KnownObstacle("w", (1.0, -0.5), (1.0, 2.0), 0.025)
    a = g.avoid(beliefs([wall]), [wall], Move(0.0, 0.3))
    assert a.move.heading < 0  # the lower end is nearer the request: pass below it
    assert math.tan(a.move.heading) * 1.0 < -0.5  # ...outside the grown end


# -- equation 8, in the physics world ----------------------------------------------------------
def gap_scenario(make_scenario, gap):
    obstacles = [{"circle": {"center": [3.0, 2.0 + s * gap / 2], "radius": 0.1}} for s in (-1, 1)]
    return make_scenario(arena={"width": 6.0, "height": 5.0}, robot={"start": [0.8, 2.0], "heading_deg": 0},
                         target={"at": [5.2, 2.0]}, obstacles=obstacles, noise={"odometry": 0.0},
                         mission={"time_limit": 120, "seed": 1})


def crossing_y(mission_poses, x=3.0):
    """Where the robot crossed the obstacles' line x = 3."""
    for (x0, y0), (x1, y1) in zip(mission_poses, mission_poses[1:]):
        if x0 < x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return None


def drive_mission(sc, perception="oracle"):
    """Equation 8 is a property of the pilot: isolate it from vision with the oracle perception."""
    m = Mission(RunSpec.build(sc, pilot="potential-field", perception=perception))
    poses = [(m.world.pose.x, m.world.pose.y)]
    while m.outcome is None:
        t = m.step()
        poses.append((t.pose.x, t.pose.y))
    return m, poses


def test_eq8_drives_between_two_obstacles_1_1_m_apart_without_touching(make_scenario):
    m, poses = drive_mission(gap_scenario(make_scenario, 1.1))
    assert m.outcome == "reached" and m.world.bumps == 0
    y = crossing_y(poses)
    assert y is not None and abs(y - 2.0) < 0.55 - 0.1 - 0.25  # between them, clear of both


def test_eq8_goes_around_two_obstacles_0_6_m_apart(make_scenario):
    m, poses = drive_mission(gap_scenario(make_scenario, 0.6))
    assert m.outcome == "reached" and m.world.bumps == 0
    y = crossing_y(poses)
    assert y is not None and abs(y - 2.0) > 0.3 + 0.1 + 0.25  # outside the pair, not through it


def test_crossing_a_diverting_target_line_ends_the_mission(make_scenario):
    sc = make_scenario(target={"line": [[4.0, 0.5], [4.0, 3.5]]}, robot={"start": [1.0, 1.0], "heading_deg": 0})
    m, poses = drive_mission(sc)
    assert m.outcome == "reached"
    assert poses[-2][0] < 4.0 <= poses[-1][0]
    assert poses[-1][1] == pytest.approx(1.0, abs=0.2)  # straight across, inside the corridor
