"""What a run looks like, from a scenario or from logs: ``plot field|bids|map``, ``render``,
``layout``, ``report``."""

from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..analysis.files import without_mark
from .common import (
    SCENARIO_HELP,
    ForceOption,
    ParamOption,
    app,
    build_spec,
    finite,
    out_file,
    out_folder,
    plot_app,
    progress_bar,
)
from .errors import about, refuse, say

app.add_typer(plot_app, name="plot")

WallsOption = Annotated[
    bool, typer.Option(help="Let the room's walls push too (the paper's figures show an example without walls).")
]


def _plot(
    kind: str,
    scenario: Path,
    out: Optional[Path],
    step: Optional[float],
    param: list[str] | None,
    walls: bool = False,
    force: bool = False,
) -> None:
    spec = build_spec(scenario, param)
    out = out_file(out or Path("logs") / spec.scenario.name / f"{kind}.png", (".png",), "PNG image", force=force)
    from ..experiments import figures

    fn = figures.plot_field if kind == "field" else figures.plot_bids
    with progress_bar() as bar, about("--step"):
        task = bar.add_task(f"{kind}: rows of the grid", total=None)
        path = fn(
            spec,
            out,
            step or (0.2 if kind == "field" else 0.05),
            walls,
            progress=lambda i, n: bar.update(task, completed=i, total=n),
        )
    typer.echo(f"wrote {path}")


@plot_app.command("field")
def plot_field(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + ".")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/field.png).")] = None,
    step: Annotated[
        Optional[float], typer.Option(min=0.02, callback=finite, help="Grid spacing in metres (default 0.2).")
    ] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
    force: ForceOption = False,
) -> None:
    """Direction of the net virtual force over the arena (pilot paper, Figure 9)."""
    _plot("field", scenario, out, step, param, walls, force)


@plot_app.command("bids")
def plot_bids(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + ".")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: logs/<scenario>/bids.png).")] = None,
    step: Annotated[
        Optional[float], typer.Option(min=0.02, callback=finite, help="Grid spacing in metres (default 0.05).")
    ] = None,
    param: ParamOption = None,
    walls: WallsOption = False,
    force: ForceOption = False,
) -> None:
    """The pilot's bid (eq. 9) over the arena (pilot paper, Figure 10)."""
    _plot("bids", scenario, out, step, param, walls, force)


@plot_app.command("map")
def plot_map(
    log: Annotated[Path, typer.Argument(metavar="LOG", help="A log of a run (.mcap).")],
    out: Annotated[Optional[Path], typer.Option(help="PNG file (default: next to the log, <log>-map.png).")] = None,
    force: ForceOption = False,
) -> None:
    """The Map Manager's final map (mapped landmarks, regions, blocked edges) over the true arena."""
    from ..analysis.mapplot import plot_map as draw

    out = out_file(out or log.with_name(log.stem + "-map.png"), (".png",), "PNG image", force=force)
    typer.echo(f"wrote {draw(log, out)}")


@app.command()
def render(
    log: Annotated[Path, typer.Argument(metavar="LOG", help="A navcli log (.mcap).")],
    out: Annotated[
        Optional[Path], typer.Option(help="run.gif or run.mp4 (MP4 needs ffmpeg); default: the log's name with .gif.")
    ] = None,
    speed: Annotated[
        float, typer.Option(min=0.01, max=10_000.0, callback=finite, help="Simulated seconds per second of video.")
    ] = 10.0,
    start: Annotated[
        Optional[float], typer.Option("--from", min=0.0, callback=finite, help="First simulated second shown.")
    ] = None,
    end: Annotated[
        Optional[float], typer.Option("--to", min=0.0, callback=finite, help="Last simulated second shown.")
    ] = None,
    fps: Annotated[float, typer.Option(min=1.0, max=60.0, callback=finite, help="Frames per second of video.")] = 10.0,
    dpi: Annotated[int, typer.Option(min=20, max=300, help="Pixels per inch of the 5 x 6.4 inch frame.")] = 80,
    force: ForceOption = False,
) -> None:
    """A video of a run from its log alone: the true arena and path, the robot's beliefs (the
    visual memory), the pilot's force arrows, and the bids per resource under it."""
    from ..analysis.render import render as render_video

    target = out_file(out or log.with_suffix(".gif"), (".gif", ".mp4"), "video", force=force)
    bar = progress_bar() if sys.stderr.isatty() else None
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
    finally:
        if bar is not None:
            bar.stop()
    typer.echo(f"wrote {res.path} ({res.frames} frames, {res.size[0]}x{res.size[1]} px)")


LayoutFormat = Enum("LayoutFormat", {"app": "app", "sdk": "sdk"}, type=str)


@app.command()
def layout(
    out: Annotated[Optional[Path], typer.Option(help="Write the layout here (default: print it).")] = None,
    format: Annotated[
        LayoutFormat,
        typer.Option(
            "--format",
            help="app: the file Foxglove's Layouts > Import from file reads (also Lichtblick, Foxglove "
            "Studio 1.x); sdk: foxglove-sdk's layout JSON (foxglove.layouts, notebooks).",
        ),
    ] = LayoutFormat.app,
    force: ForceOption = False,
) -> None:
    """Write a Foxglove layout for navcli logs and --live runs: the arena in 2D top-down (frame
    world), bids per resource, the pilot's forces, the events and the summary."""
    import json

    from ..log.layout import app_json, sdk_json

    text = json.dumps(app_json() if format is LayoutFormat.app else sdk_json(), indent=1)
    if out is None:
        typer.echo(text)
        return
    from ..outputs import write_text

    write_text(out_file(out, (".json",), "layout file", force=force), text + "\n")
    typer.echo(f"wrote {out}")


@app.command()
def report(
    logdir: Annotated[
        Path,
        typer.Argument(
            metavar="LOGDIR",
            help=(
                "A folder of logs (searched recursively), or a sweep's results table (results.parquet or "
                "results.csv): then every parameter point is a condition of its own, and no plots are made."
            ),
        ),
    ],
    out: Annotated[
        Optional[Path],
        typer.Option(help="Where to write the table and plots (default: LOGDIR, or the results table's folder)."),
    ] = None,
    baseline: Annotated[
        str,
        typer.Option(
            help="The pilot the others are compared with (a pilot of the logs; the "
            "report says so when none of the runs is its)."
        ),
    ] = "geometric",
    force: ForceOption = False,
) -> None:
    """Rebuild the comparison table and plots from existing logs, running nothing; with several
    conditions (parameter points of a sweep), a table of every pilot against the baseline per
    condition comes first."""
    table = logdir.is_file() and logdir.suffix in (".parquet", ".csv")
    if not (logdir.is_dir() or table):
        raise refuse(
            f"{logdir}: no such file or folder"
            if not logdir.exists()
            else f"{logdir}: expected a folder of logs or a sweep's results table (.parquet or .csv)"
        )
    from ..analysis.tables import REPORT_FILES
    from ..plugins import UnknownPlugin, pilot

    try:
        pilot(baseline)
        anywhere = False
    except UnknownPlugin:  # no pilot navcli can run: it must be one of the logs'
        anywhere = True
    folder = out_folder(out or (logdir.parent if table else logdir), REPORT_FILES, force=force)
    if out is None:
        say(f"the table and plots go to {folder} (--out to choose another folder)")
    write_tables(logdir, baseline, folder, table=table, baseline_in_runs=anywhere)


def write_tables(
    logdir: Path,
    baseline: str,
    out: Path,
    logs: list[str | Path] | None = None,
    table: bool = False,
    baseline_in_runs: bool = False,
) -> None:
    """The table of the logs under ``logdir`` (or of ``logs``; with ``table``, of the sweep
    results table ``logdir``), printed and written to ``out``; an unreadable log is skipped with a
    line naming it; the same run twice, or no readable log at all, is refused, and so, with
    ``baseline_in_runs``, is a baseline none of the runs has."""
    from ..analysis.tables import load_runs, load_sweep, write_report

    skipped: list[tuple[str, str]] = []
    try:
        runs = load_sweep(logdir) if table else load_runs(logdir, paths=logs, skipped=skipped)
    finally:
        for path, why in skipped:
            say(f"skipped {path}: {why}")
    pilots = sorted(set(runs["pilot"]))
    if baseline_in_runs and baseline not in pilots:
        raise refuse(
            f"--baseline: {baseline!r} is not a pilot: none of these runs' ({', '.join(pilots)}), and none "
            "navcli can find (navcli's, an installed plugin's, module:Class)"
        )
    files = write_report(runs, out, baseline, skipped, plots=not table)
    typer.echo("")
    typer.echo(without_mark(files["markdown"].read_text()))
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}")
