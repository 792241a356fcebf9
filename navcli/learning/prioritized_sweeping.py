"""Prioritized Sweeping (Moore & Atkeson 1993, as Kaelbling, Littman & Moore's 1996 survey states
it): model-based reinforcement learning over a small discrete state space, the learner of the
Learning Agent (learning-agent paper, section 5).

- **Model from counts**: ``N(s, a, s')`` and the summed rewards give ``P(s'|s, a) = N(s, a, s') /
  N(s, a)`` and ``R(s, a)``, the mean reward (the paper's three-dimensional matrices). Reaching
  the goal is a transition to an absorbing state of value 0, one more column of ``N``.
- **After each real step** the counts are updated and the state just left goes to the top of the
  queue; then up to ``k`` states are popped, highest priority first, and backed up:
  ``V(s) = max_a [R(s, a) + gamma sum_s' P(s'|s, a) V(s')]`` over the actions tried in s; with
  ``delta = |V(s) - V_old(s)|`` every predecessor ``s_pred`` (a state with ``N(s_pred, a, s) > 0``
  under some a) has its priority raised to ``delta P(s | s_pred, a)`` (the largest over a) unless
  it is higher already, and only when that exceeds the ``threshold``.
- **Exploration** of rarely tried actions (Moore & Atkeson's optimism in the face of
  uncertainty): an action tried fewer than ``explore`` times in a state is valued at
  ``optimistic``, an upper bound of any return (0 when every reward is a cost), in the backups
  and when acting, so the learner is drawn, through the sweeps, toward the states and actions it
  knows least until it has tried them enough; then it acts greedily on its model. The greedy
  policy (what is evaluated and shipped) ranks untried actions last and never explores.

The queue is a priority per state and an arg-max per pop: with at most a thousand states an
arg-max over a numpy array is cheaper than keeping a heap consistent with raised priorities.
Parameters (``gamma``, ``k``, ``threshold``, ``explore``) are :class:`~navcli.params.LearningParams`'
``gamma``, ``backups``, ``threshold``, ``explore``.
"""

from __future__ import annotations

import numpy as np


class PrioritizedSweeping:
    """See the module docstring. States and actions are integers from 0."""

    algorithm = "prioritized-sweeping"

    def __init__(
        self,
        n_states: int,
        n_actions: int,
        *,
        gamma: float = 0.99,
        backups: int = 20,
        threshold: float = 1e-3,
        explore: int = 2,
        optimistic: float = 0.0,
        rng: np.random.Generator | None = None,
    ):
        self.n_states, self.n_actions = n_states, n_actions
        self.gamma, self.backups, self.threshold, self.explore = gamma, backups, threshold, explore
        self.optimistic = optimistic
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.counts = np.zeros((n_states, n_actions, n_states + 1), dtype=np.int32)  # last column: the goal
        self.tried = np.zeros((n_states, n_actions), dtype=np.int64)  # N(s, a)
        self.reward_sum = np.zeros((n_states, n_actions))
        self.values = np.zeros(n_states + 1)  # V; the goal's stays 0
        self.priority = np.zeros(n_states)
        self.predecessors: list[set[int]] = [set() for _ in range(n_states + 1)]
        self.steps = 0

    # -- the model
    def q_values(self, s: int, optimism: bool = True) -> np.ndarray:
        """``R(s, a) + gamma sum_s' P(s'|s, a) V(s')`` per action; with ``optimism`` an action
        tried fewer than ``explore`` times is worth ``optimistic``; without, an action never
        tried is worth -inf."""
        n = self.tried[s]
        q = (self.reward_sum[s] + self.gamma * (self.counts[s] @ self.values)) / np.maximum(n, 1)
        q[n == 0] = -np.inf
        if optimism:
            q[n < self.explore] = self.optimistic
        return q

    # -- learning
    def observe(self, s: int, a: int, r: float, s_next: int | None, terminal: bool = False) -> None:
        """One real step: ``s`` --a, reward r--> ``s_next``; ``terminal``: the goal was reached
        (``s_next`` is then ignored). A step cut short (a time limit) is an ordinary step."""
        col = self.n_states if terminal or s_next is None else int(s_next)
        self.counts[s, a, col] += 1
        self.predecessors[col].add(s)
        self.tried[s, a] += 1
        self.reward_sum[s, a] += r
        self.steps += 1
        self.priority[s] = np.inf  # the state just left goes to the top
        self.sweep()

    def sweep(self, backups: int | None = None) -> int:
        """Up to ``backups`` (default k) backups, highest priority first; returns how many were made."""
        done = 0
        for _ in range(self.backups if backups is None else backups):
            s = int(self.priority.argmax())
            if self.priority[s] <= self.threshold:
                break
            self.priority[s] = 0.0
            old = self.values[s]
            self.values[s] = self.q_values(s).max()
            done += 1
            delta = abs(self.values[s] - old)
            preds = self.predecessors[s]
            if delta <= self.threshold or not preds:
                continue
            pred = np.fromiter(preds, dtype=np.int64, count=len(preds))
            p = (self.counts[pred, :, s] / np.maximum(self.tried[pred], 1)).max(axis=1) * delta
            self.priority[pred] = np.maximum(self.priority[pred], np.where(p > self.threshold, p, 0.0))
        return done

    # -- acting
    def act(self, s: int) -> int:
        """The action to take in ``s`` while learning: the best with optimism (a random one of
        the best on a tie, so that equally unknown actions are tried alike)."""
        q = self.q_values(s)
        best = np.nonzero(q >= q.max() - 1e-12)[0]
        return int(best[0] if best.size == 1 else self.rng.choice(best))

    def greedy(self, s: int) -> int:
        """The action of highest value in ``s`` without optimism (lowest index on a tie; 0 in a
        state never visited)."""
        return int(np.argmax(self.q_values(s, optimism=False)))

    def greedy_policy(self) -> np.ndarray:
        """The greedy action of every state."""
        return np.array([self.greedy(s) for s in range(self.n_states)], dtype=np.int8)

    # -- saving
    def to_arrays(self) -> dict[str, np.ndarray]:
        """The model and values as arrays (counts sparse: the non-zero ``(s, a, s')`` and their counts)."""
        idx = np.nonzero(self.counts)
        return {
            "count_index": np.stack(idx).astype(np.int16),
            "count_value": self.counts[idx],
            "tried": self.tried,
            "reward_sum": self.reward_sum,
            "values": self.values,
            "priority": self.priority,
            "policy": self.greedy_policy(),
            "steps": np.array(self.steps),
        }

    def load_arrays(self, d) -> None:
        """The inverse of :meth:`to_arrays` (shapes must agree)."""
        self.counts[...] = 0
        i = d["count_index"].astype(np.int64)
        self.counts[i[0], i[1], i[2]] = d["count_value"]
        self.predecessors = [set() for _ in range(self.n_states + 1)]
        for a, b in zip(i[0].tolist(), i[2].tolist()):
            self.predecessors[b].add(a)
        self.tried[...] = d["tried"]
        self.reward_sum[...] = d["reward_sum"]
        self.values[...] = d["values"]
        self.priority[...] = d["priority"]
        self.steps = int(d["steps"])
