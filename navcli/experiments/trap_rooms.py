"""The trap rooms per room, for ``navcli reproduce``: each pilot's share of runs reached against
:data:`TRAP_REACHED_TARGET`, the runs that ended ``blocked`` (the Rescuer found no way out while
time remained; target: none), the runs timed out, and the contacts per run. The thesis gives no
figure of contacts for its robot, and the table says so rather than set one beside navcli's."""

from __future__ import annotations

from typing import Any

from ..analysis.stats import bootstrap_mean, wilson_interval
from .document import Report, interval_text

TRAP_REACHED_TARGET = 0.95
"""Our target for the trap rooms: at least this share of each pilot's runs in each room reached."""


def table(report: Report, rooms: tuple[str, ...], runs, pilots: tuple[str, ...]) -> None:
    """Per trap room and pilot: reached against :data:`TRAP_REACHED_TARGET`, how the runs that did
    not reach ended (a ``blocked`` end, the Rescuer finding no way out, while time remained; a
    time-out), and the contacts per run."""
    report.text(
        f"Per room and pilot. Targets: at least {TRAP_REACHED_TARGET:.0%} of the runs reached; no run ended "
        'blocked ("no way out") while time remained. The thesis gives no figure of contacts for its robot, so '
        "none stands beside navcli's. A set with a run that ended in error gets no verdict."
    )
    rows = []
    for room in rooms:
        for pilot in pilots:
            g = runs[(runs["scenario"] == room) & (runs["pilot"] == pilot) & (runs["outcome"] != "interrupted")]
            rows.append(_row(room, pilot, g))
    report.table(
        [
            "room",
            "pilot",
            "reached [95 % CI]",
            f"target (at least {TRAP_REACHED_TARGET:.0%})",
            "ended blocked",
            "target (none)",
            "timed out",
            "contacts per run [95 % CI]",
            "the thesis' contacts",
        ],
        rows,
    )


def _row(room: str, pilot: str, g) -> list[Any]:
    """One trap room's row for one pilot (its runs ``g``, errors among them)."""
    from ..analysis.tables import errored, errored_verdict

    n, bad = len(g), errored(g)
    k = int((g["outcome"] == "reached").sum())
    blocked, timeout = int((g["outcome"] == "blocked").sum()), int((g["outcome"] == "timeout").sum())
    lo, hi = wilson_interval(k, n)
    no = errored_verdict(bad) if bad else ""
    m, c_lo, c_hi = bootstrap_mean(g["collisions"].to_numpy(dtype=float))
    return [
        room,
        pilot,
        f"{k}/{n} [{lo:.0%}, {hi:.0%}]" + (f", {bad} errored" if bad else "") if n else "-",
        no or ("met" if n and k >= TRAP_REACHED_TARGET * n else "not met"),
        f"{blocked}/{n}",
        no or ("met" if blocked == 0 else "not met"),
        f"{timeout}/{n}",
        interval_text(m, c_lo, c_hi),
        "no figure",
    ]


__all__ = ["TRAP_REACHED_TARGET", "table"]
