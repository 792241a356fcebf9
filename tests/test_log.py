"""A run's MCAP log: every topic, simulation time as log time, a summary that agrees with the
poses, the scenario attached, determinism, and a readable file after an interruption."""

from __future__ import annotations

import math

import pytest

from navcli.analysis import path_length, read_log
from conftest import SCENARIOS
from navcli.config import RunSpec
from navcli.params import CONTROL_DT
from navcli.runner import run_mission
from navcli.scenario import load_scenario

TOPICS = {
    "/tf",
    "/robot/pose",
    "/robot/odometry",
    "/world/scene",
    "/robot/scene",
    "/pilot",
    "/bids",
    "/events",
    "/mission/summary",
    "/vision",
    "/memory/scene",
    "/robot/body",
    "/robot/camera",
}


@pytest.fixture(scope="module")
def open_run(tmp_path_factory):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    out = tmp_path_factory.mktemp("logs") / "run.mcap"
    res = run_mission(RunSpec.build(sc, seed=3), out=out)
    return sc, res, read_log(out)


def test_every_topic_is_present(open_run):
    _, _, log = open_run
    assert TOPICS <= set(log.topics)


def test_state_a_viewer_needs_is_complete_in_every_message_and_repeated(open_run):
    """A viewer restores the latest message per topic after a seek or a late join: the arena,
    the robot's body and the camera's field of view are each on a topic of their own, whole in
    every message, and repeated at least every SCENE_REFRESH seconds until the end."""
    from navcli.params import SCENE_REFRESH

    sc, res, log = open_run
    arena = {"walls", "target"} | {f"landmark-{o.key}" for o in sc.objects if o.kind == "landmark"}
    end = res.summary["time_s"]
    for topic, ids in (("/world/scene", arena), ("/robot/body", {"robot"}), ("/robot/camera", {"camera"})):
        df = log[topic]
        assert all(set(e) == ids for e in df["entities"]), topic
        t = df["time_s"].to_numpy()
        assert t[0] == 0.0 and (t[1:] - t[:-1]).max() <= SCENE_REFRESH + 1e-9 and end - t[-1] <= SCENE_REFRESH, topic


def test_log_time_is_simulation_time(open_run):
    _, res, log = open_run
    poses = log["/robot/pose"]
    t = poses["log_time_ns"].to_numpy()
    assert t[0] == 0 and (t[1:] > t[:-1]).all()  # strictly increasing from the start
    step = round(CONTROL_DT * 1e9)
    assert (t == step * poses.index.to_numpy()).all()  # one pose per control tick, exactly
    assert t[-1] / 1e9 == pytest.approx(res.summary["time_s"])
    assert log["/mission/summary"]["log_time_ns"].iloc[0] == t[-1]


def test_summary_agrees_with_the_poses(open_run):
    sc, res, log = open_run
    s = log.summary
    assert s == res.summary
    assert s["outcome"] == "reached" and s["scenario"] == sc.name and s["seed"] == 3
    assert s["path_length_m"] == pytest.approx(path_length(log["/robot/pose"]), rel=0.01)
    last = log["/robot/pose"].iloc[-1]
    assert math.dist((last.x, last.y), sc.target.point) <= sc.target.tolerance
    assert s["ticks"] == len(log["/bids"])


def test_metadata_and_attachment_reproduce_the_run(open_run):
    sc, _, log = open_run
    run = log.metadata["run"]
    assert run["scenario"] == sc.name and run["seed"] == "3" and run["scenario_sha256"] == sc.sha256
    assert log.attachments["open-arena.yaml"].decode() == sc.text


def test_bids_show_every_system_and_the_winner(open_run):
    _, _, log = open_run
    bids = log["/bids"]
    assert {"motion.pilot", "motion.navigation", "motion.winner", "camera.pilot", "camera.navigation"} <= set(bids)
    assert bids["motion.navigation"].between(0, 1).all()
    won = bids["motion.winner"] == "navigation"
    assert (bids.loc[won, "motion.navigation"] >= bids.loc[won, "motion.pilot"]).all()


def test_same_seed_same_run_other_seed_other_noise(tmp_path):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    logs = {}
    for name, seed in (("a", 5), ("b", 5), ("c", 6)):
        run_mission(RunSpec.build(sc, seed=seed), out=tmp_path / f"{name}.mcap")
        logs[name] = read_log(tmp_path / f"{name}.mcap")
    cols = ["log_time_ns", "x", "y", "theta"]
    assert logs["a"]["/robot/pose"][cols].equals(logs["b"]["/robot/pose"][cols])
    assert logs["a"]["/robot/odometry"][cols].equals(logs["b"]["/robot/odometry"][cols])
    odo_a, odo_c = logs["a"]["/robot/odometry"], logs["c"]["/robot/odometry"]
    n = min(len(odo_a), len(odo_c))
    assert not odo_a[["x", "y"]].iloc[:n].equals(odo_c[["x", "y"]].iloc[:n])


def test_interrupted_run_leaves_a_readable_log_marked_interrupted(tmp_path):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    out = tmp_path / "cut.mcap"

    def ctrl_c(mission, tick):
        if tick.index == 40:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_mission(RunSpec.build(sc), out=out, on_tick=ctrl_c)
    assert out.exists() and not out.with_name("cut.mcap.partial").exists()
    log = read_log(out)
    assert log.summary["outcome"] == "interrupted" and log.summary["ticks"] == 40
    assert len(log["/robot/pose"]) == 41
    assert "stopped by the user" in log["/events"]["message"].iloc[-1]


def test_error_in_a_run_leaves_a_log_marked_error(tmp_path):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    out = tmp_path / "err.mcap"

    def boom(mission, tick):
        if tick.index == 5:
            raise RuntimeError("sensor on fire")

    with pytest.raises(RuntimeError):
        run_mission(RunSpec.build(sc), out=out, on_tick=boom)
    s = read_log(out).summary
    assert s["outcome"] == "error" and "sensor on fire" in s["reason"]


@pytest.mark.parametrize(
    "stop, outcome, reason",
    [
        (KeyboardInterrupt(), "interrupted", "stopped by the user (Ctrl-C)"),
        (RuntimeError("disk on fire"), "error", "RuntimeError: disk on fire"),
    ],
)
def test_a_run_stopped_while_its_log_begins_says_why(tmp_path, monkeypatch, stop, outcome, reason):
    """The log's start (the configuration, the first pose) is written before the first tick: a stop
    there leaves a log labelled as a stop inside the run is, not an empty reason."""
    from navcli.log.writer import Recorder

    start = Recorder.start

    def start_then_stop(self, *args):
        start(self, *args)
        raise stop

    monkeypatch.setattr(Recorder, "start", start_then_stop)
    out = tmp_path / "early.mcap"
    with pytest.raises(type(stop)):
        run_mission(RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml")), out=out)
    log = read_log(out)
    assert (log.summary["outcome"], log.summary["reason"], log.summary["ticks"]) == (outcome, reason, 0)
    assert log["/events"]["message"].iloc[-1] == reason


def test_time_limit_ends_the_run_as_timeout(tmp_path):
    sc = load_scenario(SCENARIOS / "open-arena.yaml")
    res = run_mission(RunSpec.build(sc, time_limit=2.0), out=tmp_path / "t.mcap")
    assert res.summary["outcome"] == "timeout" and res.summary["time_s"] == pytest.approx(2.0)
    assert res.summary["ticks"] == 20


def test_vision_topic_reports_images_with_fuzzy_detections(open_run, tmp_path):
    _, res, log = open_run
    v = log["/vision"]
    assert len(v) == res.summary["ticks"]
    images = v[v["image"]]
    assert len(images) == res.summary["camera_looks"] > 0
    from navcli.bidding import PURPOSES

    assert (
        set(images["purpose"]) <= set(PURPOSES) and images["purpose"].notna().all()
    )  # every image says what it was for
    assert v.loc[v["state"] == "idle", "purpose"].isna().all()
    # the open room has no landmark: the Risk Manager searches (bid at R = 1) and finds nothing, for
    # a search registers landmarks only; the Pilot's looks ahead (its bid reaches 1 after d_m) find the walls
    assert set(images["purpose"]) == {"search", "obstacles"}
    found = images[[c for c in images.columns if c.endswith(".kind")]]
    assert found[images["purpose"] == "search"].isna().all().all()
    assert set(found[images["purpose"] == "obstacles"].stack()) == {"wall"}
    sc = load_scenario(SCENARIOS / "landmarks-12.yaml")  # a room with landmarks: searches find them
    run_mission(RunSpec.build(sc, seed=3, time_limit=20.0), out=tmp_path / "l12.mcap")
    images = read_log(tmp_path / "l12.mcap")["/vision"].query("image")
    columns = [c for c in images.columns if c.startswith("detections.") and c.endswith(".points")]
    seen = [p for c in columns for p in images[c].dropna()]
    assert len(seen) > 0, "landmarks are seen"
    for points in seen:
        for p in points:
            h, d = p["heading_deg"], p["distance_m"]
            for cut in (h, d):
                assert cut["lo0"] <= cut["lo70"] <= cut["core"] <= cut["hi70"] <= cut["hi0"]
            assert 0 <= d["lo0"] < d["hi0"] and d["lo0"] <= 6.0  # the support holds the true distance, within range


def test_the_pilots_decorations_are_drawn_every_draw_period_and_its_forces_logged_every_tick(open_run):
    """/robot/scene (force arrows and grown obstacles) is drawn from the first tick on, every
    DRAW_PERIOD; the forces it draws are in /pilot at every tick."""
    from navcli.params import DRAW_PERIOD

    _, res, log = open_run
    scene = log["/robot/scene"]
    every = round(DRAW_PERIOD / CONTROL_DT)  # ticks between two drawings
    ticks = (scene["log_time_ns"] // round(CONTROL_DT * 1e9)).to_numpy()
    assert ticks[0] == 1 and ((ticks - 1) % every == 0).all()
    assert len(scene) == (res.summary["ticks"] - 1) // every + 1
    assert all(
        set(e) == {"forces", "grown-obstacles"} for e in scene["entities"]
    )  # the potential-field pilot has forces
    pilot = log["/pilot"]
    assert len(pilot) == res.summary["ticks"] and not pilot[["net.x", "net.y"]].isna().any().any()


def test_the_log_ends_with_the_final_memory_and_map(open_run):
    """Drawn every few seconds (vision.draw_every, navigation.map_draw_every), the visual memory and
    the map are drawn at the last tick too, so a log's last drawing of each is the final one."""
    _, _, log = open_run
    end = log["/robot/pose"]["log_time_ns"].iloc[-1]
    for topic in ("/memory/scene", "/map/scene"):
        t = log[topic]["log_time_ns"]
        assert t.iloc[-1] == end and len(t) >= 2, topic


def test_the_camera_frame_in_tf_turns_by_the_pan_of_every_tick(open_run):
    """Each /tf message holds world -> base_link (the true pose) and base_link -> camera, turned by
    the pan /vision reports at that time; the field of view is drawn once in that frame."""
    from navcli.analysis.logs import scene_messages

    _, res, log = open_run
    tf = {ns: m for ns, m in scene_messages(log.path, "/tf")}
    pans = dict(zip(log["/vision"]["log_time_ns"], log["/vision"]["pan_deg"]))
    assert len(pans) == res.summary["ticks"] and set(pans) <= set(tf)
    assert any(abs(p) > 1.0 for p in pans.values())  # the camera did pan
    for ns, pan in pans.items():
        base, cam = tf[ns].transforms
        assert (base.parent_frame_id, base.child_frame_id, cam.parent_frame_id, cam.child_frame_id) == (
            "world",
            "base_link",
            "base_link",
            "camera",
        )
        q = cam.rotation
        assert math.degrees(2 * math.atan2(q.z, q.w)) == pytest.approx(pan, abs=1e-9)
    assert all(e == ["camera"] for e in log["/robot/camera"]["entities"])


def test_no_numeric_field_of_the_pilot_log_is_missing(open_run):
    _, _, log = open_run
    nums = log["/pilot"].select_dtypes("number")
    forces = [c for c in nums if c.startswith(("net.", "target.", "repulsive.", "turn_deg", "bid"))]
    assert forces and not nums[forces].isna().any().any()  # NaN would have been written as null


def test_oracle_perception_is_recorded_and_still_reaches(tmp_path):
    sc = load_scenario(SCENARIOS / "paper-8x8.yaml")
    res = run_mission(RunSpec.build(sc, perception="oracle"), out=tmp_path / "o.mcap")
    log = read_log(tmp_path / "o.mcap")
    assert log.metadata["run"]["perception"] == "oracle" and res.summary["outcome"] == "reached"
    assert "/memory/scene" not in log.topics  # no visual memory to draw


def test_the_pose_messages_built_inline_are_those_of_the_plain_helpers(tmp_path):
    """Recorder._pose_msgs builds its messages inline (a measured hot path); every byte written
    must be what stamp, yaw and place give, turned or not, at a whole second or between."""
    from mcap.reader import make_reader

    from navcli.geometry import Pose
    from foxglove.messages import FrameTransform, FrameTransforms, PoseInFrame, Pose as FxPose, Vector3

    from navcli.log.scenes import CAMERA_AT, stamp, yaw
    from navcli.log.writer import Recorder

    cases = [
        (Pose(1.5, 2.25, 0.7), Pose(1.4, 2.5, -2.9), 2_000_000_000, 0.3),
        (Pose(0.0, 3.0, 0.0), Pose(-0.5, 0.0, 0.0), 2_100_000_000, 0.0),
        (Pose(7.0, 0.5, -math.pi), Pose(7.1, 0.4, 3.1), 2_200_000_000, -1.2),
    ]
    rec = Recorder(tmp_path / "p.mcap")
    for truth, odom, ns, pan in cases:
        rec._pose_msgs(truth, odom, ns, pan)
    rec.writer.close()
    with open(rec.partial, "rb") as f:
        got = [(c.topic, m.log_time, m.data) for _, c, m in make_reader(f).iter_messages(log_time_order=False)]
    want = []
    for truth, odom, ns, pan in cases:
        ts, q = stamp(ns), yaw(truth.theta)
        at = Vector3(x=truth.x, y=truth.y, z=0.0)
        want += [
            (
                "/tf",
                ns,
                FrameTransforms(
                    transforms=[
                        FrameTransform(
                            timestamp=ts,
                            parent_frame_id="world",
                            child_frame_id="base_link",
                            translation=at,
                            rotation=q,
                        ),
                        FrameTransform(
                            timestamp=ts,
                            parent_frame_id="base_link",
                            child_frame_id="camera",
                            translation=CAMERA_AT,
                            rotation=yaw(pan),
                        ),
                    ]
                ).encode(),
            ),
            (
                "/robot/odometry",
                ns,
                PoseInFrame(
                    timestamp=ts,
                    frame_id="world",
                    pose=FxPose(position=Vector3(x=odom.x, y=odom.y, z=0.0), orientation=yaw(odom.theta)),
                ).encode(),
            ),
            (
                "/robot/pose",
                ns,
                PoseInFrame(timestamp=ts, frame_id="world", pose=FxPose(position=at, orientation=q)).encode(),
            ),
        ]
    assert got == want
    rec.lock.release()


def test_the_log_format_document_names_every_topic_metadata_field_and_summary_field(open_run):
    """docs/log-format.md is the reference a user reads: its topic table lists exactly the topics
    of a run's log, and it names every field of the ``run`` metadata and of the summary (its
    table once lacked four topics, and the summary three fields)."""
    import re

    from conftest import ROOT

    from navcli.log.format import MissionSummary

    _, _, log = open_run
    doc = (ROOT / "docs" / "log-format.md").read_text()
    table = set(re.findall(r"^\| `(/[^`]+)` \|", doc, flags=re.M))
    assert table == set(log.topics)
    named = set(re.findall(r"`([a-z_0-9]+)`", doc))
    assert set(log.metadata["run"]) <= named
    assert set(MissionSummary.__struct_fields__) <= named


# --- how the chunks are compressed (navcli.log.compression) ---


def test_every_compression_writes_the_same_messages_in_chunks_compressed_as_named(tmp_path):
    """The choice reaches the writer (the chunks say their compression, and the two zstd levels
    make files of different bytes), changes no message, and navcli.analysis reads every one."""
    from mcap.reader import make_reader

    from navcli.log.compression import COMPRESSIONS, DEFAULT

    spec = RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"), seed=3, time_limit=5.0)
    messages, chunks, files = {}, {}, {}
    for name in COMPRESSIONS:
        out = tmp_path / f"{name}.mcap"
        run_mission(spec, out=out, log_compression=name)
        with out.open("rb") as f:
            reader = make_reader(f)
            chunks[name] = {c.compression for c in reader.get_summary().chunk_indexes}
            messages[name] = [(ch.topic, m.log_time, m.data) for _, ch, m in reader.iter_messages(log_time_order=True)]
        files[name] = out.read_bytes()
        log = read_log(out)
        assert log.summary["ticks"] == 50 and len(log["/robot/pose"]) == 51, name
    assert chunks == {name: {kind or ""} for name, (kind, _) in COMPRESSIONS.items()}
    assert all(m == messages[DEFAULT] for m in messages.values())
    assert len(messages[DEFAULT]) > 300  # some topics every tick, for 50 ticks
    assert files["zstd-1"] != files["zstd-3"]
    assert len(files["none"]) > 2 * len(files[DEFAULT])


def test_an_unknown_compression_is_refused_before_the_run_with_the_choices(tmp_path):
    from navcli.checks.arguments import ArgumentError

    spec = RunSpec.build(load_scenario(SCENARIOS / "open-arena.yaml"), seed=3, time_limit=1.0)
    with pytest.raises(ArgumentError, match="log_compression='gzip': expected one of 'zstd-1', .*'none'"):
        run_mission(spec, out=tmp_path / "run.mcap", log_compression="gzip")
    assert not list(tmp_path.iterdir())
