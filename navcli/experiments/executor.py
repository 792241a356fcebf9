"""One execution layer for ``compare``, ``sweep``, ``tune`` and training evaluations.

Runs go to any :class:`concurrent.futures.Executor`:

* by default, a **local pool** of worker processes forked from this one (navcli already imported,
  so a pool starts in milliseconds and each run pays nothing for imports);
* with ``scheduler="tcp://HOST:PORT"``, an existing **Dask distributed** cluster, through
  ``Client(address).get_executor(pure=False, retries=...)``. ``pure=False`` because two runs of
  the same function with equal arguments are still two runs (Dask's default ``pure=True`` would
  collapse identical submissions into one); ``retries`` lets a run that raised be tried again.
  A run whose worker dies is rescheduled by the scheduler on another worker, whatever ``retries``.

Dask workers do not inherit the pool's forked imports: every task carries its whole
:class:`~navcli.config.RunSpec` (the scenario's text included), never a path a worker must
re-read; only the log path (``--out``) must be writable by every worker.

Stopping: while an executor is open (:func:`executor`), Ctrl-C raises ``KeyboardInterrupt`` and
SIGTERM :class:`Terminated` in the main thread, whatever the shell set (a script's background job
starts with SIGINT ignored). On either, the runs not started are cancelled and every local worker
is sent the same signal: a worker in a run ends it like the main process was ended (its log closed,
marked ``interrupted``, "stopped by the user (Ctrl-C)" or "stopped by SIGTERM"); an idle one just
exits; any still alive after a grace period is killed; then the interruption is re-raised. The same
holds when the signal reaches the whole process group (a terminal's Ctrl-C), and a pool broken by
its own workers' exit then is reported as the interruption it is. A worker whose main process died
outright (SIGKILL) notices within a second and ends itself likewise, so no process is left behind.
The CLI exits 130 for Ctrl-C and 143 for SIGTERM (``navcli.signals.exit_code``).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Iterable, Iterator, NoReturn, Sequence

from ..checks.arguments import MAX_JOBS
from ..checks.extras import MissingExtra, require  # noqa: F401 (where the execution layer's callers take them)
from ..signals import Terminated, in_physics_callback, raising

RETRIES = 2
"""Times Dask tries a run again after it raised (a worker's death is retried by the scheduler anyway)."""

GRACE_S = 2.0
"""Seconds a local worker is given to close its log after SIGTERM before it is killed."""

ORPHAN_CHECK_S = 0.5
"""How often a local worker checks that the process that forked it is still alive."""


# --- the local pool -----------------------------------------------------------------------
_busy = False  # in a local worker: a run is under way (a signal then ends it, closing its log)


def _ignore(signum: int, frame: Any) -> None:
    """A handler that does nothing: unlike ``SIG_IGN`` it cannot make a signal already pending raise
    Python's "signal ignored due to race condition" error."""


_first: list[int] = []  # in a local worker: the first signal received, which the run's log names


def _worker_signal(signum: int, frame: Any) -> None:
    # The first signal decides how the run ends: a later one (the SIGALRM of a retry, the SIGTERM
    # the pool sends its other workers when one exits on a group's Ctrl-C) only hurries it.
    if not _first:
        _first.append(signal.SIGTERM if signum == signal.SIGALRM else signum)
    signum = _first[0]
    if not _busy:
        os._exit(128 + signum)  # idle: nothing to close
    if in_physics_callback(frame):  # an exception raised there is printed and swallowed: try again in 10 ms
        signal.setitimer(signal.ITIMER_REAL, 0.01)
        return
    for s in (signal.SIGTERM, signal.SIGINT, signal.SIGALRM):  # the log is closed undisturbed, even by
        signal.signal(s, _ignore)  # the pool's stop() after a group's Ctrl-C
    # the run ends as the main process was ended; run_mission closes the log marked interrupted
    raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt


def _watch_parent(parent: int) -> None:
    """End this worker like SIGTERM would once the process that forked it is gone (killed outright:
    nobody else will stop us)."""
    while os.getppid() == parent:
        time.sleep(ORPHAN_CHECK_S)
    os.kill(os.getpid(), signal.SIGTERM)


def _worker_init(parent: int) -> None:
    for s in (signal.SIGTERM, signal.SIGINT, signal.SIGALRM):
        signal.signal(s, _worker_signal)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True, name="navcli-orphan-check").start()


def _in_worker(fn: Callable, args: tuple) -> Any:
    """Run ``fn(*args)`` in a local worker; an interrupted run ends the worker after its log is closed."""
    global _busy
    _busy = True
    try:
        return fn(*args)
    except KeyboardInterrupt:
        os._exit(128 + signal.SIGINT)
    finally:
        _busy = False


class LocalPool(ProcessPoolExecutor):
    """A process pool forked from this process, whose workers stop cleanly on SIGINT/SIGTERM
    (see the module docstring) and which :meth:`stop` ends without leaving a process behind."""

    def __init__(self, workers: int):
        import multiprocessing as mp

        from ..log import writer  # noqa: F401
        from .. import runner  # noqa: F401  (imported once here, inherited by the forked workers)

        ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else None
        super().__init__(max_workers=workers, mp_context=ctx, initializer=_worker_init, initargs=(os.getpid(),))
        self.workers = workers

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> Future:
        assert not kwargs, "LocalPool passes positional arguments only"
        return super().submit(_in_worker, fn, args)

    def stop(self, signum: int = signal.SIGTERM) -> None:
        """Cancel what has not started, send the workers ``signum`` (the one that stopped the main
        process, so a run's log says which), SIGKILL those alive after GRACE_S, reap them."""
        procs = list((self._processes or {}).values())
        manager = self._executor_manager_thread  # shutdown(wait=False) forgets it
        self.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            with contextlib.suppress(ProcessLookupError, OSError):
                if p.pid is not None:
                    os.kill(p.pid, signum)
        deadline = time.monotonic() + GRACE_S
        for p in procs:
            p.join(max(0.0, deadline - time.monotonic()))
        for p in procs:
            if p.is_alive():
                p.kill()
                p.join(1.0)
        # Python 3.11's exit hook wakes the pool's manager thread without its lock; if that thread is
        # closing its wake-up pipe at the same moment, the hook prints "OSError: Bad file descriptor".
        # With every worker gone the thread ends at once: wait for it, so the exit finds it closed.
        if manager is not None:
            manager.join(GRACE_S)  # type: ignore[attr-defined]  # typeshed types this private attribute wrongly


def workers(jobs: int | None) -> int:
    """The local workers asked for by ``jobs`` (``--jobs``, ``jobs=``): as many, or without a number
    one per core, at most :data:`~navcli.checks.arguments.MAX_JOBS` (each forks the whole of navcli).
    The one place the default is made, for every command and the API."""
    return jobs or min(os.cpu_count() or 1, MAX_JOBS)


@contextlib.contextmanager
def executor(jobs: int, scheduler: str | None = None) -> Iterator[Executor]:
    """An executor for ``jobs`` local workers, or for the Dask cluster at ``scheduler``; its
    ``workers`` attribute says how many runs it holds at once (a batch of trials).

    ``jobs <= 1`` without a scheduler runs in this process (a :class:`SerialExecutor`). While it is
    open, Ctrl-C and SIGTERM interrupt (:func:`interruptible`); on any exception the local workers
    are stopped (:meth:`LocalPool.stop`) before it is re-raised."""
    with interruptible():
        if scheduler:
            distributed = require("distributed", "--scheduler")
            try:
                client = distributed.Client(scheduler, timeout="10s", set_as_default=False)
            except OSError as e:
                raise ConnectionError(f"cannot reach the Dask scheduler at {scheduler}: {e}") from None
            try:
                ex = client.get_executor(pure=False, retries=RETRIES)
                ex.workers = sum(client.nthreads().values()) or 1  # how many runs the cluster holds at once
                yield ex
            finally:
                client.close()
            return
        if jobs <= 1:
            yield SerialExecutor()
            return
        pool = LocalPool(jobs)
        try:
            yield pool
        except BaseException as e:
            cause = _as_interruption(e)
            pool.stop(_signal_of(cause))
            if cause is not e:
                raise cause from None
            raise
        pool.shutdown(wait=True)


class SerialExecutor(Executor):
    """Runs each submission at once, in this process (one worker, no pool; easy to debug)."""

    workers = 1

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> Future:
        f: Future = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except Exception as e:
            f.set_exception(e)
        return f


_received: list[int] = []  # the signals that interrupted this process while interruptible()


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """While inside, Ctrl-C raises ``KeyboardInterrupt`` and SIGTERM :class:`Terminated` in the main
    thread, whatever the dispositions were (a shell starts a script's background job with SIGINT
    ignored, yet a ``kill -INT`` of its group must still stop it). Outside the main thread, nothing."""

    def note(exc: type[BaseException]) -> Callable[[int, Any], None]:
        handler = raising(exc)

        def noted(signum: int, frame: Any) -> None:
            if signum not in _received:
                _received.append(signum)
            handler(signum, frame)

        return noted

    try:
        old = {
            s: signal.signal(s, note(e)) for s, e in ((signal.SIGINT, KeyboardInterrupt), (signal.SIGTERM, Terminated))
        }
    except ValueError:  # not the main thread: leave signals alone
        yield
        return
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


def _as_interruption(e: BaseException) -> BaseException:
    """``e``, or the Ctrl-C or SIGTERM behind it: when a signal reached the whole process group, a
    local worker that was idle exits at once, and the pool reports itself broken; the signal that
    broke it reaches this process as well (its handler runs within the pause below)."""
    if not isinstance(e, BrokenProcessPool):
        return e
    try:
        time.sleep(0.2)
    except KeyboardInterrupt as k:
        return k
    if _received:
        return Terminated() if _received[-1] == signal.SIGTERM else KeyboardInterrupt()
    return e


def _signal_of(e: BaseException) -> int:
    """The signal to pass on to the workers: SIGINT for Ctrl-C, SIGTERM for anything else."""
    return signal.SIGINT if isinstance(e, KeyboardInterrupt) and not isinstance(e, Terminated) else signal.SIGTERM


def submit_all(
    fn: Callable[[Any], Any], items: Sequence[Any], ex: Executor, cost: Callable[[Any], float] | None = None
) -> dict[Future, int]:
    """Submit ``fn(item)`` for every item, the costliest first when ``cost`` (an item's expected
    length, in any unit) is given: longest-processing-time-first list scheduling, so that a long
    run does not start last and hold the pool's tail alone. Returns each future's item index.
    (A :class:`SerialExecutor` runs each at its submission.)

    >>> order = []
    >>> _ = submit_all(order.append, ["a", "bbb", "cc"], SerialExecutor(), cost=len)
    >>> order
    ['bbb', 'cc', 'a']

    Interrupted while submitting, it stops what it submitted (:func:`_stop`) and re-raises.
    """
    futures: dict[Future, int] = {}
    try:
        for i in _ranked(items, cost):
            futures[ex.submit(fn, items[i])] = i
    except BaseException as e:
        _stop(futures, ex, e)
    return futures


def collect(futures: dict[Future, int], ex: Executor, on_done: Callable[[int, Future], None]) -> None:
    """Call ``on_done(index, future)`` for each of ``futures`` (:func:`submit_all`'s) as it finishes.

    On Ctrl-C or SIGTERM the runs not yet finished are cancelled (local workers stopped, see
    :meth:`LocalPool.stop`) and the interruption is re-raised."""
    with interruptible():
        try:
            for f in futures if isinstance(ex, SerialExecutor) else as_completed(futures):
                on_done(futures[f], f)
        except BaseException as e:
            _stop(futures, ex, e)


def run_each(
    fn: Callable[[Any], Any], items: Sequence[Any], ex: Executor, on_done: Callable[[int, Future], None]
) -> None:
    """Submit ``fn(item)`` for every item and call ``on_done(index, future)`` as each finishes (in
    the order they finish; the future holds the result or the exception). A
    :class:`SerialExecutor` runs and reports each before the next.

    On Ctrl-C or SIGTERM the runs not yet finished are cancelled (local workers stopped, see
    :meth:`LocalPool.stop`) and the interruption is re-raised."""
    with interruptible():
        if isinstance(ex, SerialExecutor):  # one at a time, each reported before the next starts
            for i, item in enumerate(items):
                on_done(i, ex.submit(fn, item))
            return
        collect(submit_all(fn, items, ex), ex, on_done)


def _ranked(items: Sequence[Any], cost: Callable[[Any], float] | None) -> list[int]:
    """The items' indices, the costliest first (stable), or in order without ``cost``."""
    return sorted(range(len(items)), key=lambda i: -cost(items[i])) if cost else list(range(len(items)))


def _stop(futures: dict[Future, int], ex: Executor, e: BaseException) -> NoReturn:
    """Stop what runs after the exception ``e`` (the local workers, or ``futures`` on a cluster) and
    re-raise it, as the interruption it is."""
    cause = _as_interruption(e)
    if isinstance(ex, LocalPool):
        ex.stop(_signal_of(cause))
    else:
        for f in futures:
            f.cancel()
    if cause is not e:
        raise cause from None
    raise e


def map_ordered(fn: Callable[[Any], Any], items: Iterable[Any], ex: Executor) -> list[Any]:
    """``[fn(item) for item in items]`` on ``ex``, in order (DEAP's ``toolbox.map``, Optuna batches);
    stops the workers on Ctrl-C/SIGTERM like :func:`run_each`."""
    items = list(items)
    out: list[Any] = [None] * len(items)

    def keep(i: int, f: Future) -> None:
        out[i] = f.result()

    run_each(fn, items, ex, keep)
    return out
