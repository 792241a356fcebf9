"""Learned models on disk: one numpy ``.npz`` holding the learner's arrays (model counts, values,
greedy policy) and its metadata as JSON (``meta``: algorithm, scenario sha256, seed, trials,
parameters, learning curve so far), with the same JSON beside it (``FILE.json``) for people.
A model is resumable: ``navcli train --resume`` loads its arrays into a new learner of the same
algorithm (:meth:`~.prioritized_sweeping.PrioritizedSweeping.load_arrays`) and goes on."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from .features import N_STATES
from .actions import ACTIONS

BUNDLED = Path(__file__).resolve().parent / "models" / "landmarks-12.npz"
"""The model learned on scenarios/landmarks-12.yaml, shipped with navcli (README: how it was made)."""


class ModelError(ValueError):
    """A file that is not a usable model (missing, unreadable, wrong shape)."""


def save(path: Path, learner, meta: dict[str, Any]) -> Path:
    """Write ``learner``'s arrays and ``meta`` to ``path`` (.npz) and ``path``.json."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(meta, sort_keys=True, indent=1)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez_compressed(tmp, meta=np.array(text), **learner.to_arrays())
    tmp.replace(path)
    path.with_suffix(".json").write_text(text + "\n")
    return path


def load(path: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The arrays and metadata of a model file; raises :class:`ModelError` naming the file."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        meta = json.loads(str(arrays.pop("meta")))
    except FileNotFoundError:
        raise ModelError(f"{path}: no such model file") from None
    except (OSError, ValueError, KeyError) as e:
        raise ModelError(f"{path}: not a navcli model ({e})") from None
    policy = arrays.get("policy")
    if policy is None or policy.shape != (N_STATES,) or policy.min() < 0 or policy.max() >= len(ACTIONS):
        raise ModelError(f"{path}: its policy is not one of {len(ACTIONS)} actions for each of {N_STATES} states")
    return arrays, meta


def load_policy(path: Path | None = None) -> np.ndarray:
    """The greedy policy (an action per state) of a model file, by default the bundled one."""
    return load(path or BUNDLED)[0]["policy"].astype(np.int64)
