"""The Learning Agent's five actions and their rewards (learning-agent paper, section 5.3).

Each action is a motion and (except MB) a look, carried out through the Pilot and Vision by bids
like any Navigation agent's (the Pilot still overrules when it must, the Rescuer's scans overrule
both):

====  ===========================================  =======================================  ======
name  motion                                       camera                                   reward
====  ===========================================  =======================================  ======
MB    toward the target                            none (left to the Pilot)                 -1
MLL   toward the target                            the sector with the fewest known          -10
                                                   landmarks: look for new ones
MOT   orthogonally to the target                   at the target                            -6
MVL   toward the target                            the sector whose landmarks are the        -5
                                                   most imprecise (highest I-bar(s)):
                                                   re-acquire them
MVT   toward the target                            at the target                            -5
====  ===========================================  =======================================  ======

Reaching the target gives 0 (it ends the trial). "Toward the target" is the centre of the target's
fuzzy heading; when the target is lost the paper takes the centre of [0, 2 pi], pi: the robot
"pace[s] back and forth, turning 180 degrees (pi radians) each time an action is executed". How
an action aims then is :class:`~navcli.learning.learning_agent.LearningAgent`'s (``learning.pace``):
pi fixed in the odometry frame when the action starts, driven as a reversal (``reverse``). Each look runs the routine its purpose names (section 5.3: "The vision system can either search
for new landmarks or re-acquire already-detected landmarks, but it is not able to do both things
at the same time"; :mod:`navcli.vision.routines`): MLL a search (new landmarks only), MVL a
re-acquisition of the known landmarks (not the target), MVT and MOT a re-acquisition of the
target (nothing else); MB takes no image. Looks are clipped to the pan unit's limit; MLL and MVL choose among the sectors the camera can see
any of (:func:`reachable`): with the 100 degree pan limit, the five but the one behind.
"""

from __future__ import annotations

import math
from typing import Sequence

from ..bidding import Bid, Look, LookPurpose, Move
from ..geometry import orthogonal
from ..navigation.risk_manager import SECTORS
from ..navigation.situation import Situation
from .features import BEST, landmarks_of, sector_imprecision, sectors

ACTIONS = ("MB", "MLL", "MOT", "MVL", "MVT")
"""The actions in the order of the action index."""
MB, MLL, MOT, MVL, MVT = range(5)
REWARDS = (-1.0, -10.0, -6.0, -5.0, -5.0)
"""The immediate reward of each action (section 5.3: MB -1, MLL -10, MOT -6, MVL -5, MVT -5)."""

AT_TARGET = 0.0
"""The reward on reaching the target."""


def reward_of(counts: Sequence[int]) -> float:
    """The reward of actions taken ``counts[a]`` times each (reaching the target adds AT_TARGET, 0)."""
    return float(sum(REWARDS[a] * n for a, n in enumerate(counts)))


def target_bearing(s: Situation) -> float:
    """The heading (rad, egocentric) the target is believed to lie at; pi when it is lost."""
    b = s.bearing
    return math.pi if b is None else b


SECTOR_HALF = math.pi / 6  # a sector is 60 degrees wide, the camera's field of view (section 5.2)


def reachable(pan_limit: float) -> list[int]:
    """The sectors the camera can see any of: those whose near edge lies within the view at the pan
    limit, ``pan_limit`` plus half the view (60 degrees, one sector). With the pan unit's 100
    degrees, five of six: the sectors at +-120 degrees only in part (the view reaches 130), the
    one behind not at all.

    >>> [round(math.degrees(SECTORS[i])) for i in reachable(math.radians(100))]
    [0, 60, -60, 120, -120]
    """
    return [i for i, c in enumerate(SECTORS) if abs(c) - SECTOR_HALF < pan_limit + SECTOR_HALF - 1e-9]


def least_known_sector(s: Situation, pan_limit: float, target_key: str | None = None) -> float:
    """The centre (rad) of the sector the camera can see (:func:`reachable`) with the fewest known
    landmarks (nearest ahead on a tie); a look there is clipped at the pan limit."""
    per = sectors(landmarks_of(s, target_key))
    reach = reachable(pan_limit)
    return SECTORS[min(reach, key=lambda i: (min(BEST, len(per[i])), abs(SECTORS[i])))]


def most_imprecise_sector(s: Situation, pan_limit: float, target_key: str | None = None) -> float:
    """The centre (rad) of the sector the camera can see (:func:`reachable`), among those with known
    landmarks, whose I-bar(s) is highest ("the sector with the maximum imprecision": a sector with
    no known landmark has none to re-acquire); straight ahead when no such sector holds one (our
    choice: an MVL then re-acquires nothing, and pays its cost)."""
    per = sectors(landmarks_of(s, target_key))
    reach = [i for i in reachable(pan_limit) if per[i]]
    if not reach:
        return 0.0
    return SECTORS[max(reach, key=lambda i: (sector_imprecision(per[i]), -abs(SECTORS[i])))]


def action_bids(
    action: int,
    s: Situation,
    *,
    bidder: str,
    value: float,
    speed: float,
    pan_limit: float,
    target_key: str | None = None,
    side: float = 1.0,
    bearing: float | None = None,
    reverse: bool = False,
) -> list[Bid]:
    """The bids that carry out ``action`` in situation ``s``: a move at ``speed`` (m/s) and a look,
    each bid at ``value``. ``side`` (+1 left, -1 right) is MOT's side of the target; ``bearing``
    (egocentric, rad) the heading the action aims at, by default :func:`target_bearing`'s; with
    ``reverse`` a move toward a heading behind the robot (more than 90 degrees off) is driven
    backwards, the body keeping its heading (the pacing of a lost target)."""
    bearing = target_bearing(s) if bearing is None else bearing
    heading = bearing
    look: float | None = None
    purpose: LookPurpose = "target"
    if action == MOT:
        heading = math.remainder(bearing + side * math.pi / 2, 2 * math.pi)
        look = bearing
    elif action == MVT:
        look = bearing
    elif action == MLL:
        look, purpose = least_known_sector(s, pan_limit, target_key), "search"
    elif action == MVL:
        look, purpose = most_imprecise_sector(s, pan_limit, target_key), "landmarks"
    elif action != MB:
        raise ValueError(f"unknown action {action}")
    move = Move(heading, speed)
    if reverse and abs(heading) > math.pi / 2:
        move = Move(math.remainder(heading - math.pi, 2 * math.pi), -speed)
    bids = [Bid(bidder, "motion", move, value)]
    if look is not None:
        bids.append(Bid(bidder, "camera", Look(max(-pan_limit, min(pan_limit, look)), purpose), value))
    return bids


def orthogonal_side(s: Situation) -> float:
    """MOT's side: the one needing the smaller turn (+1 left of the target, -1 right)."""
    return orthogonal(target_bearing(s))[1]
