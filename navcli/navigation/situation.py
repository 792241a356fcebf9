"""What the Navigation agents know at one tick: the robot's beliefs and the Map Manager's answers."""

from __future__ import annotations

import math
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping, NamedTuple, Protocol

from ..beliefs import Beliefs
from ..bidding import Bid
from ..fuzzy import FuzzyPoint
from ..geometry import Point
from ..params import ParamSet, Params

if TYPE_CHECKING:
    import numpy as np


class Situation(NamedTuple):
    """The Navigation agents' input (they see nothing else).

    Built every tick, twice while diverting (a NamedTuple: docs/design.md, "Values made every tick").

    Attributes:
        beliefs: what the robot believes this tick (:class:`~navcli.beliefs.Beliefs`).
        target: the current target's best estimate (an egocentric fuzzy point, m: the original
            target, or the middle of a diverting line), or None when it is not known.
        target_line: the line to cross (a diverting target, or a line target: two egocentric
            points, m), or None.
        target_source: where ``target`` came from (``memory``, ``map:ABC/D``).
        I_a: the target's heading imprecision, in [0, 1] (Target Tracker, eq. 6 of the thesis).
        landmarks: the known landmarks by id (egocentric fuzzy points, m).
        ahead: the ids of the landmarks ahead.
        quality_ahead: the Map Manager's ``q_S`` of the landmarks ahead, in [0, 1].
        quality_around: the Map Manager's ``q_S`` of all the known landmarks, in [0, 1].
    """

    beliefs: Beliefs
    target: FuzzyPoint | None
    target_line: tuple[Point, Point] | None
    target_source: str
    I_a: float
    landmarks: Mapping[str, FuzzyPoint] = MappingProxyType({})  # read-only: one default serves all
    ahead: tuple[str, ...] = ()
    quality_ahead: float = 0.0
    quality_around: float = 0.0

    @property
    def time(self) -> float:
        return self.beliefs.time

    @property
    def aim(self) -> Point | None:
        """Where the target is (the crisp centre), egocentric."""
        return None if self.target is None else (self.target.x, self.target.y)

    @property
    def bearing(self) -> float | None:
        a = self.aim
        return None if a is None else math.atan2(a[1], a[0])


class Agent(Protocol):
    """What a Navigation agent is (the Target Tracker, the Risk Manager, the Distance Estimator, or
    the Learning Agent that replaces them): a name for the logs, and the situation in, bids out.
    Agents keep their own state between ticks but learn of the world only through the
    :class:`Situation` (and its :class:`~navcli.beliefs.Beliefs`)."""

    @property
    def name(self) -> str:  # read-only: a frozen dataclass's field, or a class attribute
        ...

    def bid(self, s: Situation) -> list[Bid]:
        """The agent's bids this tick.

        Args:
            s: what the agent knows this tick.

        Returns:
            Its bids, each a :class:`~navcli.bidding.Bid` under the agent's ``name``, for the
            wheels (a :class:`~navcli.bidding.Move`) or the camera (a
            :class:`~navcli.bidding.Look`); an empty list bids for nothing.
        """
        ...


class AgentSetup(NamedTuple):
    """What a Navigation agent given by a plugin (``--navigation NAME``, or ``agents+NAME`` beside
    navcli's bidding agents) is made with: ``cls(setup)``.

    Attributes:
        params: every parameter of the run (``params.robot.max_speed`` ...).
        own_params: the agent's own set (its class's ``Params``, with the run's overrides), or None.
        pan_limit: how far the camera pans either side of ahead (rad).
        target_key: how the visual memory names the target (``target``, or a landmark's id).
        rng: the run's generator for plugins (seeded from the run's seed: draw from it, never
            from a global generator, so the same seed gives the same run).
    """

    params: Params
    own_params: ParamSet | None
    pan_limit: float
    target_key: str
    rng: np.random.Generator
