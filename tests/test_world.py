"""The pymunk world: walls and obstacles stop the robot, contacts become bumps, odometry drifts."""

from __future__ import annotations

import math

import numpy as np
import pytest

import navcli
from navcli.params import CONTROL_DT, ROBOT
import navcli.world as world_module
from navcli.world import World

c_servo_only = pytest.mark.skipif(world_module.C_SERVO is None, reason="this build has no servo in C")
SERVOS = ["python", pytest.param("c", marks=c_servo_only)]


@pytest.fixture
def servo(request, monkeypatch) -> str:
    """The servo the worlds made in the test drive their robot with (``python``: the reference)."""
    if request.param == "python":
        monkeypatch.setattr(world_module, "C_SERVO", None)
    return request.param


def world_for(make_scenario, speed=0.3, noise=0.0, slip=0.0, **over) -> World:
    """A world whose wheels execute the command exactly unless ``slip`` says otherwise."""
    sc = make_scenario(
        robot={"start": [1.0, 2.0], "heading_deg": 0, "max_speed": speed},
        noise={"odometry": noise, "slip": slip},
        **over,
    )
    return World(sc, np.random.default_rng(0), motion_rng=np.random.default_rng(1))


def drive(world: World, v: float, omega: float, seconds: float):
    bumps = []
    for _ in range(round(seconds / CONTROL_DT)):
        bumps += world.step(v, omega)
    return bumps


@pytest.mark.parametrize("speed", [0.3, 2.0])
def test_wall_stops_the_robot_at_top_speed(make_scenario, speed):
    w = world_for(make_scenario, speed=speed)
    drive(w, speed, 0.0, 20.0)
    r = w.robot.radius
    assert w.pose.x + r <= 6.0 + 0.01  # no more than slop into the wall, never through it
    assert w.pose.x + r >= 6.0 - 0.01  # and it did drive all the way to it
    assert w.speed[0] == pytest.approx(speed)  # the wheels kept pushing the whole time


@pytest.mark.parametrize("speed", [0.3, 2.0])
@pytest.mark.parametrize(
    "obstacle",
    [
        {"circle": {"center": [3.0, 2.0], "radius": 0.15}},
        {"segment": {"from": [3.0, 0.5], "to": [3.0, 3.5], "thickness": 0.02}},
    ],
    ids=["circle", "thin-segment"],
)
def test_obstacle_stops_the_robot(make_scenario, speed, obstacle):
    w = world_for(make_scenario, speed=speed, obstacles=[obstacle])
    bumps = drive(w, speed, 0.0, 8.0)
    r = w.robot.radius
    half = obstacle["circle"]["radius"] if "circle" in obstacle else 0.01
    assert w.pose.x <= 3.0 - half - r + 0.01
    assert w.pose.x >= 3.0 - half - r - 0.02
    assert [b.what for b in bumps] == ["obstacle 0"]


def test_bump_event_reports_what_where_and_bearing(make_scenario):
    w = world_for(make_scenario, obstacles=[{"circle": {"center": [2.0, 2.0], "radius": 0.15}}])
    bumps = drive(w, 0.3, 0.0, 6.0)
    assert len(bumps) == 1 and w.bumps == 1
    (b,) = bumps
    assert b.what == "obstacle 0"
    assert b.point[0] == pytest.approx(2.0 - 0.15, abs=0.01) and b.point[1] == pytest.approx(2.0, abs=0.01)
    assert b.bearing == pytest.approx(0.0, abs=0.05)  # dead ahead
    assert 1.0 < b.time < 3.0  # a 0.6 m gap (1.25 to 1.85) at 0.3 m/s, after a 0.6 s ramp-up: about 2.3 s


def test_a_new_contact_counts_again_only_after_letting_go(make_scenario):
    w = world_for(make_scenario, obstacles=[{"circle": {"center": [2.0, 2.0], "radius": 0.15}}])
    assert len(drive(w, 0.3, 0.0, 6.0)) == 1  # pushing on counts once
    drive(w, -0.3, 0.0, 3.0)
    assert len(drive(w, 0.3, 0.0, 6.0)) == 1  # backing off and driving in again: a new bump
    assert w.bumps == 2


def test_touching_again_soon_after_letting_go_is_the_same_bump(make_scenario):
    w = world_for(make_scenario, obstacles=[{"circle": {"center": [2.0, 2.0], "radius": 0.15}}])
    assert len(drive(w, 0.3, 0.0, 6.0)) == 1 and w.touching  # pushing on it: the bumper stays pressed
    # reversing at 0.5 m/s^2 from 0.3 m/s: the contact holds for 0.6 s, then the robot backs off
    # for 0.2 s (1 cm); driving in again, it is back within about 0.5 s, under BUMP_REARM
    touching = []
    for v, seconds in ((-0.3, 0.8), (0.3, 3.0)):
        for _ in range(round(seconds / CONTROL_DT)):
            assert w.step(v, 0.0) == []
            touching.append(w.touching)
    assert touching[:5] == [True] * 5  # still pushed on while the wheels slow down
    assert False in touching and touching[-1]  # let go of it, and touching it again
    assert w.bumps == 1


def test_limits_on_speed_acceleration_and_turn_rate(make_scenario):
    w = world_for(make_scenario, speed=0.3)
    w.step(5.0, 10.0)
    v, omega = w.speed
    assert v == pytest.approx(min(0.3, ROBOT.max_accel * CONTROL_DT))
    assert omega == pytest.approx(min(ROBOT.max_turn_rate, ROBOT.max_turn_accel * CONTROL_DT))
    drive(w, 5.0, 10.0, 3.0)
    assert w.speed == pytest.approx((0.3, ROBOT.max_turn_rate))


def test_drives_like_a_differential_base(make_scenario):
    w = world_for(make_scenario)
    drive(w, 0.0, math.radians(45), 2.5)  # turn in place
    drive(w, 0.0, 0.0, 1.0)  # and come to rest
    assert abs(w.pose.x - 1.0) < 1e-6 and abs(w.pose.y - 2.0) < 1e-6
    assert w.path_length < 1e-6
    theta = w.pose.theta
    drive(w, 0.2, 0.0, 3.0)
    dx, dy = w.pose.x - 1.0, w.pose.y - 2.0
    assert math.atan2(dy, dx) == pytest.approx(theta, abs=1e-3)  # no sideways slip
    assert w.path_length == pytest.approx(math.hypot(dx, dy), rel=1e-6)


def test_odometry_is_exact_without_noise(make_scenario):
    w = world_for(make_scenario, noise=0.0)
    drive(w, 0.3, 0.6, 10.0)  # a 0.5 m circle, across the +-pi wrap, clear of the walls
    o, t = w.odometry.pose, w.pose
    assert math.hypot(o.x - t.x, o.y - t.y) < 0.01 * w.path_length  # dead reckoning at 10 Hz
    assert abs(o.theta - t.theta) < 1e-9


def test_odometry_distance_error_has_the_scenario_relative_spread(make_scenario):
    sc = make_scenario(robot={"start": [1.0, 2.0], "heading_deg": 0}, noise={"odometry": 0.05, "slip": 0.0})
    rel = []
    for seed in range(40):
        w = World(sc, np.random.default_rng(seed))
        drive(w, 0.3, 0.0, 10.0)
        believed = math.hypot(w.odometry.pose.x - 1.0, w.odometry.pose.y - 2.0)
        rel.append(believed / w.path_length - 1.0)
    # per-run calibration error (sd 0.05) dominates the averaged per-tick error (sd 0.05/sqrt(100))
    assert 0.03 < float(np.std(rel)) < 0.08
    assert abs(float(np.mean(rel))) < 0.03  # unbiased


def test_odometry_heading_drifts_along_a_straight_run_by_the_scenario_spread(make_scenario):
    """``noise.odometry_drift_deg_per_m: 1`` and no other error: driving straight 3 m (0.3 m/s,
    10 s), the believed heading turns by 3 m x (the per-run rate, sd 1 deg/m) plus the per-tick
    parts (30 ticks of 0.03 m x sd 1 deg/m: sd 0.03 x sqrt(100) = 0.3 deg all told), while the
    true heading stays. Over 60 runs the spread is about 3 deg, the mean about 0."""
    sc = make_scenario(
        robot={"start": [1.0, 2.0], "heading_deg": 0},
        noise={"odometry": 0.0, "odometry_drift_deg_per_m": 1.0, "slip": 0.0},
    )
    turned = []
    for seed in range(60):
        w = World(sc, np.random.default_rng(seed))
        drive(w, 0.3, 0.0, 10.0)
        assert abs(w.pose.theta) < 1e-3  # the truth goes straight
        turned.append(math.degrees(w.odometry.pose.theta) / w.path_length)  # deg per metre believed
    assert 0.7 < float(np.std(turned)) < 1.3
    assert abs(float(np.mean(turned))) < 0.4  # unbiased: sd 1 / sqrt(60) = 0.13


@pytest.mark.parametrize("servo", SERVOS, indirect=True)
def test_a_tick_stopped_between_physics_steps_keeps_path_and_pose_together(make_scenario, monkeypatch, servo):
    steps: list[float] = []  # the physics steps of the interrupted tick
    armed = False

    def interrupt(dt: float) -> None:  # Ctrl-C arrives after the second of the tick's physics steps
        if armed:
            steps.append(dt)
            if len(steps) == 2:
                raise KeyboardInterrupt

    if servo == "c":  # the C servo's step
        velocity, c_step = world_module.C_SERVO

        def interrupting(space, body, v, w, dt):
            c_step(space, body, v, w, dt)
            interrupt(dt)

        monkeypatch.setattr(world_module, "C_SERVO", (velocity, interrupting))
    real = world_module.chipmunk

    class Interrupting:  # Chipmunk's library, whose step the Python servo's world calls
        def __getattr__(self, name):
            return getattr(real, name)

        def cpSpaceStep(self, space, dt):
            real.cpSpaceStep(space, dt)
            interrupt(dt)

    monkeypatch.setattr(world_module, "chipmunk", Interrupting())
    w = world_for(make_scenario)
    drive(w, 0.3, 0.0, 2.0)  # straight ahead, at speed
    x0, y0, before = w.pose.x, w.pose.y, w.path_length
    armed = True
    with pytest.raises(KeyboardInterrupt):
        w.step(0.3, 0.0)
    moved = math.hypot(w.pose.x - x0, w.pose.y - y0)
    assert moved > 0.005  # two steps at about 0.3 m/s: a run's log ends at this pose
    assert w.path_length - before == pytest.approx(moved, rel=1e-9)  # and its path length agrees with it
    assert len(steps) == 2


# --- the servo in C (navcli/servo.c) and in Python (World._drive, the reference) ---


def test_the_compiled_build_drives_with_the_servo_in_c_and_the_pure_builds_in_python():
    assert (world_module.C_SERVO is not None) == (navcli.BUILD == "compiled")


def servo_run(make_scenario, seed: int) -> tuple[list, list, int]:
    """Random commands for 60 s in a cluttered room, with slip: every pose and bump, and how many."""
    w = world_for(
        make_scenario,
        speed=1.0,
        slip=0.1,
        obstacles=[
            {"circle": {"center": [3.0, 2.0], "radius": 0.3}},
            {"segment": {"from": [1.0, 3.0], "to": [5.0, 3.2], "thickness": 0.02}},
        ],
    )
    commands = np.random.default_rng(seed).uniform([-0.2, -1.5], [1.0, 1.5], (600, 2))
    poses, bumps = [], []
    for v, omega in commands:
        bumps += w.step(float(v), float(omega))
        poses.append(w.pose)
    return poses, bumps, w.bumps


@c_servo_only
@pytest.mark.parametrize("seed", [1, 2])
def test_the_c_servo_drives_the_robot_exactly_as_the_python_servo(make_scenario, monkeypatch, seed):
    """To the last bit: the same Chipmunk calls with the same numbers, every physics step, in
    contact (sliding along walls and obstacles) as in the open, the wheels slipping."""
    c = servo_run(make_scenario, seed)
    monkeypatch.setattr(world_module, "C_SERVO", None)
    python = servo_run(make_scenario, seed)
    assert c[2] >= 2  # the robot did meet things
    assert len({(round(p.x, 1), round(p.y, 1)) for p in c[0]}) > 30  # and went places
    assert c == python


@c_servo_only
@pytest.mark.parametrize("room", ["paper-8x8", "trap-box"])
def test_a_mission_on_the_c_servo_logs_every_message_as_on_the_python_servo(monkeypatch, tmp_path, room):
    from conftest import SCENARIOS
    from navcli.config import RunSpec
    from mcap.reader import make_reader

    from navcli.runner import run_mission
    from navcli.scenario import load_scenario

    spec = RunSpec.build(load_scenario(SCENARIOS / f"{room}.yaml"), pilot="potential-field", seed=3, time_limit=60.0)
    run_mission(spec, out=tmp_path / "c.mcap")
    monkeypatch.setattr(world_module, "C_SERVO", None)
    run_mission(spec, out=tmp_path / "python.mcap")

    def messages(name: str) -> list[tuple[str, int, bytes]]:
        with (tmp_path / f"{name}.mcap").open("rb") as f:
            return [(ch.topic, m.log_time, m.data) for _, ch, m in make_reader(f).iter_messages(log_time_order=True)]

    c, python = messages("c"), messages("python")
    assert len(c) > 1000
    assert c == python


# --- the wheels' slip (robot.slip_noise, Webots' DifferentialWheels slipNoise) ---


def test_slip_factors_are_uniform_within_the_stated_bound_per_wheel_and_step():
    """Uniform in [1 - s, 1 + s]: each factor within the bound, mean 1, SD s / sqrt(3) (0.0577 for
    s = 0.1); 2 x PHYSICS_SUBSTEPS per tick, left and right not the same draw."""
    from navcli.params import PHYSICS_SUBSTEPS
    from navcli.world import Slip

    slip = Slip(0.1, 0.5, np.random.default_rng(3))
    ticks = [slip.factors() for _ in range(2000)]
    assert all(len(f) == 2 * PHYSICS_SUBSTEPS for f in ticks)
    f = np.array(ticks)
    assert f.min() >= 0.9 and f.max() <= 1.1
    assert float(f.mean()) == pytest.approx(1.0, abs=0.002)  # SE 0.0577 / sqrt(20000) = 0.0004
    assert float(f.std()) == pytest.approx(0.1 / math.sqrt(3), rel=0.03)
    assert abs(float(np.corrcoef(f[:, 0], f[:, 1])[0, 1])) < 0.05  # the wheels draw apart


def test_slip_turns_the_wheels_speeds_back_into_the_drives():
    """Wheels at v -/+ omega * axle / 2: equal factors scale both v and omega; a faster right
    wheel alone turns the robot left by its extra speed over the axle."""
    from navcli.world import Slip

    s = Slip(0.1, 0.5, np.random.default_rng(0))
    assert s.executed(0.2, 0.4, 1.05, 1.05) == pytest.approx((0.21, 0.42))
    # v 0.2 straight, right wheel 10 % fast: right 0.22, left 0.2 -> v 0.21, omega 0.02 / 0.5 = 0.04
    assert s.executed(0.2, 0.0, 1.0, 1.1) == pytest.approx((0.21, 0.04))


def test_the_executed_speed_strays_by_the_stated_spread_tick_by_tick(make_scenario):
    """Driving straight at 0.1 m/s with ``noise.slip: 0.1``: per physics step the forward speed is
    the mean of the two wheels', relative SD 0.1 / sqrt(3) / sqrt(2); a tick averages 5 such steps,
    so the distance driven per tick has relative SD 0.1 / sqrt(30) = 0.0183, and mean the command."""
    w = world_for(make_scenario, speed=0.1, slip=0.1)
    drive(w, 0.1, 0.0, 1.0)  # up to speed (0.5 m/s^2)
    rel = []
    for _ in range(300):
        before = w.path_length
        w.step(0.1, 0.0)
        rel.append((w.path_length - before) / (0.1 * CONTROL_DT) - 1.0)
    assert float(np.std(rel)) == pytest.approx(0.1 / math.sqrt(30), rel=0.15)  # SE of an SD, 300 samples: 4 %
    assert abs(float(np.mean(rel))) < 0.005  # SE 0.0183 / sqrt(300) = 0.001
    assert w.speed == pytest.approx((0.1, 0.0))  # the drive's own state keeps the command: no noise builds up in it


def test_without_slip_the_robot_drives_the_command_exactly(make_scenario):
    w = world_for(make_scenario, speed=0.1, slip=0.0)
    drive(w, 0.1, 0.0, 1.0)
    lengths = []
    for _ in range(20):
        before = w.path_length
        w.step(0.1, 0.0)
        lengths.append(w.path_length - before)
    assert lengths == pytest.approx([0.1 * CONTROL_DT] * 20, abs=1e-9)
    assert abs(w.pose.theta) < 1e-12


def test_slip_needs_a_generator_of_its_own(make_scenario):
    sc = make_scenario(noise={"slip": 0.1})
    with pytest.raises(ValueError, match="generator"):
        World(sc, np.random.default_rng(0))
