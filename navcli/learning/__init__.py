"""The Learning Agent (learning-agent paper, sections 4-6): learning which of five actions to take
to reach the current target while using the camera little, by Prioritized Sweeping over 980
belief states.

One module per concept: :mod:`.features` (the belief state), :mod:`.actions` (MB, MLL, MOT, MVL,
MVT and their rewards), :mod:`.learning_agent` (the agent that bids them), :mod:`.hand_coded`
(section 6's hand-coded policy), :mod:`.prioritized_sweeping` (the learner), :mod:`.q_learning`
(the model-free baseline) and :mod:`.model_file` (models on disk). The training harness (trials,
``navcli train``, ``navcli compare policies``) is :mod:`navcli.training`.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..params import LEARNING, ROBOT, LearningParams
from .learning_agent import LearningAgent, hand_coded_agent, table_policy

__all__ = ["LearningAgent", "hand_coded_agent", "policy_agent", "table_policy"]


def policy_agent(
    kind: str,
    file: str = "",
    params: LearningParams = LEARNING,
    *,
    max_speed: float = ROBOT.max_speed,
    pan_limit: float = math.radians(100.0),
    target_key: str | None = None,
) -> LearningAgent:
    """The agent of the Navigation policy ``kind``: ``hand-coded``, or ``learned`` from the model
    ``file`` (the bundled one when empty). Raises :class:`~.model_file.ModelError` for a bad model
    file."""
    if kind == "hand-coded":
        return hand_coded_agent(params=params, max_speed=max_speed, pan_limit=pan_limit, target_key=target_key)
    if kind != "learned":
        raise ValueError(f"no policy agent for navigation {kind!r}")
    from .model_file import load_policy

    return LearningAgent(
        table_policy(load_policy(Path(file) if file else None)),
        params=params,
        max_speed=max_speed,
        pan_limit=pan_limit,
        target_key=target_key,
    )
