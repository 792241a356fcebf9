"""What a viewer shows of a log, and what the log costs: the default view (truth, robot, path,
beliefs) apart from the layers a user switches on (supports, regions, forces), the path whole in
every message, and the log's bytes per simulated second within the budget docs/log-format.md states."""

from __future__ import annotations

import json
import math
import re

import pytest

from conftest import ROOT
from navcli.analysis import path_length, read_log
from navcli.analysis.logs import scene_messages
from navcli.config import RunSpec
from navcli.log import layout
from navcli.log.scenes import PATH_STEP
from navcli.params import SCENE_REFRESH
from navcli.runner import run_mission
from navcli.scenario import load_scenario

SECONDS = 60.0


@pytest.fixture(scope="module")
def minute(tmp_path_factory):
    """The first simulated minute of paper-8x8 (vision): its memory and map drawn many times."""
    out = tmp_path_factory.mktemp("view") / "run.mcap"
    res = run_mission(RunSpec.build(load_scenario("paper-8x8"), time_limit=SECONDS), out=out)
    return res, out


def test_the_layout_shows_truth_robot_path_and_beliefs_and_lists_the_layers_off():
    app = layout.app_json()
    three_d = next(v for k, v in app["configById"].items() if k.startswith("3D!"))
    visible = {t for t, v in three_d["topics"].items() if v["visible"]}
    assert visible == {"/world/scene", "/robot/path", "/robot/body", "/robot/camera", "/memory/scene", "/map/scene"}
    assert set(three_d["topics"]) - visible == {"/memory/supports", "/map/regions", "/robot/scene"}
    assert three_d["scene"]["transforms"]["showLabel"] is False  # no frame names written across the robot
    sdk = json.dumps(layout.sdk_json())
    assert '"/memory/supports": {"visible": false}' in sdk


def test_beliefs_and_their_supports_are_apart_but_drawn_together(minute):
    """Every drawing of the memory is two messages at the same time: the 70 % cut discs in
    /memory/scene and, in the entity of the same id, a ring per disc in /memory/supports."""
    _, out = minute
    scene = dict(scene_messages(out, "/memory/scene"))
    supports = dict(scene_messages(out, "/memory/supports"))
    assert len(scene) >= SECONDS / 3 - 1 and scene.keys() == supports.keys()
    for ns, m in scene.items():
        rings = {e.id: e.lines for e in supports[ns].entities}
        assert {e.id for e in m.entities} == set(rings)
        for e in m.entities:
            assert all(len(ln.points) == 2 for ln in e.lines)  # only a linear obstacle's axis: no ring here
            assert len(rings[e.id]) == len(e.cylinders) and all(len(ln.points) == 16 for ln in rings[e.id])


def test_the_maps_regions_are_a_layer_of_their_own(minute):
    _, out = minute
    maps = dict(scene_messages(out, "/map/scene"))
    regions = dict(scene_messages(out, "/map/regions"))
    assert regions and set(regions) <= set(maps)
    assert all(ln.type != 1 for m in maps.values() for e in m.entities for ln in e.lines)  # no LineLoop: no triangle
    assert any(ln.type == 1 for m in regions.values() for e in m.entities for ln in e.lines)


def test_the_path_is_whole_in_every_message_and_follows_the_poses(minute):
    """Republished every SCENE_REFRESH s, each /robot/path message runs from the start to the pose
    of its time, its points PATH_STEP apart or more (the last one excepted), never far from the
    poses' own polyline, and as long as it up to the corners the decimation cuts."""
    res, out = minute
    log = read_log(out, topics=["/robot/pose"])
    poses = log["/robot/pose"].set_index("log_time_ns")
    paths = list(scene_messages(out, "/robot/path"))
    times = [ns for ns, _ in paths]
    assert times[0] == 0 and max(b - a for a, b in zip(times, times[1:])) <= 10 * SCENE_REFRESH * 1e9
    for ns, m in paths:
        (entity,) = m.entities
        assert entity.frame_id == "world"
        pts = [(p.x, p.y) for p in entity.lines[0].points]
        at = poses.loc[ns]
        assert pts[0] == pytest.approx(tuple(poses.iloc[0][["x", "y"]])) and pts[-1] == pytest.approx((at.x, at.y))
        assert all(math.dist(a, b) >= PATH_STEP - 1e-9 for a, b in zip(pts[:-2], pts[1:-1]))
    walked = path_length(log["/robot/pose"])
    drawn = sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
    assert walked > 1.0 and 0.95 * walked <= drawn <= walked + 1e-9


BUDGET = re.compile(r"at most \*\*([\d,]+) bytes\*\* a simulated second")


def test_the_log_stays_within_the_size_docs_log_format_states(minute):
    """docs/log-format.md states a budget per simulated second; the first minute of paper-8x8
    (where the memory and the map fill up) keeps to it."""
    res, out = minute
    budget = int(BUDGET.search((ROOT / "docs" / "log-format.md").read_text()).group(1).replace(",", ""))
    assert out.stat().st_size / res.summary["time_s"] <= budget


def test_the_pilots_per_obstacle_forces_are_written_to_four_decimals(minute):
    _, out = minute
    pilot = read_log(out, topics=["/pilot"])["/pilot"]
    forces = [c for c in pilot if c.startswith("obstacles.") and c.endswith((".x", ".y", ".mag"))]
    values = pilot[forces].stack().dropna()
    assert len(values) > 1000 and (values.round(4) == values).all()
