"""The Navigation system (learning-agent paper, section 3; notes, sections 1-4): agents that bid
among themselves for what the robot should do next, and the Communicator that forwards the
winners to the Pilot and to Vision. Today's agent is the Target Tracker; each agent is an
:class:`~navcli.bidding.Agent` in a module of its own."""

from __future__ import annotations

from dataclasses import dataclass

from ..beliefs import Beliefs
from ..bidding import Agent, Bid
from ..params import NAVIGATION, PILOT, ROBOT, NavigationParams, PilotParams, RobotParams
from .communicator import Communicator
from .target_tracker import TargetTracker

__all__ = ["Communicator", "NavigationOutput", "NavigationSystem", "TargetTracker"]


@dataclass(frozen=True)
class NavigationOutput:
    """The system's bids to the robot's arbiter, and the agents' bids they were chosen from."""

    bids: tuple[Bid, ...]
    agent_bids: tuple[Bid, ...]


class NavigationSystem:
    """The agents plus the Communicator."""

    name = "navigation"

    def __init__(self, params: NavigationParams = NAVIGATION, robot: RobotParams = ROBOT,
                 pilot: PilotParams = PILOT):
        self.agents: tuple[Agent, ...] = (TargetTracker(params, robot.max_speed, pilot.corridor_margin),)
        self.communicator = Communicator(self.name)

    def bid(self, beliefs: Beliefs) -> NavigationOutput:
        """Every agent bids; the Communicator forwards each resource's winner."""
        agent_bids = tuple(b for agent in self.agents for b in agent.bid(beliefs))
        return NavigationOutput(tuple(self.communicator.forward(agent_bids)), agent_bids)
