"""One mission and its files: ``run``, ``validate``, ``bench``, ``recover``, ``params``, ``schema``."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Annotated, Any, Optional

import typer

from .common import (
    MAX_JOBS,
    MAX_SEED,
    NAVIGATION_HELP,
    SCENARIO_HELP,
    ParamOption,
    PerceptionName,
    PilotOption,
    app,
    build_spec,
    ForceOption,
    check_model,
    choice,
    finite,
)
from ..log import compression
from .errors import EXIT_BAD_INPUT, EXIT_FAILED_MISSION, about, refuse, say


CompressionName = Enum("CompressionName", {n: n for n in compression.COMPRESSIONS}, type=str)  # type: ignore[misc]


@app.command()
def run(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + ".")],
    seed: Annotated[
        Optional[int], typer.Option(min=0, max=MAX_SEED, help="Random seed (default: the scenario's mission.seed).")
    ] = None,
    pilot: PilotOption = None,
    out: Annotated[
        Optional[Path],
        typer.Option(
            help="Log file (default: logs/<scenario>/<pilot>-seed<N>-<run id>.mcap, the run id a hash of the whole "
            "configuration). Missing folders are created."
        ),
    ] = None,
    time_limit: Annotated[
        Optional[float],
        typer.Option(min=0.1, callback=finite, help="Simulated seconds before the run is declared failed."),
    ] = None,
    live: Annotated[
        bool, typer.Option(help="Also serve the run to Foxglove (ws://127.0.0.1:PORT), paced to real time.")
    ] = False,
    port: Annotated[int, typer.Option(min=0, max=65535, help="WebSocket port for --live (0: any free port).")] = 8765,
    linger: Annotated[
        Optional[float],
        typer.Option(
            min=0.0,
            max=86_400.0,
            callback=finite,
            metavar="S",
            help="With --live: once the mission ends, keep serving its final state this many seconds "
            "(default: until Ctrl-C), so the viewer keeps it on screen.",
        ),
    ] = None,
    param: ParamOption = None,
    perception: Annotated[
        Optional[PerceptionName],
        typer.Option(
            help="What the agents know: vision (camera and visual memory) or oracle (ground truth, to isolate the "
            "pilot). Default: the scenario's mission.perception, else vision."
        ),
    ] = None,
    navigation: Annotated[
        str, typer.Option(metavar="POLICY", help=NAVIGATION_HELP[0].upper() + NAVIGATION_HELP[1:] + ".")
    ] = "agents",
    force: ForceOption = False,
    log_compression: Annotated[
        CompressionName, typer.Option(help=compression.HELP, show_default=False)
    ] = CompressionName(compression.DEFAULT),
) -> None:
    """Run one mission, record it to an MCAP log and print how it ended."""
    spec = build_spec(
        scenario,
        param,
        seed=seed,
        pilot=pilot,
        time_limit=time_limit,
        perception=choice(perception),
        navigation=navigation,
    )
    check_model(spec.navigation)
    import signal

    from ..log.files import beside
    from ..log.writer import check_log_path
    from ..runner import run_mission
    from ..signals import Terminated, exit_code, raising
    from .common import MissionProgress

    if out is None:  # the default name: a rerun writes beside the log before it (--force: over it)
        out = spec.default_log_path() if force else beside(spec.default_log_path())
    with about("--out"):
        out = check_log_path(out, (str(scenario),), overwrite=force)
    # a kill from a scheduler ends the run like Ctrl-C: the log closed, marked interrupted; neither is
    # raised inside a pymunk callback, where it would be lost
    signal.signal(signal.SIGTERM, raising(Terminated))
    signal.signal(signal.SIGINT, raising(KeyboardInterrupt))

    served = []

    def opened(recorder) -> None:  # said once the log is this run's (not before: another run may hold it)
        served.append(recorder)
        if recorder.kept_aside:
            say(
                f"note: {recorder.partial} was the unfinished log of an earlier run; it is kept as "
                f"{recorder.kept_aside} (`navcli recover` makes a readable log of it)"
            )
        if recorder.port is not None:
            say(f"serving the run live on ws://127.0.0.1:{recorder.port} (open it in Foxglove: Open connection)")

    progress = MissionProgress(spec.time_limit, spec.scenario.name)
    try:
        res = run_mission(
            spec,
            out=out,
            live=live,
            port=port,
            on_tick=progress,
            on_open=opened,
            keep_serving=live,
            overwrite=force,
            log_compression=log_compression.value,
        )
    except KeyboardInterrupt as e:  # Ctrl-C or SIGTERM: the log was closed by run_mission
        progress.close()
        say(
            ("terminated (SIGTERM)" if isinstance(e, Terminated) else "interrupted")
            + ": the log is closed and marked 'interrupted'"
        )
        raise typer.Exit(exit_code(e)) from None
    finally:
        progress.close()
    s = res.summary
    if live and served:
        try:
            _linger(served[0], s, linger)
        finally:
            served[0].stop_serving()  # a stop between the run's end and the linger's start too
    typer.echo(f"outcome      {s['outcome']} ({s['reason']})")
    typer.echo(f"sim time     {s['time_s']:.1f} s  ({res.realtime_factor:.0f}x real time)")
    typer.echo(f"path length  {s['path_length_m']:.2f} m")
    typer.echo(f"collisions   {s['collisions']}")
    typer.echo(f"log          {res.log}")
    if s["outcome"] != "reached":
        raise typer.Exit(EXIT_FAILED_MISSION)


def _linger(recorder, summary: dict, seconds: float | None) -> None:
    """Keep a live run's server up after the mission ended (its log is complete), so the viewer
    keeps the final state on screen, ``seconds`` or until Ctrl-C / SIGTERM, which here end the
    serving, not the run: the exit code is the mission's."""
    import math
    import time

    say(
        f"the mission ended ({summary['outcome']}) and its log is complete; still serving its final state on "
        f"ws://127.0.0.1:{recorder.port} " + (f"for {seconds:g} s" if seconds is not None else "until Ctrl-C")
    )
    end = time.monotonic() + (seconds if seconds is not None else math.inf)
    try:
        while (left := end - time.monotonic()) > 0:
            recorder.serve_final_state()  # every second, for a viewer that joins late
            time.sleep(min(1.0, left))
    except KeyboardInterrupt:
        pass
    finally:
        recorder.stop_serving()


@app.command()
def validate(files: Annotated[list[Path], typer.Argument(metavar="FILES", help="Scenario files to check.")]) -> None:
    """Check scenario files without running them."""
    from ..scenario import ScenarioError, load_scenario

    bad = 0
    for f in files:
        try:
            sc = load_scenario(f)
        except ScenarioError as e:
            bad += 1
            say(str(e))
            continue
        typer.echo(
            f"{f}: ok ({sc.name}: {sc.arena.width:g} m x {sc.arena.height:g} m, "
            f"{len(sc.obstacles)} obstacles, {len(sc.landmarks)} landmarks)"
        )
    if bad:
        say(f"{bad} of {len(files)} files refused")
        raise typer.Exit(EXIT_BAD_INPUT)


@app.command()
def scenarios(
    name: Annotated[
        Optional[str],
        typer.Argument(
            metavar="[NAME]",
            help=(
                "Print this bundled scenario's YAML instead, to start a room of your own from it "
                "(navcli scenarios paper-8x8 > my-room.yaml)."
            ),
        ),
    ] = None,
) -> None:
    """List the scenarios bundled with navcli, with their descriptions: every command takes them by
    name, from any folder (navcli run paper-8x8); a file of that name in the folder wins."""
    from ..scenario import bundled, load_scenario

    if name is not None:
        found = bundled.name_of(name)
        if found is None:
            raise refuse(f"{name!r} is not a bundled scenario ({bundled.suggestion(name)})")
        typer.echo(bundled.path(found).read_text(encoding="utf-8"), nl=False)
        return
    import shutil
    import textwrap

    names = bundled.names()
    pad = max(map(len, names)) + 2
    width = max(shutil.get_terminal_size((100, 24)).columns, pad + 40)
    for n in names:
        about_it = " ".join(load_scenario(bundled.path(n)).description.split()) or "-"
        typer.echo(textwrap.fill(about_it, width, initial_indent=n.ljust(pad), subsequent_indent=" " * pad))
    typer.echo(f"\n{len(names)} scenarios, in {bundled.FOLDER}; `navcli scenarios NAME` prints one.")


@app.command()
def bench(
    scenario: Annotated[
        Optional[Path],
        typer.Argument(
            metavar="SCENARIO",
            help=SCENARIO_HELP + ", to time (default: paper-8x8; with --training, landmarks-12).",
            show_default=False,
        ),
    ] = None,
    repeat: Annotated[int, typer.Option(min=1, max=1000, help="Runs per configuration; the median is reported.")] = 5,
    pilot: PilotOption = None,
    seed: Annotated[Optional[int], typer.Option(min=0, max=MAX_SEED)] = None,
    occlusion: Annotated[bool, typer.Option(help="Instead: time the pilot's occlusion test, loop vs numpy.")] = False,
    param: ParamOption = None,
    perception: Annotated[
        Optional[PerceptionName], typer.Option(help="vision or oracle (default: the scenario's).")
    ] = None,
    objects: Annotated[
        bool, typer.Option(help="Instead: cost per tick with the scenario's own objects, then 50 and 200.")
    ] = False,
    long: Annotated[
        bool,
        typer.Option(
            "--long",
            help="Instead: cost per tick in the last minute of a 20-minute run against the first "
            "(the map must not slow a long run down; try scenarios/trap-box.yaml).",
        ),
    ] = False,
    training: Annotated[
        bool,
        typer.Option(
            "--training",
            help="Instead: the learning task's throughput: actions per second of its Gym env's step, and "
            "a whole training's wall time (the paper's: 2,000 trials, 99 test starts every 100; minutes).",
        ),
    ] = False,
    trials: Annotated[
        int, typer.Option(min=1, max=100_000, help="With --training: the training's trials (evaluated every 100).")
    ] = 2000,
    eval_starts: Annotated[
        int, typer.Option(min=1, max=10_000, help="With --training: the test starts of each evaluation.")
    ] = 99,
    jobs: Annotated[
        Optional[int],
        typer.Option(
            min=1, max=MAX_JOBS, help="With --training: worker processes for the evaluations (default: the cores)."
        ),
    ] = None,
    actions: Annotated[int, typer.Option(min=1, max=1_000_000, help="With --training: env.step calls timed.")] = 300,
) -> None:
    """Real-time factor (simulated s per wall s) of a full mission, with logging on and off."""
    from .. import BUILD, builds

    typer.echo(f"build: {builds.describe(BUILD)}")
    if occlusion:
        from ..experiments.bench import occlusion_benchmark

        occlusion_benchmark(echo=typer.echo)
        return
    if training:
        from ..experiments.bench import training_benchmark
        from ..experiments.executor import workers

        spec = build_spec(scenario or Path("landmarks-12"), param, task=True)
        training_benchmark(
            spec,
            actions=actions,
            trials=trials,
            eval_starts=eval_starts,
            workers=workers(jobs),
            seed=1 if seed is None else seed,
            echo=typer.echo,
        )
        return
    spec = build_spec(scenario or Path("paper-8x8"), param, seed=seed, pilot=pilot, perception=choice(perception))
    from ..experiments.bench import benchmark, long_run_benchmark, objects_benchmark

    if long:
        long_run_benchmark(spec, echo=typer.echo)
    elif objects:
        objects_benchmark(spec, echo=typer.echo)
    else:
        benchmark(spec, repeat=repeat, echo=typer.echo)


@app.command()
def recover(
    partial: Annotated[
        Path,
        typer.Argument(
            metavar="PARTIAL",
            help="The .partial file a killed run left (or a .partial-<n> kept aside), or a log cut short.",
        ),
    ],
    out: Annotated[Optional[Path], typer.Option(help="The log to write (default: the name without .partial).")] = None,
    force: ForceOption = False,
) -> None:
    """Make a readable log of a run killed outright: its complete chunks (all but at most the last
    simulated second), marked interrupted, "recovered after an abrupt end". A log cut short after
    its summary (its end lost, so no reader opens it) is rebuilt whole, with its own outcome."""
    from ..log.files import LogPathError
    from ..log.recover import recover as recover_log

    if not partial.is_file():
        raise refuse(
            f"{partial}: "
            + (
                "is a folder; give the .partial file a killed run left"
                if partial.is_dir()
                else "a link that leads nowhere (or to itself)"
                if partial.is_symlink()
                else "no such file"
                if not partial.exists()
                else "not a regular file"
            )
        )
    with about("--out", LogPathError):  # the log to write; the other refusals are about PARTIAL
        path, s = recover_log(partial, out, overwrite=force)
    if s["damaged_bytes"]:
        say(
            f"warning: {partial} is damaged before its end (a record fails its check): the {s['damaged_bytes']} "
            f"bytes after the damage are not recovered; the log ends at the last good record"
        )
    typer.echo(
        f"recovered {s['ticks']} ticks, {s['time_s']:.1f} simulated s, into {path} (outcome {s['outcome']}); "
        f"{partial} is left as it was"
    )


@app.command()
def params(
    scenario: Annotated[
        Optional[Path], typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + ": show the values it resolves to.")
    ] = None,
    param: ParamOption = None,
    pilot: PilotOption = None,
    navigation: Annotated[
        Optional[str],
        typer.Option(metavar="POLICY", help="A Navigation policy whose parameters to show too (a plugin's)."),
    ] = None,
    markdown: Annotated[
        bool, typer.Option("--markdown", help="Print the reference table in Markdown (the docs' parameter reference).")
    ] = False,
) -> None:
    """List every parameter by its --param name, with its value, unit, the range an override must lie in,
    and what it is: navcli's, and a plugin's own (NAME.x) for the pilot and policy chosen, or, without a
    scenario or a choice, for every installed plugin.

    Without a scenario, the defaults; with one, its values after its blocks and any --param."""
    from ..params import Params, parse_override
    from ..plugins import GROUPS, installed
    from ..plugins import navigation as policies
    from ..plugins import pilot as find_pilot
    from ..plugins.registry import with_params

    if scenario is not None:
        values = build_spec(scenario, param, pilot=pilot, navigation=navigation).params
    else:
        chosen = ([find_pilot(pilot)] if pilot else []) + list(policies(navigation) if navigation else [])
        if not chosen:  # every installed plugin's (one that cannot be loaded is left out: `plugins list` says why)
            chosen = [c for kind in GROUPS for c in installed(kind) if not isinstance(c, tuple)]
        values = with_params(Params(), chosen)
        with about("--param"):
            values = values.override(dict(parse_override(i) for i in param or []))
    rows = param_rows(values)
    if markdown:
        typer.echo(params_markdown(values), nl=False)
        return
    header = ("name", "value", "unit", "range", "description")
    widths = [max(len(r[i]) for r in rows + [header]) for i in range(4)]
    for row in [header] + rows:
        typer.echo(
            f"{row[0]:{widths[0]}s}  {row[1]:>{widths[1]}s}  {row[2]:{widths[2]}s}  {row[3]:{widths[3]}s}  {row[4]}"
        )


def param_rows(values: Any) -> list[tuple[str, str, str, str, str]]:
    """One row per parameter of ``values`` (a :class:`~navcli.params.Params`): its --param name, value,
    unit, the range an override must lie in, and what it is."""
    return [
        (name, _shown(value), d.unit or "-", d.range_text(), d.description) for name, d, value in values.declarations()
    ]


def params_markdown(values: Any) -> str:
    """``navcli params --markdown``: the parameter reference as a Markdown table (the docs' reference
    page is made by this function too)."""
    lines = ["| parameter | default | unit | range | what it is |", "| --- | --- | --- | --- | --- |"]
    for row in param_rows(values):
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in (f"`{row[0]}`",) + row[1:]) + " |")
    return "\n".join(lines) + "\n"


def _shown(value) -> str:
    """A parameter's value as ``navcli params`` prints it (a switch as true/false, as --param takes it)."""
    return (
        str(value).lower() if isinstance(value, bool) else str(list(value)) if isinstance(value, tuple) else str(value)
    )


@app.command()
def schema(
    markdown: Annotated[
        bool,
        typer.Option(
            "--markdown",
            help="Instead: every field with what it is, its default, range and unit, as a Markdown table (the docs').",
        ),
    ] = False,
) -> None:
    """Print the scenario format as a JSON Schema, for editors (the YAML language server:
    `# yaml-language-server: $schema=scenario.schema.json` at the top of a scenario)."""
    import json

    from ..scenario import json_schema
    from ..scenario.schema import reference_table

    typer.echo(reference_table() if markdown else json.dumps(json_schema(), indent=2), nl=not markdown)
