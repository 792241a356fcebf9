"""Where a command may write: every output path checked before the work starts, every file
written whole or not at all.

Our design (the papers are silent; the rule is the house's): a command refuses up front, with one
sentence, an output that

* is a folder where a file is meant, or a file where a folder is meant;
* exists and is not a regular file (``/dev/null``, ``/dev/full``, a FIFO): a device is never
  replaced;
* has a name the command does not write (``plot field --out x.txt``: a PNG is written);
* exists and is not a file navcli wrote (a user's notes as ``table.md``, a photo as the PNG's
  ``--out``): a file is replaced only by a newer one of its own kind, recognised by its content
  (:func:`navcli_wrote`), never one the command could not have written; the same holds for every
  file a command writes into a folder (:func:`check_folder`);
* exists at all, unless the user asked for it to be replaced (:data:`FORCE`: ``--force`` on the
  command line, ``overwrite=True`` from Python): a finished log, figure or table is never lost
  to a second command that happens to name it (:class:`OutputExists`). The commands that resume
  (``compare``, ``sweep``, ``tune``, ``reproduce``) keep what their folder holds instead, and remake
  their tables from all of it;
* lies in a folder that cannot be made or written (its nearest existing ancestor must be a
  folder this process may write into).

Nothing is created by a check: a command refused later for another reason leaves nothing behind.
:func:`atomic` then writes through a temporary file beside the target, renamed over it only once
complete, so an interrupted or failed write leaves the old file (or none), never half of one.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from pathlib import Path

from . import NavcliError
from .analysis.files import MARK, atomic  # the one definition (analysis may not import navcli)

HEAD_BYTES = 4096
"""What is read of an existing file to tell whether navcli wrote it (and, at its end, of a zip or
Parquet file, whose directory is there)."""
CSV_COLUMNS = (
    {"run_id", "pilot", "outcome"},
    {"condition", "pilot", "success_rate"},
    {"condition", "baseline", "improvement_pct"},
    {"policy", "successes"},
    {"policy", "run", "start"},
    {"trials", "successes", "reward_per_trial"},
    {"trial", "outcome", "actions"},
    {"trial", "objective"},
    {"scenario_sha256", "point", "outcome"},
)
"""Columns that mark a CSV file navcli writes (its header holds one of these sets): runs, the
table, improvements; policies and their trials; a learning curve; a training's trials; tune's
history; a sweep's results."""
JSON_KEYS = (
    {"configById"},
    {"content", "version"},
    {"algorithm", "scenario"},
    {"objective", "params", "value"},
    {"key", "generation", "population"},
    {"key", "policy", "trials"},
    {"temperature", "grid"},
    {"navcli_version", "configurations"},
    {"navcli_version", "command", "commit"},
)
"""The keys that mark a JSON file navcli writes: a layout (app, SDK), a model's metadata, tune's
best values, the GA's checkpoint, a policy comparison's run, reproduce's conditions and its
report's provenance (``source.json``), tune-softmax's choice."""


def navcli_wrote(path: Path) -> bool:
    """Does the existing regular file ``path`` look like one navcli writes under its name?

    Our design: a command replaces only a file of its own kind, recognised by content, so that a
    user's file of the same name survives: a PNG made by Matplotlib, a zip holding a model's
    ``meta.npy``, an MCAP written by foxglove-sdk or ``navcli recover``, a Parquet table with a
    ``run_id`` column, JSON with one of :data:`JSON_KEYS`, a CSV with one of :data:`CSV_COLUMNS`,
    Markdown with :data:`MARK`, tune's YAML block, Optuna's journal. GIF and MP4 carry no mark of
    their writer: for them the format's own signature is all that is checked."""
    suffix = path.suffix.lower()
    with path.open("rb") as f:
        head, tail = f.read(HEAD_BYTES), b""
        if suffix in (".npz", ".zip", ".parquet"):  # their directory is at the end
            f.seek(max(0, os.fstat(f.fileno()).st_size - 65536))
            tail = f.read(65536)
    if suffix == ".json":
        return _json_navcli_wrote(path)
    recognise = _SIGNATURES.get(suffix)
    return recognise is not None and recognise(head, tail)


def _first_line(head: bytes) -> bytes:
    return head.split(b"\n", 1)[0].strip()


def _csv_navcli_wrote(head: bytes) -> bool:
    columns = set(_first_line(head).decode("utf-8", "replace").split(","))
    return any(c <= columns for c in CSV_COLUMNS)


def _json_navcli_wrote(path: Path) -> bool:
    import json

    try:
        with path.open("rb") as f:
            d = json.loads(f.read(1 << 22))  # 4 MiB: more than any JSON navcli writes
    except (ValueError, UnicodeDecodeError, RecursionError):  # (deep nesting: json's own recursion limit)
        return False
    return isinstance(d, dict) and any(keys <= d.keys() for keys in JSON_KEYS)


_SIGNATURES: dict[str, Callable[[bytes, bytes], bool]] = {
    ".png": lambda head, _: head.startswith(b"\x89PNG\r\n\x1a\n") and b"Matplotlib" in head,
    ".gif": lambda head, _: head[:6] in (b"GIF87a", b"GIF89a"),
    ".mp4": lambda head, _: head[4:8] == b"ftyp",
    ".npz": lambda head, tail: head.startswith(b"PK\x03\x04") and b"meta.npy" in tail,
    # a Stable-Baselines3 agent train-rl saved (its archive names its version)
    ".zip": lambda head, tail: head.startswith(b"PK\x03\x04") and b"_stable_baselines3_version" in tail,
    ".mcap": lambda head, _: (
        head.startswith(b"\x89MCAP") and (b"foxglove-sdk" in head[:256] or b"navcli" in head[:256])
    ),
    ".parquet": lambda head, tail: head.startswith(b"PAR1") and b"run_id" in tail,
    ".csv": lambda head, _: _csv_navcli_wrote(head),
    ".md": lambda head, _: _first_line(head).decode("utf-8", "replace") == MARK,
    ".html": lambda head, _: MARK.encode() in head[:256],
    ".yaml": lambda head, _: _first_line(head).startswith(b"# navcli "),
    ".journal": lambda head, _: _first_line(head).startswith(b'{"op_code"'),
    ".log": lambda head, _: _first_line(head).startswith(b'{"op_code"'),
}
"""What marks a file navcli writes, by suffix, from its first :data:`HEAD_BYTES` bytes (``head``) and,
for formats whose directory is at the end, its last 64 KiB (``tail``)."""


class OutputError(NavcliError):
    """An output path a command must not write; the message says why, naming the path."""


FORCE = "--force"
"""How the command line asks for an existing output to be replaced; the Python API's is
``overwrite=True`` (each check takes the words of its caller, ``ask``)."""


class OutputExists(OutputError):
    """An output file that exists and was not asked to be replaced; the message says how to ask."""


def refuse_existing(path: Path, what: str, ask: str = FORCE) -> OutputExists:
    """The refusal of an existing output ``path`` (a ``what``), naming ``ask``: for ``raise``."""
    return OutputExists(f"{path}: exists; a {what} is not replaced unless asked ({ask} replaces it)")


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


def check_file(
    path: Path, suffixes: tuple[str, ...], what: str = "file", *, overwrite: bool = False, ask: str = FORCE
) -> Path:
    """``path`` if a command may write the ``what`` (a file named ``*<suffix>``, one of
    ``suffixes``) there, else :class:`OutputError` saying why. An existing file is refused
    (:class:`OutputExists`, naming ``ask``) unless ``overwrite``. Nothing is created."""
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
            ours = navcli_wrote(path)
        except OSError as e:
            raise OutputError(f"{path}: cannot be read ({e.strerror or e})") from None
        if not ours:
            raise OutputError(
                f"{path}: exists and is not a {path.suffix.lower()} file navcli writes; "
                f"it is not replaced (choose another name)"
            )
        if not overwrite:
            raise refuse_existing(path, what, ask)
        if not os.access(path, os.W_OK):
            raise OutputError(f"{path}: cannot be replaced (no permission)")
    _writable_folder(path.parent, path)
    return path


def check_folder(path: Path, files: tuple[str, ...] = (), *, overwrite: bool = False, ask: str = FORCE) -> Path:
    """``path`` if a command may write its files into this folder (existing or to be made), else
    :class:`OutputError`. ``files``: the names (glob patterns) the command writes there; each that
    exists must be a file navcli wrote, and is refused unless ``overwrite`` (:func:`check_file`).
    Nothing is created."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{path}: is a file; give a folder")
    _writable_folder(path, path)
    if path.is_dir():
        for pattern in files:
            for f in sorted(path.glob(pattern)):
                check_file(f, (f.suffix.lower(),), f"{f.suffix.lower()[1:]} file", overwrite=overwrite, ask=ask)
    return path


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (:func:`atomic`)."""
    with atomic(path) as tmp:
        tmp.write_text(text)
    return Path(path)
