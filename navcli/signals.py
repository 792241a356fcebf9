"""Ctrl-C and SIGTERM as exceptions: how every command stops cleanly (a log closed and marked
``interrupted``, a temporary file removed, every worker stopped) instead of dying mid-write.

Standard library only, so the command line can install these handlers before it imports anything
heavy.
"""

from __future__ import annotations

import signal
from typing import Any, Callable


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
