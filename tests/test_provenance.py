"""Provenance: ``navcli reproduce`` records the command line that gives its settings (argv, every
choice spelled out), the commit, whether the sources differed from it, the build and the
libraries' versions; :func:`~navcli.experiments.provenance.stale` tells a report older than the
code it depends on (``navcli/`` but its documentation files), in a repository made here."""

from __future__ import annotations

import platform
import subprocess
from dataclasses import replace
from pathlib import Path

import pytest
import typer

import navcli
from conftest import ROOT
from navcli.cli import app
from navcli.experiments import provenance
from navcli.experiments.reproduce import FULL, QUICK, command_line

GIT = ["git", "-c", "user.name=test", "-c", "user.email=test@example.org", "-c", "commit.gpgsign=false"]


def _git(root: Path, *args: str) -> str:
    return subprocess.run([*GIT, "-C", str(root), *args], capture_output=True, text=True, check=True).stdout.strip()


def _commit(root: Path, files: dict[str, str], message: str) -> str:
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    _git(root, "add", "-A")
    _git(root, "commit", "-q", "-m", message)
    return _git(root, "rev-parse", "HEAD")


@pytest.fixture
def repo(tmp_path) -> Path:
    _git(tmp_path, "init", "-q")
    _commit(tmp_path, {"navcli/a.py": "A = 1\n", "docs/page.md": "# page\n"}, "first")
    return tmp_path


def test_a_report_of_the_last_commit_stands_and_docs_only_commits_leave_it_standing(repo):
    source = provenance.record(["navcli", "reproduce"], root=repo)
    assert source["commit"] == _git(repo, "rev-parse", "HEAD") and source["dirty"] is False
    assert provenance.stale(source, repo) == []
    _commit(repo, {"navcli/notes.md": "why\n", "docs/page.md": "# page, edited\n", "README.md": "x\n"}, "docs")
    assert provenance.stale(source, repo) == []


def test_a_commit_that_changes_navcli_makes_the_report_stale(repo):
    source = provenance.record(None, root=repo)
    _commit(repo, {"navcli/a.py": "A = 2\n"}, "a changes")
    problems = provenance.stale(source, repo)
    assert problems[0] == "1 file(s) of navcli/ differ from the report's: navcli/a.py (changed)"
    assert problems[1].startswith(f"1 commit(s) since the report's commit {source['commit'][:12]}")
    assert problems[1].endswith("a changes") and len(problems) == 2


def test_an_edit_not_committed_or_a_file_added_makes_the_report_stale_and_says_which(repo):
    source = provenance.record(None, root=repo)
    (repo / "navcli" / "a.py").write_text("A = 1  # edited\n")
    assert provenance.stale(source, repo) == ["1 file(s) of navcli/ differ from the report's: navcli/a.py (changed)"]
    (repo / "navcli" / "a.py").write_text("A = 1\n")
    _commit(repo, {"navcli/b.py": "B = 1\n"}, "b added")
    assert provenance.stale(source, repo)[0] == "1 file(s) of navcli/ differ from the report's: navcli/b.py (added)"


def test_a_report_made_from_uncommitted_changes_is_stale_and_says_which(repo):
    (repo / "navcli" / "a.py").write_text("A = 3\n")
    (repo / "navcli" / "new.py").write_text("B = 1\n")
    source = provenance.record(None, root=repo)
    assert source["dirty"] is True and source["dirty_sources"] == ["navcli/a.py", "navcli/new.py"]
    assert provenance.stale(source, repo) == [
        "the report was made from uncommitted changes to navcli/a.py, navcli/new.py"
    ]
    assert "with uncommitted changes to navcli/a.py, navcli/new.py" in provenance.describe(source)


def test_a_report_stands_by_its_sources_digests_where_its_commit_is_unknown(repo):
    """A shallow clone lacks the report's commit: the files' digests still tell."""
    source = provenance.record(None, root=repo)
    assert provenance.stale(source | {"commit": "0" * 40}, repo) == []
    (repo / "navcli" / "a.py").write_text("A = 5\n")
    assert provenance.stale(source | {"commit": "0" * 40}, repo) == [
        "1 file(s) of navcli/ differ from the report's: navcli/a.py (changed)"
    ]


def test_a_report_without_a_build_or_digests_is_stale(repo):
    source = provenance.record(None, root=repo)
    for missing in ("build", "sources"):
        old = {k: v for k, v in source.items() if k != missing}
        assert provenance.stale(old, repo) == [
            "the report records no build or no digests of its sources (its source.json lacks 'build' or 'sources')"
        ]


def test_outside_a_checkout_nothing_is_claimed(tmp_path):
    source = provenance.record(None, root=tmp_path)
    assert (source["commit"], source["dirty"]) == ("unknown", None)
    assert "outside a git checkout" in provenance.describe(source)


@pytest.mark.skipif(not provenance.checkout(ROOT), reason="not a git checkout")
def test_this_checkouts_provenance_names_its_commit_build_and_libraries():
    import msgspec
    import numpy
    import pymunk
    import scipy

    source = provenance.record(["navcli", "reproduce"])
    assert source["commit"] == _git(ROOT, "rev-parse", "HEAD")
    assert source["build"] == navcli.BUILD and source["navcli_version"] == navcli.__version__
    libs = source["libraries"]
    assert libs["python"] == platform.python_version()
    for name, version in (
        ("numpy", numpy.__version__),
        ("pymunk", pymunk.version),
        ("scipy", scipy.__version__),
        ("msgspec", msgspec.__version__),
    ):
        assert libs[name] == version, name
    assert f"the {navcli.BUILD} build" in provenance.describe(source)


@pytest.mark.parametrize(
    "which, settings, jobs, scheduler, pilots",
    [
        ("all", QUICK, 3, None, ()),
        ("pilots", replace(FULL, train_seeds=2), 2, "tcp://host:8786", ("vfh_pilot:VFHPilot", "mine:Pilot")),
        ("learning", replace(QUICK, train_seeds=5), 1, None, ()),
        ("all", FULL, 16, None, ()),
    ],
)
def test_the_recorded_command_line_gives_the_same_settings_back(which, settings, jobs, scheduler, pilots, tmp_path):
    argv = command_line(which, tmp_path / "out", settings, jobs, scheduler, pilots)
    assert argv is not None and argv[:3] == ["navcli", "reproduce", which]
    command = typer.main.get_command(app).commands["reproduce"]  # type: ignore[attr-defined]
    p = command.make_context("reproduce", argv[2:]).params
    parsed = QUICK if p["quick"] else FULL
    if p["train_seeds"] is not None:
        parsed = replace(parsed, train_seeds=p["train_seeds"])
    assert (p["which"], parsed, p["jobs"], p["scheduler"], tuple(p["pilot"] or ())) == (
        which,
        settings,
        jobs,
        scheduler,
        pilots,
    )
    assert Path(p["out"]) == (tmp_path / "out").resolve()


def test_settings_no_command_line_gives_record_no_command(tmp_path):
    assert command_line("all", tmp_path, replace(QUICK, reruns=7), 2, None, ()) is None
    assert "Made from Python" in provenance.describe(provenance.record(None, root=tmp_path))
