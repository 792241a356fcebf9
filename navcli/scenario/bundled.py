"""The scenarios that ship inside navcli, by name: ``navcli run paper-8x8`` from any folder.

They live in the package (``navcli/data/scenarios/``; ``scenarios/`` of the repository links
there), so a wheel carries them. Wherever navcli takes a scenario (a command's argument, a sweep
plan's ``scenarios:``, :func:`~navcli.scenario.load_scenario`, the Gymnasium environment), it is
resolved by :func:`resolve`:

1. a path that exists is that file: a path always wins over a name;
2. else a bundled scenario's name, written as the documentation writes it (``paper-8x8``,
   ``paper-8x8.yaml`` or ``scenarios/paper-8x8.yaml``), is the bundled file;
3. else it stays the path it was, and loading it is refused (exit 2) naming the bundled scenarios
   it could have meant (:func:`not_found`).

>>> resolve("paper-8x8") == FOLDER / "paper-8x8.yaml"
True
>>> [name_of(r) for r in ("paper-8x8", "paper-8x8.yaml", "scenarios/paper-8x8.yaml", "rooms/paper-8x8.yaml")]
['paper-8x8', 'paper-8x8', 'paper-8x8', None]
>>> str(resolve("paper-8x9"))  # no such file, no such name: left as written, for the refusal
'paper-8x9'
>>> not_found("paper-8x9")
'no such file, nor a bundled scenario of that name (did you mean paper-8x8 or paper-fig9? `navcli scenarios` lists them)'
"""

from __future__ import annotations

import difflib
import functools
from pathlib import Path

FOLDER = Path(__file__).resolve().parent.parent / "data" / "scenarios"
"""Where the bundled scenarios are, in the installed package."""
SUFFIX = ".yaml"


@functools.cache
def names() -> tuple[str, ...]:
    """The bundled scenarios' names (their files' names without ``.yaml``), sorted."""
    return tuple(sorted(p.name.removesuffix(SUFFIX) for p in FOLDER.glob(f"*{SUFFIX}")))


def path(name: str) -> Path:
    """The file of the bundled scenario ``name`` (:class:`KeyError` if there is none)."""
    if name not in names():
        raise KeyError(name)
    return FOLDER / f"{name}{SUFFIX}"


def name_of(ref: str | Path) -> str | None:
    """The bundled scenario that ``ref`` names (``NAME``, ``NAME.yaml`` or ``scenarios/NAME.yaml``),
    or None."""
    p = Path(ref)
    if str(p.parent) not in (".", "scenarios") or p.suffix not in ("", SUFFIX):
        return None
    name = p.name.removesuffix(SUFFIX)
    return name if name in names() else None


def resolve(ref: str | Path, root: Path | None = None) -> Path:
    """The file ``ref`` stands for (module docstring): ``ref`` itself (under ``root``, a plan's
    folder, when given) if it exists, else the bundled scenario it names, else ``ref`` as written."""
    given = Path(ref)
    candidate = root / given if root is not None else given
    if candidate.exists() or candidate.is_symlink():
        return candidate
    name = name_of(given)
    return FOLDER / f"{name}{SUFFIX}" if name is not None else candidate


def not_found(ref: str | Path) -> str:
    """Why ``ref`` (neither a file nor a bundled name) is refused, with the names it could have meant."""
    return f"no such file, nor a bundled scenario of that name ({suggestion(ref)})"


def suggestion(ref: str | Path) -> str:
    """The bundled names close to ``ref``'s, and where to see them all."""
    stem = Path(ref).name.removesuffix(SUFFIX)
    close = difflib.get_close_matches(stem, names(), n=3, cutoff=0.6)
    return (f"did you mean {' or '.join(close)}? " if close else "") + "`navcli scenarios` lists them"
