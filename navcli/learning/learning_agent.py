"""The Learning Agent (learning-agent paper, section 4): one Navigation agent in place of the
Target Tracker, the Risk Manager and the Distance Estimator, choosing one of five actions
(:mod:`.actions`) from the belief state (:mod:`.features`) by a policy: a learned table, the
hand-coded policy of section 6, or, while training, whatever the trainer sets.

An action lasts ``action_s`` simulated seconds (:class:`~navcli.params.LearningParams`; our
design, its reason there): every tick the agent re-aims the action at the current target (the
Rescuer may have set a diverting one) and bids for it; at the end of an action it reads the state
and chooses again. It counts the actions it took and the reward they cost.

**A lost target: pacing** (``learning.pace`` on, the default). Section 5.3: "If the heading is
completely unknown, the center of this interval will be pi. This causes the robot 'pace' back and
forth, turning 180 degrees (pi radians) each time an action is executed." So an action that starts
with the target's heading unknown aims at a heading fixed in the odometry frame for the whole
action: pi from the robot's heading when it starts, and, after an action that paced, pi from that
action's aim (so a run of lost actions paces along one line, back and forth, whatever the drive
made of the last turn). The turn of 180 degrees is driven as a reversal: the robot backs along the
line, its body keeping its heading (the pilot paper's own way with a turn above 160 degrees,
section 3.5, here without its limit on the distance driven backwards: pacing comes back over the
same line), and the next lost action drives forward again. MOT aims 90 degrees off the paced
heading. A target found during the action is aimed at from the next tick. Off: the action re-aims
at pi in the robot's own frame every tick, which a Pilot executes as a reversal while its backward
budget lasts and then as a circle of the turning radius, the camera sweeping with it.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from ..bidding import Bid
from ..navigation.situation import Situation
from ..params import CONTROL_DT, LEARNING, ROBOT, LearningParams
from .actions import ACTIONS, action_bids, orthogonal_side, reward_of
from .features import features, state_index
from .hand_coded import hand_coded_action

Policy = Callable[[int], int]


def table_policy(table: np.ndarray) -> Policy:
    """A policy from a table of actions indexed by state (a learned model's greedy policy)."""
    t = np.asarray(table, dtype=np.int64)
    return lambda state: int(t[state])


class LearningAgent:
    """See the module docstring. ``policy`` maps a state to an action; ``None`` leaves the choice
    to whoever sets :attr:`next_action` (the trainer)."""

    name = "learning-agent"

    def __init__(
        self,
        policy: Policy | None = None,
        params: LearningParams = LEARNING,
        max_speed: float = ROBOT.max_speed,
        pan_limit: float = math.radians(100.0),
        target_key: str | None = None,
    ):
        self.policy = policy
        self.params = params
        self.max_speed = max_speed
        self.pan_limit = pan_limit
        self.target_key = target_key
        self.ticks_per_action = max(1, round(params.action_s / CONTROL_DT))
        self.action: int | None = None
        self.next_action: int | None = None
        self.state: int | None = None  # the belief state read when choosing and on an action's last tick
        self.counts = [0] * len(ACTIONS)  # the actions taken, of each kind
        self._left = 0  # ticks left of the current action
        self._side = 1.0
        self._aim: float | None = None  # the current action's paced heading (odometry frame), None when not pacing

    def take(self, action: int) -> None:
        """The trainer's choice (an agent without a policy): ``action`` begins at the next tick,
        ending the current one if any."""
        self.next_action, self._left = action, 0

    @property
    def between_actions(self) -> bool:
        """The last action has run its length (the trainer may read the state and choose)."""
        return self._left == 0

    @property
    def actions_taken(self) -> int:
        return sum(self.counts)

    @property
    def reward(self) -> float:
        return reward_of(self.counts)

    def observe(self, s: Situation) -> int:
        """Read (and remember) the belief state of ``s``."""
        self.state = state_index(features(s, self.target_key), self.params)
        return self.state

    def bid(self, s: Situation) -> list[Bid]:
        if self._left <= 1:  # the state is read only where it is used: choosing an action, and on an
            self.observe(s)  # action's last tick, where the trainer reads the state it led to
        if self._left <= 0:
            state = self.state
            assert state is not None  # just observed
            a = self.policy(state) if self.policy is not None else self.next_action
            if a is None:
                return []
            self.next_action = None  # the trainer's choice is taken once
            self.action, self._left = a, self.ticks_per_action
            self._side = orthogonal_side(s)
            self._aim = self._paced_aim(s)
            self.counts[a] += 1
        self._left -= 1
        assert self.action is not None  # chosen above, or running on
        aim = self._aim if s.bearing is None else None  # pacing: the aim in the robot's frame now
        return action_bids(
            self.action,
            s,
            bidder=self.name,
            value=self.params.bid,
            speed=self.max_speed,
            pan_limit=self.pan_limit,
            target_key=self.target_key,
            side=self._side,
            bearing=None if aim is None else math.remainder(aim - s.beliefs.odometry.theta, 2 * math.pi),
            reverse=aim is not None,
        )

    def _paced_aim(self, s: Situation) -> float | None:
        """The heading (odometry frame) an action starting now paces at (module docstring): pi
        from the last paced aim, or from the robot's heading; None with the target's heading known
        or ``pace`` off."""
        if not self.params.pace or s.bearing is not None:
            return None
        last = self._aim if self._aim is not None else s.beliefs.odometry.theta
        return math.remainder(last + math.pi, 2 * math.pi)

    def info(self) -> dict[str, Any]:
        """For the mission summary: the actions taken, of each kind, and their reward."""
        return {"actions": self.actions_taken, "reward": self.reward, "action_counts": dict(zip(ACTIONS, self.counts))}


def hand_coded_agent(**kw: Any) -> LearningAgent:
    """The hand-coded policy of section 6 as an agent."""
    return LearningAgent(hand_coded_action, **kw)
