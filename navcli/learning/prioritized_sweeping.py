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

import math

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
        # N(s, a, s'), the last column the goal: floats holding whole numbers, so that the backups'
        # products with V run on BLAS without a cast (saved as integers: to_arrays)
        self.counts = np.zeros((n_states, n_actions, n_states + 1))
        self.tried = np.zeros((n_states, n_actions), dtype=np.int64)  # N(s, a)
        self._tried = [[0] * n_actions for _ in range(n_states)]  # N(s, a) again, as Python ints for the sweeps
        self._into: list[dict[int, list[int]]] = [{} for _ in range(n_states + 1)]  # s -> {pred: N(pred, a, s) per a}
        self.reward_sum = np.zeros((n_states, n_actions))
        self.values = np.zeros(n_states + 1)  # V; the goal's stays 0
        self.priority = np.zeros(n_states)
        self.steps = 0

    # -- the model
    def q_values(self, s: int, optimism: bool = True) -> np.ndarray:
        """``R(s, a) + gamma sum_s' P(s'|s, a) V(s')`` per action; with ``optimism`` an action
        tried fewer than ``explore`` times is worth ``optimistic``; without, an action never
        tried is worth -inf."""
        return np.array(self._q(s, optimism))

    def _q(self, s: int, optimism: bool = True) -> list[float]:
        """:meth:`q_values` as a list: with five actions numpy's per-call cost outweighs the
        arithmetic, so only the sum over successors runs in numpy (the same float64 operations
        in the same order, so the same bits as the array expression)."""
        expected = (self.counts[s] @ self.values).tolist()  # sum_s' N(s, a, s') V(s')
        reward = self.reward_sum[s].tolist()
        q = []
        for a, n in enumerate(self._tried[s]):
            if optimism and n < self.explore:
                q.append(self.optimistic)
            elif n == 0:
                q.append(-math.inf)
            else:
                q.append((reward[a] + self.gamma * expected[a]) / n)  # n = max(N(s, a), 1)
        return q

    # -- learning
    def observe(self, s: int, a: int, r: float, s_next: int | None, terminal: bool = False) -> None:
        """One real step: ``s`` --a, reward r--> ``s_next``; ``terminal``: the goal was reached
        (``s_next`` is then ignored). A step cut short (a time limit) is an ordinary step."""
        col = self.n_states if terminal or s_next is None else int(s_next)
        self.counts[s, a, col] += 1
        self._into[col].setdefault(s, [0] * self.n_actions)[a] += 1
        self.tried[s, a] += 1
        self._tried[s][a] += 1
        self.reward_sum[s, a] += r
        self.steps += 1
        self.priority[s] = np.inf  # the state just left goes to the top
        self.sweep()

    def sweep(self, backups: int | None = None) -> int:
        """Up to ``backups`` (default k) backups, highest priority first; returns how many were made.

        A predecessor's priority is raised in plain Python from the sparse counts ``_into`` (the
        same divisions, maximum and product as the array expression ``(N[pred, :, s] /
        max(N(pred, a), 1)).max() * delta``, each exact in IEEE arithmetic, so the same bits):
        a state has a handful of predecessors, where numpy's fancy indexing cost more than the
        arithmetic (our design, measured by the training benchmark)."""
        done = 0
        priority, values, threshold, into, tried = self.priority, self.values, self.threshold, self._into, self._tried
        for _ in range(self.backups if backups is None else backups):
            s = int(priority.argmax())
            if priority[s] <= threshold:
                break
            priority[s] = 0.0
            old = values[s]
            values[s] = max(self._q(s))
            done += 1
            delta = float(abs(values[s] - old))
            preds = into[s]
            if delta <= threshold or not preds:
                continue
            for pred, to_s in preds.items():
                p = max([c / (n if n > 1 else 1) for c, n in zip(to_s, tried[pred])]) * delta
                if p > threshold and p > priority[pred]:
                    priority[pred] = p
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
            "count_value": self.counts[idx].astype(np.int32),
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
        self._into = [{} for _ in range(self.n_states + 1)]
        for s, a, s2, c in zip(*i.tolist(), d["count_value"].tolist()):
            self._into[s2].setdefault(s, [0] * self.n_actions)[a] = c
        self.tried[...] = d["tried"]
        self._tried = self.tried.tolist()
        self.reward_sum[...] = d["reward_sum"]
        self.values[...] = d["values"]
        self.priority[...] = d["priority"]
        self.steps = int(d["steps"])
