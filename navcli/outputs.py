"""Where a command may write: every output path checked before the work starts, every file
written whole or not at all.

Our design (the papers are silent; the rule is the house's): a command refuses up front, with one
sentence, an output that

* is a folder where a file is meant, or a file where a folder is meant;
* exists and is not a regular file (``/dev/null``, ``/dev/full``, a FIFO): a device is never
  replaced;
* has a name the command does not write (``plot field --out x.txt``: a PNG is written);
* exists and is not of the kind the command writes (a scenario given as a PNG's ``--out``): a
  file is replaced only by a newer one of its own kind (its first bytes say which), never one the
  command could not have written;
* lies in a folder that cannot be made or written (its nearest existing ancestor must be a
  folder this process may write into).

Nothing is created by a check: a command refused later for another reason leaves nothing behind.
:func:`atomic` then writes through a temporary file beside the target, renamed over it only once
complete, so an interrupted or failed write leaves the old file (or none), never half of one.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from . import NavcliError
from .analysis.files import atomic  # the one definition (analysis may not import navcli)

MAGIC: dict[str, tuple[bytes, ...]] = {
    ".png": (b"\x89PNG\r\n\x1a\n",),
    ".gif": (b"GIF87a", b"GIF89a"),
    ".mp4": (b"ftyp",),  # at byte 4, after the box size
    ".npz": (b"PK\x03\x04",),
    ".json": (b"{", b"["),
    ".csv": (),
    ".md": (),
    ".parquet": (b"PAR1",),
    ".journal": (b"{",),  # Optuna's journal: JSON lines
    ".log": (b"{",),
}
"""The first bytes of every kind of file navcli writes (an empty tuple: text with no signature,
recognised by its name alone inside a folder the command owns)."""


class OutputError(NavcliError):
    """An output path a command must not write; the message says why, naming the path."""


def _kind_of(path: Path, suffix: str) -> bool:
    """True when the existing file ``path`` starts like a ``suffix`` file navcli writes."""
    marks = MAGIC.get(suffix, ())
    if not marks:
        return True
    with path.open("rb") as f:
        head = f.read(16)
    if suffix == ".mp4":
        return head[4:8] in marks
    if suffix == ".json":
        return head.lstrip()[:1] in marks
    return any(head.startswith(m) for m in marks)


def _writable_folder(folder: Path, shown: Path) -> None:
    """Refuse unless ``folder`` is, or could be made as, a folder this process can write into."""
    probe = folder
    while not probe.exists():
        if probe.is_symlink():
            raise OutputError(f"{shown}: {probe} is a broken link")
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        raise OutputError(f"{shown}: {probe} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"{shown}: the folder {probe} cannot be written")


def check_file(path: Path, suffixes: tuple[str, ...], what: str = "file") -> Path:
    """``path`` if a command may write the ``what`` (a file named ``*<suffix>``, one of
    ``suffixes``) there, else :class:`OutputError` saying why. Nothing is created."""
    path = Path(path)
    text = str(path)
    if text.endswith(os.sep) or (path.exists() and path.is_dir()):
        raise OutputError(f"{path}: is a folder; give a {what} name ending in {' or '.join(suffixes)}")
    if path.suffix.lower() not in suffixes:
        raise OutputError(f"{path}: a {what} is written; give a name ending in {' or '.join(suffixes)}")
    if path.exists() or path.is_symlink():
        try:
            mode = path.stat().st_mode
        except OSError as e:
            raise OutputError(f"{path}: cannot be checked ({e.strerror or e})") from None
        if not stat.S_ISREG(mode):
            raise OutputError(f"{path}: is not a regular file (a device, a pipe ...); it is never replaced")
        try:
            ours = _kind_of(path, path.suffix.lower())
        except OSError as e:
            raise OutputError(f"{path}: cannot be read ({e.strerror or e})") from None
        if not ours:
            raise OutputError(f"{path}: exists and is not a {path.suffix.lower()} file navcli writes; "
                              f"it is not replaced (choose another name)")
        if not os.access(path, os.W_OK):
            raise OutputError(f"{path}: cannot be replaced (no permission)")
    _writable_folder(path.parent, path)
    return path


def check_folder(path: Path) -> Path:
    """``path`` if a command may write its files into this folder (existing or to be made), else
    :class:`OutputError`. Nothing is created."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{path}: is a file; give a folder")
    _writable_folder(path, path)
    return path


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (:func:`atomic`)."""
    with atomic(path) as tmp:
        tmp.write_text(text)
    return Path(path)
