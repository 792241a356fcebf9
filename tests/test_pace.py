"""Progress is measured in distance, not seconds: every window that is about progress
(the Rescuer's blocked window and diverting timeout, the Pilot's stall watch and its reflex's
backup) lasts as long as the robot takes to cover its distance, so a robot at 0.05, 0.1, 0.3 or
0.6 m/s is never declared blocked, or stalled, for being slow."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from navcli.bidding import Bid, Move
from navcli.config import RunSpec
from navcli.mission import Mission
from navcli.navigation.regions import Crossing
from navcli.navigation.rescuer import Rescuer
from navcli.geometry import Pose
from navcli.params import CONTROL_DT, NAVIGATION, PILOT, RobotParams
from navcli.pilot.base import Pilot
from test_navigation import _sweep, situation
from test_pilots import beliefs

SPEEDS = (0.05, 0.1, 0.3, 0.6)
LONG_ONLY = replace(NAVIGATION, stall_rule=False)  # the long window (the stall rule: its own tests below)


def test_the_rescuers_windows_are_never_shorter_than_a_few_stops():
    """At 2 m/s, 12 m take 6 s, less than a scan and a reflex; the windows stay at MIN_WINDOW_S."""
    from navcli.navigation.rescuer import MIN_WINDOW_S

    r = Rescuer(NAVIGATION, np.random.default_rng(0), RobotParams(max_speed=2.0))
    assert NAVIGATION.blocked_window_m / 2.0 < MIN_WINDOW_S
    assert r.window_s == MIN_WINDOW_S and r.timeout_s == max(MIN_WINDOW_S, NAVIGATION.diverting_timeout_m / 2.0)


@pytest.mark.parametrize("speed", SPEEDS)
def test_the_rescuer_gives_a_slow_robot_the_time_its_progress_takes(speed):
    """A robot that gets closer to its target at a tenth of its top speed gains 0.1 x 12 m = 1.2 m
    in a blocked window, more than the 0.5 m that counts as progress, at any speed: it is never
    blocked. The same robot making no progress is blocked once the window, 12 m / speed, is over."""
    robot = RobotParams(max_speed=speed)
    window = NAVIGATION.blocked_window_m / speed
    asked = []
    r = Rescuer(LONG_ONLY, np.random.default_rng(0), robot)
    assert r.window_s == pytest.approx(window) and r.timeout_s == pytest.approx(NAVIGATION.diverting_timeout_m / speed)
    t = t0 = _sweep(r)
    while t < t0 + 3 * window:  # three windows of slow progress
        t += CONTROL_DT
        d = 5.0 - 0.1 * speed * (t - t0)  # from the 5 m of the sweep's situations, 3.6 m closer in 3 windows
        r.decide(situation(target=(d, 0.0), time=t), lambda f: asked.append(f))
    assert asked == [] and r.state == "normal"
    t_stuck = t
    while not asked and t < t_stuck + 2 * window:  # now no progress at all
        t += CONTROL_DT
        r.decide(situation(target=(d, 0.0), time=t), lambda f: asked.append(f) or None)
    # the best distance was set at most 0.5 m of progress (5 / speed s) before the robot stopped
    assert asked == [None] and window < t - t_stuck + 0.5 / (0.1 * speed) + 2 * CONTROL_DT
    assert t - t_stuck <= window + 2 * CONTROL_DT


@pytest.mark.parametrize("speed", SPEEDS)
def test_the_diverting_timeout_is_a_distance(speed):
    """A diverting target held while the robot keeps getting closer to its line (never blocked)
    fails once the robot could have driven diverting_timeout_m at full speed."""
    robot = RobotParams(max_speed=speed)
    r = Rescuer(LONG_ONLY, np.random.default_rng(0), robot)
    t = _sweep(r)
    crossing = Crossing("L", "R", (30.0, 1.0), (30.0, -1.0), 3.0)
    asked = []

    def ask(failed):
        asked.append(failed)
        return crossing

    while not asked:  # no progress toward the target: blocked, the diverting target is set
        t += CONTROL_DT
        r.decide(situation(time=t), ask)
    set_at = t
    x = 30.0
    while len(asked) < 2 and t < set_at + 3 * r.timeout_s:
        t += CONTROL_DT
        x -= 0.6 * speed * CONTROL_DT  # steady progress toward the line, which is far away
        marks = {"L": _crisp(x, 1.0), "R": _crisp(x, -1.0)}
        r.decide(situation(time=t, landmarks=marks), ask)
    assert len(asked) == 2 and asked[1] == frozenset({"L", "R"})  # abandoned, its edge reported
    assert r.timeout_s < t - set_at <= r.timeout_s + 2 * CONTROL_DT


def _crisp(x, y):
    from navcli.fuzzy import FuzzyPoint
    from test_navigation import CRISP

    return FuzzyPoint(x, y, CRISP)


@pytest.mark.parametrize("speed", SPEEDS + (2.0,))
def test_a_robot_starting_from_a_standstill_is_no_stall_at_any_speed(speed):
    """From a standstill the robot lags its command while it accelerates (0.5 m/s^2): at 2 m/s,
    the top speed allowed, it takes 4 s to reach full speed, twice the stall window (0.6 m at 2
    m/s: 0.3 s), and drives 0.0225 m of the 0.6 m commanded in it (a fifth would be 0.12 m). The
    stall watch must not take that for a stall."""
    robot = RobotParams(max_speed=speed)
    p = Pilot(PILOT, robot)
    x, v = 0.0, 0.0
    nav = Bid("navigation", "motion", Move(0.0, speed), 0.3)
    for _ in range(round(3 * p.stall_window_s / CONTROL_DT)):
        cmd, _ = p.execute(nav)
        v = min(cmd, v + robot.max_accel * CONTROL_DT)  # the drive's rate limit
        x += v * CONTROL_DT
        out = p.decide(beliefs(odom=_pose(x)))
        assert out.info["mode"] != "reflex", (speed, x)


@pytest.mark.parametrize("speed", SPEEDS)
def test_a_reflex_backs_up_its_distance_at_any_speed(speed):
    """The reflex backs up backup_distance (0.3 m) at most at the robot's top speed: at 0.05 m/s
    that takes 6 s, longer than the 4 s a stop or look phase may last, and it is not cut short."""
    robot = RobotParams(max_speed=speed)
    p = Pilot(PILOT, robot)
    p._bumped((_bump(),))
    x, backed_ticks = 0.0, 0
    out = p.decide(beliefs(odom=_pose(x)))
    for _ in range(2000):
        if out.info.get("phase") == "look":
            p._looked(next(b.action for b in out.bids if b.resource == "camera"))
        motion = next((b for b in out.bids if b.resource == "motion"), None)
        v, _ = p.execute(motion)
        if out.info.get("phase") == "backup":
            backed_ticks += 1
            assert v == pytest.approx(-min(PILOT.backup_speed, speed))
        x += v * CONTROL_DT
        out = p.decide(beliefs(odom=_pose(x)))
        if out.info.get("phase") == "done":
            break
    assert out.info.get("phase") == "done"
    assert -x == pytest.approx(PILOT.backup_distance, abs=min(PILOT.backup_speed, speed) * CONTROL_DT + 1e-9)
    assert backed_ticks == pytest.approx(PILOT.backup_distance / min(PILOT.backup_speed, speed) / CONTROL_DT, abs=1)


def _pose(x):
    from navcli.geometry import Pose

    return Pose(x, 0.0, 0.0)


def _bump():
    from navcli.beliefs import Bump

    return Bump(0.0, "obstacle 0", (0.3, 0.0), 0.0)


@pytest.mark.parametrize("speed", SPEEDS)
def test_a_mission_around_an_obstacle_is_reached_at_any_speed(make_scenario, speed):
    """A real run: around a post to a target 4.4 m away, at each speed, with vision. Reached, and
    no blocked or stall event on the way (its time limit is three times the drive at full speed,
    plus the initial sweep)."""
    sc = make_scenario(
        arena={"width": 6.0, "height": 4.0},
        robot={"start": [0.8, 2.0], "heading_deg": 0},
        target={"at": [5.2, 2.0]},
        obstacles=[{"circle": {"center": [3.0, 2.05], "radius": 0.15}}],
        mission={"time_limit": round(3 * 4.4 / speed + 20), "seed": 1},
    )
    m = Mission(RunSpec.build(sc, pilot="potential-field", overrides={"robot.max_speed": speed}), snapshots=False)
    events = []
    while m.outcome is None:
        events += [e.message for e in m.step().events]
    assert m.outcome == "reached", (m.reason, events[-5:])
    assert not [e for e in events if "blocked" in e or "stalled" in e]


# -- the stall rule: a short window in time and distance ----------------------------------------
STALL_S = {0.05: 30.0, 0.1: 20.0, 0.3: 20.0, 0.6: 20.0}  # max(20 s, 1.5 m / speed)


@pytest.mark.parametrize("speed", SPEEDS)
def test_a_robot_standing_still_is_stalled_after_the_stall_window_at_any_speed(speed):
    """The stall window is max(stall_window_s, stall_window_m / max_speed): 30 s at 5 cm/s (1.5 m
    at 0.05 m/s), 20 s from 0.075 m/s up; a robot that does not move is blocked when it is over,
    before the long window (12 m: 240 s at 5 cm/s, 40 s at 0.3 m/s; 20 s, the same, at 0.6 m/s)."""
    assert (NAVIGATION.stall_window_s, NAVIGATION.stall_window_m) == (20.0, 1.5)
    r = Rescuer(NAVIGATION, np.random.default_rng(0), RobotParams(max_speed=speed))
    assert r.stall_s == pytest.approx(STALL_S[speed]) and r.stall_s <= r.window_s
    t = swept = _sweep(r)
    asked = []
    while not asked and t < swept + r.window_s:
        t += CONTROL_DT
        r.decide(situation(time=t), lambda f: asked.append(f))
    # the trail starts at the first tick after the sweep; blocked once it spans the window
    assert asked == [None] and r.stall_s <= t - swept <= r.stall_s + 2 * CONTROL_DT


def _swing(r, t, until, ask, period=8.0, amplitude=1.2, target=(5.0, 5.0)):
    """Drive back and forth along x between 0 and ``amplitude`` m (a triangle wave of ``period``
    s: 2.4 m in 8 s, 0.3 m/s), the target fixed in the odometry frame; returns the time and the
    path length driven when the Rescuer first asked the map (or ``until``)."""
    start, path, x_last = t, 0.0, 0.0
    while t < until:
        t += CONTROL_DT
        phase = ((t - start) % period) / period
        x = amplitude * (2 * phase if phase < 0.5 else 2 - 2 * phase)
        path += abs(x - x_last)
        x_last = x
        odo = Pose(x, 0.0, 0.0)
        r.decide(situation(target=odo.to_local(target), time=t, odometry=odo), ask)
        if ask.calls:
            return t, path
    return t, path


class _Ask:
    def __init__(self):
        self.calls = []

    def __call__(self, failed):
        self.calls.append(failed)
        return None


def test_a_robot_swinging_between_two_obstacles_is_stalled_though_it_drives_on():
    """At 0.3 m/s swinging 1.2 m back and forth (8 s a swing, never bumping), the robot drives
    6 m in the 20 s window but its net displacement over the window, 1.2 - 2x for x where the
    window began (2.5 swings back), falls below 0.3 m within every half swing (4 s): blocked
    between 20 and 24 s. By the long rule alone it is not blocked before its 40 s window."""
    speed = 0.3
    r = Rescuer(NAVIGATION, np.random.default_rng(0), RobotParams(max_speed=speed))
    ask = _Ask()
    t0 = _sweep(r)
    t, path = _swing(r, t0, t0 + 60.0, ask)
    assert ask.calls == [None] and 20.0 <= t - t0 <= 24.0 + 2 * CONTROL_DT and path > 6.0
    r = Rescuer(LONG_ONLY, np.random.default_rng(0), RobotParams(max_speed=speed))
    ask = _Ask()
    t0 = _sweep(r)
    t, _ = _swing(r, t0, t0 + 60.0, ask)
    assert t - t0 > 40.0  # (the best distance is set in the first swing, 40 s before)


def test_a_deliberate_scan_is_no_stall():
    """The robot stands still while the Rescuer scans for a lost target for 25 s (a camera slow
    to answer), longer than the 20 s window: no stall is declared during the scan, and the trail
    starts again when it ends, so the still robot is blocked 20 s after the scan, not at once."""
    r = Rescuer(NAVIGATION, np.random.default_rng(0), RobotParams(max_speed=0.3))
    t = _sweep(r)
    ask = _Ask()
    scan_end = t + 25.0
    while t < scan_end:  # lost: the Rescuer scans (no look reported: the scan waits)
        t += CONTROL_DT
        out = r.decide(situation(time=t, I_a=0.9), ask)
        assert r.state == "lost" and not ask.calls and out.bids
    while not ask.calls and t < scan_end + 60.0:  # found again; still not moving
        t += CONTROL_DT
        r.decide(situation(time=t), ask)
    assert ask.calls == [None] and r.stall_s <= t - scan_end <= r.stall_s + 2 * CONTROL_DT


def test_a_bump_restarts_the_stall_window():
    """The Pilot's reflex after a bump stops and looks around (a deliberate stop): a still robot
    bumping once 15 s after the sweep is blocked 20 s after the bump, not 20 s after the sweep
    (one bump is not the three of ``blocked_bumps``)."""
    from navcli.beliefs import Bump

    r = Rescuer(NAVIGATION, np.random.default_rng(0), RobotParams(max_speed=0.3))
    t = swept = _sweep(r)
    ask = _Ask()
    bumped = None
    while not ask.calls and t < swept + 60.0:
        t += CONTROL_DT
        bumps = ()
        if bumped is None and t >= swept + 15.0:
            bumps, bumped = (Bump(t, "obstacle 0", (0.3, 0.0), 0.0),), t
        r.decide(situation(time=t, bumps=bumps), ask)
    assert ask.calls == [None] and r.stall_s <= t - bumped <= r.stall_s + 2 * CONTROL_DT


def test_a_robot_led_away_from_its_target_is_blocked_after_stall_approach_windows():
    """At 5 cm/s the stall window is 30 s; a robot driving straight away from its target at full
    speed moves 1.5 m net in each window (no stall by displacement) but comes no closer: blocked
    once ``stall_approach`` (2) windows, 60 s, are over, not after the long window's 240 s; with
    ``stall_approach`` 0, not before 240 s."""
    speed, target = 0.05, (5.0, 0.0)
    for approach, lo, hi in ((2.0, 60.0, 60.0 + 2 * CONTROL_DT), (0.0, 240.0, 300.0)):
        r = Rescuer(
            replace(NAVIGATION, stall_approach=approach), np.random.default_rng(0), RobotParams(max_speed=speed)
        )
        t = t0 = _sweep(r)
        ask = _Ask()
        while not ask.calls and t < t0 + 300.0:
            t += CONTROL_DT
            odo = Pose(-speed * (t - t0), 0.0, 0.0)
            r.decide(situation(target=odo.to_local(target), time=t, odometry=odo), ask)
        assert ask.calls == [None] and lo <= t - t0 <= hi, approach
