"""Stalls: stretches of a run in which the robot goes nowhere while it is not deliberately looking
around, read from its log.

A **stall** is a stretch of the run over which the robot's true position (``/robot/pose``) moved
less than :data:`STALL_M` net in every :data:`STALL_S` of it: at each of its poses, the robot is
under 0.3 m from where it was 60 s before (as the crow flies), whether it stood still, turned on
the spot or swung back and forth (a potential field caught in a minimum does all three). A
stretch runs from the start of its first such 60 s to its last pose, so a stall lasts at least
60 s, and a run with none has a longest stall of 0.

Time the robot spends in a **deliberate scan** does not count: the Rescuer holds the wheels and
stops them (``/bids``: the motion winner is ``navigation``; ``/navigation``: the motion bid it
forwarded is the ``rescuer``'s; the winning action's speed is 0) to sweep, scan or turn to look
around. Those ticks are taken out of the clock (a stretch's length is the time outside them) and
their poses out of the trace, so a scan neither makes a stall nor breaks one. A log without the
``/navigation`` topic (navigation by a learned or hand-coded policy) has no deliberate scans: its
every tick counts. A Pilot's reflex after a bump, the Rescuer's drive out and any move of a Pilot
are no scan: a robot that backs and bumps in one place stalls.

The thresholds are declared once here (:data:`STALL_S`, :data:`STALL_M`); ``navcli reproduce``
counts the runs with a stall per room and pilot.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..log.format import BIDS_TOPIC, NAVIGATION_TOPIC, POSE_TOPIC
from .logs import read_log, require

STALL_S = 60.0
"""s: how long the robot must stay near one place, outside deliberate scans, for a stall."""
STALL_M = 0.3
"""m: how far from where a stretch began the robot must get for the stretch to be progress."""
SCANNER = "rescuer"
"""The Navigation agent whose stops are deliberate scans (it sweeps, scans and turns to look)."""


def longest_stall(
    t: np.ndarray, xy: np.ndarray, counted: np.ndarray | None = None, window: float = STALL_S, radius: float = STALL_M
) -> float:
    """The longest stall (s; 0 for none) of poses at times ``t`` (s, increasing) and positions
    ``xy`` (n x 2, m), counting only the poses where ``counted`` is true (all when None) and only
    the time from a counted pose's predecessor to it (module docstring): the longest stretch
    covered by ``window``-long spans of counted time whose two ends lie under ``radius`` apart.

    >>> t = np.arange(8) * 10.0  # a pose every 10 s; a window of 30 s
    >>> xy = np.array([[0, 0], [1, 0], [1, 0.1], [1, 0], [1, 0.1], [1, 0], [2, 0], [3, 0]])
    >>> longest_stall(t, xy, window=30.0)  # from 10 s to 50 s near (1, 0)
    40.0
    >>> # the pose at 30 s a scan: its 10 s leave the clock
    >>> longest_stall(t, xy, np.array([True, True, True, False, True, True, True, True]), window=30.0)
    30.0
    """
    keep = np.ones(len(t), dtype=bool) if counted is None else np.asarray(counted, dtype=bool)
    times = np.asarray(t, dtype=float)
    dt = np.diff(times, prepend=times[:1])
    clock = np.cumsum(np.where(keep, dt, 0.0))[keep]  # time outside deliberate scans
    pts = np.asarray(xy, dtype=float)[keep]
    if len(clock) < 2:
        return 0.0
    back = np.searchsorted(clock, clock - window, side="right") - 1  # the last pose a window or more before
    has = back >= 0
    step = pts - pts[np.maximum(back, 0)]
    stalled = has & ((step * step).sum(axis=1) < radius * radius)
    best = 0.0
    i, n = 0, len(stalled)
    while i < n:  # each run of stalled poses covers from its first's window start to its last
        if not stalled[i]:
            i += 1
            continue
        first = i
        while i < n and stalled[i]:
            i += 1
        best = max(best, float(clock[i - 1] - clock[back[first]]))
    return best


def scanning(poses: pd.DataFrame, bids: pd.DataFrame | None, navigation: pd.DataFrame | None) -> np.ndarray:
    """Per pose of ``poses`` (in time order), whether the tick it closes was a deliberate scan
    (module docstring): the latest ``/bids`` and ``/navigation`` messages at or before the pose's time."""
    if bids is None or navigation is None or bids.empty or navigation.empty:
        return np.zeros(len(poses), dtype=bool)
    speed = bids.get("motion.actions.navigation.speed", pd.Series(np.nan, index=bids.index))
    tick = pd.DataFrame(
        {
            "log_time_ns": bids["log_time_ns"],
            "held": (bids.get("motion.winner") == "navigation").to_numpy() & (speed == 0.0).to_numpy(),
        }
    )
    agent = navigation.get("forwarded.motion_agent", pd.Series("", index=navigation.index))
    tick = tick.merge(
        pd.DataFrame({"log_time_ns": navigation["log_time_ns"], "agent": agent.fillna("")}),
        on="log_time_ns",
        how="left",
    )
    tick["scan"] = tick["held"] & (tick["agent"] == SCANNER)
    at = pd.merge_asof(poses[["log_time_ns"]], tick[["log_time_ns", "scan"]], on="log_time_ns")
    return at["scan"].fillna(False).to_numpy(dtype=bool)


def run_stall(path: str | Path) -> float:
    """The longest stall (s) of the run logged at ``path``, deliberate scans left out (module
    docstring); a run with one of :data:`STALL_S` or more stalled. :class:`~.logs.LogError` for a
    log it cannot read."""
    log = require(read_log(path, topics=[POSE_TOPIC, BIDS_TOPIC, NAVIGATION_TOPIC]), POSE_TOPIC)
    poses = log[POSE_TOPIC].sort_values("log_time_ns")
    scan = scanning(poses, log.topics.get(BIDS_TOPIC), log.topics.get(NAVIGATION_TOPIC))
    return longest_stall(poses["time_s"].to_numpy(), poses[["x", "y"]].to_numpy(), ~scan)


__all__ = ["STALL_M", "STALL_S", "longest_stall", "run_stall", "scanning"]
