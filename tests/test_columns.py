"""The tables of runs are built to the columns navcli/analysis/columns.py declares (which the docs
list): a run's row, the pilot table and the improvements hold exactly those, every one filled
where the runs say what it holds."""

from __future__ import annotations

import math

import pandas as pd

import navcli
from navcli.analysis.columns import IMPROVEMENTS, PILOT_TABLE, RUN, RUN_FROM_LOGS
from navcli.analysis.tables import improvements, pilot_table, summary_row


CONFIG = {"scenario": {"sha256": "ab" * 32}, "perception": "vision", "time_limit_s": 60.0, "params": {}}


def _summary(pilot: str, seed: int, time_s: float, path_m: float, outcome: str = "reached") -> dict:
    return {
        "scenario": "room",
        "pilot": pilot,
        "seed": seed,
        "outcome": outcome,
        "time_s": time_s,
        "path_length_m": path_m,
        "collisions": 1,
        "camera_looks": 7,
        "ticks": round(time_s * 10),
        "diverting_targets": 0,
        "navigation": "agents",
    }


def _row(pilot: str, seed: int, time_s: float, path_m: float, outcome: str = "reached") -> dict:
    return summary_row(_summary(pilot, seed, time_s, path_m, outcome), CONFIG, f"{pilot}-{seed}")


def _runs() -> pd.DataFrame:
    """Two pilots, three seeds each, every run reached but one of ``b``'s (which ran out of time)."""
    rows = [_row("a", s, 10.0 + s, 2.0 + s) for s in (1, 2, 3)]
    rows += [_row("b", s, 12.0 + s, 2.5 + s) for s in (1, 2)] + [_row("b", 3, 60.0, 9.0, "timeout")]
    return pd.DataFrame(rows)


def test_a_runs_row_holds_the_declared_columns_and_its_parameters():
    assert list(_row("a", 1, 10.0, 2.0)) == list(RUN)
    row = summary_row(_summary("a", 1, 10.0, 2.0), CONFIG | {"params": {"pilot": {"K": 30.0}}}, "x")
    assert list(row) == [*RUN, "params.pilot.K"] and row["params.pilot.K"] == 30.0


def test_the_pilot_table_holds_the_declared_columns_each_filled():
    table = pilot_table(_runs())
    assert list(table.columns) == list(PILOT_TABLE)
    b = table.set_index("pilot").loc["b"]
    assert b["runs"] == 3 and b["reached"] == 2 and b["outcome_timeout"] == 1
    assert b["time_fail_at_limit_mean"] == (13.0 + 14.0 + 60.0) / 3  # the timeout counted at its limit
    assert b["path_cm_mean"] == 100 * (3.5 + 4.5) / 2
    assert not table.isna().any().any()  # two reached runs or more per pilot: every column has a value


def test_an_empty_pilot_table_still_has_its_columns():
    assert list(pilot_table(_runs().iloc[:0]).columns) == list(PILOT_TABLE)


def test_the_improvements_hold_the_declared_columns_each_filled():
    imps = improvements(_runs(), "b")
    assert list(imps.columns) == list(IMPROVEMENTS)
    time = imps.set_index("metric").loc["time_s"]
    assert time["pairs"] == 2 and math.isclose(
        time["improvement_pct"], 100 * (13.5 - 11.5) / 13.5
    )  # means at seeds 1, 2
    assert not imps.isna().any().any()


def test_the_api_returns_the_declared_columns(tmp_path):
    kw = dict(reruns=1, time_limit=1.0, jobs=1)
    without_logs = navcli.compare(["scenarios/open-arena.yaml"], ["geometric"], **kw)
    from_logs = navcli.compare(["scenarios/open-arena.yaml"], ["geometric"], out=tmp_path, **kw)
    assert [c for c in without_logs.columns if not c.startswith("params.")] == list(RUN)
    assert {c for c in from_logs.columns if not c.startswith("params.")} == set(RUN) | set(RUN_FROM_LOGS)
    assert "params.pilot.K" in without_logs.columns and "params.pilot.K" in from_logs.columns
