"""The visual memory draws only what can be: lines felt by the bumpers lie on one object, never
through the robot's body, never twice; a fence keeps its shape when one end is corrected; a
fence's ends are anchored at landmarks by what the robot perceives."""

from __future__ import annotations

import math
from dataclasses import replace

from hypothesis import given
from hypothesis import strategies as st

from navcli.geometry import distance_to_segment
from navcli.params import VISION
from navcli.vision.perception import anchors
from navcli.vision.visual_memory import Spot, VisualMemory

NEAR = replace(VISION, bump_lines="near")  # any two bumps near each other join
RIM = 0.35  # a bump's centre: robot radius 0.25 + bump_radius 0.10


def bump(x: float, y: float) -> Spot:
    return Spot(x, y, 0.1, 0.0)


def lines(mem: VisualMemory) -> list[list[tuple[float, float]]]:
    return [[(s.x, s.y) for s in m.spots] for m in mem.items.values() if len(m.spots) == 2]


# -- bumps -------------------------------------------------------------------------------------
def test_a_bump_in_front_and_one_behind_are_two_objects_not_a_line_through_the_robot():
    """0.7 m apart (within bump_merge 1 m), felt from one place: the line between them runs through
    the robot's centre (distance 0 < 0.25 m). Two lone bumps; ``near`` drew that line."""
    mem = VisualMemory(0.0)
    mem.add_bump(bump(RIM, 0.0), 0.05)
    mem.add_bump(bump(-RIM, 0.0), 0.05)
    assert sorted(m.kind for m in mem.items.values()) == ["bump", "bump"] and lines(mem) == []
    old = VisualMemory(0.0, NEAR)
    old.add_bump(bump(RIM, 0.0), 0.05)
    old.add_bump(bump(-RIM, 0.0), 0.05)
    assert lines(old) == [[(RIM, 0.0), (-RIM, 0.0)]]


def test_two_bumps_along_one_wall_felt_from_one_side_join():
    """Bump a wall ahead at (0.35, 0); back up 0.3 m, turn left 90 degrees, drive 0.6 m, turn
    right, drive 0.3 m ahead and bump it again at (0.35, 0). In the robot's frame the first bump
    is then at (0.35, -0.6) and the robot stood at (0, -0.6): the line x = 0.35 between the bumps
    is 0.35 m (> 0.25) from both standings, which lie on its same side, and 0.6 m long (< 1)."""
    mem = VisualMemory(0.0)
    first = mem.add_bump(bump(RIM, 0.0), 0.05)
    for ds, turn in ((-0.3, 0.0), (0.0, math.pi / 2), (0.6, 0.0), (0.0, -math.pi / 2), (0.3, 0.0)):
        mem.move(ds, turn)
    assert first.felt_from is not None
    assert math.isclose(first.felt_from[0], 0.0, abs_tol=1e-9) and math.isclose(first.felt_from[1], -0.6)
    line = mem.add_bump(bump(RIM, 0.0), 0.05)
    assert line.kind == "obstacle" and first.key not in mem.items
    (a, b) = line.spots
    assert math.isclose(a.x, RIM) and math.isclose(a.y, -0.6) and (b.x, b.y) == (RIM, 0.0)


def test_bumps_felt_from_either_side_of_a_line_are_two_objects():
    """The same two bump points, x = 0.35, 0.6 m apart, but the robot stood at (0.7, -0.6), on the
    far side of that line, for the first: two objects (a post each side of a gap, say)."""
    mem = VisualMemory(0.0)
    first = mem.add_bump(bump(RIM, -0.6), 0.05)
    first.felt_from = (0.7, -0.6)
    mem.add_bump(bump(RIM, 0.0), 0.05)
    assert lines(mem) == [] and len(mem.items) == 2
    mem2 = VisualMemory(0.0)
    again = mem2.add_bump(bump(RIM, -0.6), 0.05)
    again.felt_from = (0.0, -0.6)
    assert mem2.add_bump(bump(RIM, 0.0), 0.05).kind == "obstacle"


def test_one_place_felt_four_times_is_one_point_not_two_copies_of_a_line():
    """Four bumps within 2 cm (inside each other's 0.1 m supports): one bump, fused (its support
    no wider than the first's 0.1 m). ``near`` drew two lines, equal within 3 cm."""
    mem = VisualMemory(0.0)
    for dy in (0.0, 0.02, -0.01, 0.01):
        mem.add_bump(bump(RIM, dy), 0.05, time=1.0 + dy)
    (only,) = mem.items.values()
    assert only.kind == "bump" and only.spots[0].r0 <= 0.1 and lines(mem) == []
    old = VisualMemory(0.0, NEAR)
    for dy in (0.0, 0.02, -0.01, 0.01):
        old.add_bump(bump(RIM, dy), 0.05)
    first, second = lines(old)
    assert max(math.dist(p, q) for p, q in zip(first, second)) <= 0.03


def test_a_bump_on_a_remembered_fence_confirms_it_and_one_off_it_is_its_own():
    """A fence at x = 0.35 (ends' supports 0.05 m, their 70 % cuts 0.015 m, half-width 0.025 m):
    a bump on it draws nothing, marks the fence felt now and moves it onto the contact. The fence at x = 0.65 instead: the
    bump 0.3 m off it, beyond 0.025 + 0.1 + 0.015 = 0.14 m, is a bump of its own."""
    mem = VisualMemory(0.0)
    mem._observe_line("segment:f", "obstacle", [bump(RIM, -1.0), bump(RIM, 1.0)], (True, True), 0.025, 0.0)
    mem.items["segment:f"].spots = [Spot(RIM, -1.0, 0.05, 0.0), Spot(RIM, 1.0, 0.05, 0.0)]
    assert mem.add_bump(bump(RIM, 0.2), 0.05, time=5.0).key == "segment:f"
    assert list(mem.items) == ["segment:f"] and mem.items["segment:f"].seen == 5.0
    # in contact the fence's middle is 0.25 + 0.025 m from the robot's centre: moved 0.075 m nearer,
    # whole, each end's support grown by as much (0.05 + 0.075)
    ends = [(s.x, s.y, s.r0) for s in mem.items["segment:f"].spots]
    assert [tuple(round(v, 9) for v in e) for e in ends] == [(0.275, -1.0, 0.125), (0.275, 1.0, 0.125)]
    beyond = VisualMemory(0.0)  # the robot's centre faces no part of the fence: a touch of its end, nothing moves
    beyond._observe_line("segment:g", "obstacle", [bump(RIM, 0.1), bump(RIM, 1.0)], (True, True), 0.025, 0.0)
    beyond.items["segment:g"].spots = [Spot(0.3, 0.1, 0.05, 0.0), Spot(0.3, 1.0, 0.05, 0.0)]
    beyond.add_bump(bump(0.3, 0.18), 0.05)
    assert [(s.x, s.y) for s in beyond.items["segment:g"].spots] == [(0.3, 0.1), (0.3, 1.0)]
    off = VisualMemory(0.0)
    off._observe_line("segment:f", "obstacle", [bump(0.65, -1.0), bump(0.65, 1.0)], (True, True), 0.025, 0.0)
    off.items["segment:f"].spots = [Spot(0.65, -1.0, 0.05, 0.0), Spot(0.65, 1.0, 0.05, 0.0)]
    assert off.add_bump(bump(RIM, 0.0), 0.05).kind == "bump" and len(off.items) == 2


def test_a_landmark_behind_the_robot_is_not_joined_to_a_bump_in_front():
    """A landmark at (-0.5, 0), a bump at (0.35, 0): 0.85 m apart (within 1 m), but the line between
    them runs through the robot: a lone bump (``near``: a line). A landmark at (0.35, 0.9) instead:
    the line x = 0.35 from the bump to it passes 0.35 m (> 0.25) from the robot: a line."""
    mem = VisualMemory(0.0)
    mem.add("L", "landmark", [(-0.5, 0.0)], 0.1, 0.05)
    assert mem.add_bump(bump(RIM, 0.0), 0.05).kind == "bump"
    old = VisualMemory(0.0, NEAR)
    old.add("L", "landmark", [(-0.5, 0.0)], 0.1, 0.05)
    assert old.add_bump(bump(RIM, 0.0), 0.05).kind == "obstacle"  # near: a line through the body
    ahead = VisualMemory(0.0)
    ahead.add("L", "landmark", [(RIM, 0.9)], 0.1, 0.05)
    line = ahead.add_bump(bump(RIM, 0.0), 0.05)
    assert line.kind == "obstacle" and [(s.x, s.y) for s in line.spots] == [(RIM, 0.9), (RIM, 0.0)]


def _through_body(mem: VisualMemory, body: float) -> bool:
    """Does a remembered line pass within ``body`` of the robot's centre (the memory's origin)?"""
    lines = (m.spots for m in mem.items.values() if len(m.spots) == 2)
    return any(distance_to_segment((0.0, 0.0), (a.x, a.y), (b.x, b.y)) < body - 1e-9 for a, b in lines)


@given(st.lists(st.tuples(st.floats(-math.pi, math.pi), st.floats(-0.5, 0.5), st.floats(-1.0, 1.0)), max_size=12))
def test_no_line_felt_is_drawn_through_the_robot_where_it_stands(path):
    """Whatever the robot's path and wherever on its rim it bumps, no line made of bumps passes
    within the robot's radius of its centre when it is drawn, and no two lines are the same."""
    mem = VisualMemory(0.0)
    for bearing, ds, turn in path:
        mem.move(ds, turn)
        before = set(mem.items)
        mem.add_bump(bump(RIM * math.cos(bearing), RIM * math.sin(bearing)), 0.05)
        new = {k: mem.items[k] for k in set(mem.items) - before}
        probe = VisualMemory(0.0)
        probe.items = new
        assert not _through_body(probe, mem.robot_radius)
    drawn = lines(mem)
    for i, p in enumerate(drawn):
        for q in drawn[i + 1 :]:
            assert max(math.dist(p[0], q[0]), math.dist(p[1], q[1])) > 1e-6


# -- a fence keeps its shape -------------------------------------------------------------------
def _fence(rigid: bool) -> VisualMemory:
    """A fence seen whole, ends (2, -1) and (2, 1) known to 0.3 m; odometry then reads 1.2 m for a
    drive of 1 m ahead, so the memory holds it at x = 0.8 where it stands at x = 1; end b is seen
    again, exactly, at (1, 1) (to 0.01 m), end a's side only where the view cut it, at (1, 0)."""
    mem = VisualMemory(0.0, replace(VISION, fence_rigid=rigid))
    whole = [Spot(2.0, -1.0, 0.3, 0.0), Spot(2.0, 1.0, 0.3, 0.0)]
    mem._observe_line("segment:f", "obstacle", whole, (True, True), 0.025, 0.0)
    mem.move(1.2, 0.0)
    mem._observe_line(
        "segment:f", "obstacle", [Spot(1.0, 0.0, 0.01, 0.0), Spot(1.0, 1.0, 0.01, 0.0)], (False, True), 0.025, 1.0
    )
    return mem


def test_a_fence_corrected_at_one_end_moves_whole():
    """End b is fused to (1, 1) (the sighting's disc lies inside the memory's, 0.2 + 0.01 m <= 0.306
    m: 0.3 plus the 0.005 per metre floor over 1.2 m); end a moves with it by (0.2, 0) to (1, -1),
    its support grown by 0.2 to 0.506 m: the fence keeps its 2 m and its direction (90 degrees).
    Corrected end by end (``fence_rigid`` 0), a stays at (0.8, -1): 2.01 m, tilted 5.7 degrees."""
    a, b = _fence(True).items["segment:f"].spots
    assert (round(b.x, 9), round(b.y, 9), b.r0) == (1.0, 1.0, 0.01)
    assert math.isclose(a.x, 1.0) and math.isclose(a.y, -1.0) and math.isclose(a.r0, 0.306 + 0.2)
    assert math.isclose(math.dist((a.x, a.y), (b.x, b.y)), 2.0)
    old_a, old_b = _fence(False).items["segment:f"].spots
    assert math.isclose(old_a.x, 0.8) and math.isclose(math.dist((old_a.x, old_a.y), (1.0, 1.0)), math.sqrt(4.04))
    tilt = math.degrees(math.atan2(old_b.x - old_a.x, old_b.y - old_a.y))
    assert math.isclose(tilt, math.degrees(math.atan2(0.2, 2.0)))  # 5.71 degrees


@given(
    st.floats(-0.2, 0.2),  # the distance odometry's relative error
    st.floats(-0.05, 0.05),  # its turn error (rad)
    st.floats(0.5, 3.0),  # the fence's length
    st.floats(-math.pi, math.pi),  # its direction
    st.booleans(),  # which end is seen again
)
def test_a_fence_keeps_its_length_and_direction_under_drift(err, turn_err, length, direction, which):
    """A fence seen whole at 3 m; the robot drives 1 m and turns 0.3 rad while odometry reads
    (1 + err) m and 0.3 + turn_err rad; one end is seen again where it truly is. The remembered
    fence keeps its length exactly and its direction to within the turn error (the noise bound
    of the drift: what one end cannot tell), and each end's support holds the true end."""
    half = length / 2
    ux, uy = math.cos(direction), math.sin(direction)
    ends = [(3.0 - half * ux, -half * uy), (3.0 + half * ux, half * uy)]
    mem = VisualMemory(0.0, replace(VISION, fence_rigid=True))
    mem._observe_line("segment:f", "obstacle", [Spot(x, y, 2.0, 0.0) for x, y in ends], (True, True), 0.025, 0.0)
    mem.move(1.0 + err, 0.3 + turn_err)
    mem.shove(0.5)  # (bounds the error the test's noise-free memory does not allow for)
    c, s = math.cos(-0.3), math.sin(-0.3)
    true = [(c * (x - math.cos(0.15)) - s * (y - math.sin(0.15)), s * (x - math.cos(0.15)) + c * (y - math.sin(0.15)))
            for x, y in ends]  # fmt: skip
    i = int(which)
    seen = [Spot(*true[j], 0.01, 0.0) for j in (0, 1)]
    flags = (i == 0, i == 1)
    mem._observe_line("segment:f", "obstacle", seen, flags, 0.025, 1.0)
    a, b = mem.items["segment:f"].spots
    assert math.isclose(math.dist((a.x, a.y), (b.x, b.y)), length, rel_tol=1e-9)
    got = math.atan2(b.y - a.y, b.x - a.x)
    want = math.atan2(true[1][1] - true[0][1], true[1][0] - true[0][0])
    assert abs(math.remainder(got - want, 2 * math.pi)) <= abs(turn_err) + 1e-9
    for e, t in zip((a, b), true):
        assert math.dist((e.x, e.y), t) <= e.r0 + 1e-9


# -- anchors from what is perceived -------------------------------------------------------------
def test_a_fence_end_seen_at_a_remembered_landmark_is_anchored_there():
    """A fence's end seen (exact) 0.2 m from landmark P's centre (P 0.15 m wide, the fence 0.025 m,
    gap 0.05, cuts 0.3 x 0.05 = 0.015 each: within 0.255 m): anchored at P; its other end seen 0.6 m
    from Q: not; a cut point (not the end) at Q: not."""
    mem = VisualMemory(0.0)
    mem.add("P", "landmark", [(2.0, -1.2)], 0.15, 0.05)
    mem.add("Q", "landmark", [(2.0, 1.6)], 0.15, 0.05)
    ends = [Spot(2.0, -1.0, 0.05, 0.0), Spot(2.0, 1.0, 0.05, 0.0)]
    mem._observe_line("segment:f", "obstacle", ends, (True, True), 0.025, 0.0)
    assert anchors(mem) == {"segment:f": ("P", None)}
    cut = VisualMemory(0.0)
    cut.add("Q", "landmark", [(2.0, 1.0)], 0.15, 0.05)
    cut._observe_line("segment:f", "obstacle", ends, (True, False), 0.025, 0.0)
    assert anchors(cut) == {}
