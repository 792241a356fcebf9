"""Tabular Q-learning (Watkins 1989): the model-free baseline of the Learning Agent's task, to
test the paper's claim (section 5) that model-free learning needs many more interactions.

``Q(s, a) += alpha (r + gamma max_a' Q(s', a') - Q(s, a))``, with ``max_a' Q`` taken as 0 at the
goal; epsilon-greedy while learning. Q starts at 0, above every return of a task whose rewards are
all negative, so untried actions look best: the same optimism that drives the exploration of
Prioritized Sweeping. Parameters: :class:`~navcli.params.LearningParams`' ``q_alpha``, ``gamma``,
``q_epsilon``.
"""

from __future__ import annotations

import numpy as np


class QLearning:
    algorithm = "q-learning"

    def __init__(
        self,
        n_states: int,
        n_actions: int,
        *,
        alpha: float = 0.1,
        gamma: float = 0.99,
        epsilon: float = 0.1,
        rng: np.random.Generator | None = None,
    ):
        self.n_states, self.n_actions = n_states, n_actions
        self.alpha, self.gamma, self.epsilon = alpha, gamma, epsilon
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.q = np.zeros((n_states, n_actions))
        self.tried = np.zeros((n_states, n_actions), dtype=np.int64)
        self.steps = 0

    @property
    def values(self) -> np.ndarray:
        return self.q.max(axis=1)

    def observe(self, s: int, a: int, r: float, s_next: int | None, terminal: bool = False) -> None:
        target = r + (0.0 if terminal or s_next is None else self.gamma * self.q[int(s_next)].max())
        self.q[s, a] += self.alpha * (target - self.q[s, a])
        self.tried[s, a] += 1
        self.steps += 1

    def act(self, s: int) -> int:
        if self.rng.random() < self.epsilon:
            return int(self.rng.integers(self.n_actions))
        return self.greedy(s)

    def greedy(self, s: int) -> int:
        return int(np.argmax(self.q[s]))

    def greedy_policy(self) -> np.ndarray:
        return np.argmax(self.q, axis=1).astype(np.int8)

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {
            "q": self.q,
            "tried": self.tried,
            "values": self.values,
            "policy": self.greedy_policy(),
            "steps": np.array(self.steps),
        }

    def load_arrays(self, d) -> None:
        self.q[...] = d["q"]
        self.tried[...] = d["tried"]
        self.steps = int(d["steps"])
