"""``navcli tune``: parameter values that maximise an objective over scenarios and seeds.

A *trial* (an individual, for the GA) is one point of the parameter space, evaluated by running
every scenario with the same ``seeds`` seeds (derived as ``compare``'s, so every trial meets the
same situations: common random numbers), without logs, on one worker. Trials are evaluated in
batches on the execution layer (:mod:`.executor`): the local pool or a Dask cluster.

Optimisers are well-kept libraries, not ours:

* ``tpe`` (default) and ``cmaes``: Optuna's ``TPESampler`` and ``CmaEsSampler``, driven by
  ask-and-tell from this process, with the study in a journal file (``--storage``) so an
  interrupted study resumes: finished trials are kept, trials left running are evaluated again.
  Only this process touches the storage; the workers only run missions, so a cluster needs no
  shared database.
* ``ga``: the thesis' generational genetic algorithm, DEAP's ``algorithms.eaSimple`` (each
  generation replaces the population by its offspring; Optuna's samplers keep the best of parents
  and children, which is not that algorithm), with the thesis' settings as defaults: population
  20, 100 generations, crossover probability 0.8, mutation probability 0.1, real values bounded by
  the given ranges. Our design where the thesis is silent: simulated binary crossover and
  polynomial mutation, both bounded (eta 20), each gene mutated with probability 1/n, tournament
  selection of size 3. Its ``toolbox.map`` is the executor; individuals travel as plain lists
  (DEAP's classes are made at run time with ``creator`` and do not unpickle on Dask workers). The
  population is checkpointed to ``--storage`` (JSON) after every generation, so it resumes too.

Objectives (all maximised; see :func:`objective`): ``fitness``, ``success``, ``time``.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import random
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from .. import NavcliError
from ..config import RunSpec
from ..analysis.files import write_csv
from ..outputs import atomic, write_text
from ..params import CONTROL_DT, Params, ParamError, parse_override
from ..scenario import PILOT_BLOCK
from .compare import reruns
from .executor import map_ordered, require

ALGORITHMS = ("tpe", "cmaes", "ga")
OBJECTIVES = ("fitness", "success", "time")
DEFAULT_RANGE = (0.0, 5.0)
"""A parameter named without a range is tuned in [0, 5] (the thesis' bound on its real values)."""


@dataclass(frozen=True)
class GASettings:
    """The thesis' GA settings (its defaults)."""

    population: int = 20
    generations: int = 100
    crossover: float = 0.8  # probability that two paired individuals mate (eaSimple's cxpb)
    mutation: float = 0.1  # probability that an individual is mutated (eaSimple's mutpb)


@dataclass(frozen=True)
class TuneProblem:
    """What a trial evaluates: the base configurations (one per scenario), the tuned parameters
    and their ranges, the seeds per scenario and the objective. Shipped whole to the workers."""

    bases: tuple[RunSpec, ...]
    names: tuple[str, ...]
    low: tuple[float, ...]
    high: tuple[float, ...]
    seeds: int
    objective: str

    def key(self) -> str:
        """A short hash of the problem: a study or checkpoint of another problem is never resumed."""
        blob = json.dumps([[b.run_id for b in self.bases], self.names, self.low, self.high, self.seeds, self.objective])
        return hashlib.sha256(blob.encode()).hexdigest()[:12]


def parse_range(item: str, params: Params | None = None) -> tuple[str, float, float] | tuple[str, Any]:
    """``"pilot.K=0:30"`` -> ``("pilot.K", 0.0, 30.0)`` (tuned); ``"pilot.K"`` -> tuned in
    :data:`DEFAULT_RANGE`; ``"pilot.K=30"`` -> ``("pilot.K", 30.0)`` (fixed for every trial, any
    value ``--param`` takes). Bounds and values are checked against the parameter's own range in
    ``params`` (navcli's, and a plugin pilot's own when given); whole-number, switch and list
    parameters cannot be tuned.

    >>> parse_range("pilot.K=0:30"), parse_range("navigation.alpha")
    (('pilot.K', 0.0, 30.0), ('navigation.alpha', 0.0, 5.0))
    """
    params = params or Params()
    name, sep, value = (s.strip() for s in item.partition("="))
    if not sep:
        lo, hi = DEFAULT_RANGE
    elif ":" not in value:
        name, v = parse_override(item)
        params.override({name: v})
        return name, v
    else:
        a, _, b = value.partition(":")
        lo, hi = _number(item, a), _number(item, b)
    flat = params.flat()
    if name not in flat:
        params.override({name: lo})  # raises: unknown parameter, with a suggestion
    if not isinstance(flat[name], float):
        raise ParamError(f"{name} is a whole number, a switch or a list: it cannot be tuned")
    params.override({name: lo})
    params.override({name: hi})
    if not lo < hi:
        raise ParamError(f"{item!r}: expected LOW:HIGH with LOW below HIGH")
    return name, lo, hi


def _number(item: str, s: str) -> float:
    try:
        return float(s)
    except ValueError:
        raise ParamError(f"{item!r}: {s.strip()!r} is not a number (expected NAME=LOW:HIGH)") from None


def objective(name: str, runs: Sequence[tuple[dict, float]]) -> float:
    """The objective ``name`` of a trial's runs, each ``(summary, time limit in s)``; maximised.

    * ``success``: the fraction of runs that reached the target.
    * ``time``: minus the mean time in s, a failed run counted at its time limit.
    * ``fitness`` (the thesis' combination of success rate, mean steps and their spread; its exact
      formula is lost, this is our design): ``S - (mean(u) + std(u)) / 3`` with ``S`` the success
      rate and ``u`` each run's steps as a fraction of its limit (1 for a failed run: failure is a
      step count over the threshold, as in the thesis), ``std`` over the runs (ddof 0). In
      [-2/3, 1]: success first (one more success in ten runs, +0.1, outweighs 30 % of the limit
      on mean and spread together), then fewer and steadier steps.

    >>> ok = ({"outcome": "reached", "ticks": 100, "time_s": 10.0}, 20.0)
    >>> late = ({"outcome": "timeout", "ticks": 200, "time_s": 20.0}, 20.0)
    >>> objective("success", [ok, late]), objective("time", [ok, late])
    (0.5, -15.0)
    >>> round(objective("fitness", [ok, late]), 4)  # u = 0.5, 1: S - (0.75 + 0.25) / 3
    0.1667
    """
    reached = [s["outcome"] == "reached" for s, _ in runs]
    S = sum(reached) / len(runs)
    if name == "success":
        return S
    if name == "time":
        return -sum(s["time_s"] if ok else lim for (s, lim), ok in zip(runs, reached)) / len(runs)
    u = [s["ticks"] / round(lim / CONTROL_DT) if ok else 1.0 for (s, lim), ok in zip(runs, reached)]
    mean = sum(u) / len(u)
    std = math.sqrt(sum((x - mean) ** 2 for x in u) / len(u))
    return S - (mean + std) / 3


def evaluate(problem: TuneProblem, values: Sequence[float]) -> dict[str, Any]:
    """Run one trial (in a worker): every scenario with every seed at ``values``. A run that raises
    counts as a failure at its time limit (``errors`` counts them)."""
    from ..runner import run_mission

    overrides = dict(zip(problem.names, map(float, values)))
    runs, errors = [], 0
    for base in problem.bases:
        for spec in reruns(base, overrides, problem.seeds):
            try:
                summary = run_mission(spec, record=False).summary
            except Exception:
                errors += 1
                summary = {"outcome": "error", "ticks": 0, "time_s": spec.time_limit}
            runs.append((summary, spec.time_limit))
    reached = [s for s, _ in runs if s["outcome"] == "reached"]
    return {
        "objective": objective(problem.objective, runs),
        "success": len(reached) / len(runs),
        "mean_time_s": sum(s["time_s"] for s in reached) / len(reached) if reached else float("nan"),
        "runs": len(runs),
        "errors": errors,
        **overrides,
    }


# --- Optuna: TPE and CMA-ES ------------------------------------------------------------------
MAX_CHECKPOINT_BYTES = 256 * 2**20
"""The largest GA checkpoint read (a history of about a million trials)."""

RESULT_FILES = ("history.csv", "best.json", "best.yaml", "objective.png")
"""What ``navcli tune`` writes into its folder (besides the study file)."""


class CheckpointError(NavcliError):
    """A ``--storage`` file that is not a usable checkpoint (the message names it and why)."""


def tune_optuna(
    problem: TuneProblem,
    ex: Executor,
    *,
    algorithm: str,
    trials: int,
    storage: Path,
    batch: int,
    seed: int = 1,
    on_trial: Callable[[dict], None] | None = None,
) -> list[dict]:
    """Run the study until it holds ``trials`` finished trials; ``batch`` trials are asked and
    evaluated at once (the workers' number). Returns the history, one dict per finished trial."""
    optuna = require("optuna", "navcli tune")
    if algorithm == "cmaes":
        require("cmaes", "navcli tune --algorithm cmaes")
    from optuna.distributions import FloatDistribution
    from optuna.storages.journal import JournalFileBackend, JournalStorage
    from optuna.trial import TrialState

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    sampler = (
        optuna.samplers.CmaEsSampler(seed=seed)
        if algorithm == "cmaes"
        else optuna.samplers.TPESampler(seed=seed, constant_liar=batch > 1)
    )
    storage.parent.mkdir(parents=True, exist_ok=True)
    _check_journal(storage)
    try:  # the journal is replayed here: a damaged one fails inside Optuna, in its own ways
        study = optuna.create_study(
            study_name=f"navcli-{problem.key()}",
            direction="maximize",
            sampler=sampler,
            load_if_exists=True,
            storage=JournalStorage(JournalFileBackend(str(storage))),
        )
    except Exception as e:
        raise CheckpointError(f"{storage}: not a usable Optuna journal ({type(e).__name__}: {e})"[:300]) from None
    for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):  # left by an interrupted run
        study.enqueue_trial(t.params)
        study.tell(t.number, state=TrialState.FAIL)
    space = {n: FloatDistribution(lo, hi) for n, lo, hi in zip(problem.names, problem.low, problem.high)}
    fn = functools.partial(evaluate, problem)

    def finished() -> list:
        return study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))

    while (left := trials - len(finished())) > 0:
        asked = [study.ask(space) for _ in range(min(batch, left))]
        try:
            results = map_ordered(fn, [[t.params[n] for n in problem.names] for t in asked], ex)
        except BaseException:
            for t in asked:  # evaluated again on resume
                study.enqueue_trial(t.params)
                study.tell(t, state=TrialState.FAIL)
            raise
        for t, r in zip(asked, results):
            for k in ("success", "mean_time_s", "runs", "errors"):
                t.set_user_attr(k, r[k])
            study.tell(t, r["objective"])
            if on_trial:
                on_trial(r)
    return [
        {
            "trial": i,
            "objective": t.value,
            **{k: t.user_attrs[k] for k in ("success", "mean_time_s", "runs", "errors")},
            **t.params,
        }
        for i, t in enumerate(finished())
    ]


# --- DEAP: the thesis' generational GA --------------------------------------------------------
def _creator():
    from deap import base, creator

    if not hasattr(creator, "NavcliIndividual"):
        creator.create("NavcliFitness", base.Fitness, weights=(1.0,))
        creator.create("NavcliIndividual", list, fitness=creator.NavcliFitness)
    return creator


def ga_toolbox(problem: TuneProblem, ex: Executor, history: list[dict], on_trial: Callable[[dict], None] | None = None):
    """DEAP's toolbox for the thesis' GA (see the module docstring), its ``map`` on ``ex``."""
    require("deap", "navcli tune --algorithm ga")
    from deap import base, tools

    creator = _creator()
    lo, hi, n = list(problem.low), list(problem.high), len(problem.names)
    tb = base.Toolbox()
    tb.register(
        "individual",
        tools.initIterate,
        creator.NavcliIndividual,
        lambda: [random.uniform(a, b) for a, b in zip(lo, hi)],
    )
    tb.register("population", tools.initRepeat, list, tb.individual)
    tb.register("evaluate", functools.partial(evaluate, problem))
    tb.register("mate", tools.cxSimulatedBinaryBounded, eta=20.0, low=lo, up=hi)
    tb.register("mutate", tools.mutPolynomialBounded, eta=20.0, low=lo, up=hi, indpb=1.0 / n)
    tb.register("select", tools.selTournament, tournsize=3)

    def map_(fn, individuals):
        results = map_ordered(fn, [list(i) for i in individuals], ex)  # plain lists to the workers
        for r in results:
            history.append({"trial": len(history), **r})
            if on_trial:
                on_trial(r)
        return [(r["objective"],) for r in results]

    tb.register("map", map_)
    return tb


def _check_journal(storage: Path) -> None:
    """Refuse a study journal that Optuna could not replay, before Optuna opens it (it appends to
    the file as it opens it): every line a JSON record with an ``op_code``, except an unfinished
    last one (a killed run's, which Optuna skips)."""
    if not storage.exists():
        return
    size = storage.stat().st_size
    if size > MAX_CHECKPOINT_BYTES:
        raise CheckpointError(f"{storage}: {size} bytes, larger than a study's journal ({MAX_CHECKPOINT_BYTES} bytes)")
    with storage.open("rb") as f:
        for n, line in enumerate(f, 1):
            if not line.endswith(b"\n"):
                break  # unfinished: written when the run was killed
            try:
                op = json.loads(line)
            except (ValueError, RecursionError):
                op = None
            if not isinstance(op, dict) or not isinstance(op.get("op_code"), int):
                raise CheckpointError(
                    f"{storage}:{n}: not a usable Optuna journal (a line that is not one of its records)"
                )


def read_checkpoint(storage: Path) -> dict | None:
    """The GA checkpoint at ``storage`` (None if there is none), bounded and checked whole before
    any of it is used: its key, generation, genomes with their fitness, Python's
    random state and the history of trials. One of another problem or other settings is
    valid too (it is then started afresh, and replaced)."""
    if not storage.exists():
        return None
    size = storage.stat().st_size
    if size > MAX_CHECKPOINT_BYTES:
        raise CheckpointError(f"{storage}: {size} bytes, larger than a checkpoint ({MAX_CHECKPOINT_BYTES} bytes)")
    try:
        state = json.loads(storage.read_bytes())
    except (ValueError, RecursionError) as e:
        raise CheckpointError(f"{storage}: not a GA checkpoint (not JSON: {e})"[:300]) from None
    try:
        if not isinstance(state, dict) or not isinstance(state["key"], list):
            raise TypeError("not a mapping with a key")
        gen = state["generation"]
        assert isinstance(gen, int) and gen >= 0, "generation"
        assert all(
            isinstance(g, list) and all(isinstance(x, (int, float)) and math.isfinite(x) for x in g)
            for g in state["population"]
        ), "population"
        assert len(state["fitness"]) == len(state["population"]), "fitness"
        assert all(isinstance(f, (int, float)) for f in state["fitness"]), "fitness"
        v, internal, gauss = state["random"]
        assert isinstance(v, int) and isinstance(internal, list) and len(internal) == 625, "random"
        assert all(isinstance(i, dict) for i in state["history"]), "history"
    except (TypeError, KeyError, ValueError, AssertionError) as e:
        raise CheckpointError(f"{storage}: not a usable GA checkpoint ({e or type(e).__name__})") from None
    return state


def tune_ga(
    problem: TuneProblem,
    ex: Executor,
    *,
    settings: GASettings,
    storage: Path,
    seed: int = 1,
    on_trial: Callable[[dict], None] | None = None,
) -> list[dict]:
    """Run the GA for ``settings.generations`` generations, checkpointing to ``storage`` (JSON)
    after each; a checkpoint of the same problem and settings is resumed. Returns the history."""
    from deap import algorithms

    creator = _creator()
    key = [problem.key(), settings.population, settings.crossover, settings.mutation, seed]
    history: list[dict] = []
    tb = ga_toolbox(problem, ex, history, on_trial)
    state = read_checkpoint(storage)
    if state and state["key"] == key:
        history += state["history"]
        gen = state["generation"]
        pop = []
        for genes, fit in zip(state["population"], state["fitness"]):
            ind = creator.NavcliIndividual(genes)
            ind.fitness.values = (fit,)
            pop.append(ind)
        v, internal, gauss = state["random"]
        try:
            random.setstate((v, tuple(internal), gauss))
        except (TypeError, ValueError, OverflowError) as e:
            raise CheckpointError(f"{storage}: not a usable GA checkpoint (its random state: {e})") from None
    else:
        random.seed(seed)
        pop, gen = tb.population(n=settings.population), 0
    storage.parent.mkdir(parents=True, exist_ok=True)
    while gen < settings.generations:
        # one generation per call: the first call also evaluates the initial population; later
        # calls find it evaluated, so N calls are eaSimple(ngen=N), with a checkpoint between them
        pop, _ = algorithms.eaSimple(pop, tb, cxpb=settings.crossover, mutpb=settings.mutation, ngen=1, verbose=False)
        gen += 1
        write_text(
            storage,
            json.dumps(
                {
                    "key": key,
                    "generation": gen,
                    "population": [list(i) for i in pop],
                    "fitness": [i.fitness.values[0] for i in pop],
                    "random": random.getstate(),
                    "history": history,
                }
            ),
        )
    return history


# --- the results --------------------------------------------------------------------------------
def write_results(history: list[dict], problem: TuneProblem, out: Path) -> dict[str, Path]:
    """history.csv, best.json, best.yaml (a scenario ``pilot:`` block, the other parameters as
    ``--param`` lines) and objective.png (the objective of each trial and the best so far)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    out.mkdir(parents=True, exist_ok=True)
    df = pd.DataFrame(history)
    files = dict(zip(("history", "best", "block", "plot"), (out / f for f in RESULT_FILES)))
    write_csv(files["history"], df)
    best = df.loc[df["objective"].idxmax()]
    values = {n: float(best[n]) for n in problem.names}
    write_text(
        files["best"],
        json.dumps(
            {
                "objective": problem.objective,
                "value": float(best["objective"]),
                "trial": int(best["trial"]),
                "params": values,
            },
            indent=2,
        )
        + "\n",
    )
    write_text(files["block"], scenario_block(values, problem.objective, float(best["objective"])))
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(df["trial"], df["objective"], ".", alpha=0.6, label="trial")
    ax.plot(df["trial"], df["objective"].cummax(), "-", label="best so far")
    ax.set_xlabel("trial")
    ax.set_ylabel(problem.objective)
    ax.legend()
    fig.tight_layout()
    with atomic(files["plot"]) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
    return files


def scenario_block(values: dict[str, float], objective_name: str, value: float) -> str:
    """The best values as a scenario's ``pilot:`` block (it accepts K, A_t and R_min); the others
    as ``--param`` lines, since no scenario block holds them.

    >>> print(scenario_block({"pilot.K": 12.5, "navigation.alpha": 1.25}, "fitness", 0.9), end="")
    # navcli tune: best fitness 0.9
    pilot:
      K: 12.5
    # not in a scenario's blocks; give them on the command line:
    # --param navigation.alpha=1.25
    """
    lines = [f"# navcli tune: best {objective_name} {value:.6g}"]
    in_block = [n for n in values if n.startswith("pilot.") and n[len("pilot.") :] in PILOT_BLOCK]
    if in_block:
        lines += ["pilot:"] + [f"  {n[len('pilot.') :]}: {values[n]:.6g}" for n in in_block]
    rest = [f"# --param {n}={v:.6g}" for n, v in values.items() if n not in in_block]
    if rest:
        lines += ["# not in a scenario's blocks; give them on the command line:"] + rest
    return "\n".join(lines) + "\n"
