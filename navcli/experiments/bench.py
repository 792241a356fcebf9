"""``navcli bench``: how fast a full mission runs, against its own floor.

Each configuration runs ``repeat`` times in this process after one warm-up run; the report gives
the median real-time factor (simulated seconds per wall second), the median wall time per control
tick and its ratio to the floor (the same scenario's world alone), because figures from different
machines are not comparable but ratios measured in one session are, and a shared machine's noise
hits single runs, not medians.
"""

from __future__ import annotations

import functools
import statistics
import tempfile
from pathlib import Path
from typing import Callable

from ..config import RunSpec
from ..mission import Mission
from ..runner import run_mission


def floor(spec: RunSpec, ticks: int) -> float:
    """Wall seconds for ``ticks`` control ticks of the scenario's :class:`~navcli.world.World`
    alone, driven by a scripted wheel command (forward at top speed, weaving): pymunk, odometry
    and bumpers, no agents, no log. What the stack cannot go below."""
    import math
    import time

    from ..mission import component_generators
    from ..world import World

    rngs = component_generators(spec.seed)
    world = World(spec.scenario, rngs["odometry"], spec.params.robot, rngs["motion"])
    v = spec.params.robot.max_speed
    t0 = time.perf_counter()
    for k in range(ticks):
        world.step(v, 0.8 * math.sin(k / 15.0))
    return time.perf_counter() - t0


def benchmark(spec: RunSpec, *, repeat: int = 5, echo: Callable[[str], None] = print) -> dict[str, float]:
    """Print and return, as medians of ``repeat`` runs measured in this session: the floor (the
    world alone), the stack without logging and with logging, as real-time factors, microseconds
    per tick and ratios to the floor. (Whether a tick costs more late in a long run than early:
    :func:`long_run_benchmark`, ``navcli bench --long``.)

    The three are run in turn, ``repeat`` rounds of floor, off, on: on a shared
    machine the load drifts over seconds, and interleaving puts every configuration under the same
    drift, so their ratios hold even when the absolute figures wander."""
    results: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "bench.mcap"
        first = run_mission(spec, out=log, overwrite=True)  # warm-up: imports, caches
        ticks = max(first.summary["ticks"], 1)
        floors: list[float] = []
        runs: dict[bool, list] = {False: [], True: []}
        for _ in range(repeat):
            floors.append(floor(spec, ticks) / ticks * 1e6)
            for record in (False, True):
                runs[record].append(run_mission(spec, out=log, record=record, overwrite=True))
        floor_us = statistics.median(floors)
        sim_s = ticks * 0.1
        echo(
            f"{'floor':12s} {sim_s / (floor_us * ticks / 1e6):8.0f}x real time   {floor_us:7.0f} us/tick   "
            f"{'':11s}  (the world alone, scripted wheels, {ticks} ticks, median of {repeat})"
        )
        results["floor_us"] = floor_us
        for label, record in (("logging off", False), ("logging on", True)):
            rtf = statistics.median(r.realtime_factor for r in runs[record])
            us = statistics.median(r.wall_s / max(r.summary["ticks"], 1) * 1e6 for r in runs[record])
            s = runs[record][0].summary
            echo(
                f"{label:12s} {rtf:8.0f}x real time   {us:7.0f} us/tick   {us / floor_us:5.2f}x floor  "
                f"({s['pilot']}, {s['outcome']} after {s['time_s']:.1f} s sim, {s['ticks']} ticks, median of {repeat})"
            )
            results[label.split()[1]] = rtf
            results[f"{label.split()[1]}_us"] = us
        echo(f"logging costs {100 * (results['on_us'] / results['off_us'] - 1):.0f} % on top of the stack")
    return results


def occlusion_benchmark(sizes=(12, 18, 32, 50, 100, 200), echo: Callable[[str], None] = print) -> None:
    """Time the section 5 occlusion test (n x n) as a Python loop and with numpy, on random
    layouts of point and linear obstacles: the measurement behind ``NUMPY_FROM``."""
    import random
    import timeit

    from ..beliefs import KnownObstacle
    from ..pilot.potential_field import NUMPY_FROM, facing_loop, facing_numpy

    rnd = random.Random(1)
    echo(f"{'obstacles':>9} {'loop us':>9} {'numpy us':>9}   (best of 5 x 200 calls; numpy used from {NUMPY_FROM} on)")
    for n in sizes:
        obs = []
        for i in range(n):
            x, y = rnd.uniform(-4, 4), rnd.uniform(-4, 4)
            b = (x + rnd.uniform(-1, 1), y + rnd.uniform(-1, 1)) if i % 4 == 3 else (x, y)
            obs.append(KnownObstacle(f"o{i}", (x, y), b, 0.02 if i % 4 == 3 else 0.15))
        t = [
            min(timeit.repeat(functools.partial(f, obs), number=200, repeat=5)) / 200 * 1e6
            for f in (facing_loop, facing_numpy)
        ]
        echo(f"{n:>9} {t[0]:>9.0f} {t[1]:>9.0f}")


def objects_benchmark(
    spec: RunSpec,
    *,
    sizes: tuple[int, ...] = (50, 200),
    ticks: int = 300,
    repeat: int = 3,
    echo: Callable[[str], None] = print,
) -> None:
    """Wall time per tick (logging on, the median of ``repeat`` runs of ``ticks`` ticks) with the
    scenario's own objects (obstacles and landmarks), then with extra point obstacles scattered at
    random (seeded) where they leave the start clear, up to each of ``sizes`` objects. A warm-up
    run comes first, so no size pays the imports and caches."""
    import dataclasses
    import math
    import random

    from ..scenario import Circle, Obstacle

    sc = spec.scenario
    rnd = random.Random(7)
    base: list[Obstacle] = list(sc.obstacles)
    echo(
        f"{'objects':>8} {'us/tick':>9} {'x real time':>12}   ({spec.pilot}, {spec.perception}, logging on, "
        f"median of {repeat} runs of {ticks} ticks)"
    )
    with tempfile.TemporaryDirectory() as tmp:  # warm-up: imports and caches, paid once, not by the first size
        run_mission(spec.replace(time_limit=5.0), out=Path(tmp) / "w.mcap", overwrite=True)
    own = len(base) + len(sc.landmarks)
    for n in (own, *(n for n in sizes if n > own)):
        extra: list[Obstacle] = []
        while len(base) + len(sc.landmarks) + len(extra) < n:
            c = (rnd.uniform(0.3, sc.arena.width - 0.3), rnd.uniform(0.3, sc.arena.height - 0.3))
            if math.dist(c, sc.robot.start) > 1.0 and math.dist(c, sc.target.point) > 0.8:
                extra.append(Circle(c, 0.1))
        s = dataclasses.replace(sc, obstacles=tuple(base + extra))
        costs, factors = [], []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory() as tmp:
                r = run_mission(
                    spec.replace(scenario=s, time_limit=ticks * 0.1), out=Path(tmp) / "b.mcap", overwrite=True
                )
            costs.append(r.wall_s / max(r.summary["ticks"], 1) * 1e6)
            factors.append(r.realtime_factor)
        echo(
            f"{own + len(extra):>8} {statistics.median(costs):>9.0f} {statistics.median(factors):>11.0f}x"
            + ("   (the scenario's own)" if not extra else "")
        )


def long_run_benchmark(
    spec: RunSpec, *, minutes: float = 20.0, window_s: float = 60.0, echo: Callable[[str], None] = print
) -> float:
    """Does a tick cost more late in a long run than early? Runs ``spec`` for ``minutes`` of
    simulated time (logging on; the Rescuer never gives up, so the map keeps working), and compares
    the median wall time per tick of the last ``window_s`` with that of the first (after the
    initial sweep). Returns late / early; the Map Manager's cost must not grow with the run."""
    import time

    spec = spec.replace(time_limit=minutes * 60.0, params=spec.params.override({"navigation.gives_up": 0}))
    costs: list[tuple[float, float]] = []  # (simulated s, wall s of the tick: its step and its logging)
    last = time.perf_counter()
    mission: Mission | None = None

    def timed(m, tick) -> None:
        nonlocal last, mission
        now = time.perf_counter()
        costs.append((m.time, now - last))
        last, mission = now, m

    with tempfile.TemporaryDirectory() as tmp:
        run_mission(spec, out=Path(tmp) / "long.mcap", on_tick=timed, overwrite=True)
    m = mission
    assert m is not None, "the run made no tick"
    end = costs[-1][0]
    early = [c for t, c in costs if 10.0 <= t < 10.0 + window_s]
    late = [c for t, c in costs if t >= end - window_s]
    if not early or not late:
        echo(f"the run ended after {end:.0f} s ({m.outcome}): too short to compare")
        return float("nan")
    e, lt = statistics.median(early) * 1e6, statistics.median(late) * 1e6
    echo(
        f"{spec.scenario.name}: {m.outcome} after {end:.0f} s, {len(costs)} ticks; "
        f"median {e:.0f} us/tick in the first minute, {lt:.0f} us/tick in the last: {lt / e:.2f}x "
        f"({len(m.navigation.map.network)} beta-units, {m.navigation.diverting_targets} diverting targets)"
    )
    return lt / e


def training_benchmark(
    spec: RunSpec,
    *,
    actions: int = 300,
    trials: int = 2000,
    eval_every: int = 100,
    eval_starts: int = 99,
    workers: int = 2,
    seed: int = 1,
    echo: Callable[[str], None] = print,
) -> dict[str, float]:
    """The learning task's throughput: the Gymnasium environment's ``step`` (one action of
    the Learning Agent, ``learning.action_s`` of simulated time) in actions per wall second, over
    ``actions`` actions of a uniformly random policy (seeded; the trials' resets not counted), and a
    whole training's wall time (``navcli train``: by default the paper's 2,000 trials with an
    evaluation of 99 starts every 100, in ``workers`` processes beside the learning), measured, not
    extrapolated: a trial's length falls as the policy learns (the untrained policy's test trials
    run to the limit), so the first trials say little of the rest. ``spec`` is the task's run
    (:func:`navcli.training.task.task_spec`)."""
    import time

    import numpy as np

    from ..checks.extras import require

    require("gymnasium", "navcli bench --training")  # the Gymnasium environment's step is what is timed
    from ..envs.landmark_navigation import LandmarkNavigationEnv
    from ..learning.actions import ACTIONS
    from ..training.trainer import train

    env = LandmarkNavigationEnv(spec)
    rng = np.random.default_rng(seed)
    env.reset(seed=seed)
    env.step(0)  # warm-up: imports, caches
    env.reset()
    stepping, done, trials_seen = 0.0, 0, 1
    while done < actions:
        a = int(rng.integers(len(ACTIONS)))
        t0 = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(a)
        stepping += time.perf_counter() - t0
        done += 1
        if terminated or truncated:
            env.reset()
            trials_seen += 1
    env.close()
    per_s = actions / stepping
    action_s = spec.params.learning.action_s
    echo(
        f"{'env.step':12s} {per_s:8.1f} actions/s   {1e3 / per_s:7.1f} ms/action  ({action_s:g} s simulated each, "
        f"{per_s * action_s:.0f}x real time; {actions} actions of a random policy over {trials_seen} trials, "
        f"{spec.scenario.name})"
    )
    every = min(eval_every, trials)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        r = train(
            spec,
            trials=trials,
            eval_every=every,
            eval_starts=eval_starts,
            seed=seed,
            workers=workers,
            out=Path(tmp) / "bench.npz",
        )
        wall = time.perf_counter() - t0
    echo(
        f"{'training':12s} {trials} trials in {wall:.1f} s wall ({workers} worker{'s' if workers > 1 else ''}; "
        f"evaluation every {every} trials on {eval_starts} starts): the learning trials {r.train_s:.1f} s "
        f"(serial, {r.train_s / trials:.3f} s a trial), {r.eval_trials + r.eval_reused} evaluation trials: "
        f"{r.eval_trials} run in {r.eval_s:.1f} s of worker time, {r.eval_reused} taken over"
    )
    return {
        "actions_per_s": per_s,
        "trial_s": r.train_s / trials,
        "eval_s": r.eval_s,
        "wall_s": wall,
    }
