"""Which code runs: the hot modules compiled by mypyc (``setup.py`` builds them where it can) or
their pure-Python sources, the reference.

``MODULES`` is the one list of the compiled modules (``setup.py`` reads it from this file without
importing navcli). :func:`choose`, called once by ``navcli/__init__.py`` before any other navcli
module is imported, returns the build and sets it up: ``compiled``, ``pure`` (compiled modules
installed, their ``.py`` sources run: ``NAVCLI_PURE=1``) or ``pure-only`` (none built, as on a
machine without a C compiler).
"""

from __future__ import annotations

import importlib.util
import os
import sys
from importlib.machinery import EXTENSION_SUFFIXES, ModuleSpec
from typing import Sequence

# The modules a control tick spends its time in (cProfile, callgrind: benchmarks/tick_instructions.py),
# compiled where it measurably pays. Each keeps mypyc's rules: no monkeypatching of its functions or
# classes from outside, no interpreted subclass of its classes, no class attribute aliasing a method.
MODULES = (
    "geometry",
    "fuzzy",
    "pilot.potential_field",
    "vision.visual_memory",
    "vision.perception",
    "vision.line_pieces",
    "world",
    "noise",
    "navigation.risk_manager",
    "navigation.target_tracker",
    "navigation.distance_estimator",
    "navigation.communicator",
    "log.records",
    "pilot.base",
    "beliefs",
    "navigation.map_manager",
    "navigation.beta_map",
    "navigation.rescuer",
    "navigation.scanning",
    "navigation.progress",
    "vision.bumps",
    "learning.features",
    "learning.actions",
    "learning.learning_agent",
    "mission",
)
GROUP = "_compiled"  # the shared library of them all: navcli/_compiled__mypyc.<suffix>
SERVO = "servo"
"""The wheels' velocity servo in C (``navcli/servo.c``, built beside the compiled modules and
imported by ``navcli.world`` alone): a module with no Python source, so the pure builds run
without it, on the Python servo it reproduces."""


class PureFinder:
    """Finds every ``navcli.*`` module in its ``.py`` file, never in a compiled extension beside it
    (the import system's own finders take the extension first). All modules or none: a compiled
    module calls the compiled functions of its group directly, so half of each would hold two
    versions of one class. The C servo, which has no source, is not found at all."""

    def find_spec(self, name: str, path: Sequence[str] | None, target: object = None) -> ModuleSpec | None:
        if not name.startswith("navcli.") or not path:
            return None
        if name == f"navcli.{SERVO}":
            raise ModuleNotFoundError(f"{name} is C alone: not run in a pure build", name=name)
        leaf = name.rpartition(".")[2]
        for entry in path:
            base = os.path.join(entry, leaf)
            if os.path.isfile(init := os.path.join(base, "__init__.py")):
                return importlib.util.spec_from_file_location(name, init, submodule_search_locations=[base])
            if os.path.isfile(base + ".py"):
                return importlib.util.spec_from_file_location(name, base + ".py")
        return None


def library(here: str) -> str | None:
    """The compiled modules' shared library, if this install has one."""
    for suffix in EXTENSION_SUFFIXES:
        if os.path.isfile(lib := os.path.join(here, f"{GROUP}__mypyc{suffix}")):
            return lib
    return None


STALE = "NAVCLI_STALE_MODULES"  # set by choose() beside NAVCLI_PURE: which sources outran the build


WHY = {
    "compiled": "the hot modules compiled by mypyc",
    "pure": "pure Python; the compiled modules installed, not run",
    "pure-only": "pure Python: this install has no compiled modules (built without mypyc or a C compiler,"
    " or with NAVCLI_PURE_BUILD; see docs/howto/speed.md)",
}
"""What each build is, in words: ``navcli --version`` and ``navcli bench`` say it."""


def describe(build: str) -> str:
    """The build in a line, with why it runs when it is not the compiled one.

    >>> describe("compiled")
    'compiled (the hot modules compiled by mypyc)'
    """
    why = WHY[build]
    if build == "pure" and os.environ.get(STALE, ""):
        why += f": {os.environ[STALE]} changed since the build (`python -m pip install -e .` rebuilds)"
    elif build == "pure":
        why += ": NAVCLI_PURE is set"
    return f"{build} ({why})"


def choose() -> str:
    """Set up and return the build this process runs. In a source checkout (an editable install)
    a compiled module whose source changed since the build must not run as its old self: then
    pure Python, said once on stderr and passed on to child processes (workers run the same code)."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # navcli/
    lib = library(here)
    if os.environ.get("NAVCLI_PURE", "") not in ("", "0"):
        sys.meta_path.insert(0, PureFinder())
        return "pure" if lib else "pure-only"
    if lib is None:
        return "pure-only"
    if os.path.isfile(os.path.join(os.path.dirname(here), "pyproject.toml")):
        built = os.path.getmtime(lib)
        stale = [m for m in MODULES if os.path.getmtime(os.path.join(here, *m.split(".")) + ".py") > built]
        servo = os.path.join(here, f"{SERVO}.c")
        stale += [SERVO] if os.path.isfile(servo) and os.path.getmtime(servo) > built else []
        if stale:
            named = f"{', '.join(stale[:3])}{' ...' if len(stale) > 3 else ''}"
            print(
                f"navcli: {named} changed since the compiled build: running pure Python"
                " (`python -m pip install -e .` rebuilds)",
                file=sys.stderr,
            )
            os.environ["NAVCLI_PURE"] = "1"
            os.environ[STALE] = named
            sys.meta_path.insert(0, PureFinder())
            return "pure"
    return "compiled"
