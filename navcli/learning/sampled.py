"""Stochastic policies of the Learning Agent: an action drawn at each choice from a table of action
probabilities per belief state, and the Navigation policy plugins made of one (``softmax``:
:mod:`.softmax`; ``ppo``: :mod:`.ppo`).

With four features aliasing many situations into one belief state, the best policy that maps a
belief state to one action can lose to one that draws its action (Singh, Jaakkola & Jordan 1994,
"Learning without state-estimation in partially observable Markovian decision processes"): these
are navcli's learners beyond the paper, compared with its rows, never in place of them.

A :class:`SampledPolicy` plugin is a Navigation agent (``navcli run --navigation softmax``: the
Learning Agent with its draws from the run's generator for plugins) and, for ``navcli compare
policies``, a table of probabilities (:meth:`SampledPolicy.probabilities`) that the comparison's
trials draw from, one generator per trial seeded by the trial's start (:func:`trial_sampler`), so
the same trial draws the same actions.
"""

from __future__ import annotations

import math
from typing import Any, Callable, ClassVar

import numpy as np

from ..bidding import Bid
from ..navigation.situation import AgentSetup, Situation
from ..params import ParamSet
from .actions import ACTIONS
from .features import N_STATES
from .learning_agent import LearningAgent

SAMPLE_STREAM = 11
"""A comparison trial's generator of draws: ``[the start's seed, this]`` (the uniform random
policy's is another stream, so the two never share draws)."""


def check_probabilities(p: np.ndarray) -> np.ndarray:
    """``p`` as float64, checked to be a probability row per belief state (raises ValueError)."""
    p = np.asarray(p, dtype=np.float64)
    if p.shape != (N_STATES, len(ACTIONS)):
        raise ValueError(f"action probabilities of shape {p.shape}, not ({N_STATES}, {len(ACTIONS)})")
    if not np.isfinite(p).all() or (p < 0).any() or not np.allclose(p.sum(axis=1), 1.0, atol=1e-6):
        raise ValueError("action probabilities must be finite, at least 0, and sum to 1 in every state")
    return p


def sampler(probabilities: np.ndarray, rng: np.random.Generator) -> Callable[[int], int]:
    """The policy that draws the action of belief state ``s`` from ``probabilities[s]`` with ``rng``
    (one uniform number per choice, the inverse of the row's cumulative sum).

    >>> p = np.zeros((N_STATES, len(ACTIONS))); p[:, 3] = 1.0
    >>> sampler(p, np.random.default_rng(0))(7)
    3
    """
    cumulative = np.cumsum(check_probabilities(probabilities), axis=1)
    cumulative[:, -1] = 1.0  # rounding never leaves a draw past the last action
    last = len(ACTIONS) - 1
    return lambda s: min(int(np.searchsorted(cumulative[s], rng.random(), side="right")), last)


def trial_sampler(probabilities: np.ndarray, seed: int) -> Callable[[int], int]:
    """The policy of one comparison trial whose start has ``seed`` (module docstring)."""
    return sampler(probabilities, np.random.default_rng([seed, SAMPLE_STREAM]))


def entropy(probabilities: np.ndarray) -> float:
    """The mean entropy (bits) of the rows: 0 for a table of one action per state, log2(5) = 2.32
    for the uniform random policy.

    >>> round(entropy(np.full((N_STATES, len(ACTIONS)), 1 / len(ACTIONS))), 2)
    2.32
    """
    p = check_probabilities(probabilities)
    with np.errstate(divide="ignore", invalid="ignore"):
        bits = np.where(p > 0, -p * np.log2(np.where(p > 0, p, 1.0)), 0.0)
    return float(bits.sum(axis=1).mean())


class SampledPolicy:
    """A Navigation policy plugin that draws the Learning Agent's actions from a table of
    probabilities (module docstring). A subclass gives ``Params`` (its parameter set, or None) and
    :meth:`probabilities`, and may say what it is (:meth:`describe`)."""

    Params: ClassVar[type[ParamSet] | None] = None
    version: ClassVar[str] = ""  # navcli's version (the registry reads its package's)

    def __init__(self, setup: AgentSetup):
        p = setup.params
        self.agent = LearningAgent(
            sampler(type(self).probabilities(setup.own_params), setup.rng),
            p.learning,
            max_speed=p.robot.max_speed,
            pan_limit=setup.pan_limit,
            target_key=setup.target_key,
        )

    name: ClassVar[str] = "sampled"  # a subclass's own: the name its bids and the log's /navigation go by

    def bid(self, s: Situation) -> list[Bid]:
        """The Learning Agent's bids, under this plugin's name."""
        return [Bid(self.name, b.resource, b.action, b.value) for b in self.agent.bid(s)]

    def info(self) -> dict[str, Any]:
        """The actions taken, of each kind, and their reward (as the Learning Agent's)."""
        return self.agent.info()

    @classmethod
    def probabilities(cls, own: Any = None) -> np.ndarray:
        """The action probabilities per belief state under the parameters ``own`` (the class's
        ``Params``; None: its defaults)."""
        raise NotImplementedError

    @classmethod
    def describe(cls, own: Any = None) -> str:
        """One line saying what the policy is, for a comparison's table."""
        return f"{cls.__name__}: {entropy(cls.probabilities(own)):.2f} bits of {math.log2(len(ACTIONS)):.2f} a choice"
