"""The log keeps its own contract: every bundled scenario, with both pilots and both perceptions,
run to its end (at most LIMIT simulated seconds), every JSON message validated against the schema
stored in its own log; and every enumeration the log carries is the one of the code that produces
it (the Rescuer's states, the Pilot's modes ...).

The runs go to two worker processes, each validating its own logs with jsonschema-rs (some 25 us a
message, against some 800 us with the pure-Python jsonschema: the 56 runs of the 14 bundled rooms
hold some 220,000 messages). LIMIT = 150 s (our choice, for the suite's time: the runs take some 50
CPU seconds, 44 s of wall time on two shared cores) reaches the end of the open rooms' and landmark
rooms' missions (30 of 56 reached, 3 blocked), and in the trap rooms the Rescuer's blocked
situations, drives out and explorations (its states ``drive`` and ``explore``, which the schema did
not allow before: a 400 s trap-box run wrote 243 messages its own schema refused, and these runs,
at 8a73a5e, 821); at the paper's pace (5 cm/s, the 8 m rooms) it is half a mission.
"""

from __future__ import annotations

import ast
import json
import os
from collections import Counter
from pathlib import Path

import pytest

from conftest import ROOT, SCENARIOS

LIMIT = float(os.environ.get("NAVCLI_CONTRACT_LIMIT", "150"))
"""Simulated seconds a run may last here (see the module docstring); ``NAVCLI_CONTRACT_LIMIT=900``
runs every mission to its own limit (some 5 minutes on two cores)."""
PILOTS = ("potential-field", "geometric")
PERCEPTIONS = ("vision", "oracle")


def validate_run(job: tuple[str, str, str, str]) -> dict:
    """Run one mission to its end (or LIMIT) into a log, then check every JSON message of it
    against the schema stored in the same log (in a worker process)."""
    import jsonschema_rs
    from mcap.reader import make_reader

    from navcli import RunSpec, load_scenario
    from navcli.runner import run_mission

    name, pilot, perception, folder = job
    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    # with gives_up (off by default: the Rescuer then never ends a mission), trap-box ends blocked
    # and its log holds the give-up path's messages too
    spec = RunSpec.build(
        sc,
        pilot=pilot,
        perception=perception,
        time_limit=min(sc.mission.time_limit, LIMIT),
        overrides={"navigation.gives_up": True},
    )
    log = Path(folder) / f"{name}-{pilot}-{perception}.mcap"
    summary = run_mission(spec, out=log).summary
    validators, messages, errors, rescuer = {}, 0, [], Counter()
    with log.open("rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if channel.message_encoding != "json":
                continue
            v = validators.get(channel.id)
            if v is None:
                v = validators[channel.id] = jsonschema_rs.validator_for(json.loads(schema.data))
            msg = json.loads(message.data)
            messages += 1
            if not v.is_valid(msg):
                errors += [
                    f"{channel.topic} at {message.log_time / 1e9:.1f} s: {e.message}" for e in v.iter_errors(msg)
                ]
            if channel.topic == "/navigation":
                rescuer[msg["rescuer"]] += 1
    return {
        "run": f"{name} {pilot} {perception}",
        "outcome": summary["outcome"],
        "time_s": summary["time_s"],
        "messages": messages,
        "errors": errors,
        "rescuer": rescuer,
        "topics": len(validators),
    }


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> list[dict]:
    from navcli.experiments.executor import executor, map_ordered

    folder = str(tmp_path_factory.mktemp("contract"))
    names = sorted(p.stem for p in SCENARIOS.glob("*.yaml"))
    jobs = [(n, p, q, folder) for n in names for p in PILOTS for q in PERCEPTIONS]
    with executor(2) as ex:
        return map_ordered(validate_run, jobs, ex)


def test_every_json_message_of_every_bundled_scenario_matches_the_schema_in_its_log(runs):
    names = sorted(p.stem for p in SCENARIOS.glob("*.yaml"))
    assert len(runs) == len(names) * len(PILOTS) * len(PERCEPTIONS) and len(names) >= 12
    bad = [(r["run"], e) for r in runs for e in r["errors"]]
    assert bad == [], f"{len(bad)} messages break their log's schema, first: {bad[:5]}"
    assert all(r["topics"] == 5 for r in runs)  # /pilot, /bids, /vision, /navigation, /mission/summary
    assert sum(r["messages"] for r in runs) > 100_000
    ends = Counter(r["outcome"] for r in runs)
    assert ends["reached"] >= 20 and ends["blocked"] >= 1  # most missions run to their end within the limit


def test_the_runs_meet_every_state_of_the_rescuer(runs):
    """The long runs reach the states the schema once lacked (drive, explore): the check above
    would have failed on them."""
    from navcli.navigation.rescuer import STATES

    seen = sum((r["rescuer"] for r in runs), Counter())
    assert set(seen) <= set(STATES) and {"sweep", "normal", "turn", "drive", "explore"} <= set(seen), seen


def test_each_enumeration_of_the_log_is_the_producers():
    from navcli.log.format import ENUM, MESSAGES
    from navcli.log.writer import enums, log_schema
    from navcli.mission import OUTCOMES
    from navcli.navigation.rescuer import STATES

    marked = set()

    def walk(node: dict) -> None:
        if isinstance(node, dict):
            if ENUM in node:
                marked.add(node[ENUM])
            for v in node.values():
                walk(v) if isinstance(v, dict) else [walk(x) for x in v if isinstance(x, dict)] if isinstance(
                    v, list
                ) else None

    import msgspec

    for cls in MESSAGES.values():
        walk(msgspec.json.schema(cls))
        assert ENUM not in json.dumps(log_schema(cls))  # every mark became an enum
    assert marked == set(enums()) and len(marked) == 10
    schema = log_schema(MESSAGES["/navigation"])
    assert schema["properties"]["rescuer"]["enum"] == list(STATES)
    assert log_schema(MESSAGES["/mission/summary"])["properties"]["outcome"]["enum"] == list(OUTCOMES)


def test_the_rescuer_enters_no_state_it_does_not_declare():
    """Every state the Rescuer's code sets (``self.state = ...``, ``self._enter(...)``) is one of
    its STATES: read from its source, so a new state cannot be added without declaring it."""
    from navcli.navigation.rescuer import STATES

    tree = ast.parse((ROOT / "navcli" / "navigation" / "rescuer.py").read_text())
    used = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Attribute) and t.attr == "state" for t in node.targets
        ):
            used |= {c.value for c in ast.walk(node.value) if isinstance(c, ast.Constant) and isinstance(c.value, str)}
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "_enter":
            used |= {
                c.value for c in ast.walk(node.args[0]) if isinstance(c, ast.Constant) and isinstance(c.value, str)
            }
    assert used and used <= set(STATES), used - set(STATES)
    assert {"drive", "explore"} <= used
