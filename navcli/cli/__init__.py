"""The ``navcli`` command line (typer), by command group: :mod:`~navcli.cli.run` (one mission and
its files), :mod:`~navcli.cli.views` (figures, videos, layouts, tables from logs),
:mod:`~navcli.cli.experiments` (many runs: compare, sweep, tune), :mod:`~navcli.cli.learning`
(train), :mod:`~navcli.cli.rl` (train-rl, tune-softmax) and :mod:`~navcli.cli.plugins` (plugins list, check). :mod:`~navcli.cli.errors` maps whatever ends a command to its exit code and last line;
:mod:`~navcli.cli.common` holds the checks every command makes of its inputs and outputs.
"""

from __future__ import annotations

import os

# each registers its commands on the app, in the order `navcli --help` lists them
from . import run  # noqa: F401, I001
from . import views  # noqa: F401
from . import experiments  # noqa: F401
from . import learning  # noqa: F401
from . import rl  # noqa: F401
from . import plugins  # noqa: F401
from .common import app
from .errors import guard_all

guard_all(app)

__all__ = ["app", "main"]


def main() -> None:
    """The ``navcli`` executable."""
    # One BLAS thread: navcli's arrays hold a few dozen numbers, and the threads OpenBLAS
    # starts with scipy only spin (some 60 ms of a one-shot run, and more beside compare's workers)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import signal

    from ..signals import Terminated, raising

    signal.signal(signal.SIGTERM, raising(Terminated))  # a kill ends any command like Ctrl-C: cleanly
    app()
