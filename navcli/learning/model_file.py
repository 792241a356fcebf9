"""Learned models on disk: one numpy ``.npz`` holding the learner's arrays (model counts, values,
greedy policy) and its metadata as JSON (``meta``: algorithm, scenario sha256, seed, trials,
parameters, learning curve so far), with the same JSON beside it (``FILE.json``) for people.
A model is resumable: ``navcli train --resume`` loads its arrays into a new learner of the same
algorithm (:meth:`~.prioritized_sweeping.PrioritizedSweeping.load_arrays`) and goes on.

A model file is an input like a scenario: bounded before it is read (its size on disk and the
size each array would take once unpacked, so a zip bomb is refused unread) and validated whole
(every array of its algorithm present, of its shape, kind and range, finite; ``meta`` a JSON
object), so a damaged or foreign file is refused in one sentence, never half-used."""

from __future__ import annotations

import json
import math
import stat
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from .. import NavcliError
from ..outputs import atomic, check_file
from .actions import ACTIONS
from .features import N_STATES

BUNDLED = Path(__file__).resolve().parent / "models" / "landmarks-12.npz"
"""The model learned on scenarios/landmarks-12.yaml, shipped with navcli (README: how it was made)."""

MAX_BYTES = 64 * 2**20
"""The largest model file read (on disk, and each array unpacked). A full Prioritized Sweeping
model, every ``(s, a, s')`` count non-zero, would unpack to about 48 MB; the bundled one is 60 kB."""

A = len(ACTIONS)
_INT, _FLOAT = "iu", "f"
# name: (shape, kinds, lowest, highest); -1 in a shape: any length; None: unbounded (finite)
_ARRAYS: dict[str, dict[str, tuple[tuple[int, ...], str, float | None, float | None]]] = {
    "prioritized-sweeping": {
        "count_index": ((3, -1), _INT, 0, N_STATES),  # rows s, a, s' (s' = N_STATES: the goal); checked per row
        "count_value": ((-1,), _INT, 1, 2**31 - 1),
        "tried": ((N_STATES, A), _INT, 0, None),
        "reward_sum": ((N_STATES, A), _FLOAT, None, None),
        "values": ((N_STATES + 1,), _FLOAT, None, None),
        "priority": ((N_STATES,), _FLOAT, None, None),
        "policy": ((N_STATES,), _INT, 0, A - 1),
        "steps": ((), _INT, 0, None),
    },
    "q-learning": {
        "q": ((N_STATES, A), _FLOAT, None, None),
        "tried": ((N_STATES, A), _INT, 0, None),
        "values": ((N_STATES,), _FLOAT, None, None),
        "policy": ((N_STATES,), _INT, 0, A - 1),
        "steps": ((), _INT, 0, None),
    },
    "sb3": {  # a Stable-Baselines3 agent's policy over the belief states (navcli.rl.sb3)
        "probabilities": ((N_STATES, A), _FLOAT, 0, 1),
        "policy": ((N_STATES,), _INT, 0, A - 1),
        "steps": ((), _INT, 0, None),
    },
}
"""What each algorithm's file holds (the arrays of its learner's ``to_arrays``)."""


class ModelError(NavcliError):
    """A file that is not a usable model (missing, unreadable, damaged, of the wrong shape)."""


def trials_paths(out: Path) -> tuple[Path, Path]:
    """Where training writes its trials beside the model ``out``: the CSV and the folder of logs."""
    stem = Path(out).with_suffix("")
    return Path(f"{stem}-trials.csv"), Path(f"{stem}-trials")


def curve_paths(out: Path) -> tuple[Path, Path]:
    """Where training writes its learning curve beside the model ``out``: the CSV and the PNG."""
    stem = Path(out).with_suffix("")
    return Path(f"{stem}-curve.csv"), Path(f"{stem}-curve.png")


def side_files(path: Path) -> tuple[Path, ...]:
    """The files a training writes beside its model ``path``: the metadata, the learning curve
    (CSV and PNG) and the trials CSV."""
    return (Path(path).with_suffix(".json"), *curve_paths(path), trials_paths(path)[0])


def check_out(path: Path, *, overwrite: bool = False) -> Path:
    """Refuse (:class:`~navcli.outputs.OutputError`) a model ``path`` a training must not write:
    the model and each of its side files checked as outputs (never a folder, a device, or a file of
    another kind, such as the scenario given as ``--out``; an existing one only if ``overwrite``).
    Nothing is created."""
    check_file(path, (".npz",), "model file", overwrite=overwrite)
    for side in side_files(path):
        check_file(side, (side.suffix,), f"{side.suffix} file beside the model", overwrite=overwrite)
    return Path(path)


def save(path: Path, learner, meta: dict[str, Any]) -> Path:
    """Write ``learner``'s arrays and ``meta`` to ``path`` (.npz) and ``path``.json, each atomically:
    an interrupted save leaves the previous model whole."""
    path = Path(path)
    text = json.dumps({"algorithm": learner.algorithm, **meta}, sort_keys=True, indent=1)
    with atomic(path) as tmp:
        with tmp.open("wb") as f:  # a file object: numpy would add ".npz" to a name not ending in it
            np.savez_compressed(f, meta=np.array(text), **learner.to_arrays())
    with atomic(path.with_suffix(".json")) as tmp:
        tmp.write_text(text + "\n")
    return path


def _read(path: Path) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` at ``path``, after bounding its size and each array's."""
    if path.is_dir():
        raise ModelError(f"{path}: is a folder, not a model file")
    try:
        st = path.stat()
    except FileNotFoundError:
        raise ModelError(f"{path}: no such model file") from None
    except OSError as e:  # a link to itself ...
        raise ModelError(f"{path}: cannot be read ({e.strerror or e})") from None
    if not stat.S_ISREG(st.st_mode):  # a device (/dev/zero) or a pipe would be read without end
        raise ModelError(f"{path}: is not a regular file (a device, a pipe ...), not a model file")
    size = st.st_size
    if size > MAX_BYTES:
        raise ModelError(f"{path}: {size} bytes, larger than a model can be ({MAX_BYTES} bytes)")
    if not zipfile.is_zipfile(path):
        raise ModelError(f"{path}: not a navcli model (not an .npz archive" + (": empty)" if size == 0 else ")"))
    try:
        with zipfile.ZipFile(path) as z:
            big = [i.filename for i in z.infolist() if i.file_size > MAX_BYTES]
            if big or len(z.infolist()) > 64:
                raise ModelError(f"{path}: not a navcli model (its arrays would unpack beyond {MAX_BYTES} bytes)")
            for info in z.infolist():  # what each array's header declares, before any is allocated
                if info.flag_bits & 0x1:
                    raise ModelError(f"{path}: its member {info.filename!r} is encrypted: not a navcli model")
                with z.open(info) as member:
                    version = np.lib.format.read_magic(member)
                    shape, _, dtype = (
                        np.lib.format.read_array_header_1_0(member)
                        if version == (1, 0)
                        else np.lib.format.read_array_header_2_0(member)
                    )
                if math.prod(shape) * dtype.itemsize > MAX_BYTES:
                    raise ModelError(
                        f"{path}: its array {info.filename.removesuffix('.npy')!r} declares {shape}: "
                        f"larger than a model can be ({MAX_BYTES} bytes)"
                    )
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except ModelError:
        raise
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError) as e:
        raise ModelError(f"{path}: not a navcli model, or damaged ({e})") from None


def _check_array(path: Path, name: str, a: np.ndarray | None, rule) -> None:
    shape, kinds, lo, hi = rule
    if a is None:
        raise ModelError(f"{path}: its array {name!r} is missing")
    want = " x ".join("any" if n < 0 else str(n) for n in shape) or "a scalar"
    if a.ndim != len(shape) or any(n >= 0 and m != n for m, n in zip(a.shape, shape)):
        raise ModelError(f"{path}: its array {name!r} has shape {a.shape}, not {want}")
    if a.dtype.kind not in kinds:
        raise ModelError(f"{path}: its array {name!r} holds {a.dtype}, not {'integers' if kinds == _INT else 'floats'}")
    if a.size == 0:
        return
    if kinds == _FLOAT and not np.isfinite(a).all():
        raise ModelError(f"{path}: its array {name!r} holds NaN or infinite values")
    if (lo is not None and a.min() < lo) or (hi is not None and a.max() > hi):
        raise ModelError(f"{path}: its array {name!r} holds values outside [{lo}, {hi if hi is not None else 'inf'}]")


def _check_meta(path: Path, arrays: dict[str, np.ndarray]) -> dict[str, Any]:
    m = arrays.pop("meta", None)
    if m is None or m.ndim != 0 or m.dtype.kind != "U":
        raise ModelError(f"{path}: not a navcli model (no metadata)")
    try:
        meta = json.loads(str(m))
    except ValueError as e:
        raise ModelError(f"{path}: its metadata is not JSON ({e})") from None
    if not isinstance(meta, dict):
        raise ModelError(f"{path}: its metadata is not a JSON object")
    if meta.get("algorithm") not in _ARRAYS:
        raise ModelError(f"{path}: its metadata names no known algorithm (expected one of: {', '.join(_ARRAYS)})")
    for key in ("seed", "trials"):  # needed to resume a training (checked there when missing)
        v = meta.get(key, 0)
        if not isinstance(v, int) or isinstance(v, bool) or v < 0 or v >= 2**64:
            raise ModelError(f"{path}: its metadata's {key!r} is not a whole number >= 0")
    for key in ("curve", "pending_evaluations"):
        if not isinstance(meta.get(key, []), list) or not all(isinstance(p, dict) for p in meta.get(key, [])):
            raise ModelError(f"{path}: its metadata's {key!r} is not a list of records")
    return meta


def load(path: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The arrays and metadata of a model file, validated whole; raises :class:`ModelError`
    naming the file and what is wrong with it."""
    path = Path(path)
    arrays = _read(path)
    meta = _check_meta(path, arrays)
    rules = _ARRAYS[meta["algorithm"]]
    for name, rule in rules.items():
        _check_array(path, name, arrays.get(name), rule)
    if meta["algorithm"] == "prioritized-sweeping":
        i = arrays["count_index"]
        if i.shape[1] != arrays["count_value"].shape[0]:
            raise ModelError(f"{path}: its arrays 'count_index' and 'count_value' differ in length")
        if i.size and (i[0].max() >= N_STATES or i[1].max() >= A):
            raise ModelError(f"{path}: its array 'count_index' names a state or action that does not exist")
    if meta["algorithm"] == "sb3" and not np.allclose(arrays["probabilities"].sum(axis=1), 1.0, atol=1e-6):
        raise ModelError(f"{path}: its array 'probabilities' has a state whose probabilities do not sum to 1")
    extra = sorted(set(arrays) - set(rules))
    if extra:
        raise ModelError(f"{path}: holds arrays a {meta['algorithm']} model does not ({', '.join(extra)})")
    return arrays, meta


def load_policy(path: Path | None = None) -> np.ndarray:
    """The greedy policy (an action per state) of a model file, by default the bundled one."""
    return load(path or BUNDLED)[0]["policy"].astype(np.int64)
