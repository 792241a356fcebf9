"""The pilot comparison beyond the paper's room, for ``navcli reproduce``: the potential field (PF)
against the geometric pilot (GP) on every bundled room of the paper's size (:func:`square_rooms`),
with both perceptions, the spread of time and path over the reruns, the ratio of the pilots' mean
times against :data:`TIME_RATIO_TARGET`, and the runs in which a pilot stalled
(:mod:`navcli.analysis.stall`).

The rooms are found, not listed: every bundled scenario whose arena is :data:`ROOM_SIZE`. The
paper's room keeps Table 1's reruns (its logs are shared with Table 1, so nothing runs twice); the
others run ``Settings.room_reruns`` each. Every run counts: a run that ended in error is shown
in the counts, and its room and perception get no target verdict.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..analysis.stall import STALL_M, STALL_S
from ..analysis.stats import bootstrap_mean
from ..plugins.names import label
from ..scenario import bundled
from .document import Report

ROOM_SIZE = (8.0, 8.0)
"""m: the pilot paper's arena (width, height); every bundled room of this size is compared."""
TABLE1_ROOM = "paper-8x8"
"""The room of the pilot paper's Table 1, whose reruns the comparison shares."""
TIME_RATIO_TARGET = 1.3
"""The potential field's mean time may be at most this multiple of the geometric pilot's, per room
and perception (our target: the paper has the potential field faster on its room; elsewhere it
should not be much slower)."""
PF, GP = "potential-field", "geometric"


@functools.cache
def square_rooms() -> tuple[str, ...]:
    """The bundled scenarios whose arena is :data:`ROOM_SIZE`, by name (sorted)."""
    from ..scenario import load_scenario

    return tuple(
        n for n in bundled.names() if (lambda a: (a.width, a.height))(load_scenario(bundled.path(n)).arena) == ROOM_SIZE
    )


def jobs(
    rooms: tuple[str, ...], reruns: int, table1_reruns: int, out: Path, table1_out: Path, pilots: list[str], scenario
) -> dict[tuple[str, str], list]:
    """The runs of the comparison by (room, perception): the paper's room in Table 1's folder with
    its reruns (already run there), every other room in ``out`` with ``reruns``."""
    from ..config import RunSpec
    from .compare import plan

    planned = {}
    for perception in ("vision", "oracle"):
        for room in rooms:
            spec = RunSpec.build(scenario(room), perception=perception)
            n, folder = (table1_reruns, table1_out) if room == TABLE1_ROOM else (reruns, out)
            planned[room, perception] = plan([spec], pilots, n, folder / perception)
    return planned


def _stall_of(log: str) -> float:
    """The longest stall of a run's log (s), NaN for a log that cannot be read (a run that errored
    before its first pose); run in a worker."""
    from ..analysis.logs import LogError
    from ..analysis.stall import run_stall

    try:
        return run_stall(log)
    except LogError:
        return math.nan


def stalls(logs: list[str], ex) -> dict[str, float]:
    """The longest stall of each log, read on the executor's workers."""
    from .executor import run_each

    found: dict[str, float] = {}

    def done(i: int, f) -> None:
        found[logs[i]] = f.result()

    run_each(_stall_of, logs, ex, done)
    return found


def spread(values: np.ndarray, digits: str = "{:.1f}") -> str:
    """``mean ± SD [low, high]`` of ``values`` (SD with n - 1; the bootstrap 95 % interval of the
    mean); ``-`` without values.

    >>> spread(np.array([10.0, 20.0, 30.0]))[:12]
    '20.0 ± 10.0 '
    >>> spread(np.array([5.0])), spread(np.array([]))
    ('5.0 ± - (no interval)', '-')
    """
    if len(values) == 0:
        return "-"
    m, lo, hi = bootstrap_mean(values)
    sd = digits.format(float(np.std(values, ddof=1))) if len(values) > 1 else "-"
    tail = f"[{digits.format(lo)}, {digits.format(hi)}]" if math.isfinite(lo) and math.isfinite(hi) else "(no interval)"
    return f"{digits.format(m)} ± {sd} {tail}"


def ratio_verdict(ratio: float, pf_reached: int, gp_reached: int, errored: int) -> str:
    """Whether the potential field meets :data:`TIME_RATIO_TARGET`: the ratio of the mean times
    over each pilot's reached runs at most the target, and PF reaching as many runs as GP (a run
    not reached has no time, and no mean over the others stands for it). No verdict on a set with
    errors, nor without a reached GP run.

    >>> ratio_verdict(1.2, 10, 10, 0), ratio_verdict(1.31, 10, 10, 0), ratio_verdict(1.0, 9, 10, 0)
    ('met', 'not met', 'not met: PF reached 9 runs, GP 10')
    >>> ratio_verdict(math.nan, 0, 10, 0), ratio_verdict(math.nan, 3, 0, 0), ratio_verdict(1.0, 10, 10, 2)
    ('not met: PF reached 0 runs, GP 10', 'no verdict: GP reached no run', 'no verdict: 2 runs ended in error')
    """
    from ..analysis.tables import errored_verdict

    if errored:
        return errored_verdict(errored)
    if gp_reached == 0:
        return "no verdict: GP reached no run"
    if pf_reached < gp_reached:
        return f"not met: PF reached {pf_reached} run{'s' if pf_reached != 1 else ''}, GP {gp_reached}"
    return "met" if ratio <= TIME_RATIO_TARGET else "not met"


def stall_verdict(stalled: int, errored: int) -> str:
    """The target of no stalled run (no verdict on a set with errors).

    >>> stall_verdict(0, 0), stall_verdict(1, 0), stall_verdict(0, 1)
    ('met', 'not met', 'no verdict: 1 run ended in error')
    """
    from ..analysis.tables import errored_verdict

    if errored:
        return errored_verdict(errored)
    return "met" if stalled == 0 else "not met"


def pilot_rows(room: str, perception: str, pilot: str, g) -> list[Any]:
    """A pilot's row on a room: reached of runs, the spread of time and path over its reached runs,
    its longest stall and its runs with one."""
    from ..analysis.tables import distinct_runs, errored

    ok = g[g["outcome"] == "reached"]
    bad = errored(g)
    n_distinct = len(distinct_runs(ok))
    reached = f"{len(ok)}/{len(g)}" + (f" ({n_distinct} distinct)" if n_distinct < len(ok) else "")
    reached += f", {bad} errored" if bad else ""
    longest = g["stall_s"].max()
    stalled = int((g["stall_s"] >= STALL_S).sum())
    return [
        room,
        perception,
        pilot,
        reached,
        spread(ok["time_s"].to_numpy(dtype=float)),
        spread(ok["path_cm"].to_numpy(dtype=float), "{:.0f}"),
        "-" if not math.isfinite(longest) else f"{longest:.0f}",
        f"{stalled}/{len(g)}",
    ]


def compare_rows(room: str, perception: str, runs) -> list[Any]:
    """The room's PF-against-GP row: the ratio of the mean times over reached runs and PF's stalls,
    each with its target."""
    from ..analysis.tables import errored

    pf, gp = runs[runs["pilot"] == PF], runs[runs["pilot"] == GP]
    pf_ok, gp_ok = (g.loc[g["outcome"] == "reached", "time_s"] for g in (pf, gp))
    ratio = float(pf_ok.mean() / gp_ok.mean()) if len(pf_ok) and len(gp_ok) else math.nan
    bad = int((runs["pilot"].isin((PF, GP)) & (runs["outcome"] == "error")).sum())
    stalled = int((pf["stall_s"] >= STALL_S).sum())
    return [
        room,
        perception,
        "-" if not math.isfinite(ratio) else f"{ratio:.2f}",
        ratio_verdict(ratio, len(pf_ok), len(gp_ok), bad),
        f"{stalled}/{len(pf)}",
        stall_verdict(stalled, errored(pf)),
    ]


def section(
    report: Report,
    s,
    out: Path,
    table1_out: Path,
    ex,
    pilots: tuple[str, ...],
    scenario: Callable,
    write_runs: Callable,
) -> None:
    """The section: every room of :func:`square_rooms` (or ``s.rooms``), both perceptions, the
    paper's two pilots and ``pilots``."""
    from ..analysis.tables import error_notes, errored, load_runs
    from .compare import run_on

    rooms = s.rooms if s.rooms is not None else square_rooms()
    every = [PF, GP, *pilots]
    planned = jobs(rooms, s.room_reruns, s.reruns, out, table1_out, every, scenario)
    work = [j for js in planned.values() for j in js]
    run_on(work, ex)
    logs = [j.log for j in work]
    runs = load_runs(paths=logs)
    runs["stall_s"] = runs["log"].map(stalls(logs, ex))
    write_runs(runs, out / "runs.csv")
    report.heading(f"Pilots on every {ROOM_SIZE[0]:g} m x {ROOM_SIZE[1]:g} m room")
    report.text(
        f"Every bundled room of the paper's size ({', '.join(rooms)}), with vision and with ground truth: "
        f"{s.reruns} reruns per pilot on {TABLE1_ROOM} (Table 1's runs), {s.room_reruns} on every other room, the "
        "same seeds for both pilots. Time and path over the reached runs, every rerun counted (identical reruns "
        "too: a spread of 0 says the reruns repeat one run): mean ± SD (n - 1) [bootstrap 95 % interval of the "
        f"mean]. A stall: a stretch in which the robot's true position moved less than {STALL_M:g} m net in every "
        f"{STALL_S:g} s (so at least {STALL_S:g} s long), the Rescuer's deliberate scans (it holds the wheels, "
        "stopped, to look around) left out of the time; the longest per pilot (0: none), and its runs with one. "
        f"Every run: {out / 'runs.csv'}."
    )
    errors = error_notes(runs)
    report.errored([f"Rooms: {e}" for e in errors], errored(runs))
    rows, targets = [], []
    for (room, perception), js in planned.items():
        g = runs[runs["log"].isin({j.log for j in js})]
        rows += [pilot_rows(room, perception, p, g[g["pilot"] == p]) for p in map(label, every)]
        targets.append(compare_rows(room, perception, g))
    header = ["room", "perception", "pilot", "reached", "time s: mean ± SD [95 % CI]", "path cm: mean ± SD [95 % CI]"]
    report.table(header + ["longest stall s", f"runs with a {STALL_S:g} s stall"], rows)
    report.text(
        f"The potential field against the geometric pilot, per room and perception. Targets: PF's mean time at "
        f"most {TIME_RATIO_TARGET:g}x GP's (the means over each pilot's reached runs; PF reaching fewer runs than GP "
        f"does not meet it); no PF run with a {STALL_S:g} s stall. A set with a run that ended in error gets no "
        "verdict."
    )
    report.table(
        [
            "room",
            "perception",
            "PF/GP mean time",
            f"target (at most {TIME_RATIO_TARGET:g})",
            f"PF runs with a {STALL_S:g} s stall",
            "target (none)",
        ],
        targets,
    )
    report.notes(errors)


__all__ = ["ROOM_SIZE", "TIME_RATIO_TARGET", "section", "square_rooms"]
