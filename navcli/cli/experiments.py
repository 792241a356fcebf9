"""Many runs, on the local pool or a Dask cluster: ``compare pilots``, ``compare policies``,
``sweep``, ``tune``. Each resumes: what is finished is kept, and the same command goes on."""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..analysis.files import without_mark
from ..plugins.names import BUILTIN_PILOTS
from .common import (
    MAX_SEED,
    PILOT_HELP,
    PLUGIN_FORMS,
    SCENARIO_HELP,
    SCENARIOS_HELP,
    JobsOption,
    ParamOption,
    PerceptionName,
    PilotOption,
    SchedulerOption,
    app,
    build_spec,
    choice,
    compare_app,
    executor_for,
    finite,
    out_file,
    out_folder,
    progress_bar,
    require_extra,
)
from .errors import EXIT_RUNS_ERRORED, RUNS_ERRORED_HELP, about, on_stop, refuse, say
from .views import write_tables

app.add_typer(compare_app, name="compare")


@compare_app.command("pilots", epilog=RUNS_ERRORED_HELP)
def compare_pilots(
    scenarios: Annotated[list[Path], typer.Argument(metavar="SCENARIOS", help=SCENARIOS_HELP + ".")],
    reruns: Annotated[int, typer.Option(min=1, max=10_000, help="Reruns per scenario and pilot (the paper: 45).")] = 45,
    pilots: Annotated[
        str, typer.Option(help=f"Comma-separated pilots, the last the baseline; each {PILOT_HELP}.")
    ] = ",".join(BUILTIN_PILOTS),
    jobs: JobsOption = None,
    out: Annotated[Path, typer.Option(help="Folder for the logs, the table and the plots.")] = Path("logs/compare"),
    time_limit: Annotated[
        Optional[float], typer.Option(min=0.1, callback=finite, help="Override the scenarios' time limit (s).")
    ] = None,
    param: ParamOption = None,
    perception: Annotated[
        Optional[PerceptionName],
        typer.Option(help="vision or oracle for every run (default: each scenario's mission.perception)."),
    ] = None,
    scheduler: SchedulerOption = None,
) -> None:
    """The pilot paper's Table 1: every pilot on every scenario with the same seeds, in parallel;
    logs that are already complete are kept (an interrupted comparison resumes)."""
    names = [p.strip() for p in pilots.split(",") if p.strip()]
    if not names:
        raise refuse("--pilots: no pilot given")
    from ..plugins import registry

    with about("--pilots"):
        baseline = registry.pilots(names, pilots)[-1].name
    specs = [build_spec(p, param, time_limit=time_limit, perception=choice(perception), also=names) for p in scenarios]
    first: dict[str, Path] = {}
    for path, spec in zip(scenarios, specs):
        if spec.run_id in first:
            raise refuse(
                f"SCENARIOS: {first[spec.run_id]} and {path} are the same scenario: each run would be made twice"
            )
        first[spec.run_id] = path
    from ..analysis.tables import REPORT_FILES
    from ..experiments.compare import plan, run_on
    from ..outputs import check_file

    out_folder(out, REPORT_FILES, force=True)  # resumed: its table is remade from every planned run
    work = plan(specs, names, reruns, out)
    with about("--out"):
        for j in work:  # a file at a log's path is a log of navcli's (resumed or rerun), never a user's
            if Path(j.log).exists() or Path(j.log).is_symlink():
                check_file(Path(j.log), (".mcap",), "log", overwrite=True)  # kept if complete
    t0 = time.perf_counter()
    failed: list = []
    ran = 0
    with progress_bar() as bar, executor_for(jobs, scheduler) as ex:
        workers = getattr(ex, "workers", 1)
        task = bar.add_task(f"{len(work)} runs on {workers} workers", total=len(work))

        def done(r) -> None:
            nonlocal ran
            ran += r.ran
            if r.outcome != "reached":
                failed.append(r)
            bar.advance(task)

        with on_stop("completed logs are kept; run the same command again to resume"):
            run_on(work, ex, done)
    wall = time.perf_counter() - t0
    typer.echo(
        f"{len(work)} runs ({ran} run now, {len(work) - ran} already complete) in {wall:.1f} s on {workers} workers"
    )
    for r in failed:
        j = r.job.spec
        why = r.message if r.message.startswith(r.outcome) else f"{r.outcome}: {r.message}".rstrip(": ")
        typer.echo(f"  failed: {j.scenario.name} {j.pilot} seed {j.seed}: {why} ({r.job.log})")
    write_tables(out, baseline, out, [j.log for j in work])  # the runs planned, not every log under --out
    errors = sum(r.outcome == "error" for r in failed)
    if errors:
        say(f"{errors} of {len(work)} runs ended in error: the table counts them as not reached, and its notes say why")
        raise typer.Exit(EXIT_RUNS_ERRORED)


@compare_app.command("policies", epilog=RUNS_ERRORED_HELP)
def compare_policies(
    scenario: Annotated[
        Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + " (the paper's setting: landmarks-12).")
    ],
    policy: Annotated[
        Optional[list[str]],
        typer.Option(
            "--policy",
            metavar="POLICY",
            help="learned (the bundled model), learned:FILE (a model of `navcli train`, Prioritized Sweeping "
            "or Q-learning), hand-coded, agents, random (a uniform random action at every choice, seeded), a baseline "
            "of one action in every state (all-MB, all-MLL, all-MOT, all-MVL, all-MVT), or a Navigation policy plugin (an "
            f"installed plugin's name, {PLUGIN_FORMS}, or agents+NAME: run as agents is); repeatable (default: learned, hand-coded, random, agents). Every policy runs the "
            "learning paper's task (learning.paper_task=0: a simpler one).",
        ),
    ] = None,
    runs: Annotated[int, typer.Option(min=1, max=1000, help="Runs (seeds of the missions' noise) per policy.")] = 5,
    starts: Annotated[
        int,
        typer.Option(
            min=1, max=10_000, help="Fixed random starts per run, those `navcli train` evaluates on (the paper: 99)."
        ),
    ] = 99,
    out: Annotated[
        Path,
        typer.Option(help="Folder for the per-run trials (runs/*.json), policies.csv, policies.md and trials.csv."),
    ] = Path("logs/compare-policies"),
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    param: ParamOption = None,
) -> None:
    """The learning paper's Table 1: every policy from the same starts, per run; successes, reward,
    actions and the count of each action per trial, with 95 % intervals (Wilson for successes, a
    bootstrap over the starts for the rest; too few starts are said).
    Runs already done are kept (an interrupted comparison resumes)."""
    spec = build_spec(scenario, param, task=True)
    from ..training.comparison import (
        DEFAULT_POLICIES,
        PolicyError,
        parse_policy,
        plan,
        run_all,
        write_source,
        write_table,
    )
    from ..learning.features import check_bounds

    names = list(policy or DEFAULT_POLICIES)
    with about("--param"):
        check_bounds(spec.params.learning)
    with about("--policy"):
        chosen = [parse_policy(n) for n in names]
        labels = [c.label for c in chosen]
        if len(set(labels)) < len(labels):
            raise PolicyError(f"a policy is named twice: {', '.join(labels)}")
    from ..training.comparison import SOURCE_FILE, TABLE_FILES

    out_folder(out, TABLE_FILES + (SOURCE_FILE,), force=True)  # resumed: the table is remade from every run
    out_folder(out / "runs")
    (out / "runs").mkdir(parents=True, exist_ok=True)
    work = plan(spec, chosen, runs, starts, out)
    t0 = time.perf_counter()
    with progress_bar() as bar:
        task = bar.add_task(f"{len(work)} runs of {starts} trials", total=len(work))
        with executor_for(jobs, scheduler) as ex:
            with on_stop(f"the finished runs are kept in {out / 'runs'}; run the same command again to resume"):
                results = run_all(work, ex, lambda r: bar.advance(task))
            workers = getattr(ex, "workers", 1)
    ran = sum(r.ran for r in results)
    typer.echo(
        f"{len(work)} (policy, run) pairs of {starts} trials ({ran} run now, {len(work) - ran} kept) in "
        f"{time.perf_counter() - t0:.1f} s on {workers} workers"
    )
    errors = [r for r in results if r.trials is None]
    for r in errors:
        say(f"  failed: {r.job.policy.label} run {r.job.run}: {r.error}")
    files = write_table(results, out, spec.scenario.name)
    argv = ["navcli", "compare", "policies", str(scenario), *(a for n in names for a in ("--policy", n))]
    argv += ["--runs", str(runs), "--starts", str(starts), "--out", str(out.resolve())]
    files["source"] = write_source(out, argv + [a for v in param or [] for a in ("--param", v)])
    typer.echo("")
    typer.echo(without_mark(files["markdown"].read_text()))
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}")
    if errors:
        say(f"{len(errors)} of {len(work)} runs ended in error")
        raise typer.Exit(EXIT_RUNS_ERRORED)


@app.command(epilog=RUNS_ERRORED_HELP)
def sweep(
    plan: Annotated[
        Path,
        typer.Argument(
            metavar="PLAN",
            help="Plan file (YAML): scenarios (files or bundled names), seeds, a grid or a random sample of "
            "--param values; see the README.",
        ),
    ],
    out: Annotated[
        Optional[Path],
        typer.Option(
            help="Folder for the results table (results.parquet) and the logs (default: logs/sweep/<plan name>); "
            "on a cluster, a path every worker can write."
        ),
    ] = None,
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    no_logs: Annotated[bool, typer.Option("--no-logs", help="Run without logs; keep only the results table.")] = False,
    csv: Annotated[bool, typer.Option("--csv", help="Also write the table as results.csv.")] = False,
) -> None:
    """Run every scenario x parameter point x seed of a plan; one row per run in a Parquet table.
    Runs already in the table are not run again (an interrupted sweep resumes)."""
    from ..experiments.sweep import load_plan, plan_runs, run_sweep

    p = load_plan(plan)
    out = out_folder(
        out or Path("logs") / "sweep" / plan.stem,
        ("results.parquet",) + (("results.csv",) if csv else ()),
        force=True,  # resumed: the runs already in the table are kept
    )
    runs = plan_runs(p, None if no_logs else out)
    table = out / "results.parquet"
    from rich.progress import TextColumn, TimeRemainingColumn

    t0 = time.perf_counter()
    with progress_bar(TextColumn("{task.fields[failed]} failed"), TextColumn("ETA"), TimeRemainingColumn()) as bar:
        task = bar.add_task(f"{len(runs)} runs", total=len(runs), failed=0)

        def row(r: dict, stats) -> None:
            bar.update(task, completed=stats.skipped + stats.done, failed=stats.failed)

        with executor_for(jobs, scheduler) as ex:
            with on_stop(f"the finished runs are in {table}; run the same command again to resume"):
                stats = run_sweep(runs, table, ex, csv=csv, on_row=row)
    wall = time.perf_counter() - t0
    typer.echo(
        f"{stats.total} runs: {stats.done} run now in {wall:.1f} s, {stats.skipped} already in the table; "
        f"{stats.failed} did not reach the target, {stats.errors} raised an error"
    )
    typer.echo(f"wrote {table}" + (f" and {table.with_suffix('.csv')}" if csv else ""))
    if stats.errors:
        raise typer.Exit(EXIT_RUNS_ERRORED)


@app.command()
def tune(
    scenarios: Annotated[
        list[Path], typer.Argument(metavar="SCENARIOS", help=SCENARIOS_HELP + "; every trial runs each of them.")
    ],
    param: Annotated[
        list[str],
        typer.Option(
            "--param",
            metavar="NAME=LOW:HIGH",
            help="A parameter to tune in [LOW, HIGH] (NAME alone: [0, 5]); NAME=VALUE fixes it for every trial. "
            "Repeatable; names as `navcli params` lists them.",
        ),
    ],
    algorithm: Annotated[
        str, typer.Option(help="tpe (Optuna), cmaes (Optuna) or ga (DEAP's eaSimple, the thesis' generational GA).")
    ] = "tpe",
    trials: Annotated[
        int, typer.Option(min=1, max=100_000, help="Finished trials the study should hold (tpe, cmaes).")
    ] = 100,
    seeds: Annotated[
        int, typer.Option(min=1, max=10_000, help="Runs per scenario per trial (the same seeds for every trial).")
    ] = 3,
    objective: Annotated[
        str,
        typer.Option(
            help="fitness (success rate, mean steps and their spread; see navcli/experiments/tune.py), success "
            "(rate) or time (minus the mean time, failures at the limit). Maximised."
        ),
    ] = "fitness",
    storage: Annotated[
        Optional[Path],
        typer.Option(
            help="The study's journal file (tpe, cmaes) or the GA's checkpoint; an existing one of the same problem "
            "is resumed. Default: OUT/study.journal or OUT/ga.json."
        ),
    ] = None,
    out: Annotated[Path, typer.Option(help="Folder for history.csv, best.json, best.yaml, objective.png.")] = Path(
        "logs/tune"
    ),
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    time_limit: Annotated[
        Optional[float], typer.Option(min=0.1, callback=finite, help="Override the scenarios' time limit (s).")
    ] = None,
    perception: Annotated[Optional[PerceptionName], typer.Option(help="vision or oracle for every run.")] = None,
    pilot: PilotOption = None,
    seed: Annotated[int, typer.Option(min=0, max=MAX_SEED, help="Seed of the optimiser (not of the runs).")] = 1,
    population: Annotated[int, typer.Option(min=2, max=10_000, help="GA: individuals per generation.")] = 20,
    generations: Annotated[int, typer.Option(min=1, max=100_000, help="GA: generations.")] = 100,
    crossover: Annotated[
        float, typer.Option(min=0.0, max=1.0, callback=finite, help="GA: crossover probability.")
    ] = 0.8,
    mutation: Annotated[float, typer.Option(min=0.0, max=1.0, callback=finite, help="GA: mutation probability.")] = 0.1,
) -> None:
    """Find parameter values that maximise an objective over scenarios and seeds; prints and writes the
    best values, the history, a plot of the objective against trials and a scenario pilot: block."""
    from ..experiments.tune import ALGORITHMS, OBJECTIVES, GASettings, TuneProblem, parse_range

    for name, value, allowed in (("--algorithm", algorithm, ALGORITHMS), ("--objective", objective, OBJECTIVES)):
        if value not in allowed:
            raise refuse(f"{name}: {value!r} is not one of {', '.join(allowed)}")
    probe = build_spec(scenarios[0], None, pilot=pilot).params  # navcli's parameters and the pilot's own
    with about("--param"):
        parsed = [parse_range(p, probe) for p in param]
    names = [p[0] for p in parsed]
    if len(set(names)) < len(names):
        raise refuse(f"--param: {', '.join(sorted({n for n in names if names.count(n) > 1}))} given twice")
    tuned = [p for p in parsed if len(p) == 3]
    if not tuned:
        raise refuse("--param: name at least one parameter to tune, as NAME=LOW:HIGH or NAME")
    fixed = [f"{p[0]}={p[1]}" for p in parsed if len(p) == 2]
    bases = tuple(
        build_spec(s, fixed, time_limit=time_limit, perception=choice(perception), pilot=pilot) for s in scenarios
    )
    problem = TuneProblem(
        bases, tuple(p[0] for p in tuned), tuple(p[1] for p in tuned), tuple(p[2] for p in tuned), seeds, objective
    )
    require_extra("deap" if algorithm == "ga" else "optuna", "navcli tune")
    from ..experiments.tune import RESULT_FILES

    out_folder(out, RESULT_FILES, force=True)  # resumed: remade from the study's every trial
    storage = out_file(
        storage or out / ("ga.json" if algorithm == "ga" else "study.journal"),
        (".json",) if algorithm == "ga" else (".journal", ".log"),
        "study file",
        "--storage",
        force=True,  # an existing study is resumed, not replaced
    )
    count = 0

    def trial(r: dict) -> None:
        nonlocal count
        count += 1
        if count % 10 == 0:
            say(f"  {count} trials evaluated; last {objective} {r['objective']:.4g}")

    from ..experiments import tune as t
    from ..experiments.executor import workers

    with (
        executor_for(jobs, scheduler) as ex,
        about("--storage", t.CheckpointError),
        on_stop(
            lambda: (
                f"the finished trials are in {storage}; run the same command again to resume"
                if storage.exists()
                else "no trial had finished; nothing was kept"
            )
        ),
    ):
        if algorithm == "ga":
            history = t.tune_ga(
                problem,
                ex,
                storage=storage,
                seed=seed,
                settings=GASettings(population, generations, crossover, mutation),
                on_trial=trial,
            )
        else:
            batch = getattr(ex, "workers", None) or workers(jobs)
            history = t.tune_optuna(
                problem, ex, algorithm=algorithm, trials=trials, storage=storage, batch=batch, seed=seed, on_trial=trial
            )
    files = t.write_results(history, problem, out)
    import json

    best = json.loads(files["best"].read_text())
    typer.echo(f"{len(history)} trials; best {objective} {best['value']:.4g} (trial {best['trial']}):")
    for k, v in best["params"].items():
        typer.echo(f"  {k} = {v:.6g}")
    typer.echo(f"wrote {', '.join(str(p) for p in files.values())}; study in {storage}")


@app.command(epilog=RUNS_ERRORED_HELP)
def reproduce(
    which: Annotated[str, typer.Argument(metavar="[pilots|learning|all]", help="Which paper's experiments.")] = "all",
    quick: Annotated[
        bool,
        typer.Option("--quick", help="Few reruns (minutes on 2 cores), to check the machinery; the report says so."),
    ] = False,
    out: Annotated[
        Path,
        typer.Option(
            help="Folder for the runs, report.md, report.html, source.json (the command, commit, build and libraries) and the PNGs."
        ),
    ] = Path("logs/reproduce"),
    train_seeds: Annotated[
        Optional[int],
        typer.Option(
            "--train-seeds",
            min=1,
            max=100,
            help="Trainings (seeds 1..N) behind Figure 3 (default: 5, the full "
            "reproduction's; 2 with --quick); the report says when it differs.",
        ),
    ] = None,
    jobs: JobsOption = None,
    scheduler: SchedulerOption = None,
    pilot: Annotated[
        Optional[list[str]],
        typer.Option(
            "--pilot",
            metavar="NAME",
            help=f"Also run this pilot (an installed plugin's name, {PLUGIN_FORMS}) beside the "
            "paper's two in Table 1, the rooms of the paper's size and the trap rooms; repeatable.",
        ),
    ] = None,
) -> None:
    """Both papers' experiments under their conditions, and a report of navcli's numbers with 95 %
    intervals beside the papers', saying what agrees (the pilot paper's Table 1 with both
    perceptions, the two pilots on every bundled room of its size, its sensitivity, the trap rooms'
    diverting targets, the learning paper's Table 1 and Figure 3). What earlier runs left in --out is kept: the same command resumes."""
    from ..experiments.executor import workers
    from ..experiments.reproduce import FULL, QUICK, REPORT_FILES, SECTIONS, reproduce as run_all_sections

    if which not in (*SECTIONS, "all"):
        raise refuse(f"{which!r}: expected pilots, learning or all")
    from ..config import ConfigError
    from ..plugins import registry

    extra = list(dict.fromkeys(pilot or []))
    with about("--pilot"):
        for c in registry.pilots(extra, "--pilot"):
            if c.builtin:
                raise ConfigError(f"{c.name} is one of the paper's two pilots, which reproduce runs anyway")
    out_folder(out, REPORT_FILES, force=True)  # resumed: remade from all it holds
    t0 = time.perf_counter()
    settings = QUICK if quick else FULL
    if train_seeds is not None:
        settings = dataclasses.replace(settings, train_seeds=train_seeds)
    with on_stop(f"what finished is kept in {out}; run the same command again to go on"):
        files = run_all_sections(
            which,
            out,
            settings=settings,
            jobs=workers(jobs),
            scheduler=scheduler,
            echo=say,
            pilots=tuple(extra),
        )
    typer.echo(without_mark(files["markdown"].read_text()))
    typer.echo(f"wrote {', '.join(str(f) for f in files.values())} in {time.perf_counter() - t0:.0f} s")
    import json

    errors = json.loads(files["source"].read_text())["errored_runs"]
    if errors:
        say(f"{errors} runs ended in error: the report counts them, says why, and judges no set that holds one")
        raise typer.Exit(EXIT_RUNS_ERRORED)
