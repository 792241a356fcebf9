"""Optional rows of the learning paper's Table 1 (``navcli reproduce learning``): a policy that needs
more installed than navcli's tests do is not run by ``reproduce``; its trials are read from the
folder its own ``navcli compare policies`` command wrote (:func:`optional_command`), only those of
the same room file, starts and seeds (:func:`optional_trials`), with the command recorded there
(``source.json``); a room without them says so (:func:`optional_text`). The rows themselves are
declared in :data:`navcli.experiments.learning_paper.OPTIONAL_POLICIES`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class OptionalRow:
    """A row of Table 1 that ``navcli reproduce`` does not run itself: ``policy`` (a ``--policy``
    name of ``navcli compare policies``) needs ``needs`` installed; its trials come from the folder
    :func:`optional_command` writes, and a room without them says so."""

    policy: str
    needs: str


EXTRA = "extra"
"""The folder, in a room's folder of Table 1, of the optional rows' ``compare policies`` output (one per policy)."""


def optional_command(row: OptionalRow, room: str, s: Any, folder: Path) -> str:
    """The command that makes an optional row's trials for ``room`` (the same runs and starts)."""
    return (
        f"navcli compare policies {room} --policy {row.policy} --runs {s.policy_runs} "
        f"--starts {s.policy_starts} --out {folder}"
    )


@dataclass(frozen=True)
class Found:
    """An optional row's trials as found (None: none), how many of its runs are missing, the
    command recorded with them (None: not recorded) and files set aside (why)."""

    trials: Any
    missing: int
    command: str | None
    set_aside: tuple[str, ...] = ()


def optional_trials(folder: Path, policy: str, spec, runs: int, starts: int) -> Found:
    """``policy``'s trials in a ``navcli compare policies --out`` ``folder`` (its ``runs/*.json``):
    only those of this room's file and of the same starts and seeds, run by run (a file of another
    room, other starts or another policy is set aside, and said); a run not found is missing
    (``compare policies`` writes no file for a run that ended in error)."""
    import json
    import shlex

    import pandas as pd

    from ..training.comparison import run_starts
    from ..training.task import random_starts
    from ..training.trainer import EVAL_SEED

    base = random_starts(spec, starts, EVAL_SEED)  # as comparison.plan draws them
    expected = [run_starts(base, r) for r in range(runs)]
    kept: dict[int, list[dict]] = {}
    aside = []
    for f in sorted((folder / "runs").glob("*.json")) if folder.is_dir() else []:
        try:
            d = json.loads(f.read_text())
            r = int(d["run"])
            same = d.get("policy") == policy and d.get("scenario_sha256") == spec.scenario.sha256
            places = [(t["x"], t["y"], t["heading"], t["seed"]) for t in d["trials"]]
        except (OSError, ValueError, KeyError, TypeError) as e:
            aside.append(f"{f.name} (unreadable: {type(e).__name__})")
            continue
        if not same:
            continue  # another policy's runs, or another room's: not this row's
        if r not in range(runs) or places != [(p.x, p.y, p.heading, p.seed) for p in expected[r]]:
            aside.append(f"{f.name} (other starts or seeds than run {r}'s here)")
            continue
        kept[r] = [{"policy": policy, "run": r} | t for t in d["trials"]]
    command = None
    try:
        argv = json.loads((folder / "source.json").read_text()).get("command")
        command = shlex.join(argv) if argv else None
    except (OSError, ValueError, AttributeError):
        pass
    if not kept:
        return Found(None, runs, command, tuple(aside))
    frame = pd.DataFrame([t for r in sorted(kept) for t in kept[r]])
    return Found(frame, runs - len(kept), command, tuple(aside))


def optional_text(row: OptionalRow, found: Found, room: str, s: Any, where: Path) -> str:
    """What the report says of an optional row: where its trials came from and by which command, or
    that it was not run and how to add it."""
    folder = where / EXTRA / row.policy
    wanted = optional_command(row, room, s, folder)
    aside = f"; set aside: {', '.join(found.set_aside)}" if found.set_aside else ""
    if found.trials is None:
        return (
            f"{row.policy} (optional, needs {row.needs}): not run here, so no row; to add it run `{wanted}` "
            f"where it is installed, then this command again{aside}."
        )
    made = (
        f"made by `{found.command}`" if found.command else f"its command not recorded there (the expected: `{wanted}`)"
    )
    lost = (
        f"; {found.missing} of its {s.policy_runs} runs not found (not run, or ended in error), counted as errored"
        if found.missing
        else ""
    )
    return f"{row.policy} (optional, needs {row.needs}): its trials read from {folder}, {made}{lost}{aside}."
