"""``softmax``: a stochastic policy from the same learned model as ``learned`` (navcli's, beyond the
paper; :mod:`.sampled` says why).

In belief state ``s`` the action ``a`` is drawn with probability proportional to
``exp(Q(s, a) / T)``, ``Q`` the model's action values (Prioritized Sweeping's ``R(s, a) + gamma
sum_s' P(s'|s, a) V(s')``, its discount the model's own; a Q-learning model's table), ``T`` the
temperature (reward units). Actions never tried in a state are never drawn there; a state the
model never visited draws uniformly (nothing is known of it). ``T`` = 0 is the greedy policy
(``learned``: the highest value, the lowest action on a tie); a large ``T`` the uniform random
policy over the tried actions.

The temperature is chosen on training rooms alone, never on a held-out one, by ``navcli
tune-softmax`` (:mod:`navcli.rl.temperature`): each temperature of a grid runs the same seeded
starts of the design rooms, and the best mean reward per trial wins. The choice it wrote is
bundled (:data:`CHOICE`, with the grid's numbers and the sha256 of the model it was made for: a
model trained again needs the command run again) and is the parameter ``softmax.temperature``'s
default; ``--param softmax.temperature=T`` runs another (``navcli run --navigation softmax``).
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ..params import ParamSet, param
from .actions import ACTIONS
from .features import N_STATES
from .sampled import SampledPolicy, entropy

CHOICE = Path(__file__).resolve().parent / "models" / "softmax.json"
"""The temperature ``navcli tune-softmax`` chose for the bundled model, with its grid's numbers."""


def chosen_temperature(path: Path = CHOICE) -> float:
    """The temperature written in ``path`` (``{"temperature": T, ...}``)."""
    return float(json.loads(path.read_text())["temperature"])


def action_values(arrays: dict[str, np.ndarray], meta: dict[str, Any]) -> np.ndarray:
    """``Q(s, a)`` of a model file's arrays (:func:`~.model_file.load`); -inf where ``a`` was never
    tried in ``s``."""
    tried = arrays["tried"]
    if meta["algorithm"] == "q-learning":
        return np.where(tried > 0, arrays["q"], -np.inf)
    if meta["algorithm"] != "prioritized-sweeping":
        raise ValueError(f"a {meta['algorithm']} model holds no action values")
    from .prioritized_sweeping import PrioritizedSweeping

    gamma = float(meta.get("params", {}).get("learning", {}).get("gamma", 1.0))
    learner = PrioritizedSweeping(N_STATES, len(ACTIONS), gamma=gamma)
    learner.load_arrays(arrays)
    return np.array([learner.q_values(s, optimism=False) for s in range(N_STATES)])


def softmax(q: np.ndarray, temperature: float) -> np.ndarray:
    """The probabilities ``exp(Q / T)`` normalised per row over the finite values; a row of none
    uniform; ``T`` = 0 all on the first highest value.

    >>> softmax(np.array([[0.0, -1.0, -np.inf]]), 1.0).round(3).tolist()
    [[0.731, 0.269, 0.0]]
    >>> softmax(np.array([[-2.0, -1.0, -1.0]]), 0.0).tolist()
    [[0.0, 1.0, 0.0]]
    """
    q = np.asarray(q, dtype=np.float64)
    known = np.isfinite(q)
    out = np.zeros_like(q)
    for s in range(len(q)):
        row, ok = q[s], known[s]
        if not ok.any():
            out[s] = 1.0 / q.shape[1]
        elif temperature == 0.0:
            out[s, int(np.argmax(np.where(ok, row, -np.inf)))] = 1.0
        else:
            z = np.where(ok, (row - row[ok].max()) / temperature, -np.inf)
            e = np.exp(z)
            out[s] = e / e.sum()
    return out


@functools.lru_cache(maxsize=8)
def bundled_values() -> tuple[np.ndarray, str]:
    from . import model_file

    arrays, meta = model_file.load(model_file.BUNDLED)
    return action_values(
        arrays, meta
    ), f"{meta['algorithm']}, {meta.get('trials', '?')} trials on {meta.get('scenario', '?')}"


@dataclass(frozen=True)
class SoftmaxParams(ParamSet):
    """``--param softmax.temperature=T`` (the module docstring)."""

    temperature: float = param(
        chosen_temperature(),
        "",
        "T of the softmax over the learned model's action values (reward units; 0: the greedy policy); "
        "the default is the one navcli tune-softmax chose on the training rooms",
        at_most=1e6,
    )


class SoftmaxPolicy(SampledPolicy):
    """The ``softmax`` Navigation policy plugin: the bundled model's action values through a
    softmax of temperature ``softmax.temperature`` (module docstring)."""

    name: ClassVar[str] = "softmax"
    Params: ClassVar[type[ParamSet] | None] = SoftmaxParams

    @classmethod
    def probabilities(cls, own: Any = None) -> np.ndarray:
        t = own.temperature if isinstance(own, SoftmaxParams) else SoftmaxParams().temperature
        return _probabilities(float(t))

    @classmethod
    def describe(cls, own: Any = None) -> str:
        t = own.temperature if isinstance(own, SoftmaxParams) else SoftmaxParams().temperature
        p = cls.probabilities(own)
        return (
            f"a softmax of temperature {t:g} over the bundled model's action values ({bundled_values()[1]}); "
            f"{entropy(p):.2f} bits a choice, the mean over the belief states (uniform: {math.log2(len(ACTIONS)):.2f})"
        )


@functools.lru_cache(maxsize=16)
def _probabilities(temperature: float) -> np.ndarray:
    p = softmax(bundled_values()[0], temperature)
    p.setflags(write=False)
    return p
