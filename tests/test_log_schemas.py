"""The log's published schemas: the JSON Schema of every JSON topic is checked in per format version
(navcli/log/schemas/vN/, :mod:`navcli.log.published`), so a change to a message (a field renamed,
retyped, added) fails here until the format version is bumped, its schemas written by the explicit
command and docs/log-format.md says which version it describes. The log names its version."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from conftest import ROOT
from navcli.log import format as fmt
from navcli.log import published

COMMAND = "python -m navcli.log.published --write-schemas"


def test_the_codes_schemas_are_the_checked_in_ones_of_the_format_version():
    problems = published.differences()
    assert problems == [], (
        f"the log's schemas changed: bump FORMAT_VERSION in navcli/log/format.py, run `{COMMAND}` and "
        f"describe the change in docs/log-format.md; {problems}"
    )
    assert sorted(p.name for p in published.folder().glob("*.json")) == sorted(
        published.file_name(t) for t in fmt.MESSAGES
    )
    assert not published.folder(fmt.FORMAT_VERSION + 1).exists()  # no version ahead of the code's


def test_every_published_version_is_kept():
    """A reader of an old log finds its schemas: every version up to the current one is checked in."""
    versions = sorted(int(p.name[1:]) for p in published.SCHEMAS.glob("v*"))
    assert versions == list(range(1, fmt.FORMAT_VERSION + 1))


def test_a_renamed_pilot_field_differs_from_the_published_schema(monkeypatch):
    """What the first test guards against, made on purpose: ``bid`` of ``/pilot`` renamed."""
    from navcli.log import writer

    real = writer.log_schema

    def renamed(cls):
        schema = real(cls)
        if cls is fmt.Pilot:
            props = dict(schema["properties"])
            props["motion_bid"] = props.pop("bid")
            schema = schema | {"properties": props, "required": [*schema["required"], "motion_bid"]}
        return schema

    monkeypatch.setattr(writer, "log_schema", renamed)
    problems = published.differences()
    assert len(problems) == 1 and problems[0].startswith(str(published.folder() / "pilot.json")), problems
    with pytest.raises(ValueError, match="bump FORMAT_VERSION"):
        published.write()  # the published version is not rewritten to match
    assert json.loads((published.folder() / "pilot.json").read_text())["properties"]["bid"]["maximum"] == 1.0


def test_the_write_command_writes_the_next_version_and_keeps_the_old(tmp_path, monkeypatch, capsys):
    for t in fmt.MESSAGES:  # the current version's, copied where the command looks
        name = published.file_name(t)
        (tmp_path / f"v{fmt.FORMAT_VERSION}").mkdir(exist_ok=True)
        (tmp_path / f"v{fmt.FORMAT_VERSION}" / name).write_text((published.folder() / name).read_text())
    monkeypatch.setattr(published, "SCHEMAS", tmp_path)
    assert published.main([]) == 0 and "the checked-in schemas" in capsys.readouterr().out
    monkeypatch.setattr(published, "FORMAT_VERSION", fmt.FORMAT_VERSION + 1)
    assert published.main(["--write-schemas"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"v{fmt.FORMAT_VERSION}", f"v{fmt.FORMAT_VERSION + 1}"]
    assert len(list((tmp_path / f"v{fmt.FORMAT_VERSION + 1}").glob("*.json"))) == len(fmt.MESSAGES)


def test_the_log_names_its_format_version_and_the_docs_the_current_one(tmp_path):
    from navcli.analysis import read_log
    from navcli.cli import app

    r = CliRunner().invoke(app, ["run", "open-arena", "--time-limit", "1", "--out", str(tmp_path / "a.mcap")])
    assert r.exit_code == 3, r.output  # a timeout: the log is complete
    assert read_log(tmp_path / "a.mcap").metadata["run"]["log_format"] == str(fmt.FORMAT_VERSION)
    doc = (ROOT / "docs" / "log-format.md").read_text()
    assert f"format version {fmt.FORMAT_VERSION}" in doc and COMMAND in doc
