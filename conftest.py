"""Collection rules for the whole suite (the tests' own fixtures are in tests/conftest.py).

With the compiled build installed (navcli/builds/__init__.py), a compiled module's ``.py`` file is not the
module navcli runs, so pytest cannot collect the worked examples of its docstrings from it;
tests/test_builds.py runs those under ``NAVCLI_PURE=1`` instead (and they run here as usual where
the build is pure Python)."""

from __future__ import annotations

from pathlib import Path

import navcli
from navcli import builds

HERE = Path(__file__).parent
COMPILED = (
    {(HERE / "navcli" / (m.replace(".", "/") + ".py")).resolve() for m in builds.MODULES}
    if navcli.BUILD == "compiled"
    else set()
)


def pytest_ignore_collect(collection_path: Path, config) -> bool | None:
    return True if collection_path.resolve() in COMPILED else None
