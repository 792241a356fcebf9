"""Figures 9 and 10 for a scenario: the grids behind them and the PNG files."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.cli import app
from navcli.config import RunSpec
from navcli.experiments.figures import field_grid

PNG = b"\x89PNG\r\n\x1a\n"


def test_field_points_to_the_target_in_open_space_and_away_from_obstacles(make_scenario):
    sc = make_scenario(obstacles=[{"circle": {"center": [3.0, 2.0], "radius": 0.2}}])
    X, Y, U, V, B = field_grid(RunSpec.build(sc), 0.25)
    near = lambda x, y: np.unravel_index(np.hypot(X - x, Y - y).argmin(), X.shape)  # noqa: E731
    i = near(1.625, 2.875)  # far from the obstacle and the walls: straight at the target (5, 2)
    want = math.atan2(2 - Y[i], 5 - X[i])
    # walls and obstacle are all > 1.1 m away: each pulls at most 18 / 1.1**2 = 15 against A_t = 50
    assert abs(math.atan2(V[i], U[i]) - want) < math.atan(2 * 15 / 50)
    j = near(2.625, 2.125)  # inside the grown circle (IN_DISTRESS): away from the obstacle centre
    assert U[j] * (X[j] - 3.0) + V[j] * (Y[j] - 2.0) > 0
    assert B[j] == np.float64(0.9)
    assert np.nanmax(B) <= 0.9 and np.nanmin(B) >= 0.0
    k = near(3.125, 2.125)  # inside the obstacle's body: left blank
    assert np.isnan(B[k])


def test_plot_commands_write_png_files(tmp_path):
    runner = CliRunner()
    for kind in ("field", "bids"):
        out = tmp_path / f"{kind}.png"
        r = runner.invoke(app, ["plot", kind, str(SCENARIOS / "paper-fig9.yaml"), "--out", str(out), "--step", "0.3"])
        assert r.exit_code == 0, r.output
        assert out.read_bytes()[:8] == PNG and out.stat().st_size > 10_000


def test_plot_map_draws_the_final_map_of_a_log(tmp_path):
    from navcli.config import RunSpec
    from navcli.runner import run_mission
    from navcli.scenario import load_scenario

    sc = load_scenario(SCENARIOS / "landmarks-12.yaml")
    log = run_mission(RunSpec.build(sc, time_limit=8.0), out=tmp_path / "m.mcap").log  # the sweep maps landmarks
    r = CliRunner().invoke(app, ["plot", "map", str(log), "--out", str(tmp_path / "map.png")])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "map.png").read_bytes().startswith(PNG)

    def stop(mission, tick):  # a run stopped before its first map (a finished run draws its final map)
        if tick.index == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_mission(RunSpec.build(sc), out=tmp_path / "s.mcap", on_tick=stop)
    r = CliRunner().invoke(app, ["plot", "map", str(tmp_path / "s.mcap")])
    assert r.exit_code == 2 and "no /map/scene" in r.output


def test_a_field_too_costly_to_draw_is_refused_before_any_work():
    """Points x bodies bounded (figures.MAX_GRID_WORK): 400 circles in a 40 m room at 0.2 m is
    40,000 points x 401 > 2,000,000, refused at once with the step that fits."""
    from navcli import RunSpec
    from navcli.experiments.figures import MAX_GRID_WORK, GridError, field_grid
    from navcli.scenario import parse_scenario

    circles = "".join(
        f"  - circle: {{center: [{2 + (i % 20) * 1.8:.1f}, {4 + (i // 20) * 1.6:.1f}], radius: 0.1}}\n"
        for i in range(400)
    )
    sc = parse_scenario(
        "version: 1\nname: many\narena: {width: 40, height: 40}\nrobot: {start: [1, 1]}\n"
        "target: {at: [39, 39]}\nobstacles:\n" + circles,
        "many.yaml",
    )
    with pytest.raises(GridError, match="use a step of at least") as e:
        field_grid(RunSpec.build(sc), 0.2)
    finest = float(str(e.value).rsplit("at least ", 1)[1].split(" m")[0])
    assert (40 / finest) ** 2 <= MAX_GRID_WORK // 401 < (40 / 0.2) ** 2
