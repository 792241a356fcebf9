"""How every command ends: the one mapping from what stopped it to its exit code and its last line.

====  =========================================================================================
code  meaning
====  =========================================================================================
0     success (``run``: the mission reached its target)
1     an internal error (a bug, said so in one line; ``NAVCLI_DEBUG=1`` shows its traceback), or
      a plugin failed: its code raised, returned what navcli does not take, or overran
      ``robot.decision_limit_s`` (said as that plugin's, with its name and the file and line in
      it: :class:`~navcli.plugins.PluginError`)
2     bad input: a :class:`~navcli.NavcliError` (a refused scenario, plan, model, log, option or
      output path), or a Dask scheduler that cannot be reached, or an optional extra not installed
3     ``run``: the mission ended without reaching its target (timeout, blocked)
4     ``compare``, ``sweep``, ``reproduce``: every table and report was written, but some runs
      ended in ``error``; the tables count them and say why, and the command lists them
130   interrupted by Ctrl-C; 143: stopped by SIGTERM (the shell's convention, 128 + the signal)
141   the reader of the output went away (``navcli params | head``), as if killed by SIGPIPE
====  =========================================================================================

Standard library and typer only: imported on every start.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from typing import Any, Callable, Iterator

import typer

from .. import NavcliError
from ..signals import exit_code, stopped_by

EXIT_INTERNAL, EXIT_BAD_INPUT, EXIT_FAILED_MISSION, EXIT_RUNS_ERRORED, EXIT_PIPE = 1, 2, 3, 4, 128 + 13
RUNS_ERRORED_HELP = (
    f"Exits {EXIT_RUNS_ERRORED} when some runs ended in error (everything is still written; the tables "
    "count those runs and say why)."
)
"""How the batch commands' ``--help`` states :data:`EXIT_RUNS_ERRORED`."""


def say(msg: str) -> None:
    """One line (or a few) to stderr: notes, warnings and refusals; stdout holds the results."""
    typer.echo(msg, err=True)


def describe(e: NavcliError) -> str:
    """A refusal as its command prints it: ``error: [option: ]message``, or the class's headline
    above a file's list of problems."""
    if e.headline:
        return f"error: {e.headline}\n{e}"
    return f"error: {e.option}: {e}" if e.option else f"error: {e}"


@contextlib.contextmanager
def about(option: str, kind: type[NavcliError] = NavcliError) -> Iterator[None]:
    """Refusals (of ``kind``) raised inside are about ``option`` (``--out``, ``--param`` ...),
    which they then name."""
    try:
        yield
    except kind as e:
        if e.option is None:
            e.option = option
        raise


@contextlib.contextmanager
def on_stop(what_is_kept: str | Callable[[], str]) -> Iterator[None]:
    """Ctrl-C or SIGTERM inside ends the command with what was kept and how to go on (said when
    the stop comes, if a callable), and 130 / 143."""
    try:
        yield
    except KeyboardInterrupt as e:
        say(f"{stopped_by(e)}: {what_is_kept() if callable(what_is_kept) else what_is_kept}")
        raise typer.Exit(exit_code(e)) from None


def refuse(message: str) -> typer.Exit:
    """Say ``error: message`` and return the exit of bad input, for ``raise refuse(...)``."""
    say(f"error: {message}")
    return typer.Exit(EXIT_BAD_INPUT)


def guarded(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` (a command) ending in an exit code and one line, never a traceback (see the table
    above); typer's and click's own exits pass through."""

    @functools.wraps(fn)
    def command(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except NavcliError as e:
            if os.environ.get("NAVCLI_DEBUG") and e.__cause__ is not None:  # a plugin's failure: its traceback
                import traceback

                traceback.print_exception(e.__cause__)
            say(describe(e))
            raise typer.Exit(e.exit_code) from None
        except KeyboardInterrupt as e:
            say(stopped_by(e))
            raise typer.Exit(exit_code(e)) from None
        except BrokenPipeError:  # the reader has what it wanted
            with contextlib.suppress(OSError):
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # nothing more to flush at exit
            raise typer.Exit(EXIT_PIPE) from None
        except Exception as e:
            if hasattr(e, "exit_code") or os.environ.get("NAVCLI_DEBUG"):  # typer.Exit, click's usage errors
                raise
            if isinstance(e, OSError):
                say(f"error: {e.strerror or e}" + (f": {e.filename}" if e.filename else ""))
            else:
                say(
                    f"navcli: internal error: {type(e).__name__}: {e}\n(a bug in navcli: please report it with "
                    f"the command that raised it; NAVCLI_DEBUG=1 shows the traceback)"
                )
            raise typer.Exit(EXIT_INTERNAL) from None

    return command


def guard_all(t: typer.Typer) -> None:
    """Every command of ``t`` and of its groups :func:`guarded`."""
    for c in t.registered_commands:
        if c.callback is not None:
            c.callback = guarded(c.callback)
    for g in t.registered_groups:
        if g.typer_instance is not None:
            guard_all(g.typer_instance)
