"""The Gymnasium environment as Gymnasium's users expect it: the documented ``gymnasium.make`` line
works in a fresh interpreter, ``render_mode="rgb_array"`` returns frames of ``navcli render``'s
drawing, and Gymnasium's own checker and ``RecordVideo`` accept it."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

import navcli.envs  # noqa: E402
from conftest import ROOT  # noqa: E402

SHORT = {"learning.max_actions": 3}
GOLD = (255, 215, 0)  # the robot's body in the drawing (matplotlib's "gold")


def documented_snippet() -> str:
    """The code block of ``navcli.envs``' docstring: what a user copies."""
    doc = navcli.envs.__doc__ or ""
    block = doc.split("::\n", 1)[1].split("\n\n", 1)[0]
    return textwrap.dedent(block)


def test_the_documented_make_line_works_in_a_fresh_interpreter():
    code = documented_snippet()
    assert f'gymnasium.make("{navcli.envs.MAKE_ID}", render_mode="rgb_array")' in code
    check = code.replace('render_mode="rgb_array")', f'render_mode="rgb_array", overrides={SHORT!r})') + (
        "\nobs, info = env.reset(seed=2)\nframe = env.render()\nprint(obs in range(980), frame.shape, frame.dtype)\n"
    )
    fresh = "import sys; assert not any(m.startswith('navcli') for m in sys.modules)\n" + check
    r = subprocess.run([sys.executable, "-c", fresh], capture_output=True, text=True, cwd=ROOT / "tests", timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split() == ["True", "(512,", "400,", "3)", "uint8"]


def test_the_environment_passes_gymnasiums_checker_with_its_render_mode():
    from gymnasium.utils.env_checker import check_env

    env = gym.make(navcli.envs.MAKE_ID, render_mode="rgb_array", overrides=SHORT)
    assert env.metadata["render_modes"] == ["rgb_array"] and env.metadata["render_fps"] == 4
    check_env(env.unwrapped)  # the render check too (it makes the env again from its spec, per mode)
    env.close()


def _centre_of(frame: np.ndarray, colour: tuple[int, int, int]) -> tuple[float, float]:
    rows, cols = np.nonzero((frame == colour).all(axis=2))
    assert len(rows) > 20, "the colour is not in the frame"
    return float(cols.mean()), float(rows.mean())


def test_a_frame_draws_the_robot_where_the_mission_has_it():
    """The body's gold disc lies at the true pose of the mission, mapped to pixels by the figure's
    own axes, after the reset and again after two actions (when the robot has moved)."""
    env = gym.make(navcli.envs.MAKE_ID, render_mode="rgb_array", overrides=SHORT).unwrapped
    env.reset(seed=5)
    seen = []
    for actions in (0, 2):
        for _ in range(actions // 2):
            env.step(0)
            env.step(0)
        frame = env.render()
        pose = env.task.mission.world.pose
        px, py = env._figure.ax.transData.transform((pose.x, pose.y))
        height = frame.shape[0]
        cx, cy = _centre_of(frame, GOLD)
        assert (cx, cy) == pytest.approx((px, height - py), abs=3.0)
        seen.append((pose.x, pose.y))
    assert seen[0] != seen[1]  # it moved, and the drawing followed
    env.close()


def test_record_video_writes_a_frame_per_step_from_the_reset(tmp_path):
    """Gymnasium's RecordVideo: the reset's frame and one per action, at the environment's rate."""
    import imageio
    from gymnasium.wrappers import RecordVideo

    env = RecordVideo(
        gym.make(navcli.envs.MAKE_ID, render_mode="rgb_array", overrides=SHORT),
        str(tmp_path / "videos"),
        episode_trigger=lambda episode: True,
        disable_logger=True,
    )
    env.reset(seed=1)
    steps, done = 0, False
    while not done:
        _, _, terminated, truncated, _ = env.step(0)
        steps, done = steps + 1, terminated or truncated
    env.close()
    (video,) = (tmp_path / "videos").glob("*.mp4")
    with imageio.get_reader(video) as reader:
        meta = reader.get_meta_data()
        assert reader.count_frames() == steps + 1 and 1 <= steps <= SHORT["learning.max_actions"]
        assert meta["fps"] == 4 and meta["size"] == (400, 512)


def test_render_without_a_mode_and_an_unknown_mode():
    from navcli.envs import LandmarkNavigationEnv

    env = LandmarkNavigationEnv(overrides=SHORT)
    env.reset(seed=1)
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.render() is None
    with pytest.raises(ValueError, match="human"):
        LandmarkNavigationEnv(render_mode="human")


def test_the_environment_takes_a_bundled_scenario_by_name():
    from navcli.envs import LandmarkNavigationEnv

    env = LandmarkNavigationEnv("landmarks-hall", overrides=SHORT)
    assert env.run_spec.scenario.name == "landmarks-hall"
    assert env.reset(seed=1)[0] in range(980)
