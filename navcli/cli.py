"""The ``navcli`` command line (typer).

Heavy modules (numpy, pymunk, foxglove, pandas, matplotlib) are imported inside the commands so
that ``navcli --help`` answers at once. Exit codes: 0 success (mission reached its target),
1 an internal error (the log is still closed and marked ``error``), 2 bad input (a refused
scenario, a bad option), 3 the mission ended without reaching its target (timeout, blocked),
130 interrupted by Ctrl-C, 143 stopped by SIGTERM (the log is closed and marked ``interrupted``).
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
from enum import Enum
from pathlib import Path
from typing import Annotated, Optional

import typer

from .params import PERCEPTIONS, PILOT_NAMES
from .signals import exit_code, stopped_by

app = typer.Typer(
    help="Run, record and measure missions of the bidding Pilot/Vision/Navigation robot.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain help: rich's help renderer alone takes ~0.15 s to import
)

PilotName = Enum("PilotName", {n.replace("-", "_"): n for n in PILOT_NAMES}, type=str)
PerceptionName = Enum("PerceptionName", {n: n for n in PERCEPTIONS}, type=str)
EXIT_BAD_INPUT, EXIT_FAILED_MISSION, EXIT_INTERRUPTED, EXIT_TERMINATED = 2, 3, 130, 143


def _err(msg: str) -> None:
    typer.echo(msg, err=True)


def _finite(value: Optional[float]) -> Optional[float]:
    """A float option's check: typer's ``min``/``max`` let ``nan`` through (every comparison with it
    is false) and ``inf`` past an open top; here either is refused."""
    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"{value} is not a finite number")
    return value


MAX_SEED = 2 ** 64 - 1
"""The largest seed (numpy's SeedSequence takes any; the log stores an unsigned 64-bit one)."""
MAX_JOBS = 256
"""Most local worker processes (each forks the whole of navcli: some 100 MB)."""


ParamOption = Annotated[Optional[list[str]], typer.Option(
    "--param", metavar="NAME=VALUE",
    help="Override any parameter by its dotted name (pilot.K, pilot.R_min, navigation.kappa1, robot.max_speed, "
         "vision.forget_above ...; `navcli params` lists them); repeatable, e.g. --param pilot.K=20.")]


def _load(path: Path):
    """Load a scenario or exit 2 naming what is wrong."""
    from .scenario import ScenarioError, load_scenario

    try:
        return load_scenario(path)
    except ScenarioError as e:
        _err(f"error: scenario refused\n{e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


def _spec(path: Path, params: list[str] | None = None, **choices):
    """The run configuration of a scenario file with the command line's choices (``seed``,
    ``pilot``, ``perception``, ``time_limit``; None keeps the scenario's) and ``--param``
    overrides, or exit 2 naming what is wrong."""
    from .config import ConfigError, RunSpec
    from .params import ParamError, parse_override

    sc = _load(path)
    try:
        overrides = dict(parse_override(item) for item in params or [])
        return RunSpec.build(sc, overrides=overrides, **choices)
    except (ParamError, ConfigError) as e:
        _err(f"error: --param: {e}" if isinstance(e, ParamError) else f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


def _check_model(navigation: str) -> None:
    """Exit 2 naming the file when ``learned:FILE`` is not a usable model."""
    mode, _, file = navigation.partition(":")
    if mode != "learned":
        return
    from .learning.model_file import ModelError, load_policy

    try:
        load_policy(Path(file) if file else None)
    except ModelError as e:
        _err(f"error: --navigation: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


def _out_file(path: Path, suffixes: tuple[str, ...], what: str, option: str = "--out") -> Path:
    """``path`` checked as an output file before any work (:func:`navcli.outputs.check_file`), or exit 2."""
    from .outputs import OutputError, check_file

    try:
        return check_file(path, suffixes, what)
    except OutputError as e:
        _err(f"error: {option}: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


def _out_folder(path: Path, option: str = "--out") -> Path:
    """``path`` checked as an output folder before any work (:func:`navcli.outputs.check_folder`), or exit 2."""
    from .outputs import OutputError, check_folder

    try:
        return check_folder(path)
    except OutputError as e:
        _err(f"error: {option}: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


class _Progress:
    """A progress bar on a terminal, shown only once a run has lasted more than half a second."""

    def __init__(self, limit: float, label: str):
        import time

        self.limit, self.label, self.t0, self.bar, self.task = limit, label, time.perf_counter(), None, None
        self._now = time.perf_counter
        self.enabled = sys.stderr.isatty()

    def __call__(self, mission, tick) -> None:
        if not self.enabled or tick.index % 10:
            return
        if self.bar is None:
            if self._now() - self.t0 < 0.5:
                return
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(TextColumn("{task.description}"), BarColumn(),
                                TextColumn("{task.completed:.0f}/{task.total:.0f} sim s"), TimeElapsedColumn(),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=self.limit)
        self.bar.update(self.task, completed=mission.time)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


@app.command()
def run(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file (see scenarios/).")],
    seed: Annotated[Optional[int], typer.Option(min=0, max=MAX_SEED, help="Random seed (default: the scenario's mission.seed).")] = None,
    pilot: Annotated[Optional[PilotName], typer.Option(help="Pilot (default: the scenario's mission.pilot).")] = None,
    out: Annotated[Optional[Path], typer.Option(
        help="Log file (default: logs/<scenario>/<pilot>-seed<N>-<run id>.mcap, the run id a hash of the whole "
             "configuration). Missing folders are created.")] = None,
    time_limit: Annotated[Optional[float], typer.Option(min=0.1, callback=_finite, help="Simulated seconds before the run is declared failed.")] = None,
    live: Annotated[bool, typer.Option(help="Also serve the run to Foxglove (ws://127.0.0.1:PORT), paced to real time.")] = False,
    port: Annotated[int, typer.Option(min=0, max=65535, help="WebSocket port for --live (0: any free port).")] = 8765,
    param: ParamOption = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(
        help="What the agents know: vision (camera and visual memory) or oracle (ground truth, to isolate the "
             "pilot). Default: the scenario's mission.perception, else vision.")] = None,
    navigation: Annotated[str, typer.Option(
        help="Who chooses the Navigation system's moves and looks: agents (its bidding agents), hand-coded "
             "(the learning paper's hand-coded policy) or learned[:FILE] (the Learning Agent; without FILE "
             "the model bundled with navcli).")] = "agents",
) -> None:
    """Run one mission, record it to an MCAP log and print how it ended."""
    spec = _spec(scenario, param, seed=seed, pilot=pilot.value if pilot else None, time_limit=time_limit,
                 perception=perception.value if perception else None, navigation=navigation)
    _check_model(spec.navigation)
    from .log.writer import LogPathError, check_log_path
    from .runner import run_mission
    from .signals import Terminated

    try:
        out = check_log_path(out if out is not None else spec.default_log_path(), (str(scenario),))
    except LogPathError as e:
        _err(f"error: --out: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None

    import signal

    from .signals import raising

    # a kill from a scheduler ends the run like Ctrl-C: the log closed, marked interrupted; neither is
    # raised inside a pymunk callback, where it would be lost
    signal.signal(signal.SIGTERM, raising(Terminated))
    signal.signal(signal.SIGINT, raising(KeyboardInterrupt))
    progress = _Progress(spec.time_limit, spec.scenario.name)

    def opened(recorder) -> None:  # said once the log is this run's (not before: another run may hold it)
        if recorder.kept_aside:
            _err(f"note: {recorder.partial} was the unfinished log of an earlier run; it is kept as "
                 f"{recorder.kept_aside} (`navcli recover` makes a readable log of it)")
        if recorder.port is not None:
            _err(f"serving the run live on ws://127.0.0.1:{recorder.port} (open it in Foxglove: Open connection)")

    try:
        res = run_mission(spec, out=out, live=live, port=port, on_tick=progress, on_open=opened)
    except LogPathError as e:  # another run holds the log, or the --live port is taken
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    except Terminated:
        progress.close()
        _err("terminated (SIGTERM): the log is closed and marked 'interrupted'")
        raise typer.Exit(EXIT_TERMINATED) from None
    except KeyboardInterrupt:
        progress.close()
        _err("interrupted: the log is closed and marked 'interrupted'")
        raise typer.Exit(EXIT_INTERRUPTED) from None
    except OSError as e:
        progress.close()
        _err(f"error: {e.strerror or e} ({e.filename or ''})")
        raise typer.Exit(1) from None
    progress.close()
    s = res.summary
    typer.echo(f"outcome      {s['outcome']} ({s['reason']})")
    typer.echo(f"sim time     {s['time_s']:.1f} s  ({res.realtime_factor:.0f}x real time)")
    typer.echo(f"path length  {s['path_length_m']:.2f} m")
    typer.echo(f"collisions   {s['collisions']}")
    typer.echo(f"log          {res.log}")
    if s["outcome"] != "reached":
        raise typer.Exit(EXIT_FAILED_MISSION)


@app.command()
def validate(files: Annotated[list[Path], typer.Argument(metavar="FILES", help="Scenario files to check.")]) -> None:
    """Check scenario files without running them."""
    from .scenario import ScenarioError, load_scenario

    bad = 0
    for f in files:
        try:
            sc = load_scenario(f)
        except ScenarioError as e:
            bad += 1
            _err(str(e))
            continue
        typer.echo(f"{f}: ok ({sc.name}: {sc.arena.width:g} m x {sc.arena.height:g} m, "
                   f"{len(sc.obstacles)} obstacles, {len(sc.landmarks)} landmarks)")
    if bad:
        _err(f"{bad} of {len(files)} files refused")
        raise typer.Exit(EXIT_BAD_INPUT)


@app.command()
def bench(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario to time.")] = Path("scenarios/paper-8x8.yaml"),
    repeat: Annotated[int, typer.Option(min=1, max=1000, help="Runs per configuration; the median is reported.")] = 5,
    pilot: Annotated[Optional[PilotName], typer.Option(help="Pilot (default: the scenario's).")] = None,
    seed: Annotated[Optional[int], typer.Option(min=0, max=MAX_SEED)] = None,
    occlusion: Annotated[bool, typer.Option(help="Instead: time the pilot's occlusion test, loop vs numpy.")] = False,
    param: ParamOption = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(help="vision or oracle (default: the scenario's).")] = None,
    objects: Annotated[bool, typer.Option(help="Instead: cost per tick with 12, 50 and 200 objects in the room.")] = False,
    long: Annotated[bool, typer.Option(
        "--long", help="Instead: cost per tick in the last minute of a 20-minute run against the first "
                       "(the map must not slow a long run down; try scenarios/trap-box.yaml).")] = False,
) -> None:
    """Real-time factor (simulated s per wall s) of a full mission, with logging on and off."""
    if occlusion:
        from .experiments.bench import occlusion_benchmark

        occlusion_benchmark(echo=typer.echo)
        return
    spec = _spec(scenario, param, seed=seed, pilot=pilot.value if pilot else None,
                 perception=perception.value if perception else None)
    from .experiments.bench import benchmark, long_run_benchmark, objects_benchmark

    if long:
        long_run_benchmark(spec, echo=typer.echo)
        return
    if objects:
        objects_benchmark(spec, echo=typer.echo)
        return
    benchmark(spec, repeat=repeat, echo=typer.echo)


plot_app = typer.Typer(help="Figures of the pilot paper for a scenario, as PNG files.", no_args_is_help=True)
app.add_typer(plot_app, name="plot")


WallsOption = Annotated[bool, typer.Option(
    help="Let the room's walls push too (the paper's figures show an example without walls).")]


def _plot(kind: str, scenario: Path, out: Optional[Path], step: Optional[float], param: list[str],
          walls: bool = False) -> None:
    spec = _spec(scenario, param)
    out = _out_file(out or Path("logs") / spec.scenario.name / f"{kind}.png", (".png",), "PNG image")
    from . import figures

    fn = figures.plot_field if kind == "field" else figures.plot_bids
    with _bar() as bar:
        task = bar.add_task(f"{kind}: rows of the grid", total=None)
        try:
            path = fn(spec, out, step or (0.2 if kind == "field" else 0.05), walls,
                      progress=lambda i, n: bar.update(task, completed=i, total=n))
        except figures.GridError as e:
            _err(f"error: --step: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except OSError as e:
            _err(f"error: cannot write {out}: {e.strerror or e}")
            raise typer.Exit(1) from None
    typer.echo(f"wrote {path}")


@plot_app.command("field")
def plot_field(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file.")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/field.png).")] = None,
    step: Annotated[Optional[float], typer.Option(min=0.02, callback=_finite, help="Grid spacing in metres (default 0.2).")] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
) -> None:
    """Direction of the net virtual force over the arena (pilot paper, Figure 9)."""
    _plot("field", scenario, out, step, param, walls)


@plot_app.command("bids")
def plot_bids(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file.")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/bids.png).")] = None,
    step: Annotated[Optional[float], typer.Option(min=0.02, callback=_finite, help="Grid spacing in metres (default 0.05).")] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
) -> None:
    """The pilot's bid (eq. 9) over the arena (pilot paper, Figure 10)."""
    _plot("bids", scenario, out, step, param, walls)


@plot_app.command("map")
def plot_map(
    log: Annotated[Path, typer.Argument(metavar="LOG", help="A log of a run (.mcap).")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: next to the log, <log>-map.png).")] = None,
) -> None:
    """The Map Manager's final map (mapped landmarks, regions, blocked edges) over the true arena."""
    from .analysis import LogError
    from .analysis.mapplot import plot_map as draw

    out = _out_file(out or log.with_name(log.stem + "-map.png"), (".png",), "PNG image")
    try:
        typer.echo(f"wrote {draw(log, out)}")
    except LogError as e:
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None


compare_app = typer.Typer(help="Rerun missions with many seeds and compare, from the logs.", no_args_is_help=True)
app.add_typer(compare_app, name="compare")


@compare_app.command("pilots")
def compare_pilots(
    scenarios: Annotated[list[Path], typer.Argument(metavar="SCENARIOS", help="Scenario YAML files.")],
    reruns: Annotated[int, typer.Option(min=1, max=10_000, help="Reruns per scenario and pilot (the paper: 45).")] = 45,
    pilots: Annotated[str, typer.Option(help="Comma-separated pilots; the last is the baseline.")] =
        "potential-field,geometric",
    jobs: Annotated[Optional[int], typer.Option(min=1, max=MAX_JOBS, help="Worker processes (default: the machine's cores).")] = None,
    out: Annotated[Path, typer.Option(help="Folder for the logs, the table and the plots.")] = Path("logs/compare"),
    time_limit: Annotated[Optional[float], typer.Option(min=0.1, callback=_finite, help="Override the scenarios' time limit (s).")] = None,
    param: ParamOption = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(
        help="vision or oracle for every run (default: each scenario's mission.perception).")] = None,
    scheduler: SchedulerOption = None,
) -> None:
    """The pilot paper's Table 1: every pilot on every scenario with the same seeds, in parallel;
    logs that are already complete are kept (an interrupted comparison resumes)."""
    import time

    names = [p.strip() for p in pilots.split(",") if p.strip()]
    bad = [p for p in names if p not in PILOT_NAMES]
    if bad or not names:
        _err(f"error: --pilots: unknown pilot(s) {', '.join(bad) or '(none given)'} "
             f"(expected some of: {', '.join(PILOT_NAMES)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    specs = [_spec(p, param, time_limit=time_limit, perception=perception.value if perception else None)
             for p in scenarios]
    _out_folder(out)
    from .experiments.compare import plan, run_on

    work = plan(specs, names, reruns, out)
    t0 = time.perf_counter()
    failed: list = []
    ran = 0
    with _bar() as bar, _executor(jobs, scheduler) as ex:
        workers = getattr(ex, "workers", 1)
        task = bar.add_task(f"{len(work)} runs on {workers} workers", total=len(work))

        def done(r) -> None:
            nonlocal ran
            ran += r.ran
            if r.outcome != "reached":
                failed.append(r)
            bar.advance(task)

        try:
            run_on(work, ex, done)
        except KeyboardInterrupt as e:  # Ctrl-C (130) or SIGTERM (143): every worker is stopped
            _err(f"{stopped_by(e)}: completed logs are kept; run the same command again to resume")
            raise typer.Exit(exit_code(e)) from None
    wall = time.perf_counter() - t0
    typer.echo(f"{len(work)} runs ({ran} run now, {len(work) - ran} already complete) in {wall:.1f} s "
               f"on {workers} workers")
    for r in failed:
        j = r.job.spec
        why = r.message if r.message.startswith(r.outcome) else f"{r.outcome}: {r.message}".rstrip(": ")
        typer.echo(f"  failed: {j.scenario.name} {j.pilot} seed {j.seed}: {why} ({r.job.log})")
    _report(out, names[-1], out, [j.log for j in work])  # the runs planned, not every log under --out


@app.command()
def report(
    logdir: Annotated[Path, typer.Argument(metavar="LOGDIR", help=(
        "A folder of logs (searched recursively), or a sweep's results table (results.parquet or "
        "results.csv): then every parameter point is a condition of its own, and no plots are made."))],
    out: Annotated[Optional[Path], typer.Option(help="Where to write the table and plots (default: LOGDIR, "
                                                     "or the results table's folder).")] = None,
    baseline: Annotated[str, typer.Option(help="The pilot the others are compared with.")] = "geometric",
) -> None:
    """Rebuild the comparison table and plots from existing logs, running nothing; with several
    conditions (parameter points of a sweep), a table of every pilot against the baseline per
    condition comes first."""
    table = logdir.is_file() and logdir.suffix in (".parquet", ".csv")
    if not (logdir.is_dir() or table):
        _err(f"error: {logdir}: no such file or folder" if not logdir.exists() else
             f"error: {logdir}: expected a folder of logs or a sweep's results table (.parquet or .csv)")
        raise typer.Exit(EXIT_BAD_INPUT)
    if baseline not in PILOT_NAMES:
        _err(f"error: --baseline: {baseline!r} is not a pilot (expected one of: {', '.join(PILOT_NAMES)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    _report(logdir, baseline, _out_folder(out or (logdir.parent if table else logdir)), table=table)


def _report(logdir: Path, baseline: str, out: Path, logs: list[str] | None = None, table: bool = False) -> None:
    """The table of the logs under ``logdir`` (or of ``logs``; with ``table``, of the sweep
    results table ``logdir``); an unreadable log is skipped with a line naming it; the same run
    twice, or no readable log at all, exits 2."""
    from .analysis import LogError
    from .analysis.tables import load_runs, load_sweep, write_report

    skipped: list[tuple[str, str]] = []
    try:
        runs, error = (load_sweep(logdir) if table else load_runs(logdir, paths=logs, skipped=skipped)), None
    except LogError as e:
        runs, error = None, e
    for path, why in skipped:
        _err(f"skipped {path}: {why}")
    if error is not None:
        _err(f"error: {error}")
        raise typer.Exit(EXIT_BAD_INPUT)
    files = write_report(runs, out, baseline, skipped, plots=not table)
    typer.echo("")
    typer.echo(files["markdown"].read_text())
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}")


@app.command()
def schema() -> None:
    """Print the scenario format as a JSON Schema, for editors (the YAML language server:
    `# yaml-language-server: $schema=scenario.schema.json` at the top of a scenario)."""
    import json

    from .scenario import json_schema

    typer.echo(json.dumps(json_schema(), indent=2))


@app.command()
def recover(
    partial: Annotated[Path, typer.Argument(metavar="PARTIAL", help="The .partial file a killed run left (or a .partial-<n> kept aside).")],
    out: Annotated[Optional[Path], typer.Option(help="The log to write (default: the name without .partial).")] = None,
) -> None:
    """Make a readable log of a run killed outright: its complete chunks (all but at most the last
    simulated second), marked interrupted, "recovered after an abrupt end"."""
    from .log.recover import RecoverError, recover as recover_log
    from .log.writer import LogPathError

    if not partial.is_file():
        _err(f"error: {partial}: " + ("is a folder; give the .partial file a killed run left" if partial.is_dir()
                                      else "no such file" if not partial.exists() else "not a regular file"))
        raise typer.Exit(EXIT_BAD_INPUT)
    try:
        path, s = recover_log(partial, out)
    except (RecoverError, LogPathError) as e:
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    if s["damaged_bytes"]:
        _err(f"warning: {partial} is damaged before its end (a record fails its check): the {s['damaged_bytes']} "
             f"bytes after the damage are not recovered; the log ends at the last good record")
    typer.echo(f"recovered {s['ticks']} ticks, {s['time_s']:.1f} simulated s, into {path} (outcome interrupted); "
               f"{partial} is left as it was")


@app.command()
def params(
    scenario: Annotated[Optional[Path], typer.Argument(metavar="SCENARIO", help="Show the values this scenario resolves to.")] = None,
    param: ParamOption = None,
) -> None:
    """List every parameter by its --param name, with its value.

    Without a scenario, the defaults; with one, its values after its blocks and any --param."""
    from .params import Params, ParamError, parse_override

    if scenario is not None:
        values = _spec(scenario, param).params
    else:
        try:
            values = Params().override(dict(parse_override(i) for i in param or []))
        except ParamError as e:
            _err(f"error: --param: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
    for name, value in values.flat().items():
        typer.echo(f"{name:34s} {value}")


LayoutFormat = Enum("LayoutFormat", {"app": "app", "sdk": "sdk"}, type=str)


@app.command()
def layout(
    out: Annotated[Optional[Path], typer.Option(help="Write the layout here (default: print it).")] = None,
    format: Annotated[LayoutFormat, typer.Option(
        "--format", help="app: the file Foxglove's Layouts > Import from file reads (also Lichtblick, Foxglove "
                         "Studio 1.x); sdk: foxglove-sdk's layout JSON (foxglove.layouts, notebooks).")] = LayoutFormat.app,
) -> None:
    """Write a Foxglove layout for navcli logs and --live runs: the arena in 2D top-down (frame
    world), bids per resource, the pilot's forces, the events and the summary."""
    import json

    from .log.layout import app_json, sdk_json

    text = json.dumps(app_json() if format is LayoutFormat.app else sdk_json(), indent=1)
    if out is None:
        typer.echo(text)
        return
    from .outputs import write_text

    write_text(_out_file(out, (".json",), "layout file"), text + "\n")
    typer.echo(f"wrote {out}")


@app.command()
def render(
    log: Annotated[Path, typer.Argument(metavar="LOG", help="A navcli log (.mcap).")],
    out: Annotated[Optional[Path], typer.Option(help="run.gif or run.mp4 (MP4 needs ffmpeg); default: the log's name with .gif.")] = None,
    speed: Annotated[float, typer.Option(min=0.01, max=10_000.0, callback=_finite, help="Simulated seconds per second of video.")] = 10.0,
    start: Annotated[Optional[float], typer.Option("--from", min=0.0, callback=_finite, help="First simulated second shown.")] = None,
    end: Annotated[Optional[float], typer.Option("--to", min=0.0, callback=_finite, help="Last simulated second shown.")] = None,
    fps: Annotated[float, typer.Option(min=1.0, max=60.0, callback=_finite, help="Frames per second of video.")] = 10.0,
    dpi: Annotated[int, typer.Option(min=20, max=300, help="Pixels per inch of the 5 x 6.4 inch frame.")] = 80,
) -> None:
    """A video of a run from its log alone: the true arena and path, the robot's beliefs (the
    visual memory), the pilot's force arrows, and the bids per resource under it."""
    from .analysis import LogError
    from .analysis.render import RenderError, render as render_video

    target = _out_file(out or log.with_suffix(".gif"), (".gif", ".mp4"), "video")
    bar = _bar() if sys.stderr.isatty() else None
    task = None

    def progress(i: int, n: int) -> None:
        nonlocal task
        if bar is not None:
            if task is None:
                bar.start()
                task = bar.add_task("frames", total=n)
            bar.update(task, completed=i)

    try:
        res = render_video(log, target, speed=speed, start=start, end=end, fps=fps, dpi=dpi, progress=progress)
    except (LogError, RenderError) as e:
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    finally:
        if bar is not None:
            bar.stop()
    typer.echo(f"wrote {res.path} ({res.frames} frames, {res.size[0]}x{res.size[1]} px)")


# --- sweep and tune: many runs on the local pool or a Dask cluster (navcli/experiments/) -----------
SchedulerOption = Annotated[Optional[str], typer.Option(
    metavar="ADDRESS", help="Send the runs to the Dask cluster whose scheduler is at tcp://HOST:PORT instead of "
                            "local worker processes (needs navcli[cluster]).")]
JobsOption = Annotated[Optional[int], typer.Option(min=1, max=MAX_JOBS, help="Local worker processes (default: the machine's cores).")]


def _bar(*columns):
    """A progress bar on stderr: the task's description, the bar, done/total, then ``columns``
    (default: the time elapsed). Hidden when stderr is not a terminal (logs of batch jobs)."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                    *(columns or (TimeElapsedColumn(),)), transient=True, disable=not sys.stderr.isatty())


def _extra(module: str, what: str):
    """Import a library of the cluster extra or exit saying what to install."""
    from .experiments.executor import MissingExtra, require

    try:
        return require(module, what)
    except MissingExtra as e:
        _err(f"error: {e}")
        raise typer.Exit(1) from None


@contextlib.contextmanager
def _executor(jobs: Optional[int], scheduler: Optional[str]):
    """The execution layer's executor, or exit 2 when the scheduler cannot be reached."""
    from .experiments.executor import MissingExtra, executor

    try:
        with executor(jobs or os.cpu_count() or 1, scheduler) as ex:
            yield ex
    except (ConnectionError, MissingExtra) as e:
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT if isinstance(e, ConnectionError) else 1) from None


@app.command()
def sweep(
    plan: Annotated[Path, typer.Argument(metavar="PLAN", help="Plan file (YAML): scenarios, seeds, a grid or a random sample of "
                                              "--param values; see the README.")],
    out: Annotated[Optional[Path], typer.Option(
        help="Folder for the results table (results.parquet) and the logs (default: logs/sweep/<plan name>); "
             "on a cluster, a path every worker can write.")] = None,
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    no_logs: Annotated[bool, typer.Option("--no-logs", help="Run without logs; keep only the results table.")] = False,
    csv: Annotated[bool, typer.Option("--csv", help="Also write the table as results.csv.")] = False,
) -> None:
    """Run every scenario x parameter point x seed of a plan; one row per run in a Parquet table.
    Runs already in the table are not run again (an interrupted sweep resumes)."""
    import time

    _extra("pyarrow", "navcli sweep (Parquet tables)")

    from .experiments.sweep import PlanError, load_plan, plan_runs, run_sweep

    try:
        p = load_plan(plan)
    except PlanError as e:
        _err(f"error: plan refused\n{e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    out = _out_folder(out or Path("logs") / "sweep" / plan.stem)
    runs = plan_runs(p, None if no_logs else out)
    table = out / "results.parquet"
    from rich.progress import TextColumn, TimeRemainingColumn

    t0 = time.perf_counter()
    with _bar(TextColumn("{task.fields[failed]} failed"), TextColumn("ETA"), TimeRemainingColumn()) as bar:
        task = bar.add_task(f"{len(runs)} runs", total=len(runs), failed=0)

        def row(r: dict, stats) -> None:
            bar.update(task, completed=stats.skipped + stats.done, failed=stats.failed)

        with _executor(jobs, scheduler) as ex:
            try:
                stats = run_sweep(runs, table, ex, csv=csv, on_row=row)
            except KeyboardInterrupt as e:
                _err(f"{stopped_by(e)}: the finished runs are in {table}; run the same command again to resume")
                raise typer.Exit(exit_code(e)) from None
    wall = time.perf_counter() - t0
    typer.echo(f"{stats.total} runs: {stats.done} run now in {wall:.1f} s, {stats.skipped} already in the table; "
               f"{stats.failed} did not reach the target, {stats.errors} raised an error")
    typer.echo(f"wrote {table}" + (f" and {table.with_suffix('.csv')}" if csv else ""))
    if stats.errors:
        raise typer.Exit(1)


@app.command()
def tune(
    scenarios: Annotated[list[Path], typer.Argument(metavar="SCENARIOS", help="Scenario YAML files; every trial runs each of them.")],
    param: Annotated[list[str], typer.Option(
        "--param", metavar="NAME=LOW:HIGH",
        help="A parameter to tune in [LOW, HIGH] (NAME alone: [0, 5]); NAME=VALUE fixes it for every trial. "
             "Repeatable; names as `navcli params` lists them.")],
    algorithm: Annotated[str, typer.Option(help="tpe (Optuna), cmaes (Optuna) or ga (DEAP's eaSimple, the "
                                                "thesis' generational GA).")] = "tpe",
    trials: Annotated[int, typer.Option(min=1, max=100_000, help="Finished trials the study should hold (tpe, cmaes).")] = 100,
    seeds: Annotated[int, typer.Option(min=1, max=10_000, help="Runs per scenario per trial (the same seeds for every trial).")] = 3,
    objective: Annotated[str, typer.Option(
        help="fitness (success rate, mean steps and their spread; see navcli/experiments/tune.py), success "
             "(rate) or time (minus the mean time, failures at the limit). Maximised.")] = "fitness",
    storage: Annotated[Optional[Path], typer.Option(
        help="The study's journal file (tpe, cmaes) or the GA's checkpoint; an existing one of the same problem "
             "is resumed. Default: OUT/study.journal or OUT/ga.json.")] = None,
    out: Annotated[Path, typer.Option(help="Folder for history.csv, best.json, best.yaml, objective.png.")] =
        Path("logs/tune"),
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    time_limit: Annotated[Optional[float], typer.Option(min=0.1, callback=_finite, help="Override the scenarios' time limit (s).")] = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(help="vision or oracle for every run.")] = None,
    seed: Annotated[int, typer.Option(min=0, max=MAX_SEED, help="Seed of the optimiser (not of the runs).")] = 1,
    population: Annotated[int, typer.Option(min=2, max=10_000, help="GA: individuals per generation.")] = 20,
    generations: Annotated[int, typer.Option(min=1, max=100_000, help="GA: generations.")] = 100,
    crossover: Annotated[float, typer.Option(min=0.0, max=1.0, callback=_finite, help="GA: crossover probability.")] = 0.8,
    mutation: Annotated[float, typer.Option(min=0.0, max=1.0, callback=_finite, help="GA: mutation probability.")] = 0.1,
) -> None:
    """Find parameter values that maximise an objective over scenarios and seeds; prints and writes the
    best values, the history, a plot of the objective against trials and a scenario pilot: block."""

    from .experiments.tune import ALGORITHMS, OBJECTIVES, GASettings, TuneProblem, parse_range
    from .params import ParamError

    for name, value, allowed in (("--algorithm", algorithm, ALGORITHMS), ("--objective", objective, OBJECTIVES)):
        if value not in allowed:
            _err(f"error: {name}: {value!r} is not one of {', '.join(allowed)}")
            raise typer.Exit(EXIT_BAD_INPUT)
    try:
        parsed = [parse_range(p) for p in param]
    except ParamError as e:
        _err(f"error: --param: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    tuned = [p for p in parsed if len(p) == 3]
    if not tuned:
        _err("error: --param: name at least one parameter to tune, as NAME=LOW:HIGH or NAME")
        raise typer.Exit(EXIT_BAD_INPUT)
    fixed = [f"{p[0]}={p[1]}" for p in parsed if len(p) == 2]
    bases = tuple(_spec(s, fixed, time_limit=time_limit, perception=perception.value if perception else None)
                  for s in scenarios)
    problem = TuneProblem(bases, tuple(p[0] for p in tuned), tuple(p[1] for p in tuned),
                          tuple(p[2] for p in tuned), seeds, objective)
    _extra("deap" if algorithm == "ga" else "optuna", "navcli tune")
    _out_folder(out)
    storage = _out_file(storage or out / ("ga.json" if algorithm == "ga" else "study.journal"),
                        (".json",) if algorithm == "ga" else (".journal", ".log"), "study file", "--storage")
    count = 0

    def trial(r: dict) -> None:
        nonlocal count
        count += 1
        if count % 10 == 0:
            _err(f"  {count} trials evaluated; last {objective} {r['objective']:.4g}")

    from .experiments import tune as t

    with _executor(jobs, scheduler) as ex:
        try:
            if algorithm == "ga":
                history = t.tune_ga(problem, ex, storage=storage, seed=seed,
                                    settings=GASettings(population, generations, crossover, mutation), on_trial=trial)
            else:
                batch = getattr(ex, "workers", None) or jobs or os.cpu_count() or 1
                history = t.tune_optuna(problem, ex, algorithm=algorithm, trials=trials, storage=storage,
                                        batch=batch, seed=seed, on_trial=trial)
        except t.CheckpointError as e:
            _err(f"error: --storage: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except KeyboardInterrupt as e:
            _err(f"{stopped_by(e)}: the finished trials are in {storage}; run the same command again to resume")
            raise typer.Exit(exit_code(e)) from None
    files = t.write_results(history, problem, out)
    import json

    best = json.loads(files["best"].read_text())
    typer.echo(f"{len(history)} trials; best {objective} {best['value']:.4g} (trial {best['trial']}):")
    for k, v in best["params"].items():
        typer.echo(f"  {k} = {v:.6g}")
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}; study in {storage}")


@app.command()
def train(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file (the paper's setting: scenarios/landmarks-12.yaml).")],
    trials: Annotated[int, typer.Option(min=1, max=1_000_000, help="Training trials (the paper: 2000).")] = 2000,
    eval_every: Annotated[int, typer.Option(min=1, max=1_000_000, help="Evaluate the greedy policy every this many trials.")] = 100,
    eval_starts: Annotated[int, typer.Option(min=1, max=10_000, help="Fixed test starts of each evaluation (the paper: 99).")] = 99,
    seed: Annotated[int, typer.Option(min=0, max=MAX_SEED, help="Seed of the training starts and of the learner.")] = 1,
    out: Annotated[Optional[Path], typer.Option(
        help="Model file (.npz, with FILE.json, FILE-curve.csv and FILE-curve.png beside it; default: "
             "logs/<scenario>/<algorithm>-seed<N>.npz).")] = None,
    resume: Annotated[Optional[Path], typer.Option(help="Continue the training saved in this model file.")] = None,
    algorithm: Annotated[str, typer.Option(help="prioritized-sweeping (the paper's) or q-learning (model-free baseline).")]
        = "prioritized-sweeping",
    jobs: Annotated[int, typer.Option(min=1, max=MAX_JOBS, help="Worker processes for the evaluations.")] = 2,
    log: Annotated[str, typer.Option(help="What is recorded of each training trial: summary (a row of "
                                          "FILE-trials.csv) or full (also every tick, one MCAP log per trial "
                                          "in FILE-trials/, 10-25 kB a simulated second).")] = "summary",
    param: ParamOption = None,
) -> None:
    """Train the Learning Agent (learning-agent paper, section 6): trials from seeded random starts,
    the greedy policy evaluated on fixed starts, the model saved (resumable) with its learning curve.

    Trials run the paper's task: the robot is not told where the target is, the camera is the
    Learning Agent's alone, a trial succeeds only when the robot is also confident it is at the
    target, and ends when it is blocked (--param learning.paper_task=0: navcli's first task)."""
    import time

    from .learning.training import ALGORITHMS, LOGS

    if algorithm not in ALGORITHMS:
        _err(f"error: --algorithm: unknown {algorithm!r} (expected one of: {', '.join(ALGORITHMS)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    if log not in LOGS:
        _err(f"error: --log: unknown {log!r} (expected one of: {', '.join(LOGS)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    spec = _spec(scenario, param)
    from .learning.features import check_bounds
    from .learning.model_file import ModelError
    from .learning.training import curve_paths, train as run_training, trials_paths

    try:
        check_bounds(spec.params.learning)
    except ValueError as e:
        _err(f"error: --param: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    out = out or resume or Path("logs") / spec.scenario.name / f"{algorithm}-seed{seed}.npz"
    from .learning.model_file import check_out, load
    from .outputs import OutputError, check_folder

    if resume is not None:
        try:
            load(resume)  # the input refused before the output is looked at
        except ModelError as e:
            _err(f"error: --resume: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
    try:
        check_out(out)
        if log == "full":
            check_folder(trials_paths(out)[1])
    except OutputError as e:
        _err(f"error: --out: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    t0 = time.perf_counter()
    with _bar() as bar:
        task = bar.add_task("training", total=trials)

        def on_trial(i, r, result) -> None:
            last = f"{result.curve[-1].successes}/{eval_starts} at {result.curve[-1].trials}" if result.curve else "-"
            bar.update(task, advance=1, description=f"training (test successes {last})")

        try:
            res = run_training(spec, trials=trials, eval_every=eval_every, eval_starts=eval_starts, seed=seed,
                               algorithm=algorithm, out=out, resume=resume, workers=jobs, log=log,
                               on_trial=on_trial)
        except ModelError as e:
            _err(f"error: --resume: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except KeyboardInterrupt as e:
            _err(f"{stopped_by(e)}: " + (f"the model saved at {e.training.saved} trials is in {e.training.saved_in}; "
                                          f"--resume {e.training.saved_in} --trials {e.training.end - e.training.saved} "
                                          f"completes the {e.training.end}" if getattr(e, "training", None) and
                                          e.training.saved is not None else "no model was saved yet"))
            raise typer.Exit(exit_code(e)) from None
    typer.echo(f"{res.trials} trials ({trials} now) in {time.perf_counter() - t0:.0f} s: training {res.train_s:.0f} s, "
               f"evaluations {res.eval_s:.0f} s " + ("in this process" if jobs == 1 else f"of worker time on {jobs} workers"))
    typer.echo(f"training outcomes: {res.outcomes}")
    typer.echo("trials  successes/{}  reward/trial  actions/trial".format(eval_starts))
    for p in res.curve:
        typer.echo(f"{p.trials:6d}  {p.successes:12d}  {p.reward:12.1f}  {p.actions:13.1f}")
    typer.echo(f"hand-coded policy: {res.hand_coded}/{eval_starts}")
    trials_csv, trial_logs = trials_paths(out)
    curve_csv, curve_png = curve_paths(out)
    typer.echo(f"wrote {out}, {out.with_suffix('.json')}, {curve_csv}, {curve_png}, {trials_csv}"
               + (f" and the trial logs in {trial_logs}/" if log == "full" else ""))


@compare_app.command("policies")
def compare_policies(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file (the paper's setting: scenarios/landmarks-12.yaml).")],
    policy: Annotated[Optional[list[str]], typer.Option(
        "--policy", metavar="POLICY", help="learned (the bundled model), learned:FILE (a model of `navcli train`, Prioritized Sweeping "
                         "or Q-learning), hand-coded, agents, or a baseline of one action in every state (all-MB, all-MLL, all-MOT, "
                         "all-MVL, all-MVT); repeatable (default: learned, hand-coded, agents). Every policy runs the "
                         "learning paper's task (learning.paper_task=0: navcli's first one).")] = None,
    runs: Annotated[int, typer.Option(min=1, max=1000, help="Runs (seeds of the missions' noise) per policy.")] = 5,
    starts: Annotated[int, typer.Option(min=1, max=10_000, help="Fixed random starts per run, those `navcli train` evaluates on "
                                                    "(the paper: 99).")] = 99,
    out: Annotated[Path, typer.Option(help="Folder for the per-run trials (runs/*.json), policies.csv, policies.md "
                                           "and trials.csv.")] = Path("logs/compare-policies"),
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    param: ParamOption = None,
) -> None:
    """The learning paper's Table 1: every policy from the same starts, per run; successes, reward,
    actions and the count of each action per trial, averaged over the runs with 95 % t-intervals.
    Runs already done are kept (an interrupted comparison resumes)."""
    import time

    spec = _spec(scenario, param)
    from .learning.comparison import DEFAULT_POLICIES, PolicyError, parse_policy, plan, run_all, write_table
    from .learning.features import check_bounds
    from .learning.model_file import ModelError

    names = list(policy or DEFAULT_POLICIES)
    try:
        check_bounds(spec.params.learning)
        if len(set(names)) < len(names):
            raise PolicyError(f"a policy is named twice: {', '.join(names)}")
        chosen = [parse_policy(n) for n in names]
    except ValueError as e:  # PolicyError, ModelError, bad bounds
        _err(f"error: {'--param' if not isinstance(e, (PolicyError, ModelError)) else '--policy'}: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    _out_folder(out / "runs")
    (out / "runs").mkdir(parents=True, exist_ok=True)
    work = plan(spec, chosen, runs, starts, out)
    t0 = time.perf_counter()
    with _bar() as bar:
        task = bar.add_task(f"{len(work)} runs of {starts} trials", total=len(work))
        with _executor(jobs, scheduler) as ex:
            try:
                results = run_all(work, ex, lambda r: bar.advance(task))
            except KeyboardInterrupt as e:
                _err(f"{stopped_by(e)}: the finished runs are kept in {out / 'runs'}; run the same command again to resume")
                raise typer.Exit(exit_code(e)) from None
            workers = getattr(ex, "workers", 1)
    ran = sum(r.ran for r in results)
    typer.echo(f"{len(work)} (policy, run) pairs of {starts} trials ({ran} run now, {len(work) - ran} kept) in "
               f"{time.perf_counter() - t0:.1f} s on {workers} workers")
    errors = [r for r in results if r.trials is None]
    for r in errors:
        _err(f"  failed: {r.job.policy.label} run {r.job.run}: {r.error}")
    files = write_table([r for r in results if r.trials is not None], out, spec.scenario.name)
    typer.echo("")
    typer.echo(files["markdown"].read_text())
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}")
    if errors:
        raise typer.Exit(1)


def _guarded(fn):
    """``fn`` (a command) ending in an exit code and one line, never a traceback: Ctrl-C exits 130
    and SIGTERM 143 wherever they land (a command's own handling says more, where it has any);
    an exception no command expected is a bug in navcli, said so in one line (``NAVCLI_DEBUG=1``
    shows its traceback), exit 1. typer's and click's own exits pass through."""
    import functools

    @functools.wraps(fn)
    def guarded(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except KeyboardInterrupt as e:
            _err(stopped_by(e))
            raise typer.Exit(exit_code(e)) from None
        except BrokenPipeError:  # `navcli params | head`: the reader has what it wanted
            with contextlib.suppress(OSError):
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # nothing more to flush at exit
            raise typer.Exit(128 + 13) from None  # as if killed by SIGPIPE, the shell's convention
        except Exception as e:
            if hasattr(e, "exit_code") or os.environ.get("NAVCLI_DEBUG"):  # typer.Exit, click's usage errors
                raise
            if isinstance(e, OSError):
                _err(f"error: {e.strerror or e}" + (f": {e.filename}" if e.filename else ""))
            else:
                _err(f"navcli: internal error: {type(e).__name__}: {e}\n(a bug in navcli: please report it with "
                     f"the command that raised it; NAVCLI_DEBUG=1 shows the traceback)")
            raise typer.Exit(1) from None

    return guarded


def _guard_all(t: typer.Typer) -> None:
    for c in t.registered_commands:
        c.callback = _guarded(c.callback)
    for g in t.registered_groups:
        _guard_all(g.typer_instance)


_guard_all(app)


def main() -> None:
    # One BLAS thread (our design): navcli's arrays hold a few dozen numbers, and the threads OpenBLAS
    # starts with scipy only spin (some 60 ms of a one-shot run, and more beside compare's workers)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import signal

    from .signals import Terminated, raising

    signal.signal(signal.SIGTERM, raising(Terminated))  # a kill ends any command like Ctrl-C: cleanly
    app()
