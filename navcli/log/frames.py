"""A run kept in memory: the topics a log holds as tables (the poses, ``/pilot``, ``/bids``,
``/vision``, ``/navigation``, ``/events``), as pandas DataFrames with the columns
:func:`navcli.analysis.read_log` gives the same topics of a log, without writing a file.

:class:`FrameRecorder` is an observer of a run (:func:`navcli.runner.run_mission`): told of the
mission before its first step (its start pose and events), then of every tick. It keeps the
messages the recorder would encode, as plain values (:mod:`.records`), and makes the DataFrames
once, when asked. The scenes a viewer draws (``/world/scene`` ...) and ``/tf`` are left out: they
are drawings, not tables.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from . import format as fmt
from .format import pilot_message
from .records import bids_record, navigation_record, vision_record

if TYPE_CHECKING:
    import pandas as pd

    from ..geometry import Pose
    from ..mission import Event, Mission, Tick


class FrameRecorder:
    """Keeps a run's tables in memory (see the module docstring); :meth:`frames` makes them."""

    def __init__(self) -> None:
        self.rows: dict[str, list[dict[str, Any]]] = {
            t: []
            for t in (
                fmt.POSE_TOPIC,
                fmt.ODOMETRY_TOPIC,
                fmt.PILOT_TOPIC,
                fmt.BIDS_TOPIC,
                fmt.VISION_TOPIC,
                fmt.NAVIGATION_TOPIC,
                fmt.EVENTS_TOPIC,
            )
        }
        self._last_ns = -1
        self._start: tuple[Event, ...] = ()

    def begin(self, mission: Mission) -> None:
        """The mission's start: its first poses and the events of its start, at time 0."""
        w = mission.world
        self._poses(w.pose, w.odometry.pose, 0)
        self._start = mission.pending  # (without a log they reach the first tick's events too: kept once)
        for e in self._start:
            self._event(e, 0)

    def __call__(self, mission: Mission, tick: Tick) -> None:
        ns = tick.time_ns
        self._poses(tick.pose, tick.odometry, ns)
        v, w = tick.command
        from ..analysis.logs import flatten

        self.rows[fmt.PILOT_TOPIC].append(
            flatten(pilot_message(tick.pilot.info, v, math.degrees(w))) | {"log_time_ns": ns}
        )
        self.rows[fmt.BIDS_TOPIC].append(flatten(bids_record(tick)) | {"log_time_ns": ns})
        self.rows[fmt.VISION_TOPIC].append(flatten(vision_record(tick)) | {"log_time_ns": ns})
        if tick.navigation is not None:
            self.rows[fmt.NAVIGATION_TOPIC].append(flatten(navigation_record(tick)) | {"log_time_ns": ns})
        for e in tick.events:
            if not any(e is s for s in self._start):
                self._event(e, ns)

    def end(self, mission: Mission) -> None:
        """The last poses, if a stop inside a tick left them out, and the events said after the last
        tick (an observer's stop), as the recorder writes them when it closes a log."""
        w = mission.world
        if w.time_ns != self._last_ns:
            self._poses(w.pose, w.odometry.pose, w.time_ns)
        for e in mission.pending:
            self._event(e, w.time_ns)

    def _poses(self, truth: Pose, odometry: Pose, ns: int) -> None:
        self._last_ns = ns
        for topic, p in ((fmt.POSE_TOPIC, truth), (fmt.ODOMETRY_TOPIC, odometry)):
            z, w = math.sin(p.theta / 2), math.cos(p.theta / 2)  # the heading as a log's quaternion gives it back
            self.rows[topic].append(
                {
                    "x": p.x,
                    "y": p.y,
                    "theta": math.atan2(2.0 * w * z, 1.0 - 2.0 * z * z),
                    "frame_id": "world",
                    "log_time_ns": ns,
                }
            )

    def _event(self, e: Event, ns: int) -> None:
        self.rows[fmt.EVENTS_TOPIC].append(
            {"level": e.level, "name": e.source, "message": e.message, "log_time_ns": ns}
        )

    def frames(self) -> dict[str, pd.DataFrame]:
        """The tables, one per topic that holds a row (see the module docstring)."""
        from ..analysis.logs import topic_frames

        return topic_frames({t: rows for t, rows in self.rows.items() if rows})
