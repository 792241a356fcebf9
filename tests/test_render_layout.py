"""``navcli render`` (a video from a log alone) and ``navcli layout`` (a Foxglove layout naming
only what the logs hold)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from navcli.analysis.render import RenderError, memory_in_world, render
from conftest import SCENARIOS
from navcli.cli import app
from navcli.config import RunSpec
from navcli.log.format import MESSAGES, json_schema
from navcli.runner import run_mission
from navcli.scenario import load_scenario


@pytest.fixture(scope="module")
def short_log(tmp_path_factory):
    """2 s of the 8 m room: 20 ticks, the memory drawn once, at the last tick."""
    out = tmp_path_factory.mktemp("render") / "short.mcap"
    run_mission(RunSpec.build(load_scenario(SCENARIOS / "paper-8x8.yaml"), seed=1, time_limit=2.0), out=out)
    return out


def test_render_writes_a_gif_with_one_frame_per_step(short_log, tmp_path):
    # speed 2 at 5 frames per second: a frame every 0.4 simulated s, 0.0 to 2.0 inclusive = 6;
    # the 5 x 6.4 inch figure at 30 dpi is 150 x 192 pixels
    res = render(short_log, tmp_path / "run.gif", speed=2.0, fps=5.0, dpi=30)
    assert res.frames == 6 and res.size == (150, 192)
    with Image.open(res.path) as im:
        assert im.n_frames == 6 and im.size == (150, 192)
    # --from/--to clip: 0.5 s to 1.5 s at 0.5 s per frame = 3 frames
    assert render(short_log, tmp_path / "clip.gif", speed=2.5, fps=5.0, start=0.5, end=1.5, dpi=20).frames == 3


def test_render_places_the_memory_with_the_pose_of_its_drawing():
    """A memory drawn at 1 s, one spot 1 m ahead of a robot at the origin facing +x; at 2 s the robot
    is at (5, 0) facing +y. At 2 s the spot stays at (1, 0) in the world (where the 3D view keeps a
    drawing that is not frame-locked), not 1 m ahead of the robot's new pose (5, 1); before 1 s
    nothing is drawn."""
    memory = [(1.0, [("landmark", 1.0, 0.0, 0.1, 0.5)])]
    poses = tuple(np.array(v) for v in ([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 0.0, math.pi / 2], [0.0, 1.0, 2.0]))
    ((kind, x, y, r70, r0),) = memory_in_world(memory, np.array([1.0]), poses, 2.0)
    assert kind == "landmark" and (x, y) == pytest.approx((1.0, 0.0)) and (r70, r0) == (0.1, 0.5)
    assert memory_in_world(memory, np.array([1.0]), poses, 0.9) == []


def test_render_refuses_what_it_cannot_do(short_log, tmp_path, monkeypatch):
    from matplotlib import animation

    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    with pytest.raises(RenderError, match="a GIF works"):
        render(short_log, tmp_path / "run.mp4")
    r = CliRunner().invoke(app, ["render", str(short_log), "--out", str(tmp_path / "run.avi")])
    assert r.exit_code == 2 and ".gif or .mp4" in r.output
    r = CliRunner().invoke(app, ["render", str(short_log), "--from", "3"])
    assert r.exit_code == 2 and "empty time range" in r.output


def _declares(topic: str, field: str) -> bool:
    node = json_schema(MESSAGES[topic])
    for part in field.split("."):
        node = node.get("properties", {}).get(part)
        if node is None:
            return False
    return True


def _named_topics(node, named=None) -> set[str]:
    """Every topic (and topic.field path) a layout names, anywhere in its JSON."""
    named = set() if named is None else named
    if isinstance(node, dict):
        for k, v in node.items():
            if k == "topics" and isinstance(v, dict):
                named.update(v)
            elif k in ("topicToRender", "topicPath", "value") and isinstance(v, str) and v.startswith("/"):
                named.add(v)
            _named_topics(v, named)
    elif isinstance(node, list):
        for v in node:
            _named_topics(v, named)
    return named


def _panel_titles(node, titles=None) -> list[str]:
    """The titles of an SDK layout's panels, in document order."""
    titles = [] if titles is None else titles
    if isinstance(node, dict):
        if node.get("type") == "panel" and node.get("title"):
            titles.append(node["title"])
        for v in node.values():
            _panel_titles(v, titles)
    elif isinstance(node, list):
        for v in node:
            _panel_titles(v, titles)
    return titles


@pytest.mark.parametrize("fmt", ["app", "sdk"])
def test_layout_is_json_naming_only_topics_and_fields_the_logs_have(short_log, tmp_path, fmt):
    from navcli.analysis import read_log

    out = tmp_path / "layout.json"
    r = CliRunner().invoke(app, ["layout", "--out", str(out), "--format", fmt])
    assert r.exit_code == 0, r.output
    text = out.read_text()
    data = json.loads(text)
    assert ("configById" in data) if fmt == "app" else (data["version"] == 1 and "content" in data)
    logged = set(read_log(short_log).topics)
    named = _named_topics(data)
    paths = {n for n in named if "." in n}
    topics = {n.split(".", 1)[0] for n in named}
    assert {"/world/scene", "/robot/body", "/bids", "/pilot", "/events", "/mission/summary"} <= topics
    assert topics <= logged
    for p in paths:  # every plotted field is declared in its topic's schema
        topic, field = p.split(".", 1)
        assert _declares(topic, field), p
    if fmt == "app":
        three_d = next(v for k, v in data["configById"].items() if k.startswith("3D!"))
        assert three_d["followTf"] == "world" and three_d["cameraState"]["perspective"] is False
        assert three_d["scene"]["transforms"]["enablePreloading"] is True  # no alert, beliefs in place after a seek
        # every panel titled for both apps: Foxglove reads one key, Lichtblick the other
        sdk = json.loads(CliRunner().invoke(app, ["layout", "--format", "sdk"]).output)
        titles = _panel_titles(sdk)
        configs = list(data["configById"].values())
        assert len(configs) == len(titles) == 5
        assert sorted(c["foxglovePanelTitle"] for c in configs) == sorted(titles)
        assert all(c["lichtblickPanelTitle"] == c["foxglovePanelTitle"] for c in configs)
