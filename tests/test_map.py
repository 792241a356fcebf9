"""The Map Manager's maths: Prescott's beta-coefficients (crisp and fuzzy) and the regions."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from navcli.bidding import Look
from navcli.fuzzy import FuzzyPoint
from navcli.navigation.beta_map import BetaNetwork, collinearity, encode, recall
from navcli.navigation.regions import first_crossing, triangulate
from navcli.params import NAVIGATION

CRISP = (0.0, 0.0, 0.0, 0.0)
coord = st.floats(-8.0, 8.0)
point = st.tuples(coord, coord)


def moved(p, theta, tx, ty):
    return (math.cos(theta) * p[0] - math.sin(theta) * p[1] + tx, math.sin(theta) * p[0] + math.cos(theta) * p[1] + ty)


@settings(deadline=None)
@given(st.lists(point, min_size=4, max_size=4), st.floats(-math.pi, math.pi), coord, coord)
def test_crisp_recall_is_exact_under_any_rotation_and_translation(pts, theta, tx, ty):
    a, b, c, d = pts
    assume(collinearity(a, b, c) < 0.9 and min(math.dist(a, b), math.dist(b, c), math.dist(a, c)) > 0.5)
    names = dict(zip("ABCD", pts))
    unit = encode(("A", "B", "C"), "D", {k: FuzzyPoint(*p, CRISP) for k, p in names.items()})
    assert unit is not None
    seen_again = {k: FuzzyPoint(*moved(p, theta, tx, ty), CRISP) for k, p in names.items() if k != "D"}
    got = recall(unit, seen_again)
    want = moved(d, theta, tx, ty)
    assert (got.x, got.y) == pytest.approx(want, abs=1e-6) and got.radii == pytest.approx(CRISP, abs=1e-6)


def test_collinear_triangles_are_refused():
    pts = {"A": (0.0, 0.0), "B": (1.0, 1.0), "C": (2.0, 2.0), "D": (3.0, 0.0)}
    assert encode(("A", "B", "C"), "D", {k: FuzzyPoint(*p, CRISP) for k, p in pts.items()}) is None
    # nearly collinear, but the supports make the determinant's sign unknown: refused too
    pts["C"] = (2.0, 2.05)
    fuzzy = {k: FuzzyPoint(*p, (0.2, 0.14, 0.06, 0.0)) for k, p in pts.items()}
    assert encode(("A", "B", "C"), "D", fuzzy, max_collinearity=1.0) is None


@settings(deadline=None)
@given(
    st.lists(point, min_size=4, max_size=4),
    st.floats(-math.pi, math.pi),
    coord,
    coord,
    st.lists(st.tuples(st.floats(0, 1), st.floats(-math.pi, math.pi)), min_size=7, max_size=7),
    st.floats(0.01, 0.2),
)
def test_the_fuzzy_recall_holds_the_true_position(pts, theta, tx, ty, errors, r):
    """Every position is seen with an error inside its support (radius r), when encoding and
    when recalling: the recalled support still holds the true position."""
    a, b, c, d = pts
    assume(collinearity(a, b, c) < 0.8 and min(math.dist(a, b), math.dist(b, c), math.dist(a, c)) > 1.0)
    radii = (r, 0.7 * r, 0.3 * r, 0.0)

    def seen(p, e):
        f, ang = e
        return FuzzyPoint(p[0] + f * r * math.cos(ang), p[1] + f * r * math.sin(ang), radii)

    names = dict(zip("ABCD", pts))
    unit = encode(("A", "B", "C"), "D", {k: seen(p, e) for (k, p), e in zip(names.items(), errors)})
    assume(unit is not None)
    again = {k: seen(moved(p, theta, tx, ty), e) for (k, p), e in zip(list(names.items())[:3], errors[4:])}
    got = recall(unit, again)
    assert got.contains(moved(d, theta, tx, ty))


def test_the_network_keeps_the_sharpest_units_and_recalls_the_least_imprecise():
    net = BetaNetwork(units_per_landmark=2)
    pts = {"A": (0.0, 0.0), "B": (4.0, 0.0), "C": (0.0, 4.0), "D": (4.0, 4.0), "E": (2.0, 6.0)}
    sharp = {k: FuzzyPoint(*p, (0.05, 0.035, 0.015, 0.0)) for k, p in pts.items()}
    blurred = {k: FuzzyPoint(*p, (0.3, 0.21, 0.09, 0.0)) for k, p in pts.items()}
    blurred_unit = net.learn(blurred, targets={"D"})[0]
    sharp_unit = net.learn(sharp, targets={"D"})[0]
    assert sharp_unit.basis == blurred_unit.basis and sharp_unit.spread < blurred_unit.spread
    assert list(net.units["D"].values()) == [sharp_unit]  # the same triangle: the sharper encoding replaced it
    assert net.learn(blurred, targets={"D"}) == []  # and a blurred one does not replace it back
    # other triangles: a viewframe without E, then one without A, add units up to the cap of 2
    net.learn({k: v for k, v in sharp.items() if k != "E"}, targets={"D"})
    net.learn({k: v for k, v in blurred.items() if k != "A"}, targets={"D"})
    assert len(net.units["D"]) == 2 and sharp_unit in net.units["D"].values()  # the blurriest evicted
    (p, unit) = net.locate("D", {k: v for k, v in sharp.items() if k != "D"})
    assert p.contains(pts["D"])
    assert net.locate("D", {"A": sharp["A"]}) is None  # its basis is not known now


# -- regions and the diverting target -----------------------------------------------------------
SQUARE = {"A": (0.0, 0.0), "B": (4.0, 0.0), "C": (4.0, 4.0), "D": (0.0, 4.0), "E": (2.0, 8.0)}


def test_regions_triangulate_the_landmarks_with_virtual_ones_around():
    r = triangulate(SQUARE)
    real = [t for t in r.triangles if all(not r.ids[v].startswith("~") for v in t)]
    assert len(real) == 3  # all 5 landmarks on the hull (a convex pentagon): 5 - 2 triangles
    assert sorted(i for i in r.ids if i.startswith("~")) == [
        "~A-B",
        "~A-D",
        "~B-C",
        "~C-E",
        "~D-E",
    ]  # one per hull edge
    inside = r.triangles[r.region_of((2.0, 1.0))]
    assert all(not r.ids[v].startswith("~") for v in inside)  # inside the landmarks: a real region
    outside = r.triangles[r.region_of((2.0, -3.0))]
    assert any(r.ids[v] == "~A-B" for v in outside)  # below A-B: the region of its virtual landmark


def test_the_diverting_target_is_the_first_edge_of_the_shortest_path():
    r = triangulate(SQUARE)
    robot, target = (2.0, -1.0), (2.0, 6.5)  # below A-B, the target inside C-D-E
    c = first_crossing(r, robot, target)
    assert c.edge == frozenset({"A", "B"})  # into the square first
    assert (c.left, c.right) == ("A", "B")  # looking north from (2, -1): A (west) on the left
    # block A-B: the way goes around, through a virtual region beside the square
    c2 = first_crossing(r, robot, target, blocked={frozenset({"A", "B"}): 1.0})
    assert c2 is not None and c2.edge != frozenset({"A", "B"}) and c2.virtual
    assert first_crossing(r, (2.0, 6.5), (2.1, 6.6)) is None  # the same region: nothing to cross


def test_given_what_blocks_the_view_the_diverting_target_is_the_farthest_edge_of_the_way_in_sight():
    """The way from below A-B to C-D-E crosses A-B, the diagonal A-C and D-C. With nothing known
    in the way the robot is sent straight across D-C, the way's last edge; with a fence across
    the sight line to D-C's middle (2, 4), across the diagonal A-C, whose middle (2, 2) it sees;
    without ``lines`` (``navigation.diverting_in_sight`` 0), across the first, A-B."""
    r = triangulate(SQUARE)
    robot, target = (2.0, -1.0), (2.0, 6.5)
    assert first_crossing(r, robot, target, lines=[]).edge == frozenset("CD")
    fence = ("fence", (0.5, 3.0), (3.5, 3.2))
    assert first_crossing(r, robot, target, lines=[fence]).edge == frozenset("AC")
    assert first_crossing(r, robot, target).edge == frozenset("AB")


def test_an_edge_whose_middle_is_seen_past_a_walls_end_is_not_handed_over():
    """A wall from (5, 3.5) to (2.6, 3.5) ends left of the sight line from the robot (2, -1) to
    D-C's middle (2, 4), which it so clears; but the line to the point a quarter in from C,
    (3, 4), meets y = 3.5 at x = 2.9, on the wall: the robot, led at D-C, would wedge between
    the wall's end and C. Seen whole (``diverting_seen_whole``), the edge handed over is the
    diagonal A-C, whose middle half (1, 1) to (3, 3) lies wholly below the wall."""
    from navcli.navigation.regions import crossing_along

    r = triangulate(SQUARE)
    robot, target = (2.0, -1.0), (2.0, 6.5)
    wall = ("wall", (5.0, 3.5), (2.6, 3.5))
    assert not crossing_along(robot, (2.0, 4.0), wall[1], wall[2], 0.0)  # the middle alone is in sight
    assert crossing_along(robot, (3.0, 4.0), wall[1], wall[2], 0.0)
    assert first_crossing(r, robot, target, lines=[wall], whole=True).edge == frozenset("AC")
    assert first_crossing(r, robot, target, lines=[wall]).edge == frozenset("CD")  # its middle alone


def test_a_logged_run_is_the_same_file_whatever_pythons_hash_seed(tmp_path):
    """Same scenario + seed + version = same log, byte for byte, in any process: the map's
    landmarks once followed the order of a set of strings, which ``PYTHONHASHSEED`` changes."""
    import os
    import subprocess
    import sys

    from conftest import ROOT, SCENARIOS

    logs = []
    for seed in ("1", "2"):
        out = tmp_path / f"hash{seed}.mcap"
        r = subprocess.run(
            [
                sys.executable,
                "-m",
                "navcli",
                "run",
                str(SCENARIOS / "landmarks-12.yaml"),
                "--time-limit",
                "15",
                "--out",
                str(out),
            ],
            capture_output=True,
            text=True,
            cwd=ROOT,
            env=os.environ | {"PYTHONHASHSEED": seed},
        )
        assert r.returncode == 3 and "timeout" in r.stdout, r.stderr  # 15 s: the map is drawn, the target not reached
        logs.append(out.read_bytes())
    assert logs[0] == logs[1]


def test_the_quality_of_a_landmark_set_is_that_of_its_six_best_known_now(monkeypatch):
    """``q_S`` (the Risk Manager's input) at every call of a run equals its definition worked
    out afresh: the six least imprecise points of the set *at that tick* (I(l) changes with the
    distance, so the six change as the robot moves), the largest ``1 - Col`` of their triples.
    The Map Manager caches it between images: the cache must not answer for an older six."""
    import itertools

    from conftest import SCENARIOS

    from navcli.config import RunSpec
    from navcli.navigation.map_manager import MapManager
    from navcli.runner import run_mission
    from navcli.scenario import load_scenario

    def fresh(points):
        six = sorted(points.values(), key=FuzzyPoint.imprecision)[:6]
        return max(
            (1.0 - collinearity((a.x, a.y), (b.x, b.y), (c.x, c.y)) for a, b, c in itertools.combinations(six, 3)),
            default=0.0,
        )

    seen = []  # (the Map Manager's answer, the definition's, the set's size) at every call
    quality = MapManager.quality

    def spy(self, points):
        got = quality(self, points)
        seen.append((got, fresh(points), len(points)))
        return got

    monkeypatch.setattr(MapManager, "quality", spy)
    run_mission(RunSpec.build(load_scenario(SCENARIOS / "landmarks-12.yaml"), seed=1, time_limit=30.0), record=False)
    assert sum(n > 6 for _, _, n in seen) > 50  # sets where the choice of six matters
    assert len({round(f, 6) for _, f, _ in seen}) > 10  # and the quality moves during the run
    for got, want, _ in seen:
        assert got == pytest.approx(want, abs=1e-9)


# -- regions that know the obstacles ---------------------------------------------------------------
from navcli.navigation.regions import (  # noqa: E402
    CROSS_MARGIN,
    NoCrossing,
    blocked_edges,
    crossing_along,
    obstacle_of,
    way_out,
)

# four landmarks around a fence across the middle: the robot below it, the target above it
AROUND = {"A": (-3.0, -2.0), "B": (3.0, -2.0), "C": (3.0, 3.0), "D": (-3.0, 3.0)}
FENCE = ("fence", (-2.0, 0.5), (2.0, 0.5))


def test_a_known_fence_splits_the_regions_and_the_way_round_it_is_not_through_it():
    """Four landmarks around; a 4 m fence across the middle. Without the fence the robot below it
    and the target above it share a region; with it they do not, every edge along it is blocked,
    and the cheapest way to the target's region goes round an end: no region on it is entered
    through the fence."""
    robot, target = (0.0, -1.0), (0.0, 2.0)
    r = triangulate(AROUND, obstacles=[FENCE])
    assert r.region_of(robot) != r.region_of(target)
    blocked = {e: 1.0 for e in blocked_edges(r, [FENCE])}
    along = [e for e in blocked if all(obstacle_of(k) == "fence" for k in e)]
    assert len(along) == 4  # the fence's chain: 5 points 1 m apart, 4 edges along it
    # every edge the robot's way could take across the fence's line between its ends is blocked
    for _, _, e in r.edges():
        a, b = (tuple(r.points[r.ids.index(k)]) for k in e)
        if crossing_along(a, b, FENCE[1], FENCE[2], CROSS_MARGIN):
            assert e in blocked
    c = first_crossing(r, robot, target, blocked)
    assert c is not None and c.cost < 1000.0  # a way round, at no blocked arc's cost


def test_an_obstacle_blocks_the_edges_it_crosses_not_those_it_touches_at_an_end():
    """A bump line drawn from landmark A to a bump point touches every edge of A at A: none of
    them is blocked for it; the edge it crosses in the middle is."""
    marks = {"A": (0.0, 0.0), "B": (4.0, 0.0), "C": (2.0, 1.5), "D": (2.0, -1.5)}  # C-D the shorter diagonal
    bump = ("bump-line", (0.0, 0.0), (2.5, 0.3))  # from A across the edge C-D
    r = triangulate(marks)
    blocked = blocked_edges(r, [bump])
    assert frozenset({"C", "D"}) in blocked and blocked[frozenset({"C", "D"})] == "bump-line"
    assert not [e for e in blocked if "A" in e]


def test_edges_to_virtual_landmarks_are_blocked_by_the_obstacles_they_cross():
    r = triangulate(SQUARE)
    outward = ("wall-of-fence", (-5.0, -1.0), (9.0, -1.0))  # under the square, across A-B's virtual edges
    blocked = blocked_edges(r, [outward])
    assert any(any(k.startswith("~") for k in e) for e in blocked)


def test_an_edge_too_narrow_for_the_robot_is_blocked():
    marks = {"A": (0.0, 0.0), "B": (0.6, 0.0), "C": (0.3, 3.0), "D": (0.3, -3.0)}
    r = triangulate(marks)
    assert blocked_edges(r, [], passable=0.8).get(frozenset({"A", "B"})) == "narrow"
    assert frozenset({"A", "B"}) not in blocked_edges(r, [], passable=0.5)


def test_the_map_tells_no_way_out_from_too_little_known():
    from navcli.beliefs import Beliefs, KnownLandmark, KnownObstacle
    from navcli.geometry import Pose
    from navcli.navigation.map_manager import MapManager

    mm = MapManager()
    point = lambda x, y: FuzzyPoint(x, y, (0.02, 0.014, 0.006, 0.0))  # noqa: E731
    few = Beliefs(0.0, Pose(0, 0, 0), (5.0, 0.0), None, (), landmarks=(KnownLandmark("A", point(1.0, 1.0), 0.0),))
    why = mm.diverting_target(few, (5.0, 0.0))
    assert isinstance(why, NoCrossing) and not why.trapped and "too few" in why.why
    # inside a closed fenced box, every edge out of the robot's region crosses a known side
    inside = {"A": (-1.0, -1.0), "B": (1.0, -1.0), "C": (1.0, 1.0), "D": (-1.0, 1.0), "E": (4.0, 0.0), "F": (4.0, 3.0)}
    box = [
        ((-2.0, -2.0), (2.0, -2.0)),
        ((2.0, -2.0), (2.0, 2.0)),
        ((2.0, 2.0), (-2.0, 2.0)),
        ((-2.0, 2.0), (-2.0, -2.0)),
    ]
    b = Beliefs(
        0.0,
        Pose(0, 0, 0),
        (5.0, 1.5),
        None,
        tuple(KnownObstacle(f"side-{i}", p, q, 0.025) for i, (p, q) in enumerate(box)),
        landmarks=tuple(KnownLandmark(k, point(*p), 0.0) for k, p in inside.items()),
    )
    trapped = MapManager().diverting_target(b, (5.0, 1.5))
    assert isinstance(trapped, NoCrossing) and trapped.trapped
    # with one side open, there is a way
    open_ = Beliefs(0.0, Pose(0, 0, 0), (5.0, 1.5), None, b.obstacles[:1] + b.obstacles[2:], landmarks=b.landmarks)
    assert not isinstance(MapManager().diverting_target(open_, (5.0, 1.5)), NoCrossing)


def test_what_a_fence_was_seen_to_block_between_landmarks_stays_known_when_the_memory_forgets_it():
    """The thesis' map keeps its arcs blocked once reported; the visual memory forgets a fence
    (and sees it again under a new key) as the robot moves. The Map Manager keeps, from every
    image, the landmark pairs a known fence crosses: with the fence gone from the memory, the
    way from below it to the target above no longer leads through it, as it does for a map that
    never saw it."""
    from navcli.beliefs import Beliefs, KnownLandmark, KnownObstacle
    from navcli.geometry import Pose
    from navcli.navigation.map_manager import MapManager
    from navcli.navigation.regions import crossed_pairs

    point = lambda x, y: FuzzyPoint(x, y, (0.02, 0.014, 0.006, 0.0))  # noqa: E731
    marks = {"A": (-3.0, -2.0), "B": (3.0, -2.0), "C": (3.5, 3.0), "D": (-3.0, 3.2), "E": (0.3, 4.5)}
    across = KnownObstacle("obstacle-7", (-2.5, 0.5), (2.5, 0.5), 0.025)  # short of A-D and B-C
    robot, target = (0.0, -1.5), (-2.0, 2.5)  # the origin is the robot: the map is egocentric
    shift = lambda p: (p[0] - robot[0], p[1] - robot[1])  # noqa: E731
    rel = {k: shift(p) for k, p in marks.items()}
    landmarks = tuple(KnownLandmark(k, point(*p), 0.0) for k, p in rel.items())
    fence = KnownObstacle(across.key, shift(across.a), shift(across.b), across.radius)
    seen = Beliefs(
        0.0, Pose(0, 0, 0), shift(target), None, (fence,), looked=Look(0.0, "obstacles"), landmarks=landmarks
    )
    forgot = Beliefs(0.1, Pose(0, 0, 0), shift(target), None, (), landmarks=landmarks)
    expected = set(crossed_pairs(rel, [(fence.key, fence.a, fence.b)]))
    assert expected == {frozenset(p) for p in ("AC", "BD", "AE", "BE")}  # the pairs from below to above
    mm = MapManager()
    mm.observe(seen)
    assert set(mm.seen_blocked) == expected and set(mm.seen_blocked.values()) == {"obstacle-7"}
    through = MapManager().diverting_target(forgot, shift(target))  # a map that never saw it: straight across
    assert through.edge == frozenset("AE")
    way = mm.diverting_target(forgot, shift(target))
    assert way.edge not in expected and way.cost > through.cost  # round it

    # seen open: an image showing both landmarks of a pair, no known fence across, clears its
    # record (records are taken at the first image and every SEEN_EVERY-th after it)
    from navcli.navigation.map_manager import SEEN_EVERY

    def image(mm, t, shown):
        for i in range(SEEN_EVERY):  # the landmarks ``shown`` are in each image, the others were seen at 0
            now = t + i * 0.1
            then = tuple(KnownLandmark(k, point(*p), now if k in shown else 0.0) for k, p in rel.items())
            mm.observe(Beliefs(now, Pose(0, 0, 0), shift(target), None, (), looked=Look(0.0, "search"), landmarks=then))

    image(mm, 1.0, {"A", "C"})  # (the first image was the one that saw the fence)
    assert set(mm.seen_blocked) == expected - {frozenset("AC")}
    kept = MapManager(replace(NAVIGATION, seen_closed_cost=0.0))  # closed for good
    kept.observe(seen)
    image(kept, 1.0, set(marks))
    assert set(kept.seen_blocked) == expected


def test_a_way_seen_closed_costs_more_and_never_closes_the_robot_in():
    """Records of a fence the memory no longer holds across every edge of the robot's region:
    the way out through one costs 1 + seen_closed_cost (100) for that arc, and the map gives it;
    with ``seen_closed_cost`` 0, the records block as a known fence does and the map shows no way
    out."""
    from navcli.beliefs import Beliefs, KnownLandmark
    from navcli.geometry import Pose
    from navcli.navigation.map_manager import MapManager

    point = lambda x, y: FuzzyPoint(x, y, (0.02, 0.014, 0.006, 0.0))  # noqa: E731
    marks = {"A": (-2.0, -1.0), "B": (2.0, -1.0), "C": (0.0, 2.0), "D": (0.0, 6.0), "E": (4.0, 4.0)}
    target = (0.5, 4.5)  # beyond C, in region C-D-E
    b = Beliefs(
        0.0,
        Pose(0, 0, 0),
        target,
        None,
        (),
        landmarks=tuple(KnownLandmark(k, point(*p), 0.0) for k, p in marks.items()),
    )
    r = triangulate(marks, NAVIGATION.virtual_distance)
    start = r.region_of((0.0, 0.0))
    assert {r.ids[v] for v in r.triangles[start]} == set("ABC")
    around = {e: "fence-1" for i, j, e in r.edges() if start in (i, j)}
    assert set(around) == {frozenset(p) for p in ("AB", "BC", "AC")}
    for cost, trapped in ((NAVIGATION.seen_closed_cost, False), (0.0, True)):
        mm = MapManager(replace(NAVIGATION, seen_closed_cost=cost))
        mm.seen_blocked = dict(around)
        c = mm.diverting_target(b, target)
        assert isinstance(c, NoCrossing) == trapped and (not trapped or c.trapped)
        if not trapped:  # one recorded arc on the way out (A-C or B-C toward the target), then open arcs
            assert 1.0 + cost < c.cost < 1.0 + cost + 10.0


def test_way_out_is_a_way_through_edges_not_blocked_out_of_the_robots_regions():
    r = triangulate(SQUARE)
    start = r.region_of((2.0, 1.0))
    edges = [e for i, j, e in r.edges() if start in (i, j)]
    assert way_out(r, (2.0, 1.0), {}) and not way_out(r, (2.0, 1.0), {e: 1.0 for e in edges})
    assert way_out(r, (2.0, 1.0), {e: 1.0 for e in edges[1:]})  # one edge open: out through it


def test_the_logged_map_shows_the_regions_and_blocked_edges_the_diverting_targets_use():
    from navcli.beliefs import Beliefs, KnownLandmark, KnownObstacle
    from navcli.geometry import Pose
    from navcli.navigation.map_manager import MapManager

    point = lambda x, y: FuzzyPoint(x, y, (0.02, 0.014, 0.006, 0.0))  # noqa: E731
    b = Beliefs(
        0.0,
        Pose(0, 0, 0),
        (0.0, 2.0),
        None,
        (KnownObstacle("fence", FENCE[1], FENCE[2], 0.025),),
        landmarks=tuple(KnownLandmark(k, point(*p), 0.0) for k, p in AROUND.items()),
    )
    snap = MapManager().snapshot(b)
    fence_points = {k for k in snap.vertices if k.startswith("#fence")}
    assert len(fence_points) == 5  # the chain the regions are built with
    corners = {v for tri in snap.regions for v in tri}
    assert all(snap.vertices[k] in corners for k in fence_points)
    along = [e for e in snap.blocked if all(k.startswith("#fence") for k in e)]
    assert len(along) == 4  # the edges along the fence, drawn blocked


def test_an_edge_where_a_failed_one_was_is_that_edge_again_under_its_new_names():
    """The memory names a bumped or re-seen obstacle's points anew. A diverting target through
    the edge between landmark A and a bump point failed; later the same bump, seen again as
    another obstacle a few centimetres off, gives an edge of new names in the same place: the
    map takes it as the failed edge (costly), and the way goes elsewhere. Far from it (more than
    SAME_PLACE_M), a new edge is not."""
    from navcli.beliefs import Beliefs, KnownLandmark, KnownObstacle
    from navcli.geometry import Pose
    from navcli.navigation.map_manager import SAME_PLACE_M, MapManager

    point = lambda x, y: FuzzyPoint(x, y, (0.02, 0.014, 0.006, 0.0))  # noqa: E731
    marks = {"A": (-2.0, 2.0), "B": (2.0, 2.0), "C": (-2.0, -2.0), "D": (2.0, -2.0), "E": (0.0, 5.0)}
    landmarks = tuple(KnownLandmark(k, point(*p), 0.0) for k, p in marks.items())

    def beliefs(key, shift):  # a short obstacle between A and B, a bit off the line A-B
        a, b = (0.3 + shift, 2.2), (0.9 + shift, 2.2)
        return Beliefs(0.0, Pose(0, 0, 0), (0.0, 4.0), None, (KnownObstacle(key, a, b, 0.025),), landmarks=landmarks)

    first = MapManager()
    c = first.diverting_target(beliefs("obstacle-1", 0.0), (0.0, 4.0))
    assert not isinstance(c, NoCrossing) and any(k.startswith("#obstacle-1:") for k in c.edge)
    first.report_blocked(c.edge)
    again = first.diverting_target(beliefs("obstacle-9", 0.05), (0.0, 4.0))  # the same place, new names
    renamed = frozenset(k.replace("obstacle-1:", "obstacle-9:") for k in c.edge)
    assert not isinstance(again, NoCrossing) and again.edge != renamed
    # a map that never failed there takes the renamed edge; one that failed far from it does too
    assert MapManager().diverting_target(beliefs("obstacle-9", 0.05), (0.0, 4.0)).edge == renamed
    by_ends = replace(NAVIGATION, dead_end_radius=0.0)  # matched by its ends alone (the dead end's radius: below)
    far = MapManager(by_ends)
    far.diverting_target(beliefs("obstacle-1", 0.0), (0.0, 4.0))
    far.report_blocked(c.edge)
    moved = 2.5 * SAME_PLACE_M
    far_edge = far.diverting_target(beliefs("obstacle-9", moved), (0.0, 4.0)).edge
    assert far_edge == MapManager(by_ends).diverting_target(beliefs("obstacle-9", moved), (0.0, 4.0)).edge
    # remembered by place, the dead end is that edge again: its middle moved by half of 1.25 m, inside
    # dead_end_radius (1 m), though its moved end lies 1.25 m from where it was, beyond SAME_PLACE_M
    assert 2.5 * SAME_PLACE_M / 2 < NAVIGATION.dead_end_radius < 2.5 * SAME_PLACE_M
    near = MapManager()
    near.diverting_target(beliefs("obstacle-1", 0.0), (0.0, 4.0))
    near.report_blocked(c.edge)
    assert near.dead_ends == [pytest.approx((0.3 / 2 + -2.0 / 2, 2.2 / 2 + 2.0 / 2))]  # the middle of A-(0.3, 2.2)
    renamed_far = frozenset(k.replace("obstacle-1:", "obstacle-9:") for k in c.edge)
    assert near.diverting_target(beliefs("obstacle-9", moved), (0.0, 4.0)).edge not in (far_edge, renamed_far)


def test_an_edge_to_a_virtual_landmark_is_the_failed_one_again_only_the_same_way_out():
    """From one landmark the ways out to either side are different edges: a failed edge from A
    to a virtual landmark east of it blocks, in the same place, one whose virtual end lies within
    SAME_WAY_DEG of east, not one to the north or the west."""
    from navcli.navigation.map_manager import SAME_WAY_DEG, MapManager

    mm = MapManager()
    ray = lambda deg: (1.0 + 10 * math.cos(math.radians(deg)), 10 * math.sin(math.radians(deg)))  # noqa: E731
    mm._where = {"A": (1.0, 0.0), "B": (1.0, 3.0), "~east": ray(0.0)}
    mm.report_blocked(frozenset({"A", "~east"}))
    mm._where = {
        "#obstacle-4:0": (1.2, 0.1),
        "~a": ray(0.8 * SAME_WAY_DEG),
        "~b": ray(1.2 * SAME_WAY_DEG),
        "~west": ray(180.0),
        "B": (1.0, 3.0),
    }
    again = lambda v: mm._failed_before(mm._place(frozenset({"#obstacle-4:0", v})))  # noqa: E731
    assert again("~a") and not again("~b") and not again("~west")
    assert not mm._failed_before(mm._place(frozenset({"#obstacle-4:0", "B"})))  # two real ends: another edge
