"""The ``navcli`` command line (typer).

Heavy modules (numpy, pymunk, foxglove, pandas, matplotlib) are imported inside the commands so
that ``navcli --help`` answers at once. Exit codes: 0 success (mission reached its target),
1 an internal error (the log is still closed and marked ``error``), 2 bad input (a refused
scenario, a bad option), 3 the mission ended without reaching its target (timeout, blocked),
130 interrupted by Ctrl-C (the log is closed and marked ``interrupted``).
"""

from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import Annotated, Optional

import typer

from .params import PERCEPTIONS, PILOT_NAMES

app = typer.Typer(
    help="Run, record and measure missions of the bidding Pilot/Vision/Navigation robot.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

PilotName = Enum("PilotName", {n.replace("-", "_"): n for n in PILOT_NAMES}, type=str)
PerceptionName = Enum("PerceptionName", {n: n for n in PERCEPTIONS}, type=str)
EXIT_BAD_INPUT, EXIT_FAILED_MISSION, EXIT_INTERRUPTED = 2, 3, 130


def _err(msg: str) -> None:
    typer.echo(msg, err=True)


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
    scenario: Annotated[Path, typer.Argument(help="Scenario YAML file (see scenarios/).")],
    seed: Annotated[Optional[int], typer.Option(min=0, help="Random seed (default: the scenario's mission.seed).")] = None,
    pilot: Annotated[Optional[PilotName], typer.Option(help="Pilot (default: the scenario's mission.pilot).")] = None,
    out: Annotated[Optional[Path], typer.Option(
        help="Log file (default: logs/<scenario>/<pilot>-seed<N>-<run id>.mcap, the run id a hash of the whole "
             "configuration).")] = None,
    time_limit: Annotated[Optional[float], typer.Option(min=0.1, help="Simulated seconds before the run is declared failed.")] = None,
    live: Annotated[bool, typer.Option(help="Also serve the run to Foxglove (ws://localhost:PORT), paced to real time.")] = False,
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
    from .runner import run_mission

    import signal

    def _terminate(signum, frame):  # a kill from a scheduler ends the run like Ctrl-C: log closed, marked
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _terminate)
    progress = _Progress(spec.time_limit, spec.scenario.name)
    if live:
        _err(f"serving the run live on ws://127.0.0.1:{port} (open it in Foxglove: Open connection)")
    try:
        res = run_mission(spec, out=out, live=live, port=port, on_tick=progress)
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
def validate(files: Annotated[list[Path], typer.Argument(help="Scenario files to check.")]) -> None:
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
    scenario: Annotated[Path, typer.Argument(help="Scenario to time.")] = Path("scenarios/paper-8x8.yaml"),
    repeat: Annotated[int, typer.Option(min=1, help="Runs per configuration; the median is reported.")] = 5,
    pilot: Annotated[Optional[PilotName], typer.Option(help="Pilot (default: the scenario's).")] = None,
    seed: Annotated[Optional[int], typer.Option(min=0)] = None,
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
    from . import figures

    out = out or Path("logs") / spec.scenario.name / f"{kind}.png"
    fn = figures.plot_field if kind == "field" else figures.plot_bids
    try:
        path = fn(spec, out, step, walls) if step else fn(spec, out, walls=walls)
    except OSError as e:
        _err(f"error: cannot write {out}: {e.strerror or e}")
        raise typer.Exit(1) from None
    typer.echo(f"wrote {path}")


@plot_app.command("field")
def plot_field(
    scenario: Annotated[Path, typer.Argument(help="Scenario YAML file.")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/field.png).")] = None,
    step: Annotated[Optional[float], typer.Option(min=0.02, help="Grid spacing in metres (default 0.2).")] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
) -> None:
    """Direction of the net virtual force over the arena (pilot paper, Figure 9)."""
    _plot("field", scenario, out, step, param, walls)


@plot_app.command("bids")
def plot_bids(
    scenario: Annotated[Path, typer.Argument(help="Scenario YAML file.")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/bids.png).")] = None,
    step: Annotated[Optional[float], typer.Option(min=0.02, help="Grid spacing in metres (default 0.05).")] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
) -> None:
    """The pilot's bid (eq. 9) over the arena (pilot paper, Figure 10)."""
    _plot("bids", scenario, out, step, param, walls)


compare_app = typer.Typer(help="Rerun missions with many seeds and compare, from the logs.", no_args_is_help=True)
app.add_typer(compare_app, name="compare")


@compare_app.command("pilots")
def compare_pilots(
    scenarios: Annotated[list[Path], typer.Argument(help="Scenario YAML files.")],
    reruns: Annotated[int, typer.Option(min=1, help="Reruns per scenario and pilot (the paper: 45).")] = 45,
    pilots: Annotated[str, typer.Option(help="Comma-separated pilots; the last is the baseline.")] =
        "potential-field,geometric",
    jobs: Annotated[Optional[int], typer.Option(min=1, help="Worker processes (default: the machine's cores).")] = None,
    out: Annotated[Path, typer.Option(help="Folder for the logs, the table and the plots.")] = Path("logs/compare"),
    time_limit: Annotated[Optional[float], typer.Option(min=0.1, help="Override the scenarios' time limit (s).")] = None,
    param: ParamOption = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(
        help="vision or oracle for every run (default: each scenario's mission.perception).")] = None,
) -> None:
    """The pilot paper's Table 1: every pilot on every scenario with the same seeds, in parallel;
    logs that are already complete are kept (an interrupted comparison resumes)."""
    import os
    import time

    names = [p.strip() for p in pilots.split(",") if p.strip()]
    bad = [p for p in names if p not in PILOT_NAMES]
    if bad or not names:
        _err(f"error: --pilots: unknown pilot(s) {', '.join(bad) or '(none given)'} "
             f"(expected some of: {', '.join(PILOT_NAMES)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    specs = [_spec(p, param, time_limit=time_limit, perception=perception.value if perception else None)
             for p in scenarios]
    from .experiments.compare import plan, run_all

    work = plan(specs, names, reruns, out)
    workers = jobs or os.cpu_count() or 1
    t0 = time.perf_counter()
    failed: list = []
    ran = 0
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  transient=True, disable=not sys.stderr.isatty()) as bar:
        task = bar.add_task(f"{len(work)} runs on {workers} workers", total=len(work))

        def done(r) -> None:
            nonlocal ran
            ran += r.ran
            if r.outcome != "reached":
                failed.append(r)
            bar.advance(task)

        try:
            run_all(work, workers, done)
        except KeyboardInterrupt:
            _err("interrupted: completed logs are kept; run the same command again to resume")
            raise typer.Exit(EXIT_INTERRUPTED) from None
    wall = time.perf_counter() - t0
    typer.echo(f"{len(work)} runs ({ran} run now, {len(work) - ran} already complete) in {wall:.1f} s "
               f"on {workers} workers")
    for r in failed:
        j = r.job.spec
        typer.echo(f"  failed: {j.scenario.name} {j.pilot} seed {j.seed}: {r.outcome} {r.message} ({r.job.log})")
    _report(out, names[-1], out)


@app.command()
def report(
    logdir: Annotated[Path, typer.Argument(help="A folder of logs (searched recursively).")],
    out: Annotated[Optional[Path], typer.Option(help="Where to write the table and plots (default: LOGDIR).")] = None,
    baseline: Annotated[str, typer.Option(help="The pilot the others are compared with.")] = "geometric",
) -> None:
    """Rebuild the comparison table and plots from existing logs, running nothing."""
    if not logdir.is_dir():
        _err(f"error: {logdir}: no such folder")
        raise typer.Exit(EXIT_BAD_INPUT)
    _report(logdir, baseline, out or logdir)


def _report(logdir: Path, baseline: str, out: Path) -> None:
    from analysis import LogError
    from analysis.tables import load_runs, write_report

    try:
        runs = load_runs(logdir)
    except LogError as e:
        _err(f"error: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    files = write_report(runs, out, baseline)
    typer.echo("")
    typer.echo(files["markdown"].read_text())
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}")


@app.command()
def params(
    scenario: Annotated[Optional[Path], typer.Argument(help="Show the values this scenario resolves to.")] = None,
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


@app.command()
def train(
    scenario: Annotated[Path, typer.Argument(help="Scenario YAML file (the paper's setting: scenarios/landmarks-12.yaml).")],
    trials: Annotated[int, typer.Option(min=1, help="Training trials (the paper: 2000).")] = 2000,
    eval_every: Annotated[int, typer.Option(min=1, help="Evaluate the greedy policy every this many trials.")] = 100,
    eval_starts: Annotated[int, typer.Option(min=1, help="Fixed test starts of each evaluation (the paper: 99).")] = 99,
    seed: Annotated[int, typer.Option(min=0, help="Seed of the training starts and of the learner.")] = 1,
    out: Annotated[Optional[Path], typer.Option(
        help="Model file (.npz, with FILE.json, FILE-curve.csv and FILE-curve.png beside it; default: "
             "logs/<scenario>/<algorithm>-seed<N>.npz).")] = None,
    resume: Annotated[Optional[Path], typer.Option(help="Continue the training saved in this model file.")] = None,
    algorithm: Annotated[str, typer.Option(help="prioritized-sweeping (the paper's) or q-learning (model-free baseline).")]
        = "prioritized-sweeping",
    jobs: Annotated[int, typer.Option(min=1, help="Worker processes for the evaluations.")] = 2,
    param: ParamOption = None,
) -> None:
    """Train the Learning Agent (learning-agent paper, section 6): trials from seeded random starts,
    the greedy policy evaluated on fixed starts, the model saved (resumable) with its learning curve."""
    import time

    from .learning.training import ALGORITHMS

    if algorithm not in ALGORITHMS:
        _err(f"error: --algorithm: unknown {algorithm!r} (expected one of: {', '.join(ALGORITHMS)})")
        raise typer.Exit(EXIT_BAD_INPUT)
    spec = _spec(scenario, param)
    from .learning.features import check_bounds
    from .learning.model_file import ModelError
    from .learning.training import train as run_training

    try:
        check_bounds(spec.params.learning)
    except ValueError as e:
        _err(f"error: --param: {e}")
        raise typer.Exit(EXIT_BAD_INPUT) from None
    out = out or resume or Path("logs") / spec.scenario.name / f"{algorithm}-seed{seed}.npz"
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    t0 = time.perf_counter()
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  transient=True, disable=not sys.stderr.isatty()) as bar:
        task = bar.add_task("training", total=trials)

        def on_trial(i, r, result) -> None:
            last = f"{result.curve[-1].successes}/{eval_starts} at {result.curve[-1].trials}" if result.curve else "-"
            bar.update(task, advance=1, description=f"training (test successes {last})")

        try:
            res = run_training(spec, trials=trials, eval_every=eval_every, eval_starts=eval_starts, seed=seed,
                               algorithm=algorithm, out=out, resume=resume, workers=jobs, on_trial=on_trial)
        except ModelError as e:
            _err(f"error: --resume: {e}")
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except KeyboardInterrupt:
            _err(f"interrupted: the model saved at the last evaluation is in {out}; --resume {out} continues")
            raise typer.Exit(EXIT_INTERRUPTED) from None
    typer.echo(f"{res.trials} trials ({trials} now) in {time.perf_counter() - t0:.0f} s: training {res.train_s:.0f} s, "
               f"evaluations {res.eval_s:.0f} s of worker time on {jobs} workers")
    typer.echo(f"training outcomes: {res.outcomes}")
    typer.echo("trials  successes/{}  reward/trial  actions/trial".format(eval_starts))
    for p in res.curve:
        typer.echo(f"{p.trials:6d}  {p.successes:12d}  {p.reward:12.1f}  {p.actions:13.1f}")
    typer.echo(f"hand-coded policy: {res.hand_coded}/{eval_starts}")
    typer.echo(f"wrote {out}, {out.with_suffix('.json')}, {out.with_suffix('')}-curve.csv, {out.with_suffix('')}-curve.png")


def main() -> None:
    app()
