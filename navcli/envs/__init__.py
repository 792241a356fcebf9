"""Gymnasium environments of navcli's tasks (optional: ``pip install navcli[gym]``).

``navcli/LandmarkNavigation-v0`` is the learning-agent paper's task (:mod:`.landmark_navigation`),
so other RL libraries can be compared on it. In a fresh interpreter, one line makes it, with
Gymnasium's ``"module:EnvId"`` form, which imports this package (and so registers the id) first::

    import gymnasium
    env = gymnasium.make("navcli.envs:navcli/LandmarkNavigation-v0", render_mode="rgb_array")

(Gymnasium 1.0 removed the entry-point plugins that registered a package's environments on
``import gymnasium``; the module prefix is its documented replacement. Once ``navcli.envs`` is
imported, ``gymnasium.make("navcli/LandmarkNavigation-v0")`` works too.) Keyword arguments go to
:class:`LandmarkNavigationEnv`: ``scenario`` (a file or a bundled scenario's name),
``overrides`` (``{"learning.max_actions": 100}``), ``render_mode``, ``dpi``.
"""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

from .landmark_navigation import LandmarkNavigationEnv

ENV_ID = "navcli/LandmarkNavigation-v0"
MAKE_ID = f"{__name__}:{ENV_ID}"
"""What ``gymnasium.make`` takes in a fresh interpreter (module docstring)."""

__all__ = ["ENV_ID", "MAKE_ID", "LandmarkNavigationEnv"]

if ENV_ID not in registry:
    register(id=ENV_ID, entry_point="navcli.envs.landmark_navigation:LandmarkNavigationEnv")
