"""A log checked against its own schemas: every JSON message against the JSON Schema its channel
carries, with no library beyond the standard one (``navcli plugins check`` runs it on a plugin's
short run; the test suite checks it agrees with ``jsonschema`` on the bundled rooms' logs).

It knows the keywords navcli's schemas use (:data:`KEYWORDS`, what
:func:`navcli.log.format.json_schema` makes of the log's message structs) and refuses a schema
using any other, so that a keyword it would silently skip cannot pass a message it breaks.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Iterator

from mcap.reader import make_reader

KEYWORDS = frozenset(
    {"title", "description", "type", "properties", "required", "additionalProperties", "items", "enum"}
    | {"minimum", "maximum"}
)
"""The JSON Schema keywords of navcli's log schemas, each checked (``title`` and ``description``
say nothing to check)."""


def unchecked(schema: Any, at: str = "") -> list[str]:
    """The keywords of ``schema`` (and the schemas inside it) outside :data:`KEYWORDS`, which
    :func:`schema_problems` would not check, as ``where: keyword``."""
    if not isinstance(schema, dict):
        return []
    out = [f"{at or 'root'}: {k}" for k in sorted(set(schema) - KEYWORDS)]
    for k, sub in schema.get("properties", {}).items():
        out += unchecked(sub, f"{at}.{k}" if at else k)
    for key in ("items", "additionalProperties"):
        out += unchecked(schema.get(key), f"{at}[{key}]")
    return out


def schema_problems(schema: dict[str, Any], value: Any, at: str = "") -> list[str]:
    """Why ``value`` (a decoded JSON message, or part of one at ``at``; a tuple counts as an
    array) breaks ``schema``, a schema :func:`unchecked` finds nothing in: one line each, empty
    when it does not."""
    where = at or "the message"
    kind = schema.get("type")
    if kind is not None and not _of_type(value, kind):
        return [f"{where} is {_short(value)}, not of type {kind}"]
    if "enum" in schema and value not in schema["enum"]:
        return [f"{where} is {_short(value)}, not one of {', '.join(map(str, schema['enum']))}"]
    out = []
    if "minimum" in schema and _of_type(value, "number") and value < schema["minimum"]:
        out.append(f"{where} is {value!r}, below its minimum {schema['minimum']!r}")
    if "maximum" in schema and _of_type(value, "number") and value > schema["maximum"]:
        out.append(f"{where} is {value!r}, above its maximum {schema['maximum']!r}")
    if isinstance(value, dict):
        out += _object_problems(schema, value, at)
    if isinstance(value, (list, tuple)) and "items" in schema:
        for i, item in enumerate(value):
            out += schema_problems(schema["items"], item, f"{at}[{i}]")
    return out


def _object_problems(schema: dict[str, Any], value: dict[str, Any], at: str) -> list[str]:
    props = schema.get("properties", {})
    extra = schema.get("additionalProperties", True)
    out = [f"{at + '.' if at else ''}{k} is missing" for k in schema.get("required", ()) if k not in value]
    for k, v in value.items():
        here = f"{at}.{k}" if at else k
        if k in props:
            out += schema_problems(props[k], v, here)
        elif extra is False:
            out.append(f"{here}: a key its schema does not allow (allowed: {', '.join(props) or 'none'})")
        elif isinstance(extra, dict):
            out += schema_problems(extra, v, here)
    return out


def _of_type(value: Any, kind: str | list[str]) -> bool:
    if isinstance(kind, list):
        return any(_of_type(value, k) for k in kind)
    if kind == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind == "integer":
        return isinstance(value, int) and not isinstance(value, bool) or isinstance(value, float) and value.is_integer()
    if kind == "null":
        return value is None
    types: dict[str, type | tuple[type, ...]] = {"object": dict, "array": (list, tuple), "string": str, "boolean": bool}
    return isinstance(value, types[kind])


def _short(x: Any) -> str:
    r = json.dumps(x) if not isinstance(x, float) or math.isfinite(x) else repr(x)
    return r if len(r) <= 80 else r[:77] + "..."


def json_messages(path: str | Path) -> Iterator[tuple[str, float, dict[str, Any], Any]]:
    """(topic, log time in s, its channel's schema, the decoded message) of every JSON message of
    the log at ``path``, in the order they were written."""
    schemas: dict[int, dict[str, Any]] = {}
    with Path(path).open("rb") as f:
        for schema, channel, message in make_reader(f).iter_messages(log_time_order=False):
            if channel.message_encoding != "json" or schema is None:
                continue
            parsed = schemas.get(channel.id)
            if parsed is None:
                parsed = schemas[channel.id] = json.loads(schema.data)
            yield channel.topic, message.log_time / 1e9, parsed, json.loads(message.data)


def log_problems(path: str | Path) -> tuple[int, list[str]]:
    """How many JSON messages the log at ``path`` holds, and every way one breaks its channel's
    schema (``topic at T s: problem``). Raises ``ValueError`` for a schema :func:`unchecked` finds
    keywords in."""
    count, out, seen = 0, [], set()
    for topic, t, schema, message in json_messages(path):
        count += 1
        if topic not in seen:
            seen.add(topic)
            bad = unchecked(schema)
            if bad:
                raise ValueError(f"{topic}'s schema has keywords not checked here: {', '.join(bad)}")
        out += [f"{topic} at {t:.1f} s: {p}" for p in schema_problems(schema, message)]
    return count, out
