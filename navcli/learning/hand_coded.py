"""The hand-coded policy the Learning Agent was compared with (learning-agent paper, section 6),
on the same discretised features, exactly as the text states it:

- far from the target:
  - few landmarks: MLL;
  - enough landmarks, but highly imprecise: MVL;
  - landmarks good enough: MOT if the target's location is highly imprecise, else MB;
- not far from the target:
  - the target's location highly imprecise: MVL if the landmarks' overall imprecision is high,
    else MVT;
  - the target's location precise: MVT when really near, MB at a medium distance.

The text names the conditions but not where they begin; our reading, in intervals of the
features (bounds in :class:`~navcli.params.LearningParams`):

- *really near*: distance interval 0 (under 0.9 m); *medium*: intervals 1-2 (0.9-3 m); *far*:
  intervals 3-4 (3 m or more);
- *few landmarks*: count interval 0-1 (C-bar under 0.67: at most four sectors with one landmark);
- *landmarks highly imprecise*: I-bar interval 3 or more (I-bar 0.5 or more: three empty sectors,
  or fewer that are blurred);
- *target highly imprecise*: I(t) interval 4 or more (I(t) 0.1 or more: what a fresh sighting
  gives 4-5 m away, or a near target blurred by driving).
"""

from __future__ import annotations

from .actions import MB, MLL, MOT, MVL, MVT
from .features import state_of

NEAR = 0  # distance intervals <= NEAR: really near
MEDIUM = 2  # distance intervals <= MEDIUM (and > NEAR): medium; above: far
FEW_LANDMARKS = 1  # count intervals <= this: few landmarks
IMPRECISE_LANDMARKS = 3  # I-bar intervals >= this: landmarks highly imprecise
IMPRECISE_TARGET = 4  # I(t) intervals >= this: target highly imprecise


def hand_coded_action(state: int) -> int:
    """The hand-coded policy's action in ``state`` (an index of :mod:`.features`).

    >>> from navcli.learning.features import SHAPE
    >>> import numpy as np
    >>> far_few = int(np.ravel_multi_index((4, 0, 0, 0), SHAPE))
    >>> near_precise = int(np.ravel_multi_index((0, 0, 3, 0), SHAPE))
    >>> hand_coded_action(far_few), hand_coded_action(near_precise)  # MLL, MVT
    (1, 4)
    """
    d, it, c, il = state_of(state)
    target_blurred = it >= IMPRECISE_TARGET
    landmarks_blurred = il >= IMPRECISE_LANDMARKS
    if d > MEDIUM:  # far
        if c <= FEW_LANDMARKS:
            return MLL
        if landmarks_blurred:
            return MVL
        return MOT if target_blurred else MB
    if target_blurred:
        return MVL if landmarks_blurred else MVT
    return MVT if d <= NEAR else MB
