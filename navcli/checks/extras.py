"""The optional parts of navcli (the extras of ``pyproject.toml``: ``gym``, ``cluster``, ``docs``):
a command that needs one imports its library through :func:`require`, which says what to install
when it is missing instead of failing on an ``ImportError``.

Which extra holds a library is read from navcli's installed metadata (the ``pyproject.toml``
extras, so it is declared there alone); :data:`PULLED_IN` names the libraries an extra brings
without naming them (``dask[distributed]`` brings ``distributed``).

Standard library only: imported on every start.
"""

from __future__ import annotations

import importlib
import re
from typing import Any

from .. import NavcliError

PULLED_IN = {"distributed": "dask"}
"""A module whose distribution an extra installs through another's (module: the one named)."""


class MissingExtra(NavcliError):
    """A library of an optional extra is not installed; the message says what to install (bad
    input's exit, 2: the command asked for a part this installation lacks)."""


def extra_of(distribution: str) -> str | None:
    """The extra of navcli that installs ``distribution`` (``gymnasium``: ``gym``), or None."""
    from importlib.metadata import PackageNotFoundError, requires

    try:
        wanted = requires("navcli") or []
    except PackageNotFoundError:  # a checkout on sys.path, not installed
        return None
    for line in wanted:
        m = re.match(r"\s*([A-Za-z0-9_.\-]+).*;\s*extra\s*==\s*['\"]([^'\"]+)['\"]", line)
        if m and _canonical(m.group(1)) == _canonical(distribution) and m.group(2) != "test":
            return m.group(2)
    return None


def _canonical(name: str) -> str:
    """A distribution's name as packaging compares them (``stable_baselines3`` is ``stable-baselines3``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def install_hint(module: str) -> str:
    """What to run to get ``module``: ``pip install 'navcli[gym]'``, or its distribution alone."""
    top = module.split(".")[0]
    distribution = PULLED_IN.get(top, top)
    extra = extra_of(distribution)
    return f"pip install 'navcli[{extra}]'" if extra else f"pip install {distribution}"


def require(module: str, what: str) -> Any:
    """Import ``module`` or raise :class:`MissingExtra` saying that ``what`` (a command, an
    option) needs it and what to install."""
    try:
        return importlib.import_module(module)
    except ImportError:
        top = module.split(".")[0]
        raise MissingExtra(f"{what} needs {top}, which is not installed: {install_hint(module)}") from None
