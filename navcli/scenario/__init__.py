"""Scenario files: YAML in, frozen dataclasses out (the scenario format, version 1, in
docs/scenario-format.md).

- :mod:`~navcli.scenario.model`: the dataclasses and the ranges of their numbers;
- :mod:`~navcli.scenario.yaml_reader`: the bounded YAML reader (scenarios and sweep plans);
- :mod:`~navcli.scenario.loader`: a file checked and built into the model;
- :mod:`~navcli.scenario.schema`: the format as a JSON Schema, for editors.
"""

from __future__ import annotations

from .loader import load_scenario, parse_scenario
from .model import (
    MAX_ID,
    MAX_ITEMS,
    NAME_RE,
    PILOT_BLOCK,
    RANGES,
    SUPPORTED_VERSIONS,
    Arena,
    ArenaObject,
    CameraSpec,
    Circle,
    Landmark,
    MissionSpec,
    Noise,
    Obstacle,
    Range,
    RobotSpec,
    Scenario,
    Segment,
    Target,
)
from .schema import json_schema
from .yaml_reader import MAX_BYTES, MAX_PROBLEMS, Problem, ScenarioError

__all__ = [
    "MAX_BYTES",
    "MAX_ID",
    "MAX_ITEMS",
    "MAX_PROBLEMS",
    "NAME_RE",
    "PILOT_BLOCK",
    "RANGES",
    "SUPPORTED_VERSIONS",
    "Arena",
    "ArenaObject",
    "CameraSpec",
    "Circle",
    "Landmark",
    "MissionSpec",
    "Noise",
    "Obstacle",
    "Problem",
    "Range",
    "RobotSpec",
    "Scenario",
    "ScenarioError",
    "Segment",
    "Target",
    "json_schema",
    "load_scenario",
    "parse_scenario",
]
