"""The visual memory's containment bound (navcli/vision/visual_memory.py): a remembered point's support
(its 0 % cut, radius ``r0``) holds the true position of the point, however the robot drove, as long
as the odometry's errors are within the bounds the memory allows for (the calibration error at
``noise_bound`` deviations, the per-tick errors a random walk); the support never shrinks as the
robot drives and grows at least ``odometry_floor`` per metre; and fusing a sighting with the memory
keeps every point that lies in both supports, the fused support no larger than either.
Property tests, the odometry simulated as navcli's world measures it (navcli/world.py: the true
distance and turn scaled by a per-run and a per-tick factor)."""

from __future__ import annotations

import math
from dataclasses import replace

from hypothesis import assume, given
from hypothesis import strategies as st

from navcli.params import VISION
from navcli.vision.visual_memory import Spot, VisualMemory, fuse

coord = st.floats(-5.0, 5.0)


def egocentric(robot: tuple[float, float, float], point: tuple[float, float]) -> tuple[float, float]:
    x, y, th = robot
    dx, dy = point[0] - x, point[1] - y
    return (math.cos(th) * dx + math.sin(th) * dy, -math.sin(th) * dx + math.cos(th) * dy)


def covered(sigma: float) -> float:
    """The largest calibration error (in deviations) the memory's bound covers: it allows
    ``noise_bound sigma`` of the *measured* motion, and the world's error ``sigma e`` of the true
    motion is ``sigma |e| / (1 - sigma |e|)`` of the measured one when it under-reads; the two
    agree for ``|e| <= noise_bound / (1 + noise_bound sigma)`` (2.83 at 0.02; the world clips at
    3: see the last test of this group)."""
    return VISION.noise_bound / (1 + VISION.noise_bound * sigma)


@st.composite
def drives(draw):
    """A noise level (up to the bundled rooms' 0.02: the bound is first order, and at 0.1 a
    spin then a drive with errors it covers each leave the support by their product), the per-run
    calibration errors of distance and turn (any the bound covers, the worst included), and a drive: legs of up to 80 ticks of
    one true motion, a distance per tick (up to 5 cm ahead, 1 cm back: mostly ahead, so that
    the errors add up) and a turn (none, up to 1 deg or up to 17 deg)."""
    sigma = draw(st.sampled_from([0.0, 0.005, 0.01, 0.02]))
    cal = draw(st.tuples(*[st.floats(-covered(sigma), covered(sigma))] * 2))
    turn = draw(st.sampled_from([0.0, 0.02, 0.3]))  # straight, gently curving or twisting drives
    legs = st.tuples(st.integers(1, 80), st.floats(-0.01, 0.05), st.floats(-turn, turn))  # ticks of one motion
    ticks = [(ds, dth) for n, ds, dth in draw(st.lists(legs, min_size=1, max_size=4)) for _ in range(n)]
    return sigma, cal, ticks


def drive_and_check(sigma, cal, ticks, points, seen_within) -> None:
    """The world's odometry without its per-tick errors (measured = true x (1 + sigma e_run)):
    the memory, moved by the measured motion, keeps every point inside its support at every tick.
    (The per-tick errors are bounded as a random walk, at ``walk_bound`` deviations: a bound that
    holds with high probability, not always; the whole-mission tests of test_vision.py meet them.)"""
    ed, ea = cal
    mem = VisualMemory(odometry_noise=sigma)
    for k, p in enumerate(points):
        mem.add(f"p{k}", "landmark", [p], 0.1, seen_within)  # the robot at the origin facing +x
    x, y, th = 0.0, 0.0, 0.0
    for ds, dth in ticks:
        mid = th + dth / 2
        x, y, th = x + ds * math.cos(mid), y + ds * math.sin(mid), th + dth
        mem.move(ds * (1 + sigma * ed), dth * (1 + sigma * ea))
        for k, p in enumerate(points):
            spot = mem.items[f"p{k}"].spots[0]
            tx, ty = egocentric((x, y, th), p)
            assert math.hypot(tx - spot.x, ty - spot.y) <= spot.r0 + 1e-9, (k, spot)


@given(drives(), st.lists(st.tuples(coord, coord), min_size=1, max_size=4), st.sampled_from([0.0, 0.02, 0.3]))
def test_the_true_position_never_leaves_the_support_as_the_robot_drives(drive, points, seen_within):
    drive_and_check(*drive, points, seen_within)


def test_the_bound_holds_up_to_the_clipped_calibration_error():
    """noise.odometry 0.05, the distance under-read by the clip, 3 deviations (15 %): 100 ticks
    of 3 cm straight toward a point 5 m ahead. The robot drives 3 m and measures 2.55 m, so the
    point is 0.45 m nearer than remembered; the memory allows 0.15 / 0.85 x 2.55 = 0.45 m for the
    calibration (the error is relative to the true motion, the memory knows the measured one),
    4 x 0.05 x sqrt(100 x 0.0255^2) = 0.051 m for the random walk and 0.005 x 2.55 = 0.01275 m
    of floor: 0.51375 m. Allowing 0.15 of the measured motion (0.3825 m) would leave it out."""
    drive_and_check(0.05, (-VISION.noise_bound, 0.0), [(0.03, 0.0)] * 100, [(5.0, 0.0)], 0.0)


@given(
    st.lists(st.tuples(coord, coord, st.floats(0.0, 1.0)), min_size=1, max_size=3),
    st.lists(st.tuples(st.floats(-0.1, 0.1), st.floats(-0.5, 0.5)), min_size=1, max_size=30),
    st.sampled_from([0.0, 0.02, 0.1]),
    st.sampled_from([0.0, 0.05]),
)
def test_the_support_grows_with_the_distance_driven(spots, moves, sigma, drift):
    """At least ``odometry_floor`` per metre driven, whichever way; driving straight ahead
    without a heading drift it never shrinks. (Driving back it may: a calibration error undoes
    what it did on the way out; so may a heading drift's part once the robot has passed the
    point: the drift swings it the other way.)"""
    mem = VisualMemory(odometry_noise=sigma, heading_drift=drift)
    ahead = VisualMemory(odometry_noise=sigma)
    for k, (x, y, r) in enumerate(spots):
        mem.add(f"s{k}", "landmark", [(x, y)], 0.1, r)
        ahead.add(f"s{k}", "landmark", [(x, y)], 0.1, r)
    driven = 0.0
    for ds, dth in moves:
        before = [m.spots[0].r0 for m in ahead.items.values()]
        mem.move(ds, dth)
        ahead.move(abs(ds), 0.0)
        driven += abs(ds)
        for (_, _, r), m, b, a in zip(spots, mem.items.values(), before, ahead.items.values()):
            s = m.spots[0]
            assert s.r0 >= r + VISION.odometry_floor * driven - 1e-9
            assert s.r1 == 0.0 and s.base == r  # the core, and the radius when last seen, stay
            assert a.spots[0].r0 >= b  # straight ahead: never sharper without a sighting
            if sigma and abs(ds) > 1e-6:
                assert a.spots[0].r0 > b + VISION.odometry_floor * abs(ds)  # and more than the floor


@st.composite
def two_supports_around_a_point(draw):
    """A true point and two discs that both hold it (a memory and a sighting of it)."""
    px, py = draw(coord), draw(coord)
    discs = []
    for _ in range(2):
        r = draw(st.floats(0.01, 3.0))
        d = draw(st.floats(0.0, 1.0)) * r  # the point's distance from the centre: inside
        a = draw(st.floats(-math.pi, math.pi))
        discs.append((px + d * math.cos(a), py + d * math.sin(a), r))
    return (px, py), discs


@given(two_supports_around_a_point(), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_fusing_keeps_every_point_of_both_supports_and_never_widens(case, c1, c2):
    (px, py), ((ax, ay, ar), (bx, by, br)) = case
    memory, sighting = Spot(ax, ay, ar, c1 * ar), Spot(bx, by, br, c2 * br)
    f = fuse(memory, sighting)
    assert f.contains((px, py))  # the true point lay in both: it lies in the fused support
    # so does every point of the lens: its edge is the arcs of each circle inside the other disc
    for (cx, cy, r), (ox, oy, o_r) in (((ax, ay, ar), (bx, by, br)), ((bx, by, br), (ax, ay, ar))):
        for k in range(256):
            q = (cx + r * math.cos(k * math.pi / 128), cy + r * math.sin(k * math.pi / 128))
            if math.dist(q, (ox, oy)) <= o_r:
                assert math.dist(q, (f.x, f.y)) <= f.r0 + 1e-9 * (1 + r)
    assert f.r0 <= min(ar, br) + 1e-9 and f.r1 <= min(memory.r1, sighting.r1, f.r0)
    assert f.drift == (0.0,) * 10 and f.base == f.r0  # the drift starts again from the sighting


@given(st.tuples(coord, coord, st.floats(0.01, 1.0)), st.tuples(coord, coord, st.floats(0.01, 1.0)))
def test_supports_that_do_not_meet_give_the_sighting(a, b):
    assume(math.dist(a[:2], b[:2]) > a[2] + b[2] + 1e-9)
    f = fuse(Spot(*a, 0.0), Spot(*b, 0.5 * b[2]))
    assert (f.x, f.y, f.r0, f.r1) == (b[0], b[1], b[2], 0.5 * b[2])


def test_a_spots_cuts_hold_what_lies_within_their_radius():
    """A spot seen within 1 m, its core 0.5 m: the support (alpha 0) holds a point 1 m away,
    on its edge, the core (alpha 1) does not; a point 1.5 m away is in neither."""
    s = Spot(0.0, 0.0, 1.0, 0.5)
    assert s.contains((1.0, 0.0)) and s.contains((0.0, -1.0)) and not s.contains((1.0, 0.0), alpha=1.0)
    assert s.contains((0.3, 0.4), alpha=1.0) and not s.contains((1.5, 0.0)) and not s.contains((0.9, 0.9))


def test_a_copied_spot_keeps_the_drift_it_has_gathered():
    from navcli.vision.visual_memory import _copy

    mem = VisualMemory(odometry_noise=0.02)
    mem.add("p", "landmark", [(2.0, 1.0)], 0.1, 0.05)
    mem.move(1.0, 0.3)
    s = mem.items["p"].spots[0]
    c = _copy(s)
    assert (c.x, c.y, c.base, c.r1, c.drift, c.r0) == (s.x, s.y, s.base, s.r1, s.drift, s.r0) and c is not s
    assert c.r0 > c.base  # the drift since it was seen, kept


def test_bumps_within_the_merge_distance_join_the_nearest_into_one_obstacle():
    """``vision.bump_lines`` ``near``, ``bump_merge`` 1 m: a bump joins the nearer
    of two remembered bumps within 1 m of it, one exactly 1 m away (within), none 1.6 m away; a
    bump within 1 m of a landmark is a line from the nearest landmark; the obstacle made takes
    the new bump's radius and time."""
    near = VISION.bump_merge
    old = replace(VISION, bump_lines="near")

    mem = VisualMemory(0.0, old)
    mem.add_bump(Spot(0.0, 0.0, 0.1, 0.0), 0.1, time=1.0)
    mem.add_bump(Spot(0.0, 1.8, 0.1, 0.0), 0.1, time=1.5)  # 1.8 m from the first: apart
    mem.add_bump(Spot(0.0, 0.8, 0.1, 0.0), 0.1, time=1.8)  # 0.8 m from the first, 1 m from the second
    assert sorted(m.kind for m in mem.items.values()) == ["bump", "obstacle"]
    line = next(m for m in mem.items.values() if m.kind == "obstacle")
    assert [(s.x, s.y) for s in line.spots] == [(0.0, 0.0), (0.0, 0.8)] and (line.radius, line.seen) == (0.1, 1.8)
    far = VisualMemory(0.0, old)
    far.add_bump(Spot(3.0, 0.0, 0.1, 0.0), 0.1)
    far.add_bump(Spot(1.4, 0.0, 0.1, 0.0), 0.1)
    far.add_bump(Spot(3.0 + near, 0.0, 0.1, 0.0), 0.2, time=2.0)  # exactly bump_merge from (3, 0)
    line = next(m for m in far.items.values() if m.kind == "obstacle")
    assert [(s.x, s.y) for s in line.spots] == [(3.0, 0.0), (4.0, 0.0)] and (line.radius, line.seen) == (0.2, 2.0)
    marks = VisualMemory(0.0, old)
    marks.add("L1", "landmark", [(5.0, 5.0)], 0.1, 0.2)
    marks.add("L2", "landmark", [(1.0, 0.0)], 0.1, 0.3)
    marks.add("L3", "landmark", [(0.3, 0.0)], 0.1, 0.4)
    m = marks.add_bump(Spot(0.0, 0.0, 0.1, 0.0), 0.15, time=3.0)  # L3 the nearest, 0.3 m away
    assert m.kind == "obstacle" and [(s.x, s.y, s.r0) for s in m.spots] == [(0.3, 0.0, 0.4), (0.0, 0.0, 0.1)]
    assert (m.radius, m.seen) == (0.15, 3.0)
    edge = VisualMemory(0.0, old)
    edge.add("L", "landmark", [(near, 0.0)], 0.1, 0.2)
    assert edge.add_bump(Spot(0.0, 0.0, 0.1, 0.0), 0.1).kind == "obstacle"  # a landmark exactly 1 m away: within
    alone = VisualMemory(0.0, old).add_bump(Spot(0.0, 0.0, 0.1, 0.0), 0.12, time=4.0)
    assert (alone.kind, alone.radius, alone.seen) == ("bump", 0.12, 4.0)
    snap = {r.key: r for r in marks.snapshot()}
    assert set(snap) == set(marks.items) and snap["L1"].spots == ((5.0, 5.0, 0.2 + 0.7 * (0.0 - 0.2), 0.2),)


def test_a_lines_end_keeps_the_farther_honest_point_or_the_sharper_of_two_as_far():
    """An identified linear obstacle's end after a sighting (``_end``): the end itself seen fuses
    with a remembered end itself, or replaces a point where a view cut the line; of two cut
    points the one farther out along the line (from the other end, ``origin``) is kept, and of
    two within END_TIE (0.1 m) of each other, the sharper. Here the line runs from origin (1, 2)
    outward along (1, 1): the projections, scaled by |u| = sqrt 2, are
    (x - 1) + (y - 2)."""
    from navcli.vision.visual_memory import _end

    origin, u = Spot(1.0, 2.0, 0.1, 0.0), (1.0, 1.0)
    mem = Spot(3.0, 4.0, 0.2, 0.0)  # 4 along
    ahead, behind = Spot(4.0, 4.0, 0.3, 0.0), Spot(2.0, 3.0, 0.1, 0.0)  # 5 along; 2 along, sharper
    assert _end(mem, False, ahead, False, *u, origin) is ahead
    assert _end(mem, False, behind, False, *u, origin) is mem
    assert _end(Spot(4.0, 4.0, 0.2, 0.0), False, Spot(3.0, 4.0, 0.3, 0.0), False, *u, origin).x == 4.0
    # within the tie: 0.07 m apart along the line (0.05 along each axis)
    d = 0.05
    sharp, blurred = Spot(3.0 + d, 4.0 + d, 0.1, 0.0), Spot(3.0 + d, 4.0 + d, 0.4, 0.0)
    assert _end(mem, False, sharp, False, *u, origin) is sharp  # as far, sharper: the sighting
    assert _end(mem, False, blurred, False, *u, origin) is mem  # as far, blurrier: the memory
    assert _end(mem, False, Spot(3.0 + d, 4.0 + d, 0.2, 0.0), False, *u, origin) is mem  # as sharp: kept
    # 0.08 m apart along the line: a tie (the projections' 0.08 sqrt 2 against END_TIE |u|)
    e = 0.08 / math.sqrt(2)
    assert _end(mem, False, Spot(3.0 + e, 4.0 + e, 0.3, 0.0), False, *u, origin) is mem
    # the end itself: replaces a cut point, fuses with a remembered end itself
    seen = Spot(3.3, 4.0, 0.15, 0.0)  # 0.3 m from the remembered end: their supports meet
    assert _end(mem, False, seen, True, *u, origin) is seen
    fused = _end(mem, True, seen, True, *u, origin)
    assert fused.r0 < 0.15 and fused.contains((3.17, 4.0))  # in both supports: in the fusion
    assert _end(mem, True, ahead, False, *u, origin) is mem  # a cut point never moves a known end


def test_two_points_are_one_when_each_centre_lies_in_the_others_support():
    a, b = Spot(0.0, 0.0, 1.0, 0.0), Spot(1.0, 0.0, 1.0, 0.0)
    from navcli.vision.visual_memory import _same_point

    assert _same_point(a, b)  # exactly on each other's support edge: within
    assert not _same_point(a, Spot(1.0, 0.0, 0.5, 0.0))  # a's centre beyond b's support
    assert not _same_point(Spot(0.0, 0.0, 0.9, 0.0), Spot(1.0, 0.0, 0.9, 0.0))  # 1 m apart along x alone


def test_a_lines_sighting_moves_each_end_outward_or_to_the_end_itself():
    """A fence remembered between two cut points a (2, 3) and b (4, 1) (direction from b to a:
    (-2, 2)). A sighting whose a-side point (1, 2.4) lies 0.28 m farther out along the fence
    (though blurrier) and whose b-side point is the fence's own end (3.9, 1.1), 0.14 m short of
    the cut point b: the fence runs from (1, 2.4) to (3.9, 1.1), its b end known exactly, seen now at its new half-width. On the
    same fence remembered afresh, a b-side cut point (4.6, -0.5), farther out along (2, -2),
    moves the b end there, and an a-side point where a was keeps a."""
    mem = VisualMemory(odometry_noise=0.0)
    a, b = Spot(2.0, 3.0, 0.1, 0.0), Spot(4.0, 1.0, 0.1, 0.0)
    mem._observe_line("segment:f", "obstacle", [a, b], (False, False), 0.05, 1.0)
    m = mem.items["segment:f"]
    assert (m.seen, m.radius, m.prior, m.exact) == (1.0, 0.05, False, (False, False))
    mem._observe_line(
        "segment:f", "obstacle", [Spot(1.0, 2.4, 0.3, 0.0), Spot(3.9, 1.1, 0.1, 0.0)], (False, True), 0.07, 2.0
    )
    assert [(s.x, s.y) for s in m.spots] == [(1.0, 2.4), (3.9, 1.1)]
    assert (m.seen, m.radius, m.exact) == (2.0, 0.07, (False, True))
    other = VisualMemory(odometry_noise=0.0)
    other._observe_line(
        "segment:g", "obstacle", [Spot(2.0, 3.0, 0.1, 0.0), Spot(4.0, 1.0, 0.1, 0.0)], (False, False), 0.05, 1.0
    )
    other._observe_line(
        "segment:g", "obstacle", [Spot(2.0, 3.0, 0.1, 0.0), Spot(4.6, -0.5, 0.3, 0.0)], (False, False), 0.05, 2.0
    )
    assert [(s.x, s.y) for s in other.items["segment:g"].spots] == [(2.0, 3.0), (4.6, -0.5)]


def test_an_unidentified_point_seen_again_is_fused_not_doubled():
    """A plain obstacle point, or a bump, seen again where it is remembered: one memory, sharper,
    an obstacle, seen now; a landmark there is not taken for it. What the robot is told is
    remembered at the half-width told."""
    mem = VisualMemory(odometry_noise=0.0)
    mem.add("L", "landmark", [(2.0, 0.0)], 0.1, 0.3)
    assert mem.items["L"].radius == 0.1
    mem._observe_obstacle([Spot(2.0, 0.0, 0.4, 0.0)], 0.2, 1.0)  # on the landmark: a new obstacle
    mem._observe_obstacle([Spot(2.1, 0.0, 0.3, 0.0)], 0.2, 2.0)  # the same point again
    mem.add_bump(Spot(0.0, 3.0, 0.1, 0.0), 0.1, time=2.5)
    mem._observe_obstacle([Spot(0.0, 3.05, 0.2, 0.0)], 0.15, 3.0)  # the bump, seen
    kinds = sorted((m.kind, m.seen) for m in mem.items.values())
    assert kinds == [("landmark", 0.0), ("obstacle", 2.0), ("obstacle", 3.0)]
    seen_twice = next(m for m in mem.items.values() if m.seen == 2.0)
    assert seen_twice.spots[0].r0 < 0.4 and seen_twice.spots[0].contains((2.05, 0.0))  # sharper than first seen
    felt = next(m for m in mem.items.values() if m.seen == 3.0)
    assert felt.radius == 0.15 and felt.spots[0].r0 <= 0.1
