"""One run's whole configuration, as one value: :class:`RunSpec`.

Everything that decides a run travels in it, from the command line to a worker process and into
the log: the scenario (its text and sha256, not just a path), the seed, the pilot, the
perception, the time limit and every parameter after the scenario's and the command line's
overrides. Its :attr:`RunSpec.run_id` (a sha256 of its JSON form and navcli's version) names the
run: it is part of the default log path and the key by which comparisons resume, so two runs
share a log only if they are the same run.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from . import NavcliError
from . import __version__
from .params import CONTROL_DT, NAVIGATIONS, PERCEPTIONS, PHYSICS_DT, PILOT_NAMES, ParamError, Params
from .scenario import RANGES, Scenario, parse_scenario

LOG_ROOT = Path("logs")


class ConfigError(NavcliError):
    """A run configuration that cannot be run (an unknown pilot, a bad time limit ...)."""


@dataclass(frozen=True)
class RunSpec:
    """Everything that decides one run (see the module docstring). Build it with :meth:`build`."""

    scenario: Scenario
    seed: int
    pilot: str
    perception: str
    time_limit: float  # simulated seconds
    params: Params
    navigation: str = NAVIGATIONS[0]  # agents | hand-coded | learned[:FILE] (the Learning Agent's policy)

    def __post_init__(self) -> None:
        if self.pilot not in PILOT_NAMES:
            raise ConfigError(f"unknown pilot {self.pilot!r} (expected one of: {', '.join(PILOT_NAMES)})")
        if self.perception not in PERCEPTIONS:
            raise ConfigError(f"unknown perception {self.perception!r} (expected one of: {', '.join(PERCEPTIONS)})")
        mode, _, file = self.navigation.partition(":")
        if mode not in NAVIGATIONS or (file and mode != "learned"):
            raise ConfigError(f"unknown navigation {self.navigation!r} (expected agents, hand-coded, learned "
                              f"or learned:FILE)")
        if not (isinstance(self.seed, int) and 0 <= self.seed < 2 ** 64):
            raise ConfigError(f"the seed must be a whole number from 0 to 2**64 - 1, got {self.seed!r}")
        limit = RANGES["mission.time_limit"]
        if not (limit.lo <= self.time_limit <= limit.hi):
            raise ConfigError(f"the time limit must be from {limit.lo:g} to {limit.hi:g} simulated seconds, "
                              f"got {self.time_limit!r}")
        if not self.params.vision.told_target and self.scenario.target.kind == "line":
            raise ConfigError("vision.told_target=0 needs a point or landmark target: a line is not seen, only told")
        bound = self.params.vision.noise_bound
        noise = self.scenario.noise
        for name, sd in (("noise.odometry", noise.odometry), ("noise.vision_distance", noise.vision_distance)):
            if sd * bound >= 1.0:  # a relative error clipped at this many deviations could reach -100 %
                raise ConfigError(f"{name} ({sd:g}) times vision.noise_bound ({bound:g}) must be below 1")

    @classmethod
    def build(cls, scenario: Scenario, *, seed: int | None = None, pilot: str | None = None,
              perception: str | None = None, time_limit: float | None = None,
              overrides: Mapping[str, Any] | None = None, navigation: str | None = None) -> RunSpec:
        """The scenario's own choices, with any of them replaced, and ``overrides`` (dotted
        parameter names, ``{"pilot.K": 30}``) applied on top of the scenario's parameters."""
        m = scenario.mission
        return cls(scenario, m.seed if seed is None else seed, pilot or m.pilot, perception or m.perception,
                   float(m.time_limit if time_limit is None else time_limit),
                   scenario.params.override(overrides or {}), navigation or NAVIGATIONS[0])

    def replace(self, **changes: Any) -> RunSpec:
        """A copy with some fields changed (``seed=2``, ``pilot="geometric"``)."""
        return dataclasses.replace(self, **changes)

    def to_json(self) -> dict[str, Any]:
        """The configuration as plain JSON (the scenario by name, file and sha256; its text goes
        into the log as an attachment)."""
        sc = self.scenario
        return {"scenario": {"name": sc.name, "file": sc.source, "sha256": sc.sha256},
                "seed": self.seed, "pilot": self.pilot, "perception": self.perception,
                "time_limit_s": self.time_limit, "params": self.params.to_json(), "navigation": self.navigation}

    @classmethod
    def from_json(cls, d: Mapping[str, Any], scenario_text: str) -> RunSpec:
        """The inverse of :meth:`to_json`, given the scenario's text (a log's attachment)."""
        sc = parse_scenario(scenario_text, d["scenario"].get("file", "<log>"))
        if sc.sha256 != d["scenario"]["sha256"]:
            raise ConfigError("the scenario text does not match the configuration's sha256")
        return cls(sc, int(d["seed"]), d["pilot"], d["perception"], float(d["time_limit_s"]),
                   Params.from_json(d["params"]), d.get("navigation", NAVIGATIONS[0]))

    @functools.cached_property
    def run_id(self) -> str:
        """sha256 (hex) of the canonical JSON of :meth:`to_json` without the scenario's file name
        (a moved file is the same scenario), with navcli's version. Worked out once per spec (a
        spec is frozen; :meth:`replace` makes a new one): a sweep's plan reads it several times."""
        d = self.to_json()
        d["scenario"] = {k: v for k, v in d["scenario"].items() if k != "file"}
        blob = json.dumps([d, __version__], sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(blob.encode()).hexdigest()

    def log_name(self) -> str:
        """``<pilot>-seed<N>-<first 8 hex digits of run_id>.mcap``."""
        return f"{self.pilot}-seed{self.seed}-{self.run_id[:8]}.mcap"

    def default_log_path(self, root: Path = LOG_ROOT) -> Path:
        """``<root>/<scenario>/<pilot>-seed<N>-<id>.mcap``."""
        return root / self.scenario.name / self.log_name()

    def metadata(self) -> dict[str, str]:
        """The log's ``run`` metadata record: the configuration as JSON (``config``), its
        ``run_id``, and its main fields as plain strings for tools that only list metadata."""
        sc = self.scenario
        return {"run_id": self.run_id, "config": json.dumps(self.to_json(), sort_keys=True),
                "scenario": sc.name, "scenario_file": sc.source, "scenario_sha256": sc.sha256,
                "seed": str(self.seed), "pilot": self.pilot, "perception": self.perception,
                "time_limit_s": repr(self.time_limit), "navigation": self.navigation, "navcli_version": __version__,
                "control_dt_s": repr(CONTROL_DT), "physics_dt_s": repr(PHYSICS_DT)}


def parse_override(item: str) -> tuple[str, float | list[float] | str]:
    """``"pilot.K=30"`` -> ``("pilot.K", 30.0)``; a list-valued parameter takes its numbers in
    brackets, comma-separated (``[]`` for none); a word is kept as it is (a parameter that names
    a choice, ``vision.walls=known``). The value is checked by :meth:`Params.override`.

    >>> parse_override("navigation.kappa1=0.5")
    ('navigation.kappa1', 0.5)
    >>> parse_override("pilot.reflex_look_pans_deg=[-60, 0, 60]")
    ('pilot.reflex_look_pans_deg', [-60.0, 0.0, 60.0])
    >>> parse_override("vision.walls=known")
    ('vision.walls', 'known')
    """
    name, sep, value = item.partition("=")
    name, value = name.strip(), value.strip()
    if not sep or not name:
        raise ParamError(f"{item!r}: expected NAME=VALUE, e.g. pilot.K=30")
    if len(value) > 1000:
        raise ParamError(f"{name}: a value of {len(value)} characters is not a parameter's")
    listed = value.startswith("[") and value.endswith("]")
    parts = [v.strip() for v in value[1:-1].split(",")] if listed else [value]
    if listed and parts == [""]:
        return name, []
    numbers = []
    for v in parts:
        try:
            numbers.append(float(v))
        except ValueError:
            if not listed and v.replace("-", "").replace("_", "").isalnum():
                return name, v  # a word: a choice (the parameter's check says which words it takes)
            raise ParamError(f"{item!r}: {v!r} is not a number" + ("" if listed else
                             " (a list parameter takes [a, b, ...])" if "," in value else "")) from None
    return name, numbers if listed else numbers[0]
