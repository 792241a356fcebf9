"""The Map Manager's maths: Prescott's beta-coefficients (crisp and fuzzy) and the regions."""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from navcli.fuzzy import FuzzyPoint
from navcli.navigation.beta_map import BetaNetwork, collinearity, encode, recall
from navcli.navigation.regions import first_crossing, triangulate

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
@given(st.lists(point, min_size=4, max_size=4), st.floats(-math.pi, math.pi), coord, coord,
       st.lists(st.tuples(st.floats(0, 1), st.floats(-math.pi, math.pi)), min_size=7, max_size=7),
       st.floats(0.01, 0.2))
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
    assert sorted(i for i in r.ids if i.startswith("~")) == ["~A-B", "~A-D", "~B-C", "~C-E", "~D-E"]  # one per hull edge
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
        r = subprocess.run([sys.executable, "-m", "navcli", "run", str(SCENARIOS / "landmarks-12.yaml"),
                            "--time-limit", "15", "--out", str(out)], capture_output=True, text=True, cwd=ROOT,
                           env=os.environ | {"PYTHONHASHSEED": seed})
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
        return max((1.0 - collinearity((a.x, a.y), (b.x, b.y), (c.x, c.y))
                    for a, b, c in itertools.combinations(six, 3)), default=0.0)

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
