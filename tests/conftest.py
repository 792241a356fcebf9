"""Shared helpers: small scenarios written on the fly, so each test states the arena it needs."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import yaml
from hypothesis import settings

# CI (CI=true) runs the property tests derandomised: the same 100 examples every run, so a red CI
# is a real regression, not a new random draw. Locally they explore new examples each run
# (HYPOTHESIS_PROFILE=ci to replay CI's; HYPOTHESIS_PROFILE=thorough for 2,000 per property).
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True, max_examples=100)
settings.register_profile("dev", deadline=None, max_examples=100)
settings.register_profile("thorough", deadline=None, max_examples=2000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "dev"))

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"


def pytest_addoption(parser):
    parser.addoption(
        "--update-goldens",
        action="store_true",
        default=False,
        help="rewrite tests/golden/*.json from fresh runs instead of comparing to them",
    )


def scenario_dict(**over) -> dict:
    """A valid open-room scenario; keyword arguments replace top-level blocks."""
    d = {
        "version": 1,
        "name": "test-room",
        "arena": {"width": 6.0, "height": 4.0},
        "robot": {"start": [1.0, 2.0], "heading_deg": 0},
        "target": {"at": [5.0, 2.0]},
        "mission": {"time_limit": 60, "seed": 7},
    }
    d.update(over)
    return {k: v for k, v in d.items() if v is not None}


@pytest.fixture
def write_scenario(tmp_path):
    """Write a scenario (dict or raw text) to a file and return its path."""

    def write(content, name: str = "scenario.yaml") -> Path:
        p = tmp_path / name
        p.write_text(content if isinstance(content, str) else yaml.safe_dump(content, sort_keys=False))
        return p

    return write


@pytest.fixture
def make_scenario(write_scenario):
    """Load a scenario built from :func:`scenario_dict` overrides."""
    from navcli.scenario import load_scenario

    def make(**over):
        return load_scenario(write_scenario(scenario_dict(**over)))

    return make


@pytest.fixture
def make_results():
    """``docs/make_results.py`` (the results page's maker), imported from the docs folder."""
    import sys

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import make_results as module
    finally:
        sys.path.remove(str(ROOT / "docs"))
    return module


def module_in_folder(folder: Path, monkeypatch, name: str, source: str):
    """A generator for a fixture (``yield from``): the plugin module ``name.py`` holding ``source``
    in ``folder``, made the current folder, found fresh by the registry; yields ``folder``, then
    forgets the module again."""
    import sys

    from navcli.plugins import registry

    (folder / f"{name}.py").write_text(source)
    monkeypatch.chdir(folder)
    monkeypatch.setattr(sys, "path", list(sys.path))  # the registry adds the current folder: this test's only
    sys.modules.pop(name, None)
    registry.clear_caches()
    yield folder
    sys.modules.pop(name, None)
    registry.clear_caches()
