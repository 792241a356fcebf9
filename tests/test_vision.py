"""The camera and the visual memory: what can be seen, how it is measured, how belief drifts,
sharpens and is forgotten, and that it stays honest over a whole mission."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENARIOS
from navcli.config import RunSpec
from navcli.bidding import Look
from navcli.geometry import Pose, distance_to_segment
from navcli.mission import Mission
from navcli.params import CONTROL_DT, VISION
from navcli.scenario import Circle, load_scenario
from navcli.vision.camera import Camera, segment_steps
from navcli.vision.visual_memory import Spot, VisualMemory


def camera(make_scenario, noise=0.0, params=VISION, **over):
    sc = make_scenario(noise={"odometry": 0.0, "vision_heading_deg": noise, "vision_distance": noise / 20}, **over)
    return Camera(sc, np.random.default_rng(0), params)


LEGACY = dataclasses.replace(VISION, routines=0, line_objects=0)
"""The camera without routines and the memory of fences as pieces: every image sees all, pieces joined by geometry."""


ROBOT = Pose(1.0, 2.0, 0.0)


def seen(cam, pose=ROBOT):
    """The landmarks in an image taken from ``pose``."""
    return {d.key for d in cam.capture(pose) if d.kind == "landmark"}


def test_a_landmark_behind_an_obstacle_is_not_seen(make_scenario):
    hidden = camera(
        make_scenario,
        landmarks=[{"id": "A", "at": [4.0, 2.0]}],
        obstacles=[{"circle": {"center": [2.5, 2.05], "radius": 0.2}}],
    )
    assert "A" not in seen(hidden)
    clear = camera(
        make_scenario,
        landmarks=[{"id": "A", "at": [4.0, 2.0]}],
        obstacles=[{"circle": {"center": [2.5, 2.6], "radius": 0.2}}],
    )
    assert "A" in seen(clear)
    wall = camera(
        make_scenario,
        landmarks=[{"id": "A", "at": [4.0, 2.0]}],
        obstacles=[{"segment": {"from": [2.5, 1.0], "to": [2.5, 3.0]}}],
    )
    assert "A" not in seen(wall)


def test_field_of_view_and_range_edges(make_scenario):
    # 60 degree field of view: 29 degrees off the axis is in, 31 is out; range 6 m
    at = lambda deg, d: [1.0 + d * math.cos(math.radians(deg)), 2.0 + d * math.sin(math.radians(deg))]  # noqa: E731
    sc = dict(
        arena={"width": 9.0, "height": 6.0},
        landmarks=[
            {"id": "in", "at": at(29, 2.0)},
            {"id": "out", "at": at(-31, 2.0)},
            {"id": "near", "at": at(0, 5.9)},
            {"id": "far", "at": at(5, 6.1)},
        ],
    )
    assert seen(camera(make_scenario, **sc)) == {"in", "near"}


def test_the_pan_takes_time_and_stops_at_its_limit(make_scenario):
    cam = camera(make_scenario, landmarks=[{"id": "A", "at": [1.0, 3.5]}])  # straight to the left
    spec = cam.spec
    t, images = 0.0, []
    for _ in range(40):  # the look is asked for until its image is taken
        out = cam.step(t, ROBOT, Look(math.radians(90), "search") if not images else None, CONTROL_DT)
        if out is not None:
            images.append((t, out))
        t += CONTROL_DT
    ((t_img, dets),) = images
    assert t_img == pytest.approx(math.radians(90) / spec.pan_speed, abs=CONTROL_DT)  # 1 s at 90 deg/s
    assert [d.key for d in dets if d.kind == "landmark"] == ["A"]
    cam.step(t, ROBOT, Look(math.radians(170), "search"), CONTROL_DT)
    while cam.state == "panning":
        t += CONTROL_DT
        cam.step(t, ROBOT, Look(math.radians(170), "search"), CONTROL_DT)
    assert cam.pan == pytest.approx(spec.pan_limit)  # 100 degrees, not 170


def test_the_camera_is_busy_while_it_processes_an_image(make_scenario):
    cam = camera(make_scenario)
    images = [k for k in range(12) if cam.step(k * CONTROL_DT, ROBOT, Look(0.0, "search"), CONTROL_DT) is not None]
    period = round(cam.spec.look_time / CONTROL_DT)  # already panned: one image per processing time
    assert images == list(range(0, 12, period))


def test_measurements_hold_the_truth_in_their_support(make_scenario):
    cam = camera(make_scenario, noise=2.0, landmarks=[{"id": "A", "at": [4.0, 2.6]}])
    true_h, true_d = math.atan2(0.6, 3.0), math.hypot(3.0, 0.6)
    cores = []
    for _ in range(300):
        s = cam.measure(ROBOT, (4.0, 2.6))
        assert s.heading.contains(true_h) and s.distance.contains(true_d)
        cores.append(s.heading.centre)
    assert np.std(cores) == pytest.approx(math.radians(2.0), rel=0.2)  # the scenario's deviation
    far = cam.measure(ROBOT, (6.5, 2.0)).distance.width(0.0)
    near = cam.measure(ROBOT, (2.0, 2.0)).distance.width(0.0)
    assert far > 3 * near  # the spread grows with the distance


def test_a_linear_obstacle_was_seen_by_the_ends_of_its_visible_stretches_before(make_scenario):
    cam = camera(
        make_scenario,
        params=LEGACY,
        obstacles=[
            {"segment": {"from": [3.0, 1.5], "to": [3.0, 2.5]}},
            {"segment": {"from": [4.0, -0.0], "to": [4.0, 4.0]}},
        ],
    )
    dets = cam.capture(ROBOT)
    ends = sorted(
        tuple(
            round(
                ROBOT.to_world(
                    (p.distance.centre * math.cos(p.heading.centre), p.distance.centre * math.sin(p.heading.centre))
                )[1],
                1,
            )
            for p in d.points
        )
        for d in dets
    )
    # the short one whole; of the long one, what shows past the short one's ends, inside the view
    assert (1.5, 2.5) in ends
    assert all(len(e) == 2 for e in ends) and len(ends) == 3
    for lo, hi in ends:
        if lo != 1.5:
            assert hi <= 1.5 or lo >= 2.5


# -- the memory ------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["paper-8x8", "trap-box"])
def test_the_samples_left_out_of_a_view_are_never_visible(name):
    """Camera.in_view may only leave out samples the image could not show: from random poses and
    pans, every sample of every wall and segment that the visibility test accepts is among those
    kept, and the samples kept hug the view (a 60-degree view keeps well under all of them)."""
    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    cam = Camera(sc, np.random.default_rng(0))
    rng = np.random.default_rng(7)
    kept_total = all_total = 0
    for _ in range(400):
        pose = Pose(*rng.uniform(-1.0, 9.0, 2), float(rng.uniform(-4.0, 4.0)))
        cam.pan = float(rng.uniform(-1.8, 1.8))
        sees = cam.sight(pose)
        for o in cam.objects:
            if o.kind not in ("segment", "wall"):
                continue
            (ax, ay), (bx, by) = o.a, o.b
            n = segment_steps(o.a, o.b)  # as visible_runs
            visible = {k for k in range(n + 1) if sees(ax + (bx - ax) * k / n, ay + (by - ay) * k / n, o.key)}
            kept = set(cam.in_view(pose, o.a, o.b, n))
            assert visible <= kept, (pose, cam.pan, o.key, sorted(visible - kept))
            kept_total += len(kept)
            all_total += n + 1
    assert kept_total < all_total / 2


@pytest.mark.parametrize("name", ["paper-8x8", "trap-box", "landmarks-12", "blocked-wall"])
@pytest.mark.parametrize("reach", [None, 2.5])
def test_the_images_visibility_test_is_the_geometry_of_lines_of_sight(name, reach):
    """Camera.sight inlines :func:`blocks_sight` and :func:`crosses_sight` and keeps only the
    objects that may block inside the view: from random poses and pans, for the points an image
    tests (every object's centre and every sample of a segment, as its own) and for random points
    (of no object), it answers exactly what the plain definition does: in range, inside the
    field of view, and no physical object but its own cuts the line of sight. With the
    scenario's range, and a short one (``reach``, m) that many objects straddle."""
    import dataclasses

    from navcli.geometry import blocks_sight, crosses_sight, wrap_angle

    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    cam = Camera(sc, np.random.default_rng(0))
    if reach is not None:
        cam.spec = dataclasses.replace(cam.spec, range=reach)
    rng = np.random.default_rng(11)
    discs = [o for o in cam.objects if o.kind in ("landmark", "circle")]
    lines = [o for o in cam.objects if o.kind in ("segment", "wall")]

    def in_view(pose, p):  # in range and inside the field of view
        dx, dy = p[0] - pose.x, p[1] - pose.y
        ahead = abs(wrap_angle(math.atan2(dy, dx) - pose.theta - cam.pan))
        return math.hypot(dx, dy) <= cam.spec.range and ahead <= cam.spec.fov / 2

    def occluded(pose, p, own):
        eye = (pose.x, pose.y)
        return any(o.key != own and blocks_sight(eye, p, o.a, o.radius) for o in discs) or any(
            o.key != own and crosses_sight(eye, p, o.a, o.b) for o in lines
        )

    shown = hidden = 0
    for _ in range(150):
        w, h = sc.arena.width, sc.arena.height
        pose = Pose(float(rng.uniform(0.0, w)), float(rng.uniform(0.0, h)), float(rng.uniform(-4.0, 4.0)))
        cam.pan = float(rng.uniform(-1.8, 1.8))
        sees = cam.sight(pose)
        points = [(o.a, o.key) for o in cam.objects]
        for o in lines:
            (ax, ay), (bx, by) = o.a, o.b
            n = segment_steps(o.a, o.b)
            points += [((ax + (bx - ax) * k / n, ay + (by - ay) * k / n), o.key) for k in range(n + 1)]
        points += [((float(x), float(y)), "") for x, y in rng.uniform((0.0, 0.0), (w, h), (40, 2))]
        for p, own in points:
            seen, blocked = in_view(pose, p), occluded(pose, p, own)
            assert sees(p[0], p[1], own) == (seen and not blocked), (pose, cam.pan, p, own)
            shown += seen and not blocked
            hidden += seen and blocked
    assert shown > 300 and hidden > 20  # both answers, and occlusion inside the view, were tested


def test_drift_grows_without_looks_and_shrinks_after_a_look(make_scenario):
    sc = make_scenario(landmarks=[{"id": "A", "at": [4.0, 3.0]}], noise={"odometry": 0.02})
    cam = Camera(sc, np.random.default_rng(1))
    mem = VisualMemory(0.02)
    mem.observe(cam.capture(ROBOT), 0.0)
    r = [mem.items["A"].spots[0].r0]
    for _ in range(30):
        mem.move(0.03, 0.02)
        r.append(mem.items["A"].spots[0].r0)
    assert all(b > a for a, b in zip(r, r[1:]))  # grows with every move...
    straight = VisualMemory(0.02)
    straight.observe(cam.capture(ROBOT), 0.0)
    for _ in range(30):
        straight.move(0.03, 0.0)
    assert straight.items["A"].spots[0].r0 < r[-1]  # ...and more when turning
    # the robot has moved 0.9 m and turned 0.6 rad: look again from where it truly is
    pose = ROBOT
    for _ in range(30):
        pose = Pose(
            pose.x + 0.03 * math.cos(pose.theta + 0.01), pose.y + 0.03 * math.sin(pose.theta + 0.01), pose.theta + 0.02
        )
    cam.pan = 0.0
    mem.observe(cam.capture(pose), 3.0)
    assert mem.items["A"].spots[0].r0 < r[-1]


def test_objects_too_imprecise_are_forgotten_but_not_the_target():
    mem = VisualMemory(0.05)
    mem.add("A", "landmark", [(2.0, 0.5)], 0.15, 0.05)
    mem.add("target", "target", [(3.0, 0.0)], 0.0, 0.05, prior=True)
    turns = 0
    while "A" in mem.items:
        mem.move(0.0, 0.2)
        mem.move(0.05, -0.2)
        mem.forget()
        turns += 1
        assert turns < 2000
    assert mem.forgotten == ["A"] and "target" in mem.items
    while mem.items["target"].imprecision() <= VISION.forget_above:
        mem.move(0.05, 0.2)
    mem.forget()
    assert "target" in mem.items  # what the robot was told is kept, however blurred


def test_a_fence_is_forgotten_when_both_its_ends_blur_not_when_the_near_one_does():
    """I(l) is mostly the heading's width, and odometry errs in metres: driving up to one end of
    a fence blurs that end (a wide angle seen from nearby) while the far end, 6 m off, stays
    sharp. The fence is kept until both ends pass forget_above; with forget_line_by_one_end 1 it
    goes with its near end."""

    def drive(params):
        mem = VisualMemory(0.2, params)  # a poor odometry (20 %): the blur grows fast
        mem.add_found("obstacle", [Spot(3.0, 0.6, 0.02, 0.0), Spot(3.0, 6.0, 0.02, 0.0)], 0.025)
        ((key, m),) = mem.items.items()
        for _ in range(140):  # 2.8 m ahead, toward the near end
            mem.move(0.02, 0.0)
            mem.forget()
        return mem, key, m

    mem, key, m = drive(VISION)
    near, far = m.spots
    assert near.point().imprecision() > VISION.forget_above >= far.point().imprecision()  # the case in point...
    assert key in mem.items  # ...and the fence is kept
    mem, key, _ = drive(replace(VISION, forget_line_by_one_end=1))
    assert key not in mem.items and mem.forgotten == [key]


def test_fusing_keeps_the_truth_and_sharpens():
    from navcli.vision.visual_memory import fuse

    truth = (2.0, 1.0)
    a, b = Spot(2.3, 1.1, 0.5, 0.0), Spot(1.8, 0.8, 0.4, 0.0)
    f = fuse(a, b)
    assert f.contains(truth) and f.r0 < min(a.r0, b.r0)
    assert fuse(Spot(0, 0, 0.1, 0), Spot(5, 5, 0.1, 0)).x == 5  # inconsistent: the observation wins


def true_clearance(sc, x, y):
    """Distance from a world point to the nearest physical thing (surface), or to the walls."""
    d = [
        math.dist((x, y), o.center) - o.radius
        if isinstance(o, Circle)
        else distance_to_segment((x, y), o.start, o.end) - o.thickness / 2
        for o in sc.obstacles
    ]
    d += [math.dist((x, y), lm.at) - lm.radius for lm in sc.landmarks]
    W, H = sc.arena.width, sc.arena.height
    d += [abs(x), abs(y), abs(W - x), abs(H - y)]
    return min(d)


def _worst_excess(pilot: str, seed: int, drift: float, kinds: tuple[str, ...]):
    """Run paper-8x8 and return (mission, how far outside its support the truth lay at worst over
    the remembered points of ``kinds``, in m (<= 0: always inside), points checked)."""
    sc = load_scenario(SCENARIOS / "paper-8x8.yaml")
    sc = dataclasses.replace(sc, noise=dataclasses.replace(sc.noise, heading_drift=math.radians(drift)))
    m = Mission(RunSpec.build(sc, pilot=pilot, seed=seed))
    worst, checked = -math.inf, 0
    while m.outcome is None:
        m.step()
        if m.ticks % 5:
            continue
        pose = m.world.pose
        for item in m.perception.memory.items.values():
            if (item.kind if item.kind in ("landmark", "target") else "obstacle") not in kinds:
                continue
            for s in item.spots:
                wx, wy = pose.to_world((s.x, s.y))
                if item.kind == "landmark":
                    d = math.dist((wx, wy), next(lm.at for lm in sc.landmarks if lm.id == item.key))
                elif item.kind == "target":
                    d = math.dist((wx, wy), sc.target.point)
                else:
                    d = true_clearance(sc, wx, wy)
                worst, checked = max(worst, d - s.r0), checked + 1
    return m, worst, checked


@pytest.mark.parametrize("pilot", ["potential-field", "geometric"])
@pytest.mark.parametrize("drift", [0.0, 2.0])
def test_memory_of_landmarks_and_target_stays_honest_over_a_whole_mission(pilot, drift):
    """With the default noise (and with a heading drift of 2 deg/m besides) the true position of
    every landmark and of the target stays inside its estimate's support, and the target is
    reached (held on 12 seeds x both pilots when written; here seed 1)."""
    m, worst, checked = _worst_excess(pilot, 1, drift, ("landmark", "target"))
    assert worst <= 1e-6
    assert m.outcome == "reached"
    assert checked > 200 and m.camera_looks > 20


def test_memory_of_obstacles_stays_honest_over_whole_missions():
    for pilot, seed in (("potential-field", 1), ("geometric", 3)):
        _, worst, checked = _worst_excess(pilot, seed, 0.0, ("obstacle",))
        assert checked > 100
        assert worst <= 1e-6, (pilot, seed, worst)


def test_bumps_near_each_other_or_a_landmark_become_a_long_obstacle():
    """Notes, section 2 (Pilot): bump points close to each other or to landmarks are merged into
    a long obstacle; far apart they stay points."""
    mem = VisualMemory(0.0)
    mem.add("A", "landmark", [(3.0, 2.0)], 0.15, 0.05)
    first = mem.add_bump(Spot(1.0, -1.0, 0.1, 0.0), 0.05)
    assert first.kind == "bump"
    line = mem.add_bump(Spot(1.0, -0.2, 0.1, 0.0), 0.05)  # 0.8 m from the first bump: one obstacle
    assert line.kind == "obstacle" and [(s.x, s.y) for s in line.spots] == [(1.0, -1.0), (1.0, -0.2)]
    assert first.key not in mem.items  # the bump is part of the line now
    far = mem.add_bump(Spot(-2.0, 3.0, 0.1, 0.0), 0.05)  # nothing within a metre
    assert far.kind == "bump"
    to_mark = mem.add_bump(Spot(2.9, 1.3, 0.1, 0.0), 0.05)  # 0.71 m from landmark A
    assert to_mark.kind == "obstacle" and (to_mark.spots[0].x, to_mark.spots[0].y) == (3.0, 2.0)
    assert "A" in mem.items  # the landmark stays a landmark


# -- pieces joined by geometry (vision.line_objects 0), lines only where things are
def _stretch(a, b, r=0.05):
    return [Spot(a[0], a[1], r, 0.0), Spot(b[0], b[1], r, 0.0)]


def test_stretches_of_a_fence_join_when_they_overlap_or_nearly_touch_and_never_across_open_space():
    gap = VISION.line_join_gap
    mem = VisualMemory(0.0, LEGACY)
    mem._observe_obstacle(_stretch((2.0, -1.0), (2.0, 0.0)), 0.025, 0.0)
    mem._observe_obstacle(_stretch((2.0, 0.0 + 0.9 * gap), (2.0, 1.0)), 0.025, 0.1)  # nearly touching: one line
    (line,) = [m for m in mem.items.values() if m.kind == "obstacle"]
    assert sorted(round(s.y, 6) for s in line.spots) == [-1.0, 1.0]
    mem._observe_obstacle(_stretch((2.0, 1.0 + 1.5 * gap), (2.0, 2.0)), 0.025, 0.2)  # past the gap: another
    assert len([m for m in mem.items.values() if m.kind == "obstacle"]) == 2
    # even when the remembered ends are very imprecise (metres of support), the gap is measured
    # between their crisp positions: no line across open space
    wide = VisualMemory(0.0, LEGACY)
    wide._observe_obstacle(_stretch((2.0, -1.0), (2.0, 0.0), r=5.0), 0.025, 0.0)  # supports wider than the 4 m gap
    wide._observe_obstacle(_stretch((2.0, 4.0), (2.0, 5.0)), 0.025, 0.1)
    assert len(wide.items) == 2


def test_a_stretch_across_a_line_is_not_part_of_it():
    """A sharp 1.5 m stretch square across a very imprecise wall, both its ends within the wall's
    70 % cuts (3 m supports: cuts 0.9 m wide): their crisp directions differ by 90 degrees, so two
    walls, not one skewed one."""
    mem = VisualMemory(0.0, LEGACY)
    mem._observe_obstacle(_stretch((0.0, 3.0), (4.0, 3.0), r=3.0), 0.05, 0.0, "wall")
    mem._observe_obstacle(_stretch((3.0, 3.75), (3.0, 2.25), r=0.1), 0.05, 0.1, "wall")
    assert len([m for m in mem.items.values() if m.kind == "wall"]) == 2


def test_a_line_too_blurred_for_a_direction_takes_in_only_what_lies_near_its_crisp_line():
    """A 4 m wall whose far end is blurred by metres (its 70 % cuts together wider than tan 30 deg
    of its length: no direction). A short sharp stretch of the next wall round the corner, 1.4 m
    off the wall's crisp line (within the blurred end's 70 % cut, so plausibly on it by the cuts alone),
    starts a wall of its own; one within line_join_gap of the crisp line is taken in."""
    from navcli.fuzzy import CUT
    from navcli.vision.line_pieces import JOIN_ANGLE

    wall = _stretch((0.0, 3.0), (4.0, 3.0))
    wall[1] = Spot(4.0, 3.0, 8.0, 0.0)
    assert wall[0].radius(CUT) + wall[1].radius(CUT) > 4.0 * math.tan(JOIN_ANGLE)  # no direction
    corner = _stretch((4.2, 1.6), (4.2, 1.5), r=0.2)  # shorter than its cuts: no direction of its own
    assert abs(corner[0].y - 3.0) < corner[0].radius(CUT) + wall[1].radius(CUT)  # within the two ends' 70 % cuts
    mem = VisualMemory(0.0, LEGACY)
    mem._observe_obstacle(wall, 0.05, 0.0, "wall")
    mem._observe_obstacle(corner, 0.05, 0.1, "wall")
    assert len([m for m in mem.items.values() if m.kind == "wall"]) == 2
    near = VisualMemory(0.0, LEGACY)
    near._observe_obstacle(list(wall), 0.05, 0.0, "wall")
    off = 3.0 + 0.4 * VISION.line_join_gap
    near._observe_obstacle(_stretch((4.1, off), (4.2, off), r=0.2), 0.05, 0.1, "wall")  # short: no direction either
    assert len([m for m in near.items.values() if m.kind == "wall"]) == 1


def test_a_lone_sample_of_a_wall_is_no_obstacle_and_extends_no_fence():
    mem = VisualMemory(0.0, LEGACY)
    mem._observe_obstacle(_stretch((2.0, -1.0), (2.0, 0.0)), 0.025, 0.0)
    mem._observe_obstacle([Spot(2.0, 0.3, 0.05, 0.0)], 0.05, 0.1, "wall")  # on the fence's line, 0.3 m on
    assert [m.kind for m in mem.items.values()] == ["obstacle"]
    assert max(s.y for s in next(iter(mem.items.values())).spots) == 0.0


@pytest.mark.parametrize("name", ["blocked-wall.yaml", "hidden-fence.yaml", "u-trap.yaml", "door-wall.yaml"])
def test_the_memorys_lines_lie_along_the_true_obstacles_over_a_run(name):
    """Every remembered linear obstacle or wall, put in the world by the true pose, lies along one
    true linear obstacle or wall: each end within its support (plus the obstacle's half-width)."""
    from navcli.experiments.compare import rerun_seed

    sc = load_scenario(SCENARIOS / name)
    m = Mission(RunSpec.build(sc, seed=rerun_seed(1, 0), time_limit=120.0), snapshots=False)
    W, H = sc.arena.width, sc.arena.height
    segs = [(o.a, o.b, o.radius) for o in sc.objects if o.kind == "segment"]
    walls = [((0, 0), (W, 0), 0.0), ((W, 0), (W, H), 0.0), ((W, H), (0, H), 0.0), ((0, H), (0, 0), 0.0)]
    checked = 0
    while m.outcome is None:
        m.step()
        pose = m.world.pose
        for mem in m.perception.memory.items.values():
            if len(mem.spots) != 2 or mem.kind not in ("obstacle", "wall") or not mem.seen:
                continue
            ends = [(pose.to_world((s.x, s.y)), s.r0) for s in mem.spots]
            off = min(
                max(distance_to_segment(p, a, b) - r - rad for p, r in ends)
                for a, b, rad in (walls if mem.kind == "wall" else segs)
            )
            assert off <= 0.05, (m.time, mem.key, ends)
            checked += 1
    assert checked > 100
