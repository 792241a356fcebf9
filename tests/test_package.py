"""What every package has: a licence (in a file and in pyproject.toml), a citation file that is valid
Citation File Format, ``navcli --version``, the version written in one place, a changelog."""

from __future__ import annotations

import json
import re
import tomllib

import jsonschema
import pytest
import yaml
from typer.testing import CliRunner

import navcli
from conftest import ROOT
from navcli.cli import app

CFF_SCHEMA = ROOT / "tests" / "data" / "citation-file-format-1.2.0.schema.json"


@pytest.fixture(scope="module")
def pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


@pytest.fixture(scope="module")
def citation() -> dict:
    return yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))


def cff_errors(doc: dict) -> list[str]:
    """What the Citation File Format 1.2.0 schema (JSON Schema draft 7, with its formats) finds wrong."""
    schema = json.loads(CFF_SCHEMA.read_text())
    validator = jsonschema.Draft7Validator(schema, format_checker=jsonschema.Draft7Validator.FORMAT_CHECKER)
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(doc)]


def test_the_licence_is_mit_in_the_file_and_in_the_package_metadata(pyproject):
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License\n")
    assert "Permission is hereby granted, free of charge" in text
    assert pyproject["project"]["license"] == "MIT"  # an SPDX expression (PEP 639)
    assert pyproject["project"]["license-files"] == ["LICENSE"]


def test_the_version_is_written_once_and_navcli_says_it(pyproject):
    assert "version" not in pyproject["project"] and "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "navcli.__version__"}
    assert re.fullmatch(r"\d+\.\d+\.\d+", navcli.__version__)
    res = CliRunner().invoke(app, ["--version"])
    assert res.exit_code == 0 and res.output.startswith(f"navcli {navcli.__version__}, {navcli.BUILD} (")


def test_citation_file_is_valid_citation_file_format(citation):
    assert cff_errors(citation) == []
    assert citation["cff-version"] == "1.2.0" and citation["type"] == "software"
    assert str(citation["version"]) == navcli.__version__
    assert citation["license"] == "MIT"


def test_the_schema_check_would_refuse_a_broken_citation(citation):
    """The check above can fail: the same file without its authors, with an unknown key, with a
    reference of a type the format does not have, is refused."""
    broken = {k: v for k, v in citation.items() if k != "authors"} | {"licence": "MIT"}
    broken["references"] = [citation["references"][0] | {"type": "blog-pst"}]
    errors = "\n".join(cff_errors(broken))
    assert "'authors' is a required property" in errors
    assert "'licence' was unexpected" in errors
    assert "references/0/type" in errors


def test_citation_names_both_papers_as_references(citation):
    refs = {r["title"]: r for r in citation["references"]}
    pilot = refs[
        "Integrating a potential field based pilot into a multiagent navigation architecture for autonomous robots"
    ]
    learning = refs[
        "A multi-agent architecture integrating learning and fuzzy techniques for landmark-based robot navigation"
    ]
    assert [a["family-names"] for a in pilot["authors"]] == ["Mohan", "Busquets", "López de Màntaras", "Sierra"]
    assert [a["family-names"] for a in learning["authors"]] == ["Busquets", "López de Mántaras", "Sierra", "Dietterich"]
    assert (pilot["year"], learning["year"]) == (2004, 2002)


def test_the_changelog_keeps_a_changelog_and_its_top_release_is_this_version():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert text.startswith("# Changelog\n")
    assert "https://keepachangelog.com/en/1.1.0/" in text
    releases = re.findall(r"^## \[([^\]]+)\]", text, re.M)
    assert releases and releases[0] in ("Unreleased", navcli.__version__)
    assert navcli.__version__ in releases
    sections = set(re.findall(r"^### (\w+)", text, re.M))
    assert sections and sections <= {"Added", "Changed", "Deprecated", "Removed", "Fixed", "Security"}
