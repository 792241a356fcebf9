"""navcli: a mission runner for the bidding Pilot/Vision/Navigation robot of Busquets, Mohan et al.

The public API, for notebooks and scripts (imported lazily, so ``navcli --help`` stays fast;
:mod:`navcli.api` says more)::

    import navcli
    r = navcli.run("scenarios/paper-8x8.yaml", seed=3, params={"pilot.K": 30})  # -> Run, no file written
    r.summary["outcome"], r.bids[["time_s", "motion.pilot", "motion.navigation"]]
    df = navcli.compare(["scenarios/paper-8x8.yaml"], ["potential-field", "geometric"], reruns=5)
    df = navcli.sweep("plans/table1-sensitivity.yaml")

A pilot or Navigation policy of one's own is a plugin (:mod:`navcli.plugins`): ``Pilot``,
``Avoidance``, ``ParamSet`` and ``param`` are what it is made of.

The package reads like the papers' architecture: ``pilot/`` (the Pilot), ``vision/`` (camera,
visual memory, perception), ``navigation/`` (the Navigation agents and the Communicator),
``experiments/`` (compare, bench); ``world`` is the only module that imports pymunk and
``recorder`` the only writer of logs.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

from . import builds  # noqa: E402 (before any other navcli module is imported)

BUILD = builds.choose()
"""Which code runs: ``compiled`` (the hot modules built by mypyc, see setup.py and
:mod:`navcli.builds`), ``pure`` (compiled modules installed, their ``.py`` sources run:
``NAVCLI_PURE=1``) or ``pure-only`` (none built: the install had no C compiler)."""


class NavcliError(ValueError):
    """The root of every refusal navcli makes (a scenario, a plan, a model file, a log, an option, an
    output path): the message says what is wrong and what is expected, in one sentence or a list of
    them. The command line prints it and exits with :attr:`exit_code` (2: bad input); anything else
    raised is a bug. A ``ValueError``, so code that catches bad values catches these too.

    ``option`` (set by the command line, see ``navcli.cli.errors.about``) names the option or
    argument the refusal is about; ``headline``, when a class has one, is printed above the
    message (a file's list of problems)."""

    exit_code = 2
    headline: str | None = None
    option: str | None = None


_API = {
    "run": "api",
    "compare": "api",
    "sweep": "api",
    "spec": "api",
    "Run": "api",
    "Pilot": "pilot",
    "Avoidance": "pilot",
    "ParamSet": "params",
    "param": "params",
    "AgentSetup": "navigation.situation",
    "PluginError": "plugins",
    "UnknownPlugin": "plugins",
    "Agent": "navigation.situation",
    "Bid": "bidding",
    "Look": "bidding",
    "Move": "bidding",
    "arbitrate": "bidding",
    "Beliefs": "beliefs",
    "Bump": "beliefs",
    "KnownObstacle": "beliefs",
    "ConfigError": "config",
    "RunSpec": "config",
    "Mission": "mission",
    "Tick": "mission",
    "Event": "mission",
    "Params": "params",
    "ParamError": "params",
    "RunResult": "runner",
    "run_mission": "runner",
    "Scenario": "scenario",
    "ScenarioError": "scenario",
    "load_scenario": "scenario",
    "parse_scenario": "scenario",
}
__all__ = sorted(_API) + ["NavcliError", "__version__"]


def __getattr__(name: str) -> Any:
    if name in _API:
        value = getattr(importlib.import_module(f".{_API[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'navcli' has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
