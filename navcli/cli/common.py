"""What the commands share: the typer apps, the options that recur, and the checks every command
makes of its inputs and outputs before the work (each refusal a :class:`~navcli.NavcliError`, which
:mod:`navcli.cli.errors` turns into one line and exit 2).

Heavy modules (numpy, pymunk, foxglove, pandas, matplotlib) are imported inside the functions, so
that ``navcli --help`` answers at once.
"""

from __future__ import annotations

import contextlib
import math
import sys
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Iterator, Optional

import typer

from .. import NavcliError
from ..checks.arguments import MAX_JOBS
from ..params import PERCEPTIONS
from ..plugins.names import PLUGIN_FORMS, forms
from .errors import about

if TYPE_CHECKING:
    from ..config import RunSpec
    from ..scenario import Scenario

app = typer.Typer(
    help="Run, record and measure missions of the bidding Pilot/Vision/Navigation robot.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain help: rich's help renderer alone takes ~0.15 s to import
)


def _print_version(value: bool) -> None:
    if value:
        from .. import BUILD, __version__, builds

        typer.echo(f"navcli {__version__}, {builds.describe(BUILD)}")
        raise typer.Exit()


@app.callback()
def _options(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            callback=_print_version,
            is_eager=True,
            help="Print navcli's version and build (compiled or pure Python) and exit.",
        ),
    ] = False,
) -> None:
    pass


plot_app = typer.Typer(help="Figures of the pilot paper for a scenario, as PNG files.", no_args_is_help=True)
compare_app = typer.Typer(help="Rerun missions with many seeds and compare, from the logs.", no_args_is_help=True)

PerceptionName = Enum("PerceptionName", {n: n for n in PERCEPTIONS}, type=str)  # type: ignore[misc]

SCENARIO_HELP = "A scenario YAML file, or a bundled scenario's name (`navcli scenarios` lists them; a file wins)"
SCENARIOS_HELP = "Scenario YAML files, or bundled scenarios' names (`navcli scenarios` lists them; a file wins)"
MAX_SEED = 2**64 - 1
"""The largest seed (numpy's SeedSequence takes any; the log stores an unsigned 64-bit one)."""


def finite(value: Optional[float]) -> Optional[float]:
    """A float option's check: typer's ``min``/``max`` let ``nan`` through (every comparison with it
    is false) and ``inf`` past an open top; here either is refused."""
    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"{value} is not a finite number")
    return value


PILOT_HELP = forms("pilot")
"""The forms a pilot's name takes (:func:`navcli.plugins.names.forms`), for every option naming one."""
PilotOption = Annotated[
    Optional[str], typer.Option(metavar="NAME", help=f"Pilot: {PILOT_HELP} (default: the scenario's mission.pilot).")
]
NAVIGATION_HELP = (
    "who chooses the Navigation system's moves and looks: agents (its bidding agents), hand-coded "
    "(the learning paper's hand-coded policy), learned[:FILE] (the Learning Agent; without FILE the "
    "model bundled with navcli), a policy plugin (an installed plugin's name, entry point navcli.policies; "
    f"{PLUGIN_FORMS}), or agents+NAME: a plugin's agent bidding beside the bidding agents"
)
ParamOption = Annotated[
    Optional[list[str]],
    typer.Option(
        "--param",
        metavar="NAME=VALUE",
        help="Override any parameter by its dotted name (pilot.K, pilot.R_min, navigation.kappa1, robot.max_speed, "
        "vision.forget_above ...; `navcli params` lists them); repeatable, e.g. --param pilot.K=20.",
    ),
]


def scheduler_address(value: Optional[str]) -> Optional[str]:
    """A ``--scheduler`` checked before anything connects: ``tcp://HOST:PORT`` (the port 1-65535)."""
    import re

    if value is None:
        return None
    m = re.fullmatch(r"(?:tcp://)?([A-Za-z0-9.\-\[\]:]+):(\d{1,5})", value.strip())
    if m is None or not 0 < int(m.group(2)) < 65536:
        raise typer.BadParameter(f"{value[:80]!r} is not a scheduler address (expected tcp://HOST:PORT)")
    return value.strip()


SchedulerOption = Annotated[
    Optional[str],
    typer.Option(
        metavar="ADDRESS",
        callback=scheduler_address,
        help="Send the runs to the Dask cluster whose scheduler is at tcp://HOST:PORT instead of "
        "local worker processes (needs navcli[cluster]).",
    ),
]
JobsOption = Annotated[
    Optional[int],
    typer.Option(
        min=1, max=MAX_JOBS, help=f"Local worker processes (default: the machine's cores, at most {MAX_JOBS})."
    ),
]


def choice(value: Optional[Enum]) -> Optional[str]:
    """An enum option's value, or None when not given."""
    return value.value if value is not None else None


def load(path: Path) -> Scenario:
    """The scenario file ``path``, checked (a refusal lists every problem of the file)."""
    from ..scenario import load_scenario

    return load_scenario(path)


def build_spec(path: Path, params: list[str] | None = None, task: bool = False, **choices: Any) -> RunSpec:
    """The run configuration of a scenario file with the command line's choices (``seed``,
    ``pilot``, ``perception``, ``time_limit``, ``navigation``; None keeps the scenario's; ``also``,
    other pilots whose parameters ``--param`` may set) and ``--param`` overrides; ``task``: a run
    of the Learning Agent's task, whose conditions lie under them (``training.task.task_spec``)."""
    from ..config import RunSpec
    from ..params import ParamError, parse_override

    sc = load(path)
    with about("--param", ParamError):
        pairs = [parse_override(item) for item in params or []]
        names = [n for n, _ in pairs]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise ParamError(f"{', '.join(twice)} given twice: which value is meant?")
        overrides = dict(pairs)
        if task:
            from ..training.task import task_spec

            return task_spec(sc, overrides, **choices)
        return RunSpec.build(sc, overrides=overrides, **choices)


def check_model(navigation: str) -> None:
    """Refuse a ``learned:FILE`` that is not a usable model (the registry has refused an unknown
    name already)."""
    from ..plugins import navigation as policies

    for c in policies(navigation):
        if c.builtin and c.name.startswith("learned"):
            from ..learning.model_file import load_policy

            with about("--navigation"):
                load_policy(Path(c.argument) if c.argument else None)


ForceOption = Annotated[
    bool,
    typer.Option(
        "--force",
        help="Replace the output files if they exist (a file of navcli's only; without --force an existing one "
        "is refused, and nothing is run).",
    ),
]


def out_file(path: Path, suffixes: tuple[str, ...], what: str, option: str = "--out", *, force: bool = False) -> Path:
    """``path`` checked as an output file before any work (:func:`navcli.outputs.check_file`); an
    existing one is refused, naming ``--force``, unless ``force``."""
    from ..outputs import check_file

    with about(option):
        return check_file(path, suffixes, what, overwrite=force)


def out_folder(path: Path, files: tuple[str, ...] = (), option: str = "--out", *, force: bool = False) -> Path:
    """``path`` checked as an output folder before any work, with the ``files`` (names, glob
    patterns) the command writes there (:func:`navcli.outputs.check_folder`); one of them that
    exists is refused, naming ``--force``, unless ``force`` (a command that resumes passes True:
    it keeps what its folder holds and remakes its tables from all of it)."""
    from ..outputs import check_folder

    with about(option):
        return check_folder(path, files, overwrite=force)


def progress_bar(*columns: Any) -> Any:
    """A progress bar on stderr: the task's description, the bar, done/total, then ``columns``
    (default: the time elapsed). Hidden when stderr is not a terminal (logs of batch jobs)."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        *(columns or (TimeElapsedColumn(),)),
        transient=True,
        disable=not sys.stderr.isatty(),
    )


def require_extra(module: str, what: str) -> Any:
    """Import a library of an optional extra, or refuse saying what to install (exit 2)."""
    from ..checks.extras import require

    return require(module, what)


class SchedulerUnreachable(NavcliError):
    """The Dask scheduler of ``--scheduler`` did not answer."""


@contextlib.contextmanager
def executor_for(jobs: Optional[int], scheduler: Optional[str]) -> Iterator[Any]:
    """The execution layer's executor: ``jobs`` local workers, or the Dask cluster at ``scheduler``."""
    from ..experiments.executor import executor, workers

    try:
        with executor(workers(jobs), scheduler) as ex:
            yield ex
    except ConnectionError as e:
        raise SchedulerUnreachable(str(e)) from None


class MissionProgress:
    """A progress bar of one mission on a terminal (simulated seconds against the time limit),
    shown only once the run has lasted more than half a second; called after every tick."""

    def __init__(self, limit: float, label: str):
        import time

        self.limit, self.label = limit, label
        self.bar: Any = None  # rich's Progress, made when first shown
        self.task: Any = None
        self._now = time.perf_counter
        self.t0 = self._now()
        self.enabled = sys.stderr.isatty()

    def __call__(self, mission: Any, tick: Any) -> None:
        if not self.enabled or tick.index % 10:
            return
        if self.bar is None:
            if self._now() - self.t0 < 0.5:
                return
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                TextColumn("{task.completed:.0f}/{task.total:.0f} sim s"),
                TimeElapsedColumn(),
                transient=True,
            )
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=self.limit)
        self.bar.update(self.task, completed=mission.time)

    def close(self) -> None:
        """Remove the bar (idempotent)."""
        if self.bar is not None:
            self.bar.stop()
            self.bar = None
            self.enabled = False
