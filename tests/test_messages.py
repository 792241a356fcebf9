"""The JSON topics of real runs against their schemas (jsonschema), and every schema against the
rules of Foxglove's JSON-schema parser (the viewer drops a whole topic whose schema it rejects)."""

from __future__ import annotations

import json

import jsonschema
import pytest
import yaml
from mcap.reader import make_reader

from conftest import SCENARIOS, scenario_dict
from navcli.config import RunSpec
from navcli.log.format import MESSAGES
from navcli.log.format import viewer_problems as foxglove_problems
from navcli.log.writer import log_schema as json_schema
from navcli.runner import run_mission
from navcli.scenario import load_scenario


def test_the_checker_refuses_what_foxglove_refuses():
    assert foxglove_problems({"type": "object", "properties": {"a": {"type": "object"}}}) == [
        "a: object without properties"
    ]
    assert foxglove_problems({"type": "object", "properties": {"a": {"type": ["number", "null"]}}})
    assert foxglove_problems({"type": "object", "properties": {"a": {"$ref": "#/$defs/A"}}})
    assert foxglove_problems({"type": "object", "properties": {"a": {"enum": ["x"]}}})
    assert foxglove_problems({"type": "object", "properties": {"a": {"type": "array", "items": {"type": "null"}}}})
    assert not foxglove_problems(
        {"type": "object", "properties": {"a": {"type": "array", "items": {"type": "number"}}}}
    )


def _objects(node: dict, path: str = ""):
    yield path, node
    for name, f in node.get("properties", {}).items():
        if f.get("type") == "object":
            yield from _objects(f, f"{path}.{name}")
        if f.get("type") == "array" and f["items"].get("type") == "object":
            yield from _objects(f["items"], f"{path}.{name}[]")
    if isinstance(node.get("additionalProperties"), dict) and node["additionalProperties"].get("type") == "object":
        yield from _objects(node["additionalProperties"], f"{path}.*")


@pytest.mark.parametrize("topic", sorted(MESSAGES))
def test_every_schema_is_accepted_by_foxglove_and_fully_described(topic):
    schema = json_schema(MESSAGES[topic])
    assert schema["title"] == f"navcli.{MESSAGES[topic].__name__}"
    assert foxglove_problems(schema) == []
    jsonschema.Draft202012Validator.check_schema(schema)
    assert "$ref" not in json.dumps(schema) and "null" not in json.dumps(schema)
    for path, obj in _objects(schema):
        # a fixed shape is closed; a map (keys are ids) declares what its values are
        assert obj.get("additionalProperties") is False or isinstance(obj.get("additionalProperties"), dict), path
        for name, f in obj["properties"].items():
            assert "type" in f, f"{path}.{name}"


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Four short real runs: both pilots, vision and oracle, and one with a bump and its reflex."""
    d = tmp_path_factory.mktemp("msglogs")
    paper = load_scenario(SCENARIOS / "paper-8x8.yaml")
    bump = d / "bump.yaml"
    bump.write_text(
        yaml.safe_dump(
            scenario_dict(
                obstacles=[{"circle": {"center": [2.5, 2.0], "radius": 0.15}}],
                camera={"range": 0.3},
                noise={"odometry": 0.0},
            )
        )
    )
    fast = {"robot.max_speed": 0.3}  # in 12 s a robot at the paper's pace meets no obstacle
    runs = {
        "pf-vision": RunSpec.build(paper, seed=1, time_limit=12.0, overrides=fast),
        "geometric-vision": RunSpec.build(paper, seed=1, pilot="geometric", time_limit=12.0, overrides=fast),
        "geometric-oracle": RunSpec.build(
            paper, seed=2, pilot="geometric", perception="oracle", time_limit=12.0, overrides=fast
        ),
        "reflex": RunSpec.build(load_scenario(bump), time_limit=12.0),
    }
    out = {}
    for name, spec in runs.items():
        out[name] = d / f"{name}.mcap"
        run_mission(spec, out=out[name])
    return out


def _json_messages(path):
    with open(path, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if channel.message_encoding == "json":
                yield channel.topic, json.loads(schema.data), json.loads(message.data)


def test_every_json_message_of_real_runs_matches_its_schema(logs):
    seen: dict[str, set] = {}
    pilot_keys: set[str] = set()
    for name, path in logs.items():
        validators: dict[str, jsonschema.Draft202012Validator] = {}
        for topic, schema, msg in _json_messages(path):
            assert schema == json_schema(MESSAGES[topic])  # the schema in the file is the definition's
            v = validators.setdefault(topic, jsonschema.Draft202012Validator(schema))
            errors = [f"{name} {topic}: {e.json_path}: {e.message}" for e in v.iter_errors(msg)]
            assert not errors, errors[:3]
            seen.setdefault(topic, set()).add(name)
            if topic == "/pilot":
                pilot_keys |= set(msg)
                pilot_keys |= {f"obstacles.{k}" for k in msg.get("obstacles", {})}
    assert set(seen) == set(MESSAGES) and all(len(v) == len(logs) for v in seen.values())
    # the runs exercise every variant of /pilot: forces of remembered obstacles, the geometric
    # rules, a reflex's phases
    assert {"net", "raw_turn_deg", "nearest", "clearance", "rule", "side", "phase"} <= pilot_keys
    assert any(k.startswith("obstacles.") for k in pilot_keys)


def test_every_forwarded_bid_names_the_agent_it_came_from(logs):
    named = 0
    for name, path in logs.items():
        msgs = [m for topic, _, m in _json_messages(path) if topic == "/navigation"]
        agents = set().union(*(m["agents"] for m in msgs))
        for m in msgs:
            fwd = m["forwarded"]
            for r in ("motion", "camera"):
                if fwd[r] > 0:  # a bid was forwarded: whose, even when it was held from an earlier tick
                    assert fwd.get(f"{r}_agent") in agents, (name, m)
                    named += 1
                else:
                    assert f"{r}_agent" not in fwd
    assert named > 100
