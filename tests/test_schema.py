"""`navcli schema`: the JSON Schema editors use accepts every bundled scenario and rejects what
the loader refuses for a reason a schema can express."""

from __future__ import annotations

import json

import jsonschema
import pytest
import yaml
from typer.testing import CliRunner

from conftest import ROOT, SCENARIOS, scenario_dict
from navcli.cli import app
from navcli.scenario import RANGES, ScenarioError, json_schema, parse_scenario


@pytest.fixture(scope="module")
def validator():
    schema = json.loads(CliRunner().invoke(app, ["schema"]).output)
    jsonschema.Draft7Validator.check_schema(schema)
    return jsonschema.Draft7Validator(schema)


@pytest.mark.parametrize("path", sorted(SCENARIOS.glob("*.yaml")), ids=lambda p: p.name)
def test_every_bundled_scenario_is_valid(validator, path):
    assert list(validator.iter_errors(yaml.safe_load(path.read_text()))) == []


REFUSED = {
    "unknown field": scenario_dict(obstacels=[]),
    "missing target": scenario_dict(target=None),
    "text for a number": scenario_dict(arena={"width": "wide", "height": 4}),
    "YAML 1.1 exponent": scenario_dict(noise={"odometry": "1e-3"}),
    "zero size": scenario_dict(arena={"width": 0, "height": 4}),
    "too fast": scenario_dict(robot={"start": [1, 2], "max_speed": 50}),
    "vision noise": scenario_dict(noise={"vision_distance": 0.4}),
    "seed above 64 bits": scenario_dict(mission={"seed": 2 ** 64}),
    "bad name": scenario_dict(name="Paper 8x8"),
    "name with a newline": scenario_dict(name="r\n"),
    "two target forms": scenario_dict(target={"at": [5, 2], "line": [[3, 1], [3, 3]]}),
    # any name may be an installed plugin's, so only what no name can be is the schema's to refuse
    "a pilot no name can be": scenario_dict(mission={"pilot": "auto pilot!"}),
    "circle and segment in one item": scenario_dict(obstacles=[{"circle": {"center": [3, 3], "radius": 0.2},
                                                                "segment": {"from": [1, 1], "to": [2, 2]}}]),
}


@pytest.mark.parametrize("case", REFUSED, ids=list(REFUSED))
def test_what_the_schema_rejects_the_loader_refuses(validator, case):
    data = REFUSED[case]
    assert list(validator.iter_errors(data)), case
    with pytest.raises(ScenarioError):
        parse_scenario(yaml.safe_dump(data))


def test_the_schema_and_the_loader_share_their_ranges():
    speed = json_schema()["properties"]["robot"]["properties"]["max_speed"]
    assert speed["maximum"] == 2.0 and speed["exclusiveMinimum"] == 0.0


def test_the_documented_ranges_are_the_loaders():
    rows = [ln.split("|")[1:5] for ln in (ROOT / "docs" / "scenario-format.md").read_text().splitlines()
            if ln.startswith("| `") and "≤" in ln]
    documented = {f.strip().strip("`"): (lo.strip(), hi.strip(), unit.strip()) for f, lo, hi, unit in rows}
    assert documented == {k: (("> " if r.lo_open else "≥ ") + f"{r.lo:g}", f"≤ {r.hi:d}" if isinstance(r.hi, int)
                              else f"≤ {r.hi:g}", r.unit or "-") for k, r in RANGES.items()}
