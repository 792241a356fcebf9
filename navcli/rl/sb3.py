"""``navcli train-rl``: a Stable-Baselines3 agent (PPO or DQN) trained through navcli's Gymnasium
environment (:mod:`navcli.envs.landmark_navigation`) on the Learning Agent's task, the same
belief state (``Discrete(980)``, which Stable-Baselines3 one-hot encodes for its network) and the
same five actions and rewards.

Needs the optional extra ``navcli[rl]`` (Stable-Baselines3 and torch; :func:`require` says what
to install when they are missing). The agent is Stable-Baselines3's as its documentation gives
it: ``MlpPolicy`` with the library's default hyperparameters (our design: no tuning, so its row
says what the ecosystem's agent does out of the box), one environment, torch on the CPU with one
thread. Everything is seeded from ``seed`` (the library's ``set_random_seed``: Python's, numpy's
and torch's generators, the environment's starts through its ``reset(seed=...)``), so the same
command gives the same agent on the same machine and library versions.

What is written: Stable-Baselines3's own archive (``FILE.zip``, to load with ``PPO.load``) and a
navcli model file (``FILE.npz`` with ``FILE.json``, algorithm ``sb3``): the agent's action
probabilities in each of the 980 belief states (PPO: its policy's; DQN: all on its greedy action)
and the most probable action per state. The table is the agent's policy whole, so the ``ppo``
plugin (:mod:`navcli.learning.ppo`) and ``learned:FILE`` run it without torch.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..checks.extras import require
from ..config import RunSpec
from ..learning.actions import ACTIONS
from ..learning.features import N_STATES

AGENTS = ("ppo", "dqn")
"""The Stable-Baselines3 agents ``navcli train-rl`` trains."""
WHAT = "navcli train-rl"


def require_sb3() -> tuple[Any, Any]:
    """torch and stable_baselines3, or :class:`~navcli.checks.extras.MissingExtra` (exit 2) saying
    to ``pip install 'navcli[rl]'``."""
    torch = require("torch", WHAT)
    sb3 = require("stable_baselines3", WHAT)
    return torch, sb3


def out_paths(out: Path) -> tuple[Path, Path, Path]:
    """The files a training writes: the navcli model (.npz), its metadata (.json), the agent (.zip)."""
    out = Path(out)
    return out, out.with_suffix(".json"), out.with_suffix(".zip")


@dataclass
class RLTraining:
    """What a training did: its agent, steps, episodes and their outcomes, and its time (s)."""

    agent: str
    seed: int
    steps: int
    episodes: int = 0
    outcomes: dict[str, int] = field(default_factory=dict)
    train_s: float = 0.0
    probabilities: np.ndarray | None = None


class _Table:
    """The agent's policy as a navcli model's arrays (:func:`navcli.learning.model_file.save`)."""

    algorithm = "sb3"

    def __init__(self, probabilities: np.ndarray, steps: int):
        self.probabilities, self.steps = probabilities, steps

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {
            "probabilities": self.probabilities.astype(np.float32),
            "policy": self.probabilities.argmax(axis=1).astype(np.int8),
            "steps": np.array(self.steps),
        }


def policy_table(model: Any, agent: str) -> np.ndarray:
    """The agent's action probabilities in every belief state (module docstring)."""
    import torch

    obs, _ = model.policy.obs_to_tensor(np.arange(N_STATES))
    with torch.no_grad():
        if agent == "ppo":
            p = model.policy.get_distribution(obs).distribution.probs.cpu().numpy().astype(np.float64)
            return p / p.sum(axis=1, keepdims=True)
        q = model.q_net(obs).cpu().numpy()
    out = np.zeros((N_STATES, len(ACTIONS)))
    out[np.arange(N_STATES), q.argmax(axis=1)] = 1.0
    return out


def train(spec: RunSpec, *, agent: str = "ppo", steps: int = 100_000, seed: int = 1, out: Path) -> RLTraining:
    """Train ``agent`` for ``steps`` environment steps (actions) in ``spec``'s room under the
    learning task (``spec`` from :func:`navcli.training.task.task_spec`) and write ``out`` (.npz,
    .json, .zip; module docstring). The caller has checked the outputs."""
    if agent not in AGENTS:
        raise ValueError(f"unknown agent {agent!r} (expected one of: {', '.join(AGENTS)})")
    torch, sb3 = require_sb3()
    from ..envs.landmark_navigation import LandmarkNavigationEnv
    from ..learning import model_file

    torch.set_num_threads(1)
    result = RLTraining(agent, seed, steps)
    env = LandmarkNavigationEnv(spec)
    callback = _outcomes(sb3, result)
    cls = sb3.PPO if agent == "ppo" else sb3.DQN
    model = cls("MlpPolicy", env, seed=seed, device="cpu", verbose=0)
    t0 = time.perf_counter()
    model.learn(total_timesteps=steps, callback=callback)
    result.train_s = time.perf_counter() - t0
    env.close()
    result.probabilities = policy_table(model, agent)
    npz, _, archive = out_paths(out)
    meta = {
        "agent": agent,
        "library": f"stable-baselines3 {sb3.__version__}, torch {torch.__version__}",
        "scenario": spec.scenario.name,
        "scenario_sha256": spec.scenario.sha256,
        "seed": seed,
        "trials": result.episodes,
        "steps_trained": steps,
        "outcomes": result.outcomes,
        "hyperparameters": "Stable-Baselines3's defaults, MlpPolicy",
        "params": spec.params.to_json(),
    }
    model_file.save(npz, _Table(result.probabilities, steps), meta)
    model.save(archive)
    return result


def _outcomes(sb3: Any, result: RLTraining) -> Any:
    """A callback counting the training's episodes and how each ended (the environment's ``outcome``)."""

    from stable_baselines3.common.callbacks import BaseCallback

    class Outcomes(BaseCallback):
        def _on_step(self) -> bool:
            for done, info in zip(self.locals["dones"], self.locals["infos"]):
                if done:
                    result.episodes += 1
                    o = str(info.get("outcome") or "timeout")
                    result.outcomes[o] = result.outcomes.get(o, 0) + 1
            return True

    return Outcomes()
