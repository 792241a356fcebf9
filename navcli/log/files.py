"""A log file's life outside its contents: the path checked before a run (:func:`check_log_path`),
the lock a run holds while it writes (:class:`Lock`), and the name a killed run's ``.partial`` is
kept under (:func:`aside_name`); see :mod:`navcli.log.writer`."""

from __future__ import annotations

import fcntl
import os
from pathlib import Path
from typing import Callable

from .. import NavcliError


class LogPathError(NavcliError):
    """A log path that cannot be written (a folder, not ``.mcap``, being written by another run)."""


def check_log_path(path: Path, protect: tuple[str, ...] = (), *, overwrite: bool = False, ask: str = "--force") -> Path:
    """``path`` as a log file name, or :class:`LogPathError` saying why not: it must end in
    ``.mcap``, not be a folder, not be one of ``protect`` (the scenario file), not be an existing
    file other than a log navcli wrote (a device, a pipe, a user's file: never replaced), not be an
    existing log at all unless ``overwrite`` (the refusal names ``ask``, how its caller asks), and
    its folder must be creatable and writable. Checked before a mission starts, so a bad ``--out``
    costs nothing."""
    if str(path) in ("", ".") or path.name in ("", ".", ".."):
        raise LogPathError(f"{str(path)!r} is not a file name")
    if path.is_dir():
        raise LogPathError(f"{path} is a folder; give a file name ending in .mcap")
    if path.suffix != ".mcap":
        raise LogPathError(f"{path}: a log file name ends in .mcap")
    for other in protect:
        if other and path.exists() and Path(other).exists() and path.samefile(other):
            raise LogPathError(f"{path} is the scenario file itself")
    if path.exists() or path.is_symlink():  # replaced only if it is a log of navcli's (a regular file)
        from ..outputs import OutputError, check_file

        try:
            check_file(path, (".mcap",), "log", overwrite=overwrite, ask=ask)
        except OutputError as e:
            raise LogPathError(str(e)) from None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise LogPathError(f"cannot create the folder {path.parent}: {e.strerror or e}") from None
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise LogPathError(f"cannot write in the folder {path.parent} (permission denied)")
    if path.exists() and not os.access(path, os.W_OK):
        raise LogPathError(f"cannot overwrite {path} (permission denied)")
    return path


class Lock:
    """An exclusive, non-blocking ``flock`` on ``<log>.lock`` for the life of a run; the file is
    removed on release (re-checked by inode, so a run never holds a lock on a removed file)."""

    def __init__(self, path: Path):
        self.path = path
        while True:
            try:
                fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as e:  # a folder the permission bits allow but the file system refuses (/proc)
                raise LogPathError(f"cannot write the log {path.with_suffix('')}: {e.strerror or e}") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                raise LogPathError(f"{path.with_suffix('')} is being written by another run") from None
            try:
                same = os.fstat(fd).st_ino == os.stat(path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self.fd: int | None = fd
                return
            os.close(fd)  # the file was removed by the run that held it: take the new one

    def release(self) -> None:
        if self.fd is not None:
            try:
                os.unlink(self.path)
            finally:
                os.close(self.fd)
                self.fd = None


def _first_free(named: Callable[[int], Path], n: int) -> Path:
    """``named(n)``, ``named(n + 1)`` ...: the first that names no file (nor a dangling link)."""
    while (path := named(n)).exists() or path.is_symlink():
        n += 1
    return path


def aside_name(partial: Path) -> Path:
    """The first free ``<partial>-<n>``: where the ``.partial`` of a killed run is kept."""
    return _first_free(lambda n: partial.with_name(f"{partial.name}-{n}"), 1)


def beside(path: Path) -> Path:
    """``path`` if it is free, else the first free ``<stem>-<n><suffix>`` beside it (n from 2): where
    a run whose default log name is taken writes, so a rerun keeps the log before it.

    >>> beside(Path("/nonexistent/run.mcap")).name
    'run.mcap'
    """
    return _first_free(lambda n: path if n == 1 else path.with_name(f"{path.stem}-{n}{path.suffix}"), 1)
