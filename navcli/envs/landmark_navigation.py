"""The Learning Agent's task as a Gymnasium environment: observation ``Discrete(980)`` (the belief
state of :mod:`navcli.learning.features`), action ``Discrete(5)`` (MB, MLL, MOT, MVL, MVT),
rewards of section 5.3, under the paper's task (:mod:`navcli.training.task`; ``learning.paper_task``
0 for a simpler task); ``terminated`` when the trial ends in an end state (the target reached,
or the robot blocked), ``truncated`` when it is cut after ``max_actions`` actions or at the
scenario's time limit. ``reset(seed=...)`` draws the start from the environment's seeded generator
(:func:`navcli.training.task.random_starts`'s rules).

``render_mode="rgb_array"``: :meth:`~LandmarkNavigationEnv.render` returns the trial as
``navcli render`` draws a run (:class:`navcli.analysis.render.RunFigure`: the true room, the path
so far and the robot, what the visual memory holds, the pilot's forces, the bids), an array of
height x width x 3 bytes, the same size every time (400 x 512 pixels at the default ``dpi`` 80);
``metadata["render_fps"]`` plays one action (``learning.action_s``, 1 s) per frame at 4x real time,
as :class:`gymnasium.wrappers.RecordVideo` writes it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from ..config import RunSpec
from ..learning.actions import ACTIONS
from ..learning.features import N_STATES
from ..scenario import bundled
from ..training.task import NavigationTask, random_starts, task_spec

DEFAULT_SCENARIO = bundled.path("landmarks-12")
"""The paper's room, shipped inside the package (``scenarios/`` of the repository links there)."""
RENDER_FPS = 4
"""Frames (actions) per second of a video of the environment: 4x real time at one action a second."""


class LandmarkNavigationEnv(gym.Env):
    """The learning-agent paper's task (see the module docstring).

    Args:
        scenario: a scenario file, a bundled scenario's name (default: the paper's room,
            landmarks-12) or a :class:`RunSpec`.
        overrides: parameters by their dotted names (``{"learning.max_actions": 100}``).
        render_mode: None or ``"rgb_array"``.
        dpi: the frames' pixels per inch (a frame is 5 x 6.4 inches).

    Raises:
        ValueError: a render mode other than those.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": RENDER_FPS}

    def __init__(
        self,
        scenario: str | Path | RunSpec | None = None,
        overrides: dict | None = None,
        render_mode: str | None = None,
        dpi: int = 80,
    ):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode {render_mode!r} is not one of {self.metadata['render_modes']} (or None)")
        if isinstance(scenario, RunSpec):
            spec = scenario
        else:
            from ..scenario import load_scenario

            spec = task_spec(load_scenario(scenario or DEFAULT_SCENARIO), overrides)
        self.run_spec = spec
        self.task = NavigationTask(spec)
        self.observation_space = gym.spaces.Discrete(N_STATES)
        self.action_space = gym.spaces.Discrete(len(ACTIONS))
        self.render_mode = render_mode
        self.dpi = dpi
        self._trace: _Trace | None = None  # the trial so far, for render
        self._figure: Any = None  # the RunFigure of the trial, made at its first render
        if render_mode is not None:
            self.task.observers.append(lambda mission, tick: self._trace.tick(tick) if self._trace else None)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start a trial from a start drawn by the environment's generator.

        Args:
            seed: seeds the environment's generator (None: keep drawing from it).
            options: unused (Gymnasium's signature).

        Returns:
            The first observation (the belief state, an ``int`` below 980) and an info dict whose
            ``start`` is the start drawn, ``(x, y, heading)`` (m, m, rad).
        """
        super().reset(seed=seed)
        start = random_starts(self.run_spec, 1, int(self.np_random.integers(2**31)))[0]
        if self.render_mode is not None:
            self._close_figure()
            self._trace = _Trace(start.x, start.y, start.heading)
        state = self.task.reset(start)
        return int(state), {"start": (start.x, start.y, start.heading)}

    def step(self, action):
        """Carry out one action of the Learning Agent (its motion and its look, for one action's time).

        Args:
            action: its index in ``MB, MLL, MOT, MVL, MVT`` (:data:`navcli.learning.actions.ACTIONS`).

        Returns:
            The observation (the belief state), the reward (section 5.3's), ``terminated`` (the
            trial reached an end state: the target, or blocked), ``truncated`` (cut after
            ``max_actions`` actions or at the time limit) and an info dict whose ``outcome`` is
            the task's outcome (None while the trial goes on).

        Raises:
            ValueError: an action outside the action space.
        """
        if not self.action_space.contains(int(action)):
            raise ValueError(f"action {action!r} is not one of {len(ACTIONS)}")
        state, reward, reached, ended = self.task.step(int(action))
        # Gymnasium's contract: terminated when the episode reached an end state of the task (the
        # target, or blocked: the Rescuer gave up, nothing can follow), truncated when cut from
        # outside (max_actions, the scenario's time limit), where the value of the state remains
        terminated = reached or self.task.outcome == "blocked"
        return (int(state), float(reward), terminated, bool(ended and not terminated), {"outcome": self.task.outcome})

    def render(self) -> np.ndarray | None:
        """The trial now, as ``navcli render`` draws it (module docstring).

        Returns:
            The frame, height x width x 3 bytes; None without a render mode.
        """
        if self.render_mode is None:
            gym.logger.warn("render() without a render_mode: make the environment with render_mode='rgb_array'")
            return None
        sc = self.run_spec.scenario
        trace = self._trace or _Trace(*sc.robot.start, sc.robot.heading)  # before the first reset: the start
        if self._figure is None:
            import yaml

            from ..analysis.render import RunFigure

            drawn = yaml.safe_load(sc.text) | {"robot": {"start": [trace.x[0], trace.y[0]]}}  # the trial's start
            self._figure = RunFigure(
                drawn, f"{sc.name}  {self.run_spec.pilot}", self.run_spec.params.robot.radius, self.dpi
            )
        mission = self.task.mission if self._trace is not None else None
        return trace.draw(self._figure, mission)

    def close(self) -> None:
        """Close the trial's mission and its figure."""
        self._close_figure()
        self.task.close()
        super().close()

    def _close_figure(self) -> None:
        if self._figure is not None:
            self._figure.close()
            self._figure = None


class _Trace:
    """What a drawing of the trial needs of its past, told of every tick: the true poses, the bids
    per resource and the pilot's last explanation."""

    def __init__(self, x: float, y: float, theta: float):
        from ..analysis.render import BID_SERIES

        self.x, self.y, self.theta, self.t = [x], [y], [theta], [0.0]
        self.bids: dict[str, list[float]] = {s: [] for s in BID_SERIES}
        self.pilot: dict = {}

    def tick(self, tick) -> None:
        p = tick.pose
        self.x.append(p.x)
        self.y.append(p.y)
        self.theta.append(p.theta)
        self.t.append(tick.time_ns / 1e9)
        offered = {f"{b.resource}.{b.bidder}": b.value for b in tick.bids}
        for series, values in self.bids.items():
            values.append(offered.get(series, 0.0))  # 0: no bid, as /bids writes it
        self.pilot = tick.pilot.info

    def draw(self, figure, mission) -> np.ndarray:
        """``figure`` drawn at the last tick; the memory is ``mission``'s now, placed with the true pose."""
        from ..analysis.render import force_vectors

        t = self.t[-1]
        figure.bids(self.t[1:], self.bids, (0.0, max(t, 30.0)))
        spots: list[tuple] = []
        if mission is not None:
            pose = mission.world.pose
            for m in mission.perception.snapshot() or ():
                spots += [(m.kind, *pose.to_world((x, y)), r70, r0) for x, y, r70, r0 in m.spots]

        def get(name: str) -> float | None:  # a /pilot field by its dotted name, from the pilot's explanation
            head, _, field = name.partition(".")
            value = self.pilot.get(head)
            if not field:
                return value
            return value.get(field) if isinstance(value, dict) else None

        figure.draw(t, self.x, self.y, self.theta[-1], spots, force_vectors(get))
        return figure.rgb()
