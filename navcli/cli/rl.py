"""navcli's learners beyond the learning paper: ``train-rl`` (a Stable-Baselines3 agent through the
Gymnasium environment) and ``tune-softmax`` (the softmax policy's temperature, on training rooms)."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from .common import MAX_SEED, SCENARIO_HELP, ForceOption, JobsOption, ParamOption, app, build_spec, progress_bar
from .errors import about, refuse


@app.command("train-rl")
def train_rl(
    scenario: Annotated[
        Path, typer.Argument(metavar="SCENARIO", help=SCENARIO_HELP + " (the bundled agent's: landmarks-12).")
    ],
    agent: Annotated[str, typer.Option(help="The Stable-Baselines3 agent: ppo or dqn.")] = "ppo",
    steps: Annotated[
        int, typer.Option(min=1, max=100_000_000, help="Environment steps (actions) to train for.")
    ] = 100_000,
    seed: Annotated[
        int, typer.Option(min=0, max=2**32 - 1, help="Seed of everything: the starts, the network, the library.")
    ] = 1,
    out: Annotated[
        Optional[Path],
        typer.Option(
            help="navcli model file (.npz, with FILE.json and Stable-Baselines3's FILE.zip beside it; default: "
            "logs/<scenario>/<agent>-seed<N>.npz)."
        ),
    ] = None,
    param: ParamOption = None,
    force: ForceOption = False,
) -> None:
    """Train a Stable-Baselines3 agent (PPO or DQN, the library's defaults) through navcli's
    Gymnasium environment on the Learning Agent's task: the same belief states, actions and
    rewards. Needs the optional extra: pip install 'navcli[rl]'. Writes the agent's policy as a
    navcli model (run it with --navigation learned:FILE, or as the ppo plugin when bundled)."""
    from ..rl.sb3 import AGENTS, out_paths, require_sb3

    if agent not in AGENTS:
        raise refuse(f"--agent: unknown {agent!r} (expected one of: {', '.join(AGENTS)})")
    require_sb3()  # before any work: the extra is there
    spec = build_spec(scenario, param, task=True)
    from ..learning.features import check_bounds
    from ..outputs import check_file
    from ..rl.sb3 import train

    with about("--param"):
        check_bounds(spec.params.learning)
    out = out or Path("logs") / spec.scenario.name / f"{agent}-seed{seed}.npz"
    npz, meta, archive = out_paths(out)
    with about("--out"):
        check_file(npz, (".npz",), "model file", overwrite=force)
        check_file(meta, (".json",), ".json file beside the model", overwrite=force)
        check_file(archive, (".zip",), "Stable-Baselines3 archive beside the model", overwrite=force)
    t0 = time.perf_counter()
    res = train(spec, agent=agent, steps=steps, seed=seed, out=npz)
    typer.echo(
        f"{agent} trained {steps} steps ({res.episodes} episodes: {res.outcomes}) in "
        f"{time.perf_counter() - t0:.0f} s ({res.train_s:.0f} s learning)"
    )
    typer.echo(f"wrote {npz}, {meta} and {archive}")


@app.command("tune-softmax")
def tune_softmax(
    scenarios: Annotated[
        list[Path],
        typer.Argument(
            metavar="SCENARIO...",
            help=SCENARIO_HELP + "; training rooms only (the bundled choice: landmarks-12 landmarks-hall).",
        ),
    ],
    temperature: Annotated[
        Optional[list[float]],
        typer.Option(
            "--temperature",
            min=0.0,
            max=1e6,
            help="A temperature of the grid (repeatable; default 0.5 1 2 4 8 16).",
        ),
    ] = None,
    starts: Annotated[int, typer.Option(min=1, max=10_000, help="Seeded random starts per room.")] = 50,
    seed: Annotated[
        int, typer.Option(min=0, max=MAX_SEED, help="Seed of the starts (the evaluations' is 99: keep it apart).")
    ] = 1,
    out: Annotated[
        Path,
        typer.Option(
            help="The choice and the grid's numbers (JSON; navcli/learning/models/softmax.json is the bundled one)."
        ),
    ] = Path("logs/softmax.json"),
    jobs: JobsOption = None,
    param: ParamOption = None,
    force: ForceOption = False,
) -> None:
    """Choose the softmax policy's temperature (softmax.temperature) on training rooms: every
    temperature of the grid from the same seeded starts of each room; the best mean reward per
    trial wins. Never give a held-out room: the choice is tested there."""
    import json

    from ..outputs import check_file, write_text
    from ..rl.temperature import GRID, choose
    from .common import executor_for

    grid = tuple(sorted(set(temperature or GRID)))
    if not all(math.isfinite(t) for t in grid):
        raise refuse(f"--temperature: {', '.join(map(str, grid))}: a temperature is a finite number >= 0")
    with about("--out"):
        check_file(out, (".json",), "JSON file", overwrite=force)
    specs = [build_spec(s, param, task=True) for s in scenarios]
    names = [s.scenario.name for s in specs]
    if len(set(names)) < len(names):
        raise refuse(f"SCENARIO: a room is named twice: {', '.join(names)}")
    t0 = time.perf_counter()
    with progress_bar() as bar:
        task = bar.add_task(f"{len(grid)} temperatures x {len(specs)} rooms", total=len(grid) * len(specs))
        with executor_for(jobs, None) as ex:
            choice = choose(specs, grid, starts, seed, ex, lambda: bar.advance(task))
    typer.echo(f"{len(grid) * len(specs) * starts} trials in {time.perf_counter() - t0:.0f} s")
    typer.echo(f"temperature  successes/{starts * len(specs)}  reward/trial (+- s.e.)")
    for r in choice["grid"]:
        typer.echo(f"{r['temperature']:11g}  {r['successes']:12d}  {r['reward']:8.1f} (+- {r['reward_sem'] or 0:.1f})")
    typer.echo(f"chosen: temperature {choice['temperature']:g}")
    write_text(out, json.dumps(choice, indent=1) + "\n")
    typer.echo(f"wrote {out}")
