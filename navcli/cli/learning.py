"""The Learning Agent's training: ``train`` (learning-agent paper, section 6)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..signals import exit_code, stopped_by
from .common import MAX_JOBS, MAX_SEED, SCENARIO_HELP, ForceOption, ParamOption, app, build_spec, progress_bar
from .errors import about, refuse, say


@app.command()
def train(
    scenario: Annotated[
        Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + " (the paper's setting: landmarks-12).")
    ],
    trials: Annotated[
        int,
        typer.Option(
            min=1, max=1_000_000, help="Training trials in all (the paper: 2000); with --resume, the total to reach."
        ),
    ] = 2000,
    eval_every: Annotated[
        int, typer.Option(min=1, max=1_000_000, help="Evaluate the greedy policy every this many trials.")
    ] = 100,
    eval_starts: Annotated[
        int, typer.Option(min=1, max=10_000, help="Fixed test starts of each evaluation (the paper: 99).")
    ] = 99,
    seed: Annotated[int, typer.Option(min=0, max=MAX_SEED, help="Seed of the training starts and of the learner.")] = 1,
    out: Annotated[
        Optional[Path],
        typer.Option(
            help="Model file (.npz, with FILE.json, FILE-curve.csv and FILE-curve.png beside it; default: "
            "logs/<scenario>/<algorithm>-seed<N>.npz)."
        ),
    ] = None,
    resume: Annotated[
        Optional[Path], typer.Option(help="Continue the training saved in this model file, up to --trials in all.")
    ] = None,
    algorithm: Annotated[
        str, typer.Option(help="prioritized-sweeping (the paper's) or q-learning (model-free baseline).")
    ] = "prioritized-sweeping",
    jobs: Annotated[int, typer.Option(min=1, max=MAX_JOBS, help="Worker processes for the evaluations.")] = 2,
    log: Annotated[
        str,
        typer.Option(
            help="What is recorded of each training trial: summary (a row of "
            "FILE-trials.csv) or full (also every tick, one MCAP log per trial "
            "in FILE-trials/, 10-25 kB a simulated second)."
        ),
    ] = "summary",
    param: ParamOption = None,
    force: ForceOption = False,
) -> None:
    """Train the Learning Agent (learning-agent paper, section 6): trials from seeded random starts,
    the greedy policy evaluated on fixed starts, the model saved (resumable) with its learning curve.

    Trials run the paper's task: the robot is not told where the target is and paces while it has
    lost it, the camera is the Learning Agent's and the Pilot's, a trial succeeds only when the
    robot is also confident it is at the target, and ends when a landmark or the wall blocks it
    (--param learning.paper_task=0: a simpler task)."""
    from ..training.trainer import ALGORITHMS, LOGS

    if algorithm not in ALGORITHMS:
        raise refuse(f"--algorithm: unknown {algorithm!r} (expected one of: {', '.join(ALGORITHMS)})")
    if log not in LOGS:
        raise refuse(f"--log: unknown {log!r} (expected one of: {', '.join(LOGS)})")
    spec = build_spec(scenario, param, task=True)
    from ..learning.features import check_bounds
    from ..learning.model_file import check_out, curve_paths, load, trials_paths
    from ..training.trainer import train as run_training
    from ..outputs import check_folder

    with about("--param"):
        check_bounds(spec.params.learning)
    out = out or resume or Path("logs") / spec.scenario.name / f"{algorithm}-seed{seed}.npz"
    if resume is not None:
        with about("--resume"):
            load(resume)  # the input refused before the output is looked at
    with about("--out"):
        # a training resumed into its own model file replaces it, as --resume asks
        check_out(out, overwrite=force or (resume is not None and _same(out, resume)))
        if log == "full":
            check_folder(trials_paths(out)[1])
    t0 = time.perf_counter()
    with progress_bar() as bar:
        task = bar.add_task("training", total=trials)

        def on_trial(i, r, result) -> None:
            last = f"{result.curve[-1].successes}/{eval_starts} at {result.curve[-1].trials}" if result.curve else "-"
            bar.update(task, advance=1, description=f"training (test successes {last})")

        try:
            with about("--resume"):
                res = run_training(
                    spec,
                    trials=trials,
                    eval_every=eval_every,
                    eval_starts=eval_starts,
                    seed=seed,
                    algorithm=algorithm,
                    out=out,
                    resume=resume,
                    workers=jobs,
                    log=log,
                    on_trial=on_trial,
                )
        except KeyboardInterrupt as e:
            t = getattr(e, "training", None)
            say(
                f"{stopped_by(e)}: "
                + (
                    f"the model saved at {t.saved} trials is in {t.saved_in}; "
                    f"--resume {t.saved_in} --trials {t.end} completes the {t.end}"
                    if t is not None and t.saved is not None
                    else "no model was saved yet"
                )
            )
            raise typer.Exit(exit_code(e)) from None
    typer.echo(
        f"{res.trials} trials ({res.trials - (res.saved_at_start or 0)} now) in {time.perf_counter() - t0:.0f} s: training {res.train_s:.0f} s, "
        f"evaluations {res.eval_s:.0f} s "
        + ("in this process" if jobs == 1 else f"of worker time on {jobs} workers")
        + f" ({res.eval_trials} trials run, {res.eval_reused} repeated by a greedy policy and taken over)"
    )
    typer.echo(f"training outcomes: {res.outcomes}")
    typer.echo("trials  successes/{}  reward/trial  actions/trial".format(eval_starts))
    for p in res.curve:
        typer.echo(f"{p.trials:6d}  {p.successes:12d}  {p.reward:12.1f}  {p.actions:13.1f}")
    typer.echo(f"hand-coded policy: {res.hand_coded}/{eval_starts}; uniform random policy: {res.random}/{eval_starts}")
    trials_csv, trial_logs = trials_paths(out)
    curve_csv, curve_png = curve_paths(out)
    typer.echo(
        f"wrote {out}, {out.with_suffix('.json')}, {curve_csv}, {curve_png}, {trials_csv}"
        + (f" and the trial logs in {trial_logs}/" if log == "full" else "")
    )


def _same(a: Path, b: Path) -> bool:
    """Do ``a`` and ``b`` name one file (both existing), or the same path?"""
    try:
        return a.samefile(b)
    except OSError:
        return a.resolve() == b.resolve()
