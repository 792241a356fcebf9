"""Run one mission to its end, recording it: the engine behind ``navcli run``, the benchmark and
``navcli compare``.

It owns the lifetime of a log: whatever ends the run (the target, the time limit, Ctrl-C, an
exception) the recorder is finished with a summary that says so, and the file gets its final name.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from .checks.arguments import COMMON, checked, flag, function, instance, optional, whole
from .config import RunSpec
from .log.compression import DEFAULT as DEFAULT_COMPRESSION, refusal as compression_refusal
from .signals import Terminated, deferred
from .mission import Event, Mission, Tick

if TYPE_CHECKING:
    from .log.writer import Recorder


@dataclass(frozen=True)
class RunResult:
    summary: dict
    log: Path | None
    wall_s: float

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.summary["time_s"] / self.wall_s if self.wall_s > 0 else float("inf")


def open_log(
    spec: RunSpec,
    mission: Mission,
    path: Path,
    *,
    live: bool = False,
    port: int = 8765,
    overwrite: bool = False,
    compression: str = DEFAULT_COMPRESSION,
):
    """The log of ``mission`` at ``path``, begun: the configuration, the first pose and the events of
    the start. The scenario's own file is protected from being overwritten by it. (foxglove is
    imported here, only when a log is written.)"""
    from .log.format import plugin_pilot_message
    from .log.writer import Recorder
    from .plugins import pilot

    recorder = Recorder(
        path,
        live=live,
        port=port,
        protect=(spec.scenario.source,),
        pilot_message=plugin_pilot_message(pilot(spec.pilot)),
        overwrite=overwrite,
        compression=compression,
    )
    try:
        w = mission.world
        recorder.start(spec, w.pose, w.odometry.pose)
        for e in mission.drain_events():
            recorder.event(e, 0)
    except BaseException as e:
        _stop(mission, e)
        close_log(recorder, mission, stopped=True)  # a log begun is closed, saying what stopped its start
        raise
    return recorder


def _stop(mission: Mission, e: BaseException) -> None:
    """End ``mission`` as stopped by the exception ``e``: ``interrupted`` by Ctrl-C or SIGTERM
    (:class:`Terminated`), ``error`` by anything else, with the reason in words."""
    if isinstance(e, Terminated):
        mission.abort("interrupted", "stopped by SIGTERM")
    elif isinstance(e, KeyboardInterrupt):
        mission.abort("interrupted", "stopped by the user (Ctrl-C)")
    else:  # a plugin's failure says whose it was in words of its own
        from .plugins import PluginError

        mission.abort("error", str(e) if isinstance(e, PluginError) else f"{type(e).__name__}: {e}")


def close_log(
    recorder, mission: Mission, summary: dict | None = None, *, stopped: bool = False, keep_serving: bool = False
) -> None:
    """Write ``mission``'s summary (by default its own) and close its log, with Ctrl-C and SIGTERM
    held meanwhile; the last poses are written first if a stop inside a tick left them out.
    ``stopped``: the mission was ended by :func:`_stop`; the log's last event says why."""
    with deferred():
        w = mission.world
        for e in mission.drain_events():  # an observer's stop, said after the last tick
            recorder.event(e, w.time_ns)
        if stopped:
            recorder.event(Event(mission.time, "mission", "error", mission.reason), w.time_ns)
        recorder.finish(
            mission.summary() if summary is None else summary,
            w.time_ns,
            (w.pose, w.odometry.pose),
            keep_serving=keep_serving,
        )


Observer = Callable[[Mission, Tick], "bool | None"]
"""Told of every tick of a mission, after it: the recorder (:func:`recording`), the progress bar,
live pacing (:class:`Pacer`), a trainer, a comparison, a user's function. Observers read; they
never step the mission or change what it decides, but one may stop it: returning ``False`` (as
Stable-Baselines3's callbacks do) ends the mission ``interrupted``, "stopped by <its name>". Given
to :func:`run_mission`, one with a ``begin(mission)`` method is told of the mission before its first
step as well, and one with an ``end(mission)`` after its last."""


def advance(
    mission: Mission,
    observers: tuple[Observer, ...] | list[Observer] = (),
    until: Callable[[Mission], bool] | None = None,
) -> None:
    """The run loop: step ``mission`` until it ends, or until ``until(mission)`` holds (checked
    before each step), telling every observer of each tick in turn (one that returns ``False``
    stops it: see :data:`Observer`); with none, no tick's record is built
    (:meth:`Mission.step_unrecorded`). ``navcli run``, the benchmark, training trials, the policy
    comparison and the Gymnasium environment all run missions through here."""
    while mission.outcome is None and not (until is not None and until(mission)):
        if not observers:  # nobody reads the record: it is not built
            mission.step_unrecorded()
            continue
        tick = mission.step()
        for observe in observers:
            if observe(mission, tick) is False and mission.outcome is None:
                mission.abort(
                    "interrupted", f"stopped by {getattr(observe, '__name__', type(observe).__name__)}", say=True
                )


def recording(recorder: Recorder) -> Observer:
    """The observer that writes each tick to ``recorder`` (which holds no reference to the mission)."""
    return lambda mission, tick: recorder.tick(tick)


class Pacer:
    """The observer of a live run: it holds each tick back until its simulated time has come in
    real time, from the moment it is made."""

    def __init__(self) -> None:
        self.t0 = time.perf_counter()

    def __call__(self, mission: Mission, tick: Tick) -> None:
        lag = mission.time - (time.perf_counter() - self.t0)
        if lag > 0:
            time.sleep(lag)


ARGUMENTS = COMMON | {
    "spec": instance(RunSpec, what="a RunSpec (navcli.spec builds one from a scenario)"),
    "record": flag,
    "live": flag,
    "keep_serving": flag,
    "port": whole(0, 65535, "a port"),
    "on_tick": optional(function),
    "on_open": optional(function),
    "log_compression": compression_refusal,
}
"""The arguments of :func:`run_mission`, checked at each call (:mod:`navcli.checks.arguments`)."""


@checked(ARGUMENTS)
def run_mission(  # noqa: PLR0913 (keyword-only: each a choice of how the run is watched or logged)
    spec: RunSpec,
    *,
    out: Path | None = None,
    record: bool = True,
    live: bool = False,
    port: int = 8765,
    on_tick: Observer | None = None,
    on_open: Callable[[Recorder], None] | None = None,
    keep_serving: bool = False,
    observers: Sequence[Observer] = (),
    overwrite: bool = False,
    log_compression: str = DEFAULT_COMPRESSION,
) -> RunResult:
    """Run the configuration ``spec`` to its end and return its summary.

    A ``KeyboardInterrupt`` ends the run as ``interrupted`` (:class:`Terminated`: by SIGTERM) and
    is re-raised after the log is closed; any other exception ends it as ``error`` and is
    re-raised likewise.

    Args:
        spec: the run's whole configuration (``navcli.spec`` makes one).
        out: the log's path (default: :meth:`RunSpec.default_log_path`).
        record: False runs without a log (the benchmark's baseline).
        live: serve the run to Foxglove on ``ws://127.0.0.1:<port>``, paced to real time.
        port: the port ``live`` serves on (0: any free port).
        on_tick: observes every tick (a progress display; tests use it to interrupt a run).
        on_open: called once the log is open (what the CLI says of it: a killed run's
            ``.partial`` kept aside, the port ``--live`` took).
        keep_serving: with ``live``, a mission that ends by itself leaves the server up for its
            viewers, until the caller's ``recorder.stop_serving()``.
        observers: told of every tick, after ``on_tick``; those with a ``begin(mission)`` before
            the first step and those with an ``end(mission)`` after the last, whatever ended it;
            any may stop the run (:data:`Observer`).
        overwrite: replace an existing log at ``out`` (else it is refused before the mission).
        log_compression: how the log's chunks are compressed
            (:data:`navcli.log.compression.COMPRESSIONS`; the same messages whichever).

    Returns:
        The run's summary (``/mission/summary``'s fields), its log's path and its wall time.

    Raises:
        navcli.log.writer.LogPathError: a log path that cannot be written, or an existing log
            there without ``overwrite``, before the mission starts.
    """
    path = (out or spec.default_log_path()) if record or live else None
    explain = path is not None or on_tick is not None or bool(observers)  # someone reads the explanations
    mission = Mission(spec, snapshots=path is not None, explain=explain)
    _tell(observers, "begin", mission)
    recorder = (
        open_log(spec, mission, path, live=live, port=port, overwrite=overwrite, compression=log_compression)
        if path is not None
        else None
    )
    told: list[Observer] = [recording(recorder)] if recorder else []
    told += ([on_tick] if on_tick else []) + list(observers)
    t0 = time.perf_counter()
    told += [Pacer()] if live else []
    try:
        if recorder and on_open:
            on_open(recorder)  # inside: a stop while the caller speaks of the log still closes it
        advance(mission, told)
    except BaseException as e:
        _stop(mission, e)
        _tell(observers, "end", mission)
        if recorder:
            close_log(recorder, mission, stopped=True)
        raise
    wall = time.perf_counter() - t0
    summary = mission.summary()
    _tell(observers, "end", mission)
    if recorder:
        close_log(recorder, mission, summary, keep_serving=keep_serving)
    return RunResult(summary, path, wall)


def _tell(observers: Sequence[Observer], hook: str, mission: Mission) -> None:
    """Call ``hook`` (``begin``: before the first step; ``end``: after the last, before the log is
    closed) of each observer that has it."""
    for o in observers:
        method = getattr(o, hook, None)
        if method is not None:
            method(mission)
