"""``ppo``: the policy of a Stable-Baselines3 PPO agent trained through navcli's Gymnasium
environment (navcli's, beyond the paper; :mod:`.sampled` says why a stochastic policy).

The agent sees what the Learning Agent sees, the belief state (``Discrete(980)``, one-hot to its
network), and chooses among the same five actions; ``navcli train-rl`` (:mod:`navcli.rl.sb3`)
trains it and writes, beside Stable-Baselines3's own ``.zip``, a navcli model file (``.npz``,
algorithm ``sb3``) holding the network's action probabilities in every belief state. That table
is the policy whole (the network's input is one of 980 states), so running it needs neither
torch nor Stable-Baselines3: the ``ppo`` plugin draws its actions from the bundled table
(:data:`BUNDLED_PPO`), or with ``ppo.sample`` off takes the most probable action (what
``learned:FILE`` does with any such file).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ..params import ParamSet, param
from .actions import ACTIONS
from .sampled import SampledPolicy, entropy

BUNDLED_PPO = Path(__file__).resolve().parent / "models" / "landmarks-12-ppo.npz"
"""The PPO agent trained on landmarks-12 by ``navcli train-rl``, shipped with navcli (its
metadata, ``landmarks-12-ppo.json`` beside it, holds the command's settings)."""


@functools.lru_cache(maxsize=4)
def load_table(path: Path = BUNDLED_PPO) -> tuple[np.ndarray, dict[str, Any]]:
    """The action probabilities of an ``sb3`` model file and its metadata (raises
    :class:`~.model_file.ModelError` for a file that is not one)."""
    from . import model_file

    arrays, meta = model_file.load(path)
    if meta["algorithm"] != "sb3":
        raise model_file.ModelError(f"{path}: a {meta['algorithm']} model, not a Stable-Baselines3 agent's (sb3)")
    p = arrays["probabilities"].astype(np.float64)
    p /= p.sum(axis=1, keepdims=True)  # the float32 network's rows, summed to 1 in float64
    p.setflags(write=False)
    return p, meta


@dataclass(frozen=True)
class PPOParams(ParamSet):
    """``--param ppo.sample=0``: the most probable action instead of a draw."""

    sample: bool = param(True, "", "draw each action from the agent's probabilities (off: the most probable one)")


class PPOPolicy(SampledPolicy):
    """The ``ppo`` Navigation policy plugin: the bundled PPO agent (module docstring)."""

    name: ClassVar[str] = "ppo"
    Params: ClassVar[type[ParamSet] | None] = PPOParams

    @classmethod
    def probabilities(cls, own: Any = None) -> np.ndarray:
        p = load_table()[0]
        if isinstance(own, PPOParams) and not own.sample:
            greedy = np.zeros_like(p)
            greedy[np.arange(len(p)), p.argmax(axis=1)] = 1.0
            return greedy
        return p

    @classmethod
    def describe(cls, own: Any = None) -> str:
        meta = load_table()[1]
        p = cls.probabilities(own)
        return (
            f"Stable-Baselines3 {meta.get('agent', '?').upper()}, {meta.get('steps_trained', '?')} steps on "
            f"{meta.get('scenario', '?')}, seed {meta.get('seed', '?')}; {entropy(p):.2f} bits a choice, the mean over the belief states (uniform: "
            f"{math.log2(len(ACTIONS)):.2f})"
        )
