"""One run's whole configuration, as one value: :class:`RunSpec`.

Everything that decides a run travels in it, from the command line to a worker process and into
the log: the scenario (its text and sha256, not just a path), the seed, the pilot, the
perception, the Navigation policy, the time limit and every parameter after the scenario's and the
command line's overrides; for a plugin, its identity (name, version, origin) and its own
parameters. Its :attr:`RunSpec.run_id` (a sha256 of its JSON form and navcli's version) names the
run: it is part of the default log path and the key by which comparisons resume, so two runs
share a log only if they are the same run, and a plugin's run never takes a stock pilot's.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Mapping

from . import NavcliError
from . import __version__
from .analysis.files import file_name
from .params import CONTROL_DT, PERCEPTIONS, PHYSICS_DT, Params
from .plugins import registry
from .plugins.names import BUILTIN_POLICIES, label
from .plugins.registry import Component
from .scenario import RANGES, Scenario, parse_scenario

LOG_ROOT = Path("logs")


class ConfigError(NavcliError):
    """A run configuration that cannot be run (an unknown pilot, a bad time limit ...)."""


@dataclass(frozen=True)
class RunSpec:
    """Everything that decides one run (see the module docstring). Build it with :meth:`build`.

    ``pilot`` and ``navigation`` are values the registry resolves (:mod:`navcli.plugins`): navcli's
    own, an installed plugin's, ``module:Class`` or ``NAME=module:Class`` (:mod:`navcli.plugins.names`;
    the run goes by :attr:`pilot_name`); ``params`` holds the parameter sets of the
    plugins the run uses (their defaults when not given)."""

    scenario: Scenario
    seed: int
    pilot: str
    perception: str
    time_limit: float  # simulated seconds
    params: Params
    navigation: str = BUILTIN_POLICIES[0]  # agents | hand-coded | learned[:FILE] | a plugin's | agents+a plugin's

    def __post_init__(self) -> None:
        params = registry.with_params(self.params, self.components)
        if params is not self.params:
            object.__setattr__(self, "params", params)
        if self.perception not in PERCEPTIONS:
            raise ConfigError(f"unknown perception {self.perception!r} (expected one of: {', '.join(PERCEPTIONS)})")
        if not (isinstance(self.seed, int) and 0 <= self.seed < 2**64):
            raise ConfigError(f"the seed must be a whole number from 0 to 2**64 - 1, got {self.seed!r}")
        limit = RANGES["mission.time_limit"]
        if not (limit.lo <= self.time_limit <= limit.hi):
            raise ConfigError(
                f"the time limit must be from {limit.lo:g} to {limit.hi:g} simulated seconds, got {self.time_limit!r}"
            )
        if not self.params.vision.told_target and self.scenario.target.kind == "line":
            raise ConfigError("vision.told_target=0 needs a point or landmark target: a line is not seen, only told")
        bound = self.params.vision.noise_bound
        noise = self.scenario.noise
        for name, sd in (("noise.odometry", noise.odometry), ("noise.vision_distance", noise.vision_distance)):
            if sd * bound >= 1.0:  # a relative error clipped at this many deviations could reach -100 %
                raise ConfigError(f"{name} ({sd:g}) times vision.noise_bound ({bound:g}) must be below 1")

    @property
    def components(self) -> tuple[Component, ...]:
        """The run's pilot, then its Navigation policies, as the registry finds them (raises
        :class:`~navcli.plugins.UnknownPlugin` for an unknown name)."""
        return (registry.pilot(self.pilot),) + registry.navigation(self.navigation)

    @property
    def pilot_name(self) -> str:
        """The name the pilot goes by in the run's summary, tables and log file name: the ``NAME``
        of ``NAME=REFERENCE``, else :attr:`pilot` itself."""
        return label(self.pilot)

    @property
    def plugins(self) -> tuple[tuple[str, Component], ...]:
        """(role, component) of each plugin the run uses: ``pilot`` or ``navigation``."""
        return tuple(("pilot" if i == 0 else "navigation", c) for i, c in enumerate(self.components) if not c.builtin)

    @classmethod
    def build(
        cls,
        scenario: Scenario,
        *,
        seed: int | None = None,
        pilot: str | None = None,
        perception: str | None = None,
        time_limit: float | None = None,
        overrides: Mapping[str, Any] | None = None,
        navigation: str | None = None,
        also: Iterable[str] = (),
        preset: Mapping[str, Any] | None = None,
    ) -> RunSpec:
        """The scenario's own choices, with any of them replaced, and ``overrides`` (dotted
        parameter names, ``{"pilot.K": 30}``) applied on top of the scenario's parameters. A
        plugin's parameters (``vfh.threshold``) may be overridden when the run uses it, or when it
        is one of the pilots named in ``also`` (a comparison's other pilots). A ``preset`` (parameter
        values a named condition sets, the learning paper's task) lies under both: it sets what
        neither the scenario file (:attr:`~navcli.scenario.Scenario.given`) nor ``overrides`` gives,
        so the user's word is heard whatever its value."""
        m = scenario.mission
        pilot = pilot or m.pilot
        navigation = navigation or BUILTIN_POLICIES[0]
        params = registry.with_params(
            scenario.params,
            (registry.pilot(pilot),) + registry.navigation(navigation) + tuple(map(registry.pilot, also)),
        )
        under = {k: v for k, v in (preset or {}).items() if k not in scenario.given and k not in (overrides or {})}
        return cls(
            scenario,
            m.seed if seed is None else seed,
            pilot,
            perception or m.perception,
            float(m.time_limit if time_limit is None else time_limit),
            params.override(under).override(overrides or {}),
            navigation,
        )

    def replace(self, **changes: Any) -> RunSpec:
        """A copy with some fields changed (``seed=2``, ``pilot="geometric"``)."""
        return dataclasses.replace(self, **changes)

    def to_json(self) -> dict[str, Any]:
        """The configuration as plain JSON (the scenario by name, file and sha256; its text goes
        into the log as an attachment); ``plugins`` (only when the run uses one) names each plugin,
        its version and origin, with its own parameters."""
        sc = self.scenario
        d = {
            "scenario": {"name": sc.name, "file": sc.source, "sha256": sc.sha256},
            "seed": self.seed,
            "pilot": self.pilot,
            "perception": self.perception,
            "time_limit_s": self.time_limit,
            "params": self.params.to_json(),
            "navigation": self.navigation,
        }
        plugins = [
            {"role": role, **c.identity(), "params": own.to_json() if (own := self.params.plugin(c.group)) else {}}
            for role, c in self.plugins
        ]
        return d | {"plugins": plugins} if plugins else d

    @classmethod
    def from_json(cls, d: Mapping[str, Any], scenario_text: str) -> RunSpec:
        """The inverse of :meth:`to_json`, given the scenario's text (a log's attachment). A run of
        a plugin needs that plugin, in the same version."""
        sc = parse_scenario(scenario_text, d["scenario"].get("file", "<log>"))
        if sc.sha256 != d["scenario"]["sha256"]:
            raise ConfigError("the scenario text does not match the configuration's sha256")
        params = Params.from_json(d["params"])
        navigation = d.get("navigation", BUILTIN_POLICIES[0])
        found = [c for c in (registry.pilot(d["pilot"]),) + registry.navigation(navigation) if not c.builtin]
        for p, c in zip(d.get("plugins", []), found):  # in the order of :attr:`plugins`
            if c.version != p["version"]:
                raise ConfigError(f"the run used {p['name']} version {p['version']}; {c.label} is another")
            if c.params_class is not None:
                params = params.with_plugin(c.group, c.params_class(**p["params"]))
        return cls(
            sc,
            int(d["seed"]),
            d["pilot"],
            d["perception"],
            float(d["time_limit_s"]),
            params,
            navigation,
        )

    @functools.cached_property
    def run_id(self) -> str:
        """sha256 (hex) of the canonical JSON of :meth:`to_json` without the scenario's file name
        (a moved file is the same scenario) and the parameters that never change a run's course
        (``course=False``: the wall-clock guard), with navcli's version. Worked out once per spec (a
        spec is frozen; :meth:`replace` makes a new one): a sweep's plan reads it several times."""
        d = self.to_json()
        d["scenario"] = {k: v for k, v in d["scenario"].items() if k != "file"}
        for name, declared, _ in self.params.declarations():  # a guard of the wall clock is no change of the run
            group, _, key = name.partition(".")
            if not declared.course and group in d["params"]:
                del d["params"][group][key]
        blob = json.dumps([d, __version__], sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(blob.encode()).hexdigest()

    def log_name(self) -> str:
        """``<pilot>-seed<N>-<first 8 hex digits of run_id>.mcap``, by :attr:`pilot_name` (a
        ``module:Class`` pilot's made a file name's: ``mod_Class``)."""
        return f"{file_name(self.pilot_name)}-seed{self.seed}-{self.run_id[:8]}.mcap"

    def default_log_path(self, root: Path = LOG_ROOT) -> Path:
        """``<root>/<scenario>/<pilot>-seed<N>-<id>.mcap``."""
        return root / self.scenario.name / self.log_name()

    def metadata(self) -> dict[str, str]:
        """The log's ``run`` metadata record: the configuration as JSON (``config``), its
        ``run_id``, and its main fields as plain strings for tools that only list metadata."""
        sc = self.scenario
        return {
            "run_id": self.run_id,
            "config": json.dumps(self.to_json(), sort_keys=True),
            "scenario": sc.name,
            "scenario_file": sc.source,
            "scenario_sha256": sc.sha256,
            "seed": str(self.seed),
            "pilot": self.pilot_name,
            "perception": self.perception,
            "time_limit_s": repr(self.time_limit),
            "navigation": self.navigation,
            "navcli_version": __version__,
            "control_dt_s": repr(CONTROL_DT),
            "physics_dt_s": repr(PHYSICS_DT),
        } | ({"plugins": json.dumps([{"role": r, **c.identity()} for r, c in self.plugins])} if self.plugins else {})
