"""The Rescuer's watch on progress (see :mod:`.rescuer`, "Blocked"): the blocked window, the
bumps within it, and the stall window with its two clauses. A window restarts (:meth:`Progress.reset`)
with every change of the Rescuer's state and every new target; the stall window also at every
bump (the Pilot's reflex stops and looks around: a deliberate stop)."""

from __future__ import annotations

import math
from collections import deque
from typing import TypeVar

from ..geometry import Point
from ..params import NavigationParams, RobotParams
from .situation import Situation

T = TypeVar("T", tuple[float, float], tuple[float, float, float])

MIN_WINDOW_S = 20.0
"""s: the shortest blocked window and diverting timeout, whatever the speed (our design: a few of
the stops that take fixed time, a scan of five looks about 4 s, a reflex 4-6 s, so a fast robot
is not declared blocked by its own stops; at 0.3 m/s the windows are 40 s and 90 s)."""


class Progress:
    """Where the robot was and how near its target, over the windows that say it is blocked."""

    def __init__(self, params: NavigationParams, robot: RobotParams):
        self.params = params
        self.window_s = max(robot.time_to_drive(params.blocked_window_m), MIN_WINDOW_S)  # the blocked window, s
        self.stall_s = max(params.stall_window_s, robot.time_to_drive(params.stall_window_m))  # the stall window, s
        self.approach_s = params.stall_approach * self.stall_s  # the second clause's window, s
        self.best = math.inf  # the least distance to the target in the blocked window, m
        self.since = 0.0  # when it was set
        self.bumps: deque[float] = deque()  # their times, within the blocked window
        self.trail: deque[tuple[float, float, float]] = deque()  # (time, odometry x, y), the stall window
        self.approach: deque[tuple[float, float]] = deque()  # (time, distance to the target), stall_approach windows

    def reset(self, time: float) -> None:
        self.best, self.since = math.inf, time
        self.bumps.clear()
        self.trail.clear()
        self.approach.clear()

    def count_bumps(self, s: Situation) -> None:
        """Count the bumps of the blocked window; a bump restarts the stall window."""
        for bump in s.beliefs.bumps:
            self.bumps.append(bump.time)
            self.trail.clear()
            self.approach.clear()
        while self.bumps and self.bumps[0] < s.time - self.window_s:
            self.bumps.popleft()

    def caught(self) -> bool:
        """``blocked_bumps`` bumps or more within the blocked window."""
        return len(self.bumps) >= self.params.blocked_bumps

    def came_closer(self, s: Situation, aim: Point) -> None:
        """Note the distance to ``aim``: ``blocked_progress`` closer than the best restarts the window."""
        d = math.hypot(*aim)
        if d < self.best - self.params.blocked_progress:
            self.best, self.since = d, s.time

    def window_over(self, s: Situation) -> bool:
        """No progress within the blocked window."""
        return s.time - self.since > self.window_s

    def stalled(self, s: Situation, aim: Point) -> str | None:
        """The stall rule: over the last ``stall_s`` seconds (``max(stall_window_s, stall_window_m
        / robot.max_speed)``), the robot moved less than ``stall_progress`` net (odometry), so it
        came less than that closer to any target, whatever path it drove; or (``stall_approach``)
        over that many stall windows it came less than that closer to ``aim``."""
        closer = self._closer(s, aim) if self.params.stall_approach > 0 else None
        if closer is not None:
            return closer
        o = s.beliefs.odometry
        t0, x0, y0 = _window_start(self.trail, (s.time, o.x, o.y), self.stall_s)
        net = math.hypot(o.x - x0, o.y - y0)
        if s.time - t0 < self.stall_s or net >= self.params.stall_progress:
            return None
        return f"no progress: {net:.2f} m net in {s.time - t0:.0f} s"

    def _closer(self, s: Situation, aim: Point) -> str | None:
        """The stall rule's second clause (our design: a field that leads the robot away along a
        wall moves it on, but never closer)."""
        d = math.hypot(*aim)
        t0, d0 = _window_start(self.approach, (s.time, d), self.approach_s)
        if s.time - t0 < self.approach_s or d0 - d >= self.params.stall_progress:
            return None
        return f"no progress: {d0 - d:.2f} m closer in {s.time - t0:.0f} s"


def _window_start(trail: deque[T], now: T, span: float) -> T:
    """Append ``now`` (its first item the time) to ``trail`` and drop what lies before the window
    of ``span`` seconds ending there, keeping the last entry at or before the window's start;
    return the trail's first entry."""
    trail.append(now)
    while len(trail) > 1 and trail[1][0] <= now[0] - span:
        trail.popleft()
    return trail[0]
