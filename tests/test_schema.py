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
    "seed above 64 bits": scenario_dict(mission={"seed": 2**64}),
    "bad name": scenario_dict(name="Paper 8x8"),
    "name with a newline": scenario_dict(name="r\n"),
    "two target forms": scenario_dict(target={"at": [5, 2], "line": [[3, 1], [3, 3]]}),
    # any name may be an installed plugin's, so only what no name can be is the schema's to refuse
    "a pilot no name can be": scenario_dict(mission={"pilot": "auto pilot!"}),
    "circle and segment in one item": scenario_dict(
        obstacles=[{"circle": {"center": [3, 3], "radius": 0.2}, "segment": {"from": [1, 1], "to": [2, 2]}}]
    ),
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


def test_the_documented_fields_are_the_loaders():
    """docs/scenario-format.md holds the table made from the fields' declaration, and that table
    says each range as the loader checks it (RANGES, which the loader's Reader.number uses)."""
    from navcli.scenario.schema import reference_table

    table = reference_table()
    assert table in (ROOT / "docs" / "scenario-format.md").read_text(), "refresh it: navcli schema --markdown"
    rows = [ln.split("|")[1:7] for ln in table.splitlines() if ln.startswith("| `") and "≤" in ln]
    documented = {f.strip().strip("`"): (lo.strip(), hi.strip(), unit.strip()) for f, _, _, lo, hi, unit in rows}
    assert documented == {
        k.removeprefix("scenario."): (
            ("> " if r.lo_open else "≥ ") + f"{r.lo:g}",
            f"≤ {r.hi:d}" if isinstance(r.hi, int) else f"≤ {r.hi:g}",
            r.unit or "-",
        )
        for k, r in RANGES.items()
    }


def test_every_field_the_loader_takes_is_declared_and_in_the_schema(tmp_path):
    """A field's name is written once: an undeclared key is refused by the loader, and the schema's
    properties are the declaration's, block by block."""
    from navcli.scenario.model import FIELDS

    schema = json_schema()
    assert set(schema["properties"]) == set(FIELDS["scenario"])
    for block in ("arena", "robot", "target", "mission", "noise", "camera", "pilot"):
        assert set(schema["properties"][block]["properties"]) == set(FIELDS[block]), block
        assert schema["properties"][block]["required"] == [k for k, f in FIELDS[block].items() if f.required]
    items = schema["properties"]["obstacles"]["items"]["oneOf"]
    assert [set(i["properties"][k]["properties"]) for i, k in zip(items, ("circle", "segment"))] == [
        set(FIELDS["circle"]),
        set(FIELDS["segment"]),
    ]
    for block, fields in FIELDS.items():
        for key, f in fields.items():
            if f.default is not None and f.kind not in ("block", "list", "param") and block in schema["properties"]:
                assert schema["properties"][block]["properties"][key]["default"] == f.default, (block, key)


def test_the_documented_example_loads_and_shows_every_field():
    """docs/scenario-format.md's annotated example is a scenario the loader takes, and it writes
    every declared field (the target's other forms in comments): the docs cannot show a field that
    is not there, nor leave one out."""
    import re

    import yaml

    from navcli.scenario.model import FIELDS

    text = (ROOT / "docs" / "scenario-format.md").read_text()
    example = re.search(r"## Fields\n\n```yaml\n(.*?)```", text, re.S).group(1)
    parse_scenario(example, "docs/scenario-format.md")
    data = yaml.safe_load(example)
    uncommented = yaml.safe_load(re.sub(r"^(\s*)# (landmark|line):", r"\1\2:", example, flags=re.M))
    assert set(data) == set(FIELDS["scenario"])
    for block in ("arena", "robot", "mission", "noise", "camera", "pilot"):
        assert set(data[block]) == set(FIELDS[block]), block
    assert set(uncommented["target"]) == set(FIELDS["target"])
    kinds = {k: v for o in data["obstacles"] for k, v in o.items()}
    assert set(kinds["circle"]) == set(FIELDS["circle"]) and set(kinds["segment"]) == set(FIELDS["segment"])
    assert set(data["landmarks"][0]) == set(FIELDS["landmark"])
