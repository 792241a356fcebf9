"""The Learning Agent's task as a Gymnasium environment: observation ``Discrete(980)`` (the belief
state of :mod:`navcli.learning.features`), action ``Discrete(5)`` (MB, MLL, MOT, MVL, MVT),
rewards of section 5.3, under the paper's task (:mod:`navcli.training.task`; ``learning.paper_task``
0 for navcli's first task); ``terminated`` when the trial ends in an end state (the target reached,
or the robot blocked), ``truncated`` when it is cut after ``max_actions`` actions or at the
scenario's time limit. ``reset(seed=...)`` draws the start from the environment's seeded generator
(:func:`navcli.training.task.random_starts`'s rules)."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym

from ..config import RunSpec
from ..learning.actions import ACTIONS
from ..learning.features import N_STATES
from ..training.task import NavigationTask, random_starts

DEFAULT_SCENARIO = Path(__file__).resolve().parent.parent / "data" / "scenarios" / "landmarks-12.yaml"
"""The paper's room, shipped inside the package (``scenarios/`` of the repository links there)."""


class LandmarkNavigationEnv(gym.Env):
    """See the module docstring. ``scenario``: a scenario file (default: the paper's room,
    landmarks-12) or a :class:`RunSpec`; ``overrides``: dotted parameters (``learning.max_actions``)."""

    metadata = {"render_modes": []}

    def __init__(self, scenario: str | Path | RunSpec | None = None, overrides: dict | None = None):
        if isinstance(scenario, RunSpec):
            spec = scenario
        else:
            from ..scenario import load_scenario

            spec = RunSpec.build(load_scenario(Path(scenario or DEFAULT_SCENARIO)), overrides=overrides)
        self.run_spec = spec
        self.task = NavigationTask(spec)
        self.observation_space = gym.spaces.Discrete(N_STATES)
        self.action_space = gym.spaces.Discrete(len(ACTIONS))

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        start = random_starts(self.run_spec.scenario, 1, int(self.np_random.integers(2 ** 31)),
                              self.run_spec.params.robot.radius)[0]
        state = self.task.reset(start)
        return int(state), {"start": (start.x, start.y, start.heading)}

    def step(self, action):
        if not self.action_space.contains(int(action)):
            raise ValueError(f"action {action!r} is not one of {len(ACTIONS)}")
        state, reward, reached, ended = self.task.step(int(action))
        # Gymnasium's contract: terminated when the episode reached an end state of the task (the
        # target, or blocked: the Rescuer gave up, nothing can follow), truncated when cut from
        # outside (max_actions, the scenario's time limit), where the value of the state remains
        terminated = reached or self.task.outcome == "blocked"
        return (int(state), float(reward), terminated, bool(ended and not terminated), {"outcome": self.task.outcome})
