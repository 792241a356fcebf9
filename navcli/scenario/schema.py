"""The scenario format as a JSON Schema (for editors: the YAML language server), built from the
same ranges the loader checks."""

from __future__ import annotations

from typing import Any

from ..params import CLUSTERS, NavigationParams
from ..plugins.names import BUILTIN_PILOTS, PILOT_PATTERN
from .model import FIELDS, MAX_ID, MAX_ITEMS, POINT, Field
from .model import NAME_RE as SCENARIO_NAME_RE
from .yaml_reader import MAX_SCALAR

POINT_SCHEMA = {
    "type": "array",
    "description": "[x, y] in metres, inside the arena",
    "minItems": 2,
    "maxItems": 2,
    "items": {"type": "number", "minimum": POINT.lo, "maximum": POINT.hi},
}


def json_schema() -> dict[str, Any]:
    """The scenario format as a JSON Schema (draft-07), built from the fields' declarations
    (:data:`~navcli.scenario.model.FIELDS`) the loader reads. It catches what a schema can (fields,
    types, ranges, names); where things are (inside the arena, clear of obstacles, a reachable
    target) only the loader checks."""
    top = FIELDS["scenario"]
    return {
        "$schema": "http://json-schema.org/draft-07/schema#",
        "$id": "https://navcli/scenario-v1.schema.json",
        "title": "navcli scenario, version 1",
        "description": "Metres, seconds, degrees in keys ending _deg. Write exponents with a point and a sign "
        "(1.0e-3): YAML 1.1 reads 1e-3 as text.",
        **_block_schema(
            "scenario",
            version={"const": 1, "description": top["version"].description},
            name={
                "type": "string",
                "pattern": f"^{SCENARIO_NAME_RE.pattern}$",
                "not": {"pattern": "\n"},  # no trailing newline
                "description": top["name"].description,
            },
            arena=_block_schema("arena"),
            robot=_block_schema("robot"),
            target=_target_schema(),
            obstacles=_obstacles_schema(),
            landmarks={
                "type": "array",
                "maxItems": MAX_ITEMS,
                "description": top["landmarks"].description,
                "items": _block_schema("landmark"),
            },
            mission=_mission_schema(),
            noise=_block_schema("noise"),
            camera=_block_schema("camera"),
            pilot=_block_schema("pilot"),
            navigation=_navigation_schema(),
        ),
    }


def _field_schema(f: Field) -> dict[str, Any]:
    """One scalar field's schema: its description (with its unit), default, type and range."""
    d: dict[str, Any] = {"description": f.description + (f" ({f.range.unit})" if f.range and f.range.unit else "")}
    if f.default is not None and f.kind not in ("list", "block"):
        d["default"] = f.default
    if f.kind in ("number", "param", "integer"):
        d["type"] = "integer" if f.kind == "integer" else "number"
        if f.range is not None:
            d |= {"maximum": f.range.hi, ("exclusiveMinimum" if f.range.lo_open else "minimum"): f.range.lo}
        return d
    kinds: dict[str, dict[str, Any]] = {
        "point": POINT_SCHEMA,
        "line": {"type": "array", "minItems": 2, "maxItems": 2, "items": POINT_SCHEMA},
        "id": {"type": ["string", "integer"], "minLength": 1, "maxLength": MAX_ID},
        "text": {"type": "string", "maxLength": MAX_SCALAR},
        "choice": {"enum": list(f.choices)},
    }
    return d | kinds[f.kind]


def _block_schema(which: str, /, **special: dict) -> dict[str, Any]:
    """A block of fields (``FIELDS[which]``) as a closed object; ``special`` gives the schema of the
    fields a plain field's schema cannot describe (nested blocks, lists, patterns)."""
    fields = FIELDS[which]
    props = {k: special.get(k) or _field_schema(f) for k, f in fields.items()}
    return {
        "type": "object",
        "properties": props,
        "additionalProperties": False,
        "required": [k for k, f in fields.items() if f.required],
    }


def _target_schema() -> dict[str, Any]:
    """The target block: exactly one of a point, a landmark or a line."""
    return _block_schema("target") | {
        "description": FIELDS["scenario"]["target"].description,
        "oneOf": [{"required": [k]} for k in ("at", "landmark", "line")],
    }


def _obstacles_schema() -> dict[str, Any]:
    """The obstacle list: each item a one-key object, a circle or a segment."""

    def one(kind: str) -> dict[str, Any]:
        return {
            "type": "object",
            "properties": {kind: _block_schema(kind)},
            "required": [kind],
            "additionalProperties": False,
        }

    return {
        "type": "array",
        "maxItems": MAX_ITEMS,
        "description": FIELDS["scenario"]["obstacles"].description,
        "items": {"oneOf": [one("circle"), one("segment")]},
    }


def _mission_schema() -> dict[str, Any]:
    """The mission block, its pilot named by :mod:`navcli.plugins.names`."""
    return _block_schema(
        "mission",
        pilot={
            "type": "string",
            "pattern": PILOT_PATTERN,
            "examples": list(BUILTIN_PILOTS),
            "description": FIELDS["mission"]["pilot"].description,
            "default": BUILTIN_PILOTS[0],
        },
    )


def _navigation_schema() -> dict[str, Any]:
    """The navigation block: a cluster and the Navigation system's scalar parameters, from their
    declarations."""
    return {
        "type": "object",
        "additionalProperties": False,
        "required": [],
        "description": FIELDS["scenario"]["navigation"].description,
        "properties": {
            "cluster": {
                "enum": list(CLUSTERS),
                "description": "the thesis' GA-tuned "
                "bidding parameters: C1 (default, targets reachable directly) or C2 (behind "
                "obstacles)",
            }
        }
        | {
            k: d.json_schema(default)
            for k, d, default in NavigationParams.declarations()
            if d.kind not in ("numbers", "intervals")
        },
    }


def reference_table() -> str:
    """Every field of the format with what it is, its default, its range and unit, as a Markdown
    table: docs/scenario-format.md's "Fields, one by one" (``navcli schema --markdown``)."""
    rows = ["| field | what it is | default | from | to | unit |", "| --- | --- | --- | --- | --- | --- |"]
    for block, fields in FIELDS.items():
        for key, f in fields.items():
            if f.kind in ("block", "list"):
                continue
            where = key if block == "scenario" else f"{block}.{key}"
            default = (
                "required"
                if f.required
                else "-"
                if f.default is None
                else "empty"
                if f.default == ""
                else f"`{f.default}`"
                if not isinstance(f.default, float)
                else f"`{f.default:g}`"
            )
            r = f.range
            lo = "" if r is None else ("> " if r.lo_open else "≥ ") + f"{r.lo:g}"
            hi = "" if r is None else f"≤ {r.hi:d}" if isinstance(r.hi, int) else f"≤ {r.hi:g}"
            unit = (r.unit or "-") if r is not None else "m" if f.kind in ("point", "line") else "-"
            rows.append(f"| `{where}` | {f.description} | {default} | {lo} | {hi} | {unit} |")
    r = POINT
    rows.append(
        f"| `point` | any coordinate of a point above, before it is checked against the arena | - | "
        f"≥ {r.lo:g} | ≤ {r.hi:g} | {r.unit} |"
    )
    return "\n".join(rows) + "\n"
