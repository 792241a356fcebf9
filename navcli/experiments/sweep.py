"""``navcli sweep PLAN.yaml``: many runs over parameter values, one row of a results table each.

A plan file (format version 1; paths relative to the plan file, or a bundled scenario's name)::

    version: 1
    scenarios: [../scenarios/open-arena.yaml, ../scenarios/paper-fig9.yaml]
    seeds: 5                      # runs per scenario, point and pilot; seeds derived as compare's
    pilots: [potential-field]     # optional (default: each scenario's)
    perception: vision            # optional (default: each scenario's); or a list, [vision, oracle]
    time_limit: 60                # optional, simulated s (default: each scenario's)
    params: {pilot.R_min: 0.5}    # optional: overrides for every run
    grid:                         # every combination of these values ...
      pilot.K: [10, 18, 30]
      pilot.A_t: [30, 50]
    random:                       # ... or a seeded uniform sample of points
      samples: 20
      seed: 1
      ranges: {pilot.K: [0, 50], navigation.kappa1: [0.1, 0.9]}
    points:                       # ... or a list of points (one choice at a time: {} is the defaults)
      - {}
      - {vision.routines: 0}
      - {vision.walls: known, pilot.look_cap: 0.9}

A plan has at most one of ``grid``, ``random`` and ``points``. A point of ``points`` gives every
parameter any point names, the defaults filling in, so each row says its whole point.

Parameters are named as ``--param`` names them, and every value is checked by
:meth:`~navcli.params.Params.override`; a refusal names the plan file, the line and the field, as
the scenario loader does (the same safe loader with marks; files above :data:`MAX_PLAN_BYTES`
are refused unread).

Every run is one row: the scenario, pilot, perception, seed, the parameter point (its index and a
column per overridden parameter), the summary's fields, the log path, the run id, and for a run
that raised, its error. The table is written as Parquet (and CSV on request) atomically, every
:data:`FLUSH_S` seconds, at the end and when interrupted. Rows already in the table with an outcome
(by run id) are not run again, so an interrupted sweep resumes; rows with an error are retried.
"""

from __future__ import annotations

import itertools
import json
import time
from concurrent.futures import Executor, Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from ..config import RunSpec
from ..analysis.files import write_csv
from ..outputs import atomic
from .. import NavcliError
from ..params import PERCEPTIONS, Params, ParamError
from ..plugins import registry
from ..scenario import ScenarioError, bundled, load_scenario
from ..scenario.yaml_reader import Invalid, Reader, parse_yaml, read_bounded
from .compare import reruns

MAX_PLAN_BYTES = 1 << 20
"""A plan file larger than this (1 MiB) is refused without being parsed."""
MAX_RUNS = 1_000_000
"""A plan with more runs than this is refused (a typo in a grid, not an experiment)."""
FLUSH_S = 10.0
"""Seconds between two rewrites of the results table during a sweep."""
SUMMARY_FIELDS = (
    "outcome",
    "reason",
    "time_s",
    "path_length_m",
    "collisions",
    "camera_looks",
    "ticks",
    "diverting_targets",
)
DONE = ("reached", "timeout", "blocked")
"""Outcomes of a finished run; a row with another (``error``) is run again on resume."""


class PlanError(ScenarioError):
    """A plan file was refused; ``problems`` lists every reason found (file, line, field)."""

    headline = "plan refused"


@dataclass(frozen=True)
class Plan:
    """A validated plan: base configurations (one per scenario and pilot) and parameter points."""

    source: str
    bases: tuple[RunSpec, ...]
    points: tuple[Mapping[str, float], ...]
    seeds: int

    @property
    def size(self) -> int:
        return len(self.bases) * len(self.points) * self.seeds


@dataclass(frozen=True)
class SweepRun:
    """One run of a sweep, as shipped to a worker: its whole configuration and where its log goes."""

    spec: RunSpec
    point: int
    overrides: Mapping[str, float] = field(hash=False)
    log: str | None  # None: run without a log (--no-logs)


# --- the plan file ---------------------------------------------------------------------------
def load_plan(path: str | Path | Mapping[str, Any], source: str = "<dict>") -> Plan:
    """Read and validate a plan file; raise :class:`PlanError` naming file, line and field. A
    mapping is taken as a plan file's content (its paths relative to the current folder; refusals
    name ``source``)."""
    if isinstance(path, Mapping):
        return PlanReader(source, {}).plan(dict(path), Path.cwd())
    p = Path(path)
    text = read_bounded(p, MAX_PLAN_BYTES, "a plan file", PlanError)
    try:
        data, lines = parse_yaml(text, str(p))
    except ScenarioError as e:
        raise PlanError(e.problems) from None
    return PlanReader(str(p), lines).plan(data, p.parent)


class PlanReader(Reader):
    """The scenario loader's typed reader, for plan files."""

    known = Params()
    """The parameters the plan may set: navcli's, and those of its plugin pilots once read."""

    def integer(self, v: Any, path: tuple, rng: str = "mission.seed") -> int:
        """A whole number from 0 to 2**64 - 1 (the range of a seed)."""
        return super().integer(v, path, rng)

    def number(self, v: Any, path: tuple, rng: str | None = None, positive: bool = False) -> float:
        f = super().number(v, path, rng)
        if positive and f <= 0:
            raise self.fail(path, f"must be greater than zero, found {f:g}")
        return f

    def plan(self, d: Any, root: Path) -> Plan:
        top = self._top(d)
        g = self.guard
        if g(self.integer, top["version"], ("version",)) not in (None, 1):
            self.fail(("version",), f"unsupported plan version {top['version']} (expected 1)")
        seeds = g(self.integer, top["seeds"], ("seeds",), default=1)
        if seeds == 0:
            self.fail(("seeds",), "must be at least 1")
        pilots = g(self.pilots, top.get("pilots"), ("pilots",))
        perceptions = g(self.choices, top.get("perception"), ("perception",), PERCEPTIONS, True)
        time_limit = g(lambda: self.opt(top, "time_limit", (), self.number, None, positive=True))
        fixed = g(self.overrides, top.get("params", {}), ("params",), default={})
        points = self._points(top)
        scenarios = g(self.scenarios, top["scenarios"], root, default=[])
        if self.problems:
            raise PlanError(self.problems)
        points = self._with_fixed(top, fixed, points)
        bases = self._bases(scenarios, pilots, perceptions, time_limit)
        plan = Plan(self.source, tuple(bases), tuple(points), seeds or 1)
        if not self.problems and plan.size > MAX_RUNS:
            self.fail((), f"{plan.size} runs: more than {MAX_RUNS}; split the plan")
        if self.problems:
            raise PlanError(self.problems)
        return plan

    def _top(self, d: Any) -> dict[str, Any]:
        """The plan's top-level mapping, with at most one way of giving its points."""
        try:
            top = self.mapping(
                d,
                (),
                ("version", "scenarios", "seeds"),
                ("pilots", "perception", "time_limit", "params", "grid", "random", "points"),
            )
            ways = [k for k in ("grid", "random", "points") if k in top]
            if len(ways) > 1:
                raise self.fail((ways[1],), "a plan has a grid, a random sample or a list of points, not more than one")
        except Invalid:
            raise PlanError(self.problems) from None
        return top

    def _points(self, top: dict[str, Any]) -> list[dict[str, Any]]:
        """The parameter points: a grid, a random sample or a list (one empty point without them)."""
        g = self.guard
        if "grid" in top:
            points = g(self.grid, top["grid"], default=[{}])
        elif "random" in top:
            points = g(self.random, top["random"], default=[{}])
        elif "points" in top:
            points = g(self.points, top["points"], default=[{}])
        else:
            points = [{}]
        return points

    def _with_fixed(
        self, top: dict[str, Any], fixed: dict[str, Any], points: list[dict[str, Any]]
    ) -> list[dict[str, Any]]:
        """Each point with the plan's fixed ``params`` added; a parameter given both ways is a problem."""
        both = sorted(set(fixed) & set(points[0]))
        if both:  # a grid's or sample's value would silently replace the plan's
            self.fail(
                ("params",),
                f"{', '.join(both)} set here and in {next(k for k in ('grid', 'random', 'points') if k in top)}; "
                "give each parameter in one place",
            )
            raise PlanError(self.problems)
        return [fixed | pt for pt in points]

    def _bases(
        self, scenarios: list[Any], pilots: list[str] | None, perceptions: list[str] | None, time_limit: Any
    ) -> list[RunSpec]:
        """One run specification per scenario, pilot and perception (every pilot beside the others)."""
        bases = []
        for i, sc in enumerate(scenarios):
            for pilot in pilots or (None,):
                for perception in perceptions or (None,):
                    try:
                        bases.append(
                            RunSpec.build(
                                sc, pilot=pilot, perception=perception, time_limit=time_limit, also=pilots or ()
                            )
                        )
                    except NavcliError as e:
                        self.fail(("scenarios", i), str(e))
        return bases

    def choice(self, v: Any, path: tuple, choices: tuple[str, ...]) -> str:
        if v not in choices:
            raise self.fail(path, f"expected one of: {', '.join(choices)}, found {v!r}")
        return v

    def choices(self, v: Any, path: tuple, choices: tuple[str, ...], one: bool = False) -> list[str] | None:
        """A non-empty list of distinct names among ``choices`` (``one``: or a single name)."""
        if v is None:
            return None
        if one and isinstance(v, str):
            return [self.choice(v, path, choices)]
        if not isinstance(v, list) or not v:
            raise self.fail(path, f"expected {'one of ' + ', '.join(choices) + ' or ' if one else ''}a non-empty list")
        names = [self.choice(x, path + (i,), choices) for i, x in enumerate(v)]
        twice = sorted({x for x in names if names.count(x) > 1})
        if twice:
            raise self.fail(path, f"lists {', '.join(twice)} twice (each would run the same runs again)")
        return names

    def pilots(self, v: Any, path: tuple) -> list[str] | None:
        """The plan's pilots (a non-empty list of distinct names): navcli's, installed plugins',
        ``module:Class`` or ``NAME=module:Class``, each found; their own parameters may then be set by the plan."""
        if v is None:
            return None
        names = self.choices(v, path, tuple(v) if isinstance(v, list) else ())
        for i, name in enumerate(names or []):
            try:
                c = registry.pilot(name)
            except NavcliError as e:
                raise self.fail(path + (i,), str(e)) from None
            self.known = registry.with_params(self.known, [c])
        try:
            registry.pilots(names or [], "the plan's pilots")  # by the names they go by, NAME= ones too
        except NavcliError as e:
            raise self.fail(path, str(e)) from None
        return names

    def param(self, name: Any, value: Any, path: tuple) -> float | list[float]:
        """``value`` checked as the parameter ``name`` (its type and range; a list for a list-valued
        parameter such as ``pilot.reflex_look_pans_deg``; a plugin pilot's of the plan's pilots)."""
        try:
            return self.known.override({name: value}).flat()[name]
        except ParamError as e:
            raise self.fail(path, str(e)) from None

    def overrides(self, v: Any, path: tuple) -> dict[str, float | list[float]]:
        if not isinstance(v, dict):
            raise self.fail(path, "expected a mapping of parameter names (pilot.K ...) to values")
        return {k: self.param(k, x, path + (k,)) for k, x in v.items()}

    def grid(self, v: Any) -> list[dict[str, float | list[float]]]:
        P = ("grid",)
        if not isinstance(v, dict) or not v:
            raise self.fail(P, "expected a mapping of parameter names to lists of values")
        axes: dict[str, list[float | list[float]]] = {}
        size = 1
        for name, values in v.items():
            if not isinstance(values, list) or not values:
                raise self.fail(P + (name,), "expected a non-empty list of values")
            size *= len(values)
            if size > MAX_RUNS:  # counted before a point is made
                raise self.fail(P, f"more than {MAX_RUNS} points; split the plan")
            axes[name] = [self.param(name, x, P + (name, i)) for i, x in enumerate(values)]
        return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]

    def points(self, v: Any) -> list[dict[str, Any]]:
        """A list of parameter points, each a mapping (``{}``: the defaults); every point gives each
        parameter that any point names (the defaults filling in); the same point twice is refused."""
        P = ("points",)
        if not isinstance(v, list) or not v:
            raise self.fail(P, "expected a non-empty list of parameter points ({} for the defaults)")
        if len(v) > MAX_RUNS:
            raise self.fail(P, f"more than {MAX_RUNS} points; split the plan")
        given = [self.overrides(x, P + (i,)) for i, x in enumerate(v)]
        names = list(dict.fromkeys(n for pt in given for n in pt))
        defaults = self.known.flat()  # navcli's, and the plan's plugin pilots' own
        points = [{n: pt.get(n, defaults[n]) for n in names} for pt in given]
        for i, pt in enumerate(points):
            if pt in points[:i]:
                raise self.fail(P + (i,), f"the point of points[{points.index(pt)}] again (the same runs twice)")
        return points

    def random(self, v: Any) -> list[dict[str, float]]:
        import numpy as np

        P = ("random",)
        m = self.mapping(v, P, ("samples", "ranges"), ("seed",))
        samples = self.integer(m["samples"], P + ("samples",))
        if samples == 0:
            raise self.fail(P + ("samples",), "must be at least 1")
        if samples > MAX_RUNS:  # bounded before a sample is drawn
            raise self.fail(P + ("samples",), f"{samples} samples: more than {MAX_RUNS}; split the plan")
        seed = self.opt(m, "seed", P, self.integer, 0)
        ranges = m["ranges"]
        if not isinstance(ranges, dict) or not ranges:
            raise self.fail(P + ("ranges",), "expected a mapping of parameter names to [low, high]")
        bounds = {}
        for name, r in ranges.items():
            q = P + ("ranges", name)
            if not isinstance(r, list) or len(r) != 2:
                raise self.fail(q, "expected [low, high]")
            lo, hi = (self.param(name, x, q + (i,)) for i, x in enumerate(r))
            if isinstance(lo, list) or isinstance(hi, list):
                raise self.fail(q, f"{name} is a list of numbers: give its values in a grid, not a range")
            if isinstance(lo, int):  # a sample between is no whole number, nor a switch
                raise self.fail(
                    q,
                    f"{name} is a {'switch' if isinstance(lo, bool) else 'whole number'}: give its "
                    "values in a grid, not a range",
                )
            if lo > hi:
                raise self.fail(q, f"low {lo:g} is above high {hi:g}")
            bounds[name] = (lo, hi)
        rng = np.random.default_rng(seed)
        draws = rng.uniform(
            [b[0] for b in bounds.values()], [b[1] for b in bounds.values()], size=(samples, len(bounds))
        )
        return [{name: float(x) for name, x in zip(bounds, row)} for row in draws]

    def scenarios(self, v: Any, root: Path) -> list:
        P = ("scenarios",)
        if not isinstance(v, list) or not v:
            raise self.fail(
                P, "expected a non-empty list of scenario files (relative to the plan file) or bundled scenarios' names"
            )
        out: list = []
        seen: dict[str, int] = {}
        for i, f in enumerate(v):
            name = self.text(f, P + (i,))
            try:
                sc = load_scenario(bundled.resolve(name, root))  # a bundled one by its name too
            except ScenarioError as e:
                self.fail(P + (i,), f"scenario {name} refused")
                self.problems += e.problems
                continue
            if sc.sha256 in seen:  # the same runs twice, one row each
                self.fail(
                    P + (i,),
                    f"{name} is the scenario of scenarios[{seen[sc.sha256]}] again (each would run the same runs)",
                )
                continue
            seen[sc.sha256] = i
            out.append(sc)
        return out


def plan_runs(plan: Plan, logs: Path | None) -> list[SweepRun]:
    """Every run of the plan, in a fixed order: scenario and pilot, point, seed. Seeds are derived
    from each scenario's seed as ``compare``'s are (the same seeds at every point: paired).
    ``logs`` None: runs without logs."""
    runs = []
    for base in plan.bases:
        for k, point in enumerate(plan.points):
            for spec in reruns(base, point, plan.seeds):
                runs.append(SweepRun(spec, k, dict(point), None if logs is None else str(spec.default_log_path(logs))))
    return runs


# --- running ---------------------------------------------------------------------------------
def run_row(run: SweepRun) -> dict[str, Any]:
    """Run one sweep run (in a worker) and return its row; an exception becomes the row's error."""
    from ..runner import run_mission

    spec = run.spec
    row: dict[str, Any] = {
        "scenario": spec.scenario.name,
        "scenario_sha256": spec.scenario.sha256,
        "pilot": spec.pilot_name,
        "perception": spec.perception,
        "time_limit_s": spec.time_limit,
        "seed": spec.seed,
        "point": run.point,
        **{k: json.dumps(v) if isinstance(v, list) else v for k, v in run.overrides.items()},
    }
    try:
        res = run_mission(
            spec, out=Path(run.log) if run.log else None, record=run.log is not None, overwrite=True
        )  # a run not in the table is run again
    except Exception as e:
        return (
            row
            | {f: None for f in SUMMARY_FIELDS}
            | {"outcome": "error", "log": run.log or "", "run_id": spec.run_id, "error": f"{type(e).__name__}: {e}"}
        )
    return (
        row | {f: res.summary[f] for f in SUMMARY_FIELDS} | {"log": run.log or "", "run_id": spec.run_id, "error": ""}
    )


def read_table(path: Path):
    """The results table at ``path`` (Parquet), or None if there is none yet."""
    import pandas as pd

    return pd.read_parquet(path) if path.exists() else None


def write_table(rows: list[dict], path: Path, csv: bool = False) -> None:
    """Write ``rows`` as Parquet (and CSV beside it), each through a temporary file and a rename,
    so a reader (or a resumed sweep) never sees half a table."""
    import pandas as pd

    df = pd.DataFrame(rows)
    with atomic(path) as tmp:
        df.to_parquet(tmp, index=False)
    if csv:
        write_csv(path.with_suffix(".csv"), df)


@dataclass
class SweepStats:
    total: int
    skipped: int = 0  # already in the table
    done: int = 0
    failed: int = 0  # outcome other than reached (timeout, blocked, error)
    errors: int = 0


def run_sweep(
    runs: list[SweepRun],
    table: Path,
    ex: Executor,
    *,
    csv: bool = False,
    on_row: Callable[[dict, SweepStats], None] | None = None,
) -> SweepStats:
    """Run what of ``runs`` is not yet in ``table`` on ``ex`` and write the table (see the module
    docstring). Rows are ordered as ``runs``; rows of other plans already in the table are kept
    after them. Ctrl-C/SIGTERM: the table is written with what finished, then re-raised."""
    from .executor import run_each

    old = read_table(table)
    by_id: dict[str, dict] = {}
    if old is not None:
        by_id = {r["run_id"]: r for r in old.to_dict("records")}
    todo = [r for r in runs if by_id.get(r.spec.run_id, {}).get("outcome") not in DONE]
    stats = SweepStats(len(runs), skipped=len(runs) - len(todo))
    order = {r.spec.run_id: i for i, r in enumerate(runs)}
    last = time.monotonic()

    def flush() -> None:
        rows = sorted(by_id.values(), key=lambda r: order.get(r["run_id"], len(order)))
        write_table(rows, table, csv)

    def done(i: int, f: Future) -> None:
        nonlocal last
        row = f.result()
        by_id[row["run_id"]] = row
        stats.done += 1
        stats.failed += row["outcome"] != "reached"
        stats.errors += row["outcome"] == "error"
        if on_row:
            on_row(row, stats)
        if time.monotonic() - last > FLUSH_S:
            flush()
            last = time.monotonic()

    try:
        run_each(run_row, todo, ex, done)
    finally:
        flush()
    return stats
