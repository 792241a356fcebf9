"""Gymnasium environments of navcli's tasks (optional: ``pip install navcli[gym]``).

``navcli/LandmarkNavigation-v0`` is the learning-agent paper's task (:mod:`.landmark_navigation`),
registered when this package is imported, so other RL libraries can be compared on it.
"""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

from .landmark_navigation import LandmarkNavigationEnv

__all__ = ["LandmarkNavigationEnv"]

if "navcli/LandmarkNavigation-v0" not in registry:
    register(id="navcli/LandmarkNavigation-v0", entry_point="navcli.envs.landmark_navigation:LandmarkNavigationEnv")
