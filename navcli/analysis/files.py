"""Files written whole or not at all: every figure, video and table of the analysis package goes
through :func:`atomic` (the same rule as navcli's writers, kept here because this package never
imports navcli)."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import Any, Iterator


@contextlib.contextmanager
def atomic(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` (same suffix, so writers that choose the format by the
    name still do) that is renamed over ``path`` once the block ends normally, and removed if it
    raises or is interrupted: a reader never finds half a file. The folder is made if need be."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def file_name(label: str, empty: str = "run") -> str:
    """``label`` (a pilot's or policy's name, which may be ``pkg.mod:Class`` or a path) as part of
    a file name: every run of characters other than letters, digits, ``_``, ``.`` and ``-`` made one
    ``_`` (``empty`` if nothing is left). navcli's own names pass unchanged.

    >>> file_name("potential-field"), file_name("./my pilots/x.py:Pilot"), file_name("learned:m.npz")
    ('potential-field', 'my_pilots_x.py_Pilot', 'learned_m.npz')
    """
    import re

    return re.sub(r"[^A-Za-z0-9_.-]+", "_", label).strip("_.") or empty


MARK = "<!-- written by navcli -->"
"""The first line of every Markdown file navcli writes (invisible when rendered): how a command
knows a table of its own from a user's file of the same name, which it never replaces."""


def write_csv(path: Path, frame: Any) -> Path:
    """A pandas frame as CSV (no index), written atomically: every table navcli writes."""
    with atomic(path) as tmp:
        frame.to_csv(tmp, index=False)
    return path


def write_markdown(path: Path, text: str) -> Path:
    """``text`` as a Markdown file of navcli's (:data:`MARK` first), written atomically."""
    with atomic(path) as tmp:
        tmp.write_text(f"{MARK}\n{text}")
    return path


def without_mark(text: str) -> str:
    """A Markdown file's text as a reader wants it: without navcli's mark."""
    return text.removeprefix(MARK + "\n")
