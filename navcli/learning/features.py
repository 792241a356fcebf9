"""Belief-state features (learning-agent paper, sections 5.1-5.2): what the Learning Agent knows,
reduced to one of 980 states.

The headings around the robot are split into six 60-degree sectors (the camera's field of view is
one sector; sector 0 is straight ahead, the sectors of :data:`navcli.navigation.risk_manager.SECTORS`).
From the Navigation system's :class:`~navcli.navigation.situation.Situation`:

- D(t): the distance to the current target (the centre of its fuzzy distance, m);
- I(t): the imprecision of the target's location, the paper's I(l) with lambda 0.2 and beta 1
  (:meth:`navcli.fuzzy.FuzzyPoint.imprecision`); 1 when the target is lost;
- C-bar = 1/6 sum_s N(s), N(s) = min(4, |L(s)|), the known landmarks of sector s (the target
  landmark is the target, not one of them);
- I-bar = 1/6 sum_s I-bar(s), I-bar(s) = 1/N(s) sum over Best(4, L(s)) of I(l): the mean
  imprecision of the sector's four sharpest landmarks; an empty sector counts as 1 (our design,
  see :class:`navcli.params.LearningParams`).

Each is cut into intervals by the bounds of :class:`~navcli.params.LearningParams` (5, 7, 4, 7)
and the four interval numbers make one state index in [0, 980).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

from ..fuzzy import FuzzyPoint
from ..navigation.risk_manager import SECTORS, sector_of
from ..navigation.situation import Situation
from ..params import LEARNING, LearningParams, ParamError

SHAPE = (5, 7, 4, 7)
"""Intervals of D(t), I(t), C-bar and I-bar (section 5.2)."""
N_STATES = math.prod(SHAPE)  # 980
BEST = 4  # Best(4, L(s)) and N(s) = min(4, |L(s)|)
UNKNOWN = 1.0  # I(l) of a landmark whose place is unknown: an empty sector


@dataclass(frozen=True)
class Features:
    """The four belief-state variables before discretisation (units in the module docstring)."""

    distance: float  # D(t), m (inf when the target is lost)
    target_imprecision: float  # I(t)
    count: float  # C-bar, in [0, 4]
    landmark_imprecision: float  # I-bar, in [0, 1]


def sectors(landmarks: dict[str, FuzzyPoint]) -> list[list[float]]:
    """The I(l) of each sector's landmarks, sharpest first."""
    out: list[list[float]] = [[] for _ in SECTORS]
    for p in landmarks.values():
        out[sector_of(p.x, p.y)].append(p.imprecision())
    for s in out:
        s.sort()
    return out


def sector_imprecision(imprecisions: list[float]) -> float:
    """I-bar(s): the mean I(l) of Best(4, L(s)); :data:`UNKNOWN` for an empty sector.

    >>> sector_imprecision([0.1, 0.2, 0.3, 0.4, 0.9]), sector_imprecision([])
    (0.25, 1.0)
    """
    best = sorted(imprecisions)[:BEST]
    return sum(best) / len(best) if best else UNKNOWN


def landmarks_of(s: Situation, target_key: str | None = None) -> dict[str, FuzzyPoint]:
    """The known landmarks other than the target landmark."""
    return {k: p for k, p in s.landmarks.items() if k != target_key}


def features(s: Situation, target_key: str | None = None) -> Features:
    """The four variables of ``s`` (``target_key``: the target landmark's id, left out of the counts)."""
    per = sectors(landmarks_of(s, target_key))
    count = sum(min(BEST, len(x)) for x in per) / len(SECTORS)
    lm = sum(sector_imprecision(x) for x in per) / len(SECTORS)
    if s.target is None:
        return Features(math.inf, 1.0, count, lm)
    t = s.target
    return Features(math.hypot(t.x, t.y), t.imprecision(), count, lm)


def discretise(f: Features, params: LearningParams = LEARNING) -> tuple[int, int, int, int]:
    """The interval of each variable: ``bisect_right`` on the bounds (a value on a bound goes up).

    >>> discretise(Features(0.5, 0.0, 0.0, 0.0)), discretise(Features(math.inf, 1.0, 4.0, 1.0))
    ((0, 0, 0, 0), (4, 6, 3, 6))
    """
    p = params
    return (
        bisect.bisect_right(p.distance_bounds, f.distance),
        bisect.bisect_right(p.imprecision_bounds, f.target_imprecision),
        bisect.bisect_right(p.count_bounds, f.count),
        bisect.bisect_right(p.landmark_bounds, f.landmark_imprecision),
    )


def state_index(f: Features, params: LearningParams = LEARNING) -> int:
    """The state in [0, 980): the intervals in row-major order of :data:`SHAPE`.

    >>> state_index(Features(math.inf, 1.0, 4.0, 1.0)) == N_STATES - 1
    True
    """
    idx = 0
    for i, n in zip(discretise(f, params), SHAPE):
        idx = idx * n + i
    return idx


def state_of(index: int) -> tuple[int, int, int, int]:
    """The inverse of :func:`state_index` on the intervals.

    >>> state_of(state_index(Features(2.0, 0.05, 0.5, 0.6)))
    (2, 2, 1, 3)
    """
    out = []
    for n in reversed(SHAPE):
        index, i = divmod(index, n)
        out.append(i)
    d, t, c, i = reversed(out)
    return d, t, c, i


def check_bounds(params: LearningParams) -> None:
    """Refuse bounds that would not give the paper's interval counts (a ``ParamError`` naming them)."""
    for name, n in zip(("distance_bounds", "imprecision_bounds", "count_bounds", "landmark_bounds"), SHAPE):
        b = getattr(params, name)
        if len(b) != n - 1 or list(b) != sorted(b):
            raise ParamError(f"learning.{name} must be {n - 1} increasing numbers ({n} intervals), got {list(b)}")
