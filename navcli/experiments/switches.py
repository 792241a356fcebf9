"""The sensitivity's switches: navcli's choices where the papers are silent, each a row that
``navcli reproduce`` runs one at a time from the defaults (its report's sensitivity section)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import yaml

from ..scenario import bundled, load_scenario, parse_scenario


@dataclass(frozen=True)
class Row:
    """A row of the sensitivity's table of switches: ``label`` and what it changes from the
    defaults, ``overrides``: a parameter by its ``--param`` name (its group one of
    :attr:`~navcli.params.Params.GROUPS`: ``pilot.look_cap``) or a field of the scenario by its
    dotted place in the file (``noise.odometry``); run with each of ``perceptions``."""

    label: str
    overrides: dict[str, Any]
    perceptions: tuple[str, ...] = ("vision", "oracle")


VISION = ("vision",)
SENSITIVITY_ROWS: tuple[Row, ...] = (
    Row("navcli's defaults", {}),
    Row("no wheel slip (the command driven exactly)", {"robot.slip_noise": 0.0}),
    Row("no stall rule (only the long blocked window)", {"navigation.stall_rule": False}),
    Row(
        "no progress is not blocked (only bumps and the Pilot's report)",
        {"navigation.blocked_no_progress": False},
        VISION,
    ),
    Row("gives up when the map shows no way out", {"navigation.gives_up": True}, VISION),
    Row("ways seen closed block for good", {"navigation.seen_closed_cost": 0.0}, VISION),
    Row("dead ends matched by their ends only", {"navigation.dead_end_radius": 0.0}, VISION),
    Row("diverting edges handed over only when seen whole", {"navigation.diverting_seen_whole": True}, VISION),
    Row("every look sees all", {"vision.routines": 0}, VISION),
    Row("lines joined by geometry", {"vision.line_objects": 0}, VISION),
    Row("walls known", {"vision.walls": "known"}, VISION),
    Row("walls felt", {"vision.walls": "felt"}, VISION),
    Row("eq. 1's look capped at 0.9", {"pilot.look_cap": 0.9}, VISION),
    Row("bumps joined by nearness alone", {"vision.bump_lines": "near"}, VISION),
    Row("a fence corrected at one end moves whole", {"vision.fence_rigid": True}, VISION),
    Row(
        "the three alternatives together",
        {"vision.routines": 0, "vision.line_objects": 0, "pilot.look_cap": 0.9},
        VISION,
    ),
)
"""The sensitivity's switches, one row each: navcli's choices where the papers are silent, one at a
time from the defaults (and the three alternative sensing choices together). A switch gets its
row here, and nowhere else: ``Row("label", {"group.name": value})``."""


def overrides_text(overrides: dict[str, Any]) -> str:
    """``a=1, b=x`` (``the defaults`` for none)."""
    return ", ".join(f"{k}={v}" for k, v in overrides.items()) or "the defaults"


def scenario_with(room: str, fields: dict[str, Any]):
    """The bundled ``room`` with the scenario ``fields`` (dotted places in its file) set: its YAML
    edited and read again, so every field is checked as a scenario file's is."""
    if not fields:
        return load_scenario(bundled.FOLDER / f"{room}.yaml")

    doc = yaml.safe_load((bundled.FOLDER / f"{room}.yaml").read_text())
    for name, value in fields.items():
        *parents, leaf = name.split(".")
        node = doc
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = value
    where = f"{room} with {overrides_text(fields)}"
    return parse_scenario(yaml.safe_dump(doc, sort_keys=False), where)
