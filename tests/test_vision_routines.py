"""Vision as the papers describe it: each look runs one routine, a fence is one object,
and the walls are a stated condition. Each behaviour has a control: navcli's camera before
(``vision.routines`` 0, ``vision.line_objects`` 0) fails it."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from conftest import SCENARIOS
from navcli.bidding import Look
from navcli.config import RunSpec
from navcli.geometry import Pose, distance_to_segment
from navcli.learning.actions import MB, MVL
from navcli.mission import Mission
from navcli.params import CONTROL_DT, VISION
from navcli.scenario import load_scenario
from navcli.training.task import NavigationTask, Start, task_spec
from navcli.vision.camera import Camera
from navcli.vision.perception import VisionPerception
from navcli.vision.visual_memory import Spot, VisualMemory

OLD = dataclasses.replace(VISION, routines=0, line_objects=0)
NOISELESS = {"odometry": 0.0, "vision_heading_deg": 0.0, "vision_distance": 0.0}
ROBOT = Pose(1.0, 2.0, 0.0)


def room(make_scenario, **over):
    """A 6 m x 4 m room, the robot at (1, 2) facing +x; the target landmark T and landmarks A, B
    all in view ahead."""
    return make_scenario(
        target={"landmark": "T", "tolerance": 0.3},
        noise=NOISELESS,
        landmarks=[{"id": "T", "at": [4.0, 2.0]}, {"id": "A", "at": [3.5, 2.9]}, {"id": "B", "at": [3.5, 1.1]}],
        **over,
    )


def keys(dets):
    return sorted(d.key or d.kind for d in dets)


@pytest.mark.parametrize("params", [VISION, OLD], ids=["routines", "control: every look sees all"])
def test_a_look_for_the_target_registers_no_other_landmark(make_scenario, params):
    cam = Camera(room(make_scenario), np.random.default_rng(0), params)
    dets = cam.capture(ROBOT, "target" if params.routines else "everything", known={"A"})
    if params.routines:
        assert keys(dets) == ["T"]
    else:
        assert {"A", "B", "T"} <= set(keys(dets))  # without routines an image registers everything in view


@pytest.mark.parametrize("params", [VISION, OLD], ids=["routines", "control: every look sees all"])
def test_a_search_registers_no_known_landmark_again(make_scenario, params):
    cam = Camera(room(make_scenario), np.random.default_rng(0), params)
    dets = cam.capture(ROBOT, "search" if params.routines else "everything", known={"A", "T"})
    if params.routines:
        assert keys(dets) == ["B"]  # the new one only: A and the known target are not re-measured
    else:
        assert {"A", "T"} <= set(keys(dets))
    # the target, unknown, is a new landmark the robot can recognise: a search finds it
    assert "T" in keys(cam.capture(ROBOT, "search", known={"A"}))


def test_re_acquiring_the_known_landmarks_and_scanning_for_the_lost_target(make_scenario):
    cam = Camera(room(make_scenario), np.random.default_rng(0))
    assert keys(cam.capture(ROBOT, "landmarks", known={"A", "T"})) == ["A"]  # not the target, not the unknown B
    assert keys(cam.capture(ROBOT, "scan", known={"A"})) == ["A", "T"]  # the target, known or not, and the known


def test_the_look_for_obstacles_sees_obstacles_and_unknown_landmarks_as_plain_points(make_scenario):
    sc = room(
        make_scenario,
        obstacles=[
            {"circle": {"center": [2.5, 2.5], "radius": 0.1}},
            {"segment": {"from": [5.0, 1.0], "to": [5.0, 3.0]}},
        ],
    )
    cam = Camera(sc, np.random.default_rng(0))
    dets = cam.capture(ROBOT, "obstacles", known={"A"})
    assert [d for d in dets if d.kind == "landmark"] == []  # the obstacle routine identifies no landmark
    points = [d for d in dets if d.kind == "obstacle" and not d.key]
    assert len(points) == 3  # the circle, and the unknown landmarks B and T as plain obstacles (not A: known)
    assert [d.key for d in dets if d.kind == "obstacle" and d.ends] == ["segment:o1"]  # the fence, as itself
    assert not [d for d in cam.capture(ROBOT, "search") if d.kind in ("obstacle", "wall")]  # a search finds none
    # the memory drops a plain point once a landmark routine identifies the landmark there
    mem = VisualMemory(0.0)
    mem.observe(dets, 0.0)
    assert sum(1 for m in mem.items.values() if m.kind == "obstacle" and len(m.spots) == 1) == 3
    mem.observe(cam.capture(ROBOT, "search", known=mem.items), 0.1)
    assert {"B", "T"} <= set(mem.items)
    assert sum(1 for m in mem.items.values() if m.kind == "obstacle" and len(m.spots) == 1) == 1  # the circle


def _pan_then_stop(cam: Camera, ticks: int) -> int:
    """Ask for a look at 90 degrees (a 1 s pan) for ``ticks`` ticks, then for nothing; images taken."""
    images = 0
    for k in range(30):
        request = Look(math.radians(90), "search") if k < ticks else None
        images += cam.step(k * CONTROL_DT, ROBOT, request, CONTROL_DT) is not None
    return images


@pytest.mark.parametrize("params", [VISION, OLD], ids=["routines", "control: a pan once begun delivers"])
def test_a_pan_no_look_asks_for_any_more_is_cancelled_without_an_image(make_scenario, params):
    cam = Camera(room(make_scenario), np.random.default_rng(0), params)
    images = _pan_then_stop(cam, 3)  # the look won 3 ticks, then a move without a look (MB)
    assert images == (0 if params.routines else 1)
    assert _pan_then_stop(Camera(room(make_scenario), np.random.default_rng(0), params), 30) >= 1


def test_another_look_that_wins_turns_the_camera_and_sets_the_routine(make_scenario):
    cam = Camera(room(make_scenario), np.random.default_rng(0))
    cam.step(0.0, ROBOT, Look(math.radians(90), "search"), CONTROL_DT)
    images = []
    for k in range(1, 20):
        out = cam.step(k * CONTROL_DT, ROBOT, Look(0.0, "target"), CONTROL_DT)
        if out is not None:
            images.append((cam.looked, keys(out)))
    assert images and images[0] == (Look(0.0, "target"), ["T"])


def blind_images(overrides):
    """MVL and MB in turn in the paper's task (with ``overrides``): the images taken during the MB
    actions, and the actions run."""
    base = task_spec(load_scenario(SCENARIOS / "landmarks-12.yaml"), overrides)
    task = NavigationTask(base)
    task.reset(Start(2.0, 2.0, 0.3, 5))
    blind = 0
    for k in range(24):
        before = task.mission.camera_looks
        task.step(MB if k % 2 else MVL)
        if k % 2:
            blind += task.mission.camera_looks - before
        if task.outcome is not None:
            break
    return blind, k


@pytest.mark.parametrize("params", [VISION, OLD], ids=["routines", "control: a pan in flight delivers"])
def test_move_blind_gets_no_image_in_the_learning_task(params):
    """MVL and MB in turn, the camera the Learning Agent's alone (``pilot.looks`` off): an MB
    action takes no image, even when MVL's pan is still in flight as it begins."""
    over = {f"vision.{f}": getattr(params, f) for f in ("routines", "line_objects")}
    blind, k = blind_images(over | {"pilot.looks": False})
    assert k > 10
    assert (blind == 0) if params.routines else (blind > 0)


def test_move_blind_frees_the_camera_for_the_pilot_in_the_learning_task():
    """The paper's task leaves the Pilot its looks: an MB action leaves the camera free, and the
    Pilot's look-ahead (eq. 1) takes images then."""
    blind, k = blind_images({})
    assert k > 10 and blind > 0


# -- a linear obstacle is one object -------------------------------------------------------------
def fence_room(make_scenario, **over):
    return make_scenario(
        arena={"width": 10.0, "height": 6.0},
        robot={"start": [1.0, 1.0], "heading_deg": 0},
        target={"at": [9.0, 5.0]},
        obstacles=[{"segment": {"from": [3.0, 3.0], "to": [9.0, 3.0]}}],
        noise=NOISELESS,
        **over,
    )


def test_a_fence_cut_by_the_view_is_one_object_whose_ends_say_what_was_seen(make_scenario):
    sc = fence_room(make_scenario)
    cam = Camera(sc, np.random.default_rng(0))
    look = Pose(2.0, 1.0, math.radians(60))  # the view holds the fence's end a (3, 3) and a stretch of it
    (det,) = [d for d in cam.capture(look, "obstacles") if d.key.startswith("segment:")]
    assert det.key == "segment:o0" and det.ends == (True, False)  # a is the end; toward b the view cut it
    mem = VisualMemory(0.0)
    mem.observe([det], 0.0)
    (line,) = mem.items.values()
    a_seen = look.to_world((line.spots[0].x, line.spots[0].y))
    assert math.dist(a_seen, (3.0, 3.0)) < 1e-9  # noiseless scenario: the end itself
    # a second view, farther along: the end b in view too; end a is not moved by anything cut
    look2 = Pose(5.0, 1.0, math.atan2(2.0, 4.0))  # facing the end b (9, 3), 4.5 m away; a out of view
    travel(mem, look, look2)
    det2 = next(d for d in cam.capture(look2, "obstacles") if d.key.startswith("segment:"))
    assert det2.ends == (False, True)
    mem.observe([det2], 0.1)
    ends = [look2.to_world((s.x, s.y)) for s in mem.items["segment:o0"].spots]
    assert math.dist(ends[0], (3.0, 3.0)) < 1e-9 and math.dist(ends[1], (9.0, 3.0)) < 1e-9
    assert mem.items["segment:o0"].exact == (True, True)


def test_a_cut_point_keeps_the_farthest_extent_and_never_moves_a_seen_end():

    mem = VisualMemory(0.0)
    s = lambda x, y, r=0.05: Spot(x, y, r, 0.0)  # noqa: E731
    mem._observe_line("segment:f", "obstacle", [s(0.0, 2.0), s(1.0, 2.0)], (False, False), 0.025, 0.0)
    mem._observe_line("segment:f", "obstacle", [s(-1.0, 2.0), s(0.5, 2.0)], (False, False), 0.025, 0.1)
    a, b = mem.items["segment:f"].spots
    assert (a.x, b.x) == (-1.0, 1.0)  # the union of the two stretches seen
    mem._observe_line("segment:f", "obstacle", [s(-2.0, 2.0), s(0.0, 2.0)], (True, False), 0.025, 0.2)
    mem._observe_line("segment:f", "obstacle", [s(-2.5, 2.0), s(0.0, 2.0)], (False, False), 0.025, 0.3)
    a, b = mem.items["segment:f"].spots
    assert a.x == -2.0 and mem.items["segment:f"].exact == (True, False)  # a cut point beyond it: noise, ignored


def travel(mem: VisualMemory, a: Pose, b: Pose) -> None:
    """Move the memory as the odometry reports a robot going from ``a`` to ``b``: turn to face b,
    drive straight, turn to b's heading (each step exact for the odometry's model)."""
    h = math.atan2(b.y - a.y, b.x - a.x)
    mem.move(0.0, math.remainder(h - a.theta, math.tau))
    mem.move(math.dist((a.x, a.y), (b.x, b.y)), 0.0)
    mem.move(0.0, math.remainder(b.theta - h, math.tau))


@pytest.mark.parametrize("params", [VISION, OLD], ids=["objects", "control: pieces joined by geometry"])
def test_a_door_between_two_pieces_of_one_wall_is_never_closed(make_scenario, params):
    """A wall across the room with a 1.5 m door, its two pieces on one line, looked at from both
    sides, near and far, with the camera's noise, all folded into one memory: no remembered line
    may come within 0.5 m of the door's middle (0.75 m from each piece). The old memory's lines,
    joined by geometry, close it from some places (it closed door-wall's door in 1 of 100 runs)."""
    sc = make_scenario(
        arena={"width": 10.0, "height": 8.0},
        robot={"start": [5.0, 1.0], "heading_deg": 90},
        target={"at": [5.0, 7.0]},
        noise={"odometry": 0.0, "vision_heading_deg": 2.0, "vision_distance": 0.05},
        obstacles=[
            {"segment": {"from": [0.5, 4.0], "to": [4.25, 4.0]}},
            {"segment": {"from": [5.75, 4.0], "to": [9.5, 4.0]}},
        ],
    )
    cam = Camera(sc, np.random.default_rng(3), params)
    mem = VisualMemory(0.0, params)
    door = (5.0, 4.0)
    rng = np.random.default_rng(11)
    pose, closed, lines = Pose(5.0, 1.0, math.pi / 2), 0, 0
    for k in range(120):
        south = k < 60
        y = float(rng.uniform(0.8, 3.4) if south else rng.uniform(4.6, 7.2))
        x = float(rng.uniform(1.0, 9.0))
        aim = math.atan2(4.0 - y, float(rng.uniform(2.0, 8.0)) - x)
        nxt = Pose(x, y, aim)
        travel(mem, pose, nxt)
        pose = nxt
        mem.observe(cam.capture(pose, "obstacles" if params.routines else "everything", mem.items), 0.0)
        for m in mem.items.values():
            if len(m.spots) == 2 and m.kind != "wall":
                a, b = (pose.to_world((s.x, s.y)) for s in m.spots)
                closed += distance_to_segment(door, a, b) < 0.5
                lines += 1
    assert lines > 100
    if params.line_objects:
        assert closed == 0
        assert sorted(k for k, m in mem.items.items() if m.kind != "wall") == ["segment:o0", "segment:o1"]
    else:
        assert closed > 0  # pieces joined by geometry close the door from some places


# -- the walls, a stated condition ---------------------------------------------------------------
@pytest.mark.parametrize("walls", ["seen", "known", "felt"])
def test_how_the_robot_knows_the_walls(make_scenario, walls):
    sc = make_scenario()
    params = dataclasses.replace(VISION, walls=walls)
    perception = VisionPerception(sc, np.random.default_rng(0), params)
    told = [m for m in perception.memory.items.values() if m.kind == "wall"]
    assert len(told) == (4 if walls == "known" else 0)
    assert all(m.prior and m.exact == (True, True) for m in told)
    dets = Camera(sc, np.random.default_rng(0), params).capture(Pose(1.0, 2.0, 0.0), "obstacles")
    assert any(d.kind == "wall" for d in dets) == (walls != "felt")


def test_a_fence_between_landmarks_ends_at_them(make_scenario):
    """The thesis' linear obstacles run between landmarks: a fence whose ends the robot has seen
    at landmarks it remembers takes its ends from where the memory holds those landmarks, once
    they are the sharper; seen only in its middle, it is anchored nowhere (the robot cannot know
    where it ends)."""
    sc = make_scenario(
        arena={"width": 10.0, "height": 6.0},
        robot={"start": [5.0, 1.0], "heading_deg": 90},
        target={"at": [5.0, 5.5]},
        landmarks=[{"id": "P", "at": [2.0, 3.0]}, {"id": "Q", "at": [8.0, 3.0]}],
        obstacles=[{"segment": {"from": [2.2, 3.0], "to": [7.8, 3.0]}}],
    )
    m = Mission(RunSpec.build(sc, overrides={"navigation.initial_sweep": 0, "pilot.looks": 0}), snapshots=False)
    p = m.perception
    truth = m.world.pose
    p.memory.observe([d for d in p.camera.capture(truth, "obstacles") if d.ends], 0.0)  # the middle only
    assert p.memory.items["segment:o0"].exact == (False, False)
    for pan in (56.0, -56.0):  # P and Q, 56 degrees either side of the heading
        p.camera.pan = math.radians(pan)
        p.memory.observe(p.camera.capture(truth, "search", p.memory.items), 0.0)
    assert {"P", "Q"} <= set(p.memory.items)
    p.learn_anchors()
    (fence,) = [o for o in p.observe(0.0, truth, truth).obstacles if o.key == "segment:o0"]
    at = {k: (p.memory.items[k].spots[0].x, p.memory.items[k].spots[0].y) for k in "PQ"}
    assert all(math.dist(end, at[k]) > 1.0 for end in (fence.a, fence.b) for k in "PQ")  # its middle: not anchored
    fence_m = p.memory.items["segment:o0"]  # its ends seen close by, sharp: 0.24 m from P's and Q's centres
    assert p.memory.items["P"].radius == 0.15 and fence_m.radius == 0.025
    ends = [(at["P"][0], at["P"][1] - 0.24), (at["Q"][0], at["Q"][1] + 0.24)]
    fence_m.spots = [Spot(*e, 0.04, 0.0) for e in ends]
    fence_m.exact = (True, True)
    for k in "PQ":
        p.memory.items[k].spots[0] = Spot(*at[k], 0.05, 0.0)
    # the bodies' gap 0.24 - 0.15 - 0.025 = 0.065 m <= 0.05 + 0.3 x 0.04 + 0.3 x 0.05 = 0.077 m: anchored
    p.learn_anchors()
    (fence,) = [o for o in p.observe(0.0, truth, truth).obstacles if o.key == "segment:o0"]
    assert (fence.a, fence.b) == (ends[0], ends[1])  # its own ends, sharper than the landmarks
    fence_m.spots = [Spot(*e, 0.2, 0.0) for e in ends]  # the fence's ends blur, the landmarks stay sharp
    (fence,) = [o for o in p.observe(0.0, truth, truth).obstacles if o.key == "segment:o0"]
    assert (fence.a, fence.b) == (at["P"], at["Q"])  # the ends are where the memory holds P and Q
    far = p.memory.items["segment:o0"]
    far.spots = [Spot(ends[0][0], ends[0][1] - 0.3, 0.04, 0.0), Spot(ends[1][0], ends[1][1] + 0.3, 0.04, 0.0)]
    p._anchors.clear()  # its ends 0.54 m from P's and Q's centres: a gap of 0.365 m, as by a door
    p.learn_anchors()
    assert p._anchors == {}


def test_a_line_seen_by_one_sample_has_two_ends_each_moved_once():
    """One sample of a fence stands for both its ends: two spots, so that odometry moves each once
    (one spot held twice was moved twice: the line ran off with the robot, 4 m in 60 s)."""

    mem = VisualMemory(0.0)
    mem._observe_line("segment:f", "obstacle", [Spot(2.0, 1.0, 0.05, 0.0)], (False, False), 0.025, 0.0)
    mem.move(1.0, 0.0)
    assert [(s.x, s.y) for s in mem.items["segment:f"].spots] == [(1.0, 1.0), (1.0, 1.0)]
    mem._observe_line("segment:f", "obstacle", [Spot(1.0, 1.0, 0.05, 0.0)], (False, False), 0.025, 0.1)
    mem.move(1.0, 0.0)
    assert [(s.x, s.y) for s in mem.items["segment:f"].spots] == [(0.0, 1.0), (0.0, 1.0)]
