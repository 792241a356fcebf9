"""Ctrl-C and SIGTERM as exceptions: how every command stops cleanly (a log closed and marked
``interrupted``, a temporary file removed, every worker stopped) instead of dying mid-write.

Standard library only, so the command line can install these handlers before it imports anything
heavy.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from typing import Any, Callable, Iterator


def in_physics_callback(frame: Any) -> bool:
    """True inside a pymunk callback (called from C through cffi, which prints and swallows any
    exception raised there, so a signal's exception raised there would be lost)."""
    while frame is not None:
        if "pymunk" in frame.f_code.co_filename:
            return True
        frame = frame.f_back
    return False


def raising(exc: type[BaseException]) -> Callable[[int, Any], None]:
    """A signal handler that raises ``exc``, but never inside a pymunk callback: there it tries
    again 10 ms later (``SIGALRM``), so Ctrl-C and SIGTERM always end a run."""

    def handler(signum: int, frame: Any) -> None:
        if in_physics_callback(frame):
            signal.signal(signal.SIGALRM, handler)
            signal.setitimer(signal.ITIMER_REAL, 0.01)
            return
        raise exc

    return handler


class Terminated(KeyboardInterrupt):
    """SIGTERM (a scheduler's or a shell's kill): ends a run like Ctrl-C, and is logged as such;
    the CLI exits 143 (the shell's convention, 128 + the signal's number)."""

    exit_code = 128 + signal.SIGTERM


def exit_code(e: KeyboardInterrupt) -> int:
    """130 for Ctrl-C, 143 for SIGTERM (the shell's convention, 128 + the signal's number)."""
    return getattr(e, "exit_code", 128 + signal.SIGINT)


def stopped_by(e: KeyboardInterrupt) -> str:
    """What stopped a command, in the words its last line says."""
    return "stopped by SIGTERM" if isinstance(e, Terminated) else "interrupted (Ctrl-C)"


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """Ctrl-C and SIGTERM wait while inside (closing a log, saving a model: the file and what the
    caller is told of it must agree) and are delivered, to the handlers they had, right after.
    Handlers, not the signal mask: with a pool's threads beside the main one, a blocked signal
    would go to one of them. Outside the main thread (where no handler can be set) a no-op."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[signal.Signals] = []
    old = {
        s: signal.signal(s, lambda signum, frame: got.append(signal.Signals(signum)))
        for s in (signal.SIGINT, signal.SIGTERM)
    }
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
        for s in dict.fromkeys(got):
            signal.raise_signal(s)
