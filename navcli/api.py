"""navcli from Python, for notebooks and scripts: build a run, run it, and get its data as pandas
DataFrames; run batches (a comparison of pilots, a sweep) into one DataFrame. Nothing is written
unless asked (``log=``, ``out=``), so a notebook leaves no file in its folder.

>>> import navcli
>>> r = navcli.run("scenarios/open-arena.yaml", pilot="geometric", time_limit=6.0, params={"pilot.K": 20})
>>> r.summary["outcome"], round(r.summary["time_s"], 1), len(r.bids) == r.summary["ticks"]
('timeout', 6.0, True)
>>> {"motion.pilot", "motion.navigation", "motion.winner"} <= set(r.bids.columns)
True

``r.frames`` holds a DataFrame per topic (``/robot/pose``, ``/pilot``, ``/bids``, ``/vision``,
``/navigation``, ``/events``), with the columns :func:`navcli.analysis.read_log` gives a log's;
``r.poses``, ``r.bids`` ... name them. An observer (a function of the mission and its tick) sees
every tick, and may stop the run by returning ``False``:

>>> far = lambda mission, tick: tick.pose.x < 1.0  # stop once past x = 1 m
>>> navcli.run("scenarios/open-arena.yaml", observers=[far]).summary["reason"]
'stopped by <lambda>'

Batches run on the machine's cores (``jobs``) and return one row per run, the columns
:func:`navcli.analysis.tables.pilot_table` and :func:`~navcli.analysis.tables.improvements` take:

>>> df = navcli.compare(["scenarios/open-arena.yaml"], ["potential-field", "geometric"], reruns=2, time_limit=3.0, jobs=1)
>>> sorted(df["pilot"]), set(df["outcome"])
(['geometric', 'geometric', 'potential-field', 'potential-field'], {'timeout'})
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

from .checks.arguments import COMMON, checked, either, instance, listing, names_to_values, path
from .config import RunSpec
from .log import format as fmt
from .plugins.names import BUILTIN_PILOTS
from .scenario import Scenario, load_scenario

if TYPE_CHECKING:
    import pandas as pd

    from .runner import Observer

__all__ = ["Run", "compare", "run", "spec", "sweep"]

_SCENARIO = either(path, instance(Scenario, what=""), what="a scenario: its file or bundled name, or a Scenario")
ARGUMENTS = COMMON | {
    "scenario": either(
        _SCENARIO, instance(RunSpec, what=""), what="a scenario (its file or bundled name, a Scenario) or a RunSpec"
    ),
    "scenarios": listing(_SCENARIO, "scenarios (files, bundled names or Scenarios)"),
    "plan": either(path, names_to_values, what="a plan: its file, or the same as a dict"),
}
"""Every argument of the functions below, checked at each call (:mod:`navcli.checks.arguments`)."""
api = checked(ARGUMENTS)


@api
def spec(
    scenario: str | Path | Scenario | RunSpec,
    *,
    seed: int | None = None,
    pilot: str | None = None,
    perception: str | None = None,
    navigation: str | None = None,
    time_limit: float | None = None,
    params: Mapping[str, Any] | None = None,
    also: Iterable[str] = (),
) -> RunSpec:
    """A run's whole configuration: a scenario with any of its choices replaced and parameters on
    top; a :class:`RunSpec` given is returned with those changes. Every argument is checked
    (:mod:`navcli.checks.arguments`): a wrong one raises :class:`~navcli.checks.arguments.ArgumentError`.

    Args:
        scenario: a scenario file's path, a bundled scenario's name (``navcli scenarios``), a
            loaded :class:`~navcli.scenario.Scenario`, or a :class:`RunSpec` to change.
        seed: the run's seed (default: the scenario's ``mission.seed``).
        pilot: the pilot: navcli's (``potential-field``, ``geometric``), an installed plugin's
            name, ``module:Class`` or ``path/to/file.py:Class`` (default: the scenario's);
            ``NAME=module:Class`` (or ``NAME=path/to/file.py:Class``) calls a plugin ``NAME`` in
            the summary, tables and file names (:mod:`navcli.plugins.names`).
        perception: ``vision`` or ``oracle`` (default: the scenario's).
        navigation: the Navigation system: ``agents``, a policy's name, ``agents+NAME`` (default:
            the scenario's).
        time_limit: simulated seconds before the run is declared a timeout (default: the scenario's).
        params: parameters by their dotted names (``{"pilot.K": 30}``, a plugin's
            ``{"vfh.tau_high": 25}``; ``navcli params`` lists them).
        also: other pilots' names whose parameters ``params`` may set (``compare``'s pilots).

    Returns:
        The run's configuration (:class:`~navcli.config.RunSpec`), its run id among it.

    Raises:
        navcli.NavcliError: an unknown scenario, pilot or parameter, or a value out of its range.
    """
    if isinstance(scenario, RunSpec):
        base = scenario
        sc = base.scenario
        changes = {
            k: v
            for k, v in dict(
                seed=seed,
                pilot=pilot,
                perception=perception,
                navigation=navigation,
                time_limit=None if time_limit is None else float(time_limit),
            ).items()
            if v is not None
        }
        out = base.replace(**changes)
        return out.replace(params=out.params.override(params or {})) if params else out
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    return RunSpec.build(
        sc,
        seed=seed,
        pilot=pilot,
        perception=perception,
        time_limit=time_limit,
        overrides=params,
        navigation=navigation,
        also=also,
    )


@dataclass(frozen=True)
class Run:
    """One run's results: its configuration, its summary (``/mission/summary``'s fields), its
    tables (``frames``, a DataFrame per topic), the log if one was written, and the wall time."""

    spec: RunSpec
    summary: dict[str, Any]
    frames: dict[str, pd.DataFrame] = field(repr=False)
    log: Path | None
    wall_s: float

    def __getitem__(self, topic: str) -> pd.DataFrame:
        return self.frames[topic]

    @property
    def poses(self) -> pd.DataFrame:
        """``/robot/pose``: the true pose (x, y, theta) at the start and every tick."""
        return self.frames[fmt.POSE_TOPIC]

    @property
    def odometry(self) -> pd.DataFrame:
        """``/robot/odometry``: where the robot believed it was."""
        return self.frames[fmt.ODOMETRY_TOPIC]

    @property
    def bids(self) -> pd.DataFrame:
        """``/bids``: every system's bid per resource, the winner and the actions, every tick."""
        return self.frames[fmt.BIDS_TOPIC]

    @property
    def pilot(self) -> pd.DataFrame:
        """``/pilot``: the Pilot's decision and the quantities behind it (a plugin's fields too)."""
        return self.frames[fmt.PILOT_TOPIC]

    @property
    def navigation(self) -> pd.DataFrame:
        """``/navigation``: every Navigation agent's bids, what was forwarded, the Rescuer's state."""
        return self.frames[fmt.NAVIGATION_TOPIC]

    @property
    def vision(self) -> pd.DataFrame:
        """``/vision``: the camera's pan and state, and what each image showed."""
        return self.frames[fmt.VISION_TOPIC]

    @property
    def events(self) -> pd.DataFrame:
        """``/events``: the start, bumps, reflexes, the Rescuer's decisions, the end."""
        return self.frames[fmt.EVENTS_TOPIC]


@api
def run(
    scenario: str | Path | Scenario | RunSpec,
    *,
    seed: int | None = None,
    pilot: str | None = None,
    perception: str | None = None,
    navigation: str | None = None,
    time_limit: float | None = None,
    params: Mapping[str, Any] | None = None,
    observers: Sequence[Observer] = (),
    log: str | Path | None = None,
    overwrite: bool = False,
) -> Run:
    """Run one mission, its tables kept in memory. Ctrl-C stops the run and is raised again, as an
    exception in a plugin is (its :class:`~navcli.plugins.PluginError`).

    Args:
        scenario: the scenario, or a run's configuration: as :func:`spec` takes it.
        seed: as :func:`spec` takes it.
        pilot: as :func:`spec` takes it.
        perception: as :func:`spec` takes it.
        navigation: as :func:`spec` takes it.
        time_limit: as :func:`spec` takes it (s).
        params: as :func:`spec` takes it.
        observers: functions of the mission and its tick (:class:`~navcli.mission.Tick`), told of
            every tick; one that returns ``False`` stops the run (it ends ``interrupted``).
        log: also write the run's MCAP log there (none by default).
        overwrite: replace an existing log at ``log`` (else it is refused, before the run).

    Returns:
        The run's :class:`Run`: its configuration, its summary and a DataFrame per topic.

    Raises:
        navcli.NavcliError: a wrong argument, or a log at ``log`` without ``overwrite``.
        navcli.PluginError: a plugin's fault, named as its own.
    """
    from .log.files import check_log_path
    from .log.frames import FrameRecorder
    from .runner import run_mission

    s = spec(
        scenario,
        seed=seed,
        pilot=pilot,
        perception=perception,
        navigation=navigation,
        time_limit=time_limit,
        params=params,
    )
    out = None if log is None else check_log_path(Path(log), overwrite=overwrite, ask="overwrite=True")
    frames = FrameRecorder()
    t0 = time.perf_counter()
    res = run_mission(s, out=out, record=out is not None, observers=[frames, *observers], overwrite=overwrite)
    return Run(s, res.summary, frames.frames(), res.log, time.perf_counter() - t0)


def summary_row(spec: RunSpec) -> dict[str, Any]:
    """A run without a log (in a worker): its row, as :func:`navcli.analysis.tables.load_runs`
    makes one from a log (its configuration and summary; no poses).

    Args:
        spec: the run's configuration.

    Returns:
        The run's row (:data:`navcli.analysis.columns.RUN` and its parameters).
    """
    from .analysis.tables import summary_row as row
    from .runner import run_mission

    return row(run_mission(spec, record=False).summary, spec.to_json(), spec.run_id)


@api
def compare(
    scenarios: Sequence[str | Path | Scenario],
    pilots: Sequence[str] = BUILTIN_PILOTS,
    *,
    reruns: int = 5,
    perception: str | None = None,
    navigation: str | None = None,
    time_limit: float | None = None,
    params: Mapping[str, Any] | None = None,
    jobs: int | None = None,
    out: str | Path | None = None,
) -> pd.DataFrame:
    """``navcli compare pilots`` from Python: every pilot on every scenario with the same seeds.
    ``pilot_table(df)`` and ``improvements(df, baseline)`` of :mod:`navcli.analysis.tables` make
    the paper's Table 1 from what it returns.

    Args:
        scenarios: the scenarios (files, bundled names or Scenarios); a list, even of one.
        pilots: the pilots, as :func:`spec` takes one; a list, even of one.
        reruns: the seeds each pilot runs each scenario with (the same for every pilot).
        perception: as :func:`spec` takes it, for every run.
        navigation: as :func:`spec` takes it, for every run.
        time_limit: as :func:`spec` takes it, for every run (s).
        params: as :func:`spec` takes it, for every run (a plugin's own among them).
        jobs: worker processes (default: the machine's cores).
        out: a folder for the runs' logs (a rerun keeps the complete ones, as the command does);
            without it, nothing is written.

    Returns:
        One row per run, the columns of :data:`navcli.analysis.columns.RUN` (with ``out``, also
        :data:`~navcli.analysis.columns.RUN_FROM_LOGS`) and a ``params.*`` column per parameter.
    """
    import pandas as pd

    from .experiments.compare import plan, reruns as seeded, run_on
    from .experiments.executor import executor, map_ordered, workers

    from .plugins.registry import pilots as find_pilots

    find_pilots(pilots, "pilots")  # each found, no two going by one name
    bases = [
        spec(sc, perception=perception, navigation=navigation, time_limit=time_limit, params=params, also=pilots)
        for sc in scenarios
    ]
    with executor(workers(jobs)) as ex:
        if out is None:
            specs = [s.replace(pilot=p) for base in bases for s in seeded(base, {}, reruns) for p in pilots]
            return pd.DataFrame(map_ordered(summary_row, specs, ex))
        from .analysis.tables import load_runs

        work = plan(bases, list(pilots), reruns, Path(out))
        run_on(work, ex)
    return load_runs(paths=[j.log for j in work]).drop(columns=["xy"])


@api
def sweep(
    plan: str | Path | Mapping[str, Any], *, jobs: int | None = None, out: str | Path | None = None
) -> pd.DataFrame:
    """``navcli sweep`` from Python: every scenario x parameter point x seed of a plan.

    Args:
        plan: a plan file's path, or the same as a dict (its paths relative to the current folder).
        jobs: worker processes (default: the machine's cores).
        out: a folder for the logs and ``results.parquet`` (a rerun resumes, as the command does);
            without it, nothing is written.

    Returns:
        One row per run: its swept parameters by their names (``pilot.K``), the grid's ``point``,
        the run's configuration and summary, and ``error`` (the exception of a run that raised,
        else empty).
    """
    import pandas as pd

    from .experiments.executor import executor, run_each, workers
    from .experiments.sweep import load_plan, plan_runs, read_table, run_row, run_sweep

    p = load_plan(plan) if isinstance(plan, (str, Path)) else load_plan(plan, source="<dict>")
    runs = plan_runs(p, None if out is None else Path(out))
    with executor(workers(jobs)) as ex:
        if out is None:
            rows: list[dict] = [{}] * len(runs)

            def keep(i: int, f: Any) -> None:
                rows[i] = f.result()

            run_each(run_row, runs, ex, keep)
            return pd.DataFrame(rows)
        table = Path(out) / "results.parquet"
        run_sweep(runs, table, ex)
    return read_table(table)
