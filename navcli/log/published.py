"""The published JSON Schemas of the log's own topics, one folder per log format version.

A log's JSON messages are read by tools navcli does not know (a notebook, a Foxglove panel, a
colleague's script), so their schemas are a published contract: the schemas of format version
``N`` (:data:`~navcli.log.format.FORMAT_VERSION`) are checked in as ``navcli/log/schemas/vN/``,
one file per topic, and the tests compare what the code generates with them. Any change to a
message (a field renamed, added or retyped, an enumeration or a description changed) therefore
fails the tests until the format version is bumped and the new version's schemas are written by
an explicit command::

    python -m navcli.log.published --write-schemas

which writes the folder of the current version and refuses to change one already written (a
published version is never rewritten: bump :data:`~navcli.log.format.FORMAT_VERSION` first).
The schemas are those the log stores (:func:`navcli.log.writer.log_schema`, the producers'
enumerations included); the Foxglove topics' schemas are Foxglove's, not navcli's.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .format import FORMAT_VERSION, MESSAGES

SCHEMAS = Path(__file__).resolve().parent / "schemas"
"""The checked-in schemas: ``vN/<topic>.json`` per format version N."""


def file_name(topic: str) -> str:
    """The schema file of ``topic``: ``/mission/summary`` -> ``mission-summary.json``."""
    return topic.strip("/").replace("/", "-") + ".json"


def folder(version: int | None = None) -> Path:
    """The checked-in schemas of format ``version`` (by default the current one)."""
    return SCHEMAS / f"v{FORMAT_VERSION if version is None else version}"


def generated() -> dict[str, str]:
    """File name -> the text of each JSON topic's schema as the code generates it now (sorted keys,
    indented, a final newline: a diff shows the field that changed)."""
    from .writer import log_schema

    return {file_name(t): json.dumps(log_schema(cls), indent=2, sort_keys=True) + "\n" for t, cls in MESSAGES.items()}


def differences(version: int | None = None) -> list[str]:
    """How the generated schemas differ from the checked-in ones of ``version``: a line per file
    missing, extra or different, with its first differing line; empty when they agree."""
    want, where = generated(), folder(version)
    have = {p.name: p.read_text() for p in where.glob("*.json")} if where.is_dir() else {}
    out = [f"{where / n}: not checked in" for n in sorted(want.keys() - have.keys())]
    out += [f"{where / n}: no such topic in the log" for n in sorted(have.keys() - want.keys())]
    for n in sorted(want.keys() & have.keys()):
        if want[n] != have[n]:
            out.append(f"{where / n}: differs from the code's, first at {_first_difference(have[n], want[n])}")
    return out


def _first_difference(old: str, new: str) -> str:
    for k, (a, b) in enumerate(zip(old.splitlines(), new.splitlines()), 1):
        if a != b:
            return f"line {k}: {a.strip()!r} -> {b.strip()!r}"
    return "the end (one is longer)"


def write(version: int | None = None) -> Path:
    """Write the schemas of ``version`` into :func:`folder`; refuse (``ValueError``) when that
    version is checked in already with other schemas: a published version is never rewritten."""
    where = folder(version)
    if where.is_dir() and differences(version):
        raise ValueError(
            f"{where} holds a published format version's schemas, which differ from the code's; "
            "bump FORMAT_VERSION in navcli/log/format.py, then write the new version's"
        )
    where.mkdir(parents=True, exist_ok=True)
    for name, text in generated().items():
        (where / name).write_text(text)
    return where


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m navcli.log.published", description=__doc__.split("\n")[0])
    parser.add_argument(
        "--write-schemas", action="store_true", help="write the current format version's schemas (never rewrites one)"
    )
    args = parser.parse_args(argv)
    if args.write_schemas:
        try:
            print(f"wrote {write()}")
        except ValueError as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
        return 0
    problems = differences()
    for p in problems:
        print(p)
    print(f"format version {FORMAT_VERSION}: {'differs' if problems else 'the checked-in schemas'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
