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

    ``target`` is the current target's best estimate (egocentric fuzzy point: the original
    target, or the middle of a diverting line) and ``target_source`` where it came from
    (``memory``, ``map:ABC/D``); ``target_line`` the line to cross (a diverting target, or a
    line target); ``I_a`` the target's heading imprecision (Target Tracker, eq. 6 of the thesis);
    ``landmarks`` the known landmarks (egocentric fuzzy points); ``quality_ahead`` and
    ``quality_around`` the Map Manager's ``q_S`` of those ahead and of all.

    Built every tick, twice while diverting (a NamedTuple: docs/design.md, "Values made every tick").
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

    def bid(self, s: Situation) -> list[Bid]: ...


class AgentSetup(NamedTuple):
    """What a Navigation agent given by a plugin (``--navigation NAME``, or ``agents+NAME`` beside
    navcli's bidding agents) is made with: ``cls(setup)``.

    ``params`` holds every parameter of the run (``params.robot.max_speed`` ...); ``own_params``
    the agent's own set (its class's ``Params``, with the run's overrides), or None; ``pan_limit``
    how far the camera pans either side of ahead (rad); ``target_key`` how the visual memory names
    the target (``target``, or a landmark's id); ``rng`` the run's generator for plugins (seeded
    from the run's seed: draw from it, never from a global generator, so the same seed gives the
    same run)."""

    params: Params
    own_params: ParamSet | None
    pan_limit: float
    target_key: str
    rng: np.random.Generator
