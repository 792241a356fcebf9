"""The columns of the tables of runs that navcli's Python API and :mod:`navcli.analysis.tables`
return, each with what it holds and its unit: declared once here, the tables built to them, the
tests holding the two together and the documentation (docs/python-api.md) listing them from here.

Times are simulated seconds; a path's length is given in metres (``path_m``) and, as the pilot
paper prints it, in centimetres (``path_cm``).
"""

from __future__ import annotations

RUN = {
    "run_id": "the run's id: a hash of its whole configuration (the same run, the same id)",
    "scenario": "the scenario's name",
    "pilot": "the pilot's name, as the run named it (a plugin's too)",
    "seed": "the run's seed",
    "scenario_sha256": "the sha256 of the scenario's text (an edited file is another scenario)",
    "perception": "`vision` or `oracle`",
    "time_limit_s": "the run's time limit (s)",
    "outcome": "how the run ended: `reached`, `timeout`, `blocked`, `interrupted` or `error`",
    "reason": "why it ended, in words (an error's message)",
    "reached": "whether the robot reached the target (`outcome == 'reached'`)",
    "time_s": "the simulated time the run took (s)",
    "path_m": "the length of the robot's path (m)",
    "path_cm": "the same in cm, as the pilot paper's Table 1 prints it",
    "collisions": "the bumper contacts",
    "camera_looks": "the images the camera took",
    "ticks": "the control ticks the run took (0.1 s each)",
    "diverting_targets": "the diverting targets the Rescuer set",
    "navigation": "the Navigation system: `agents` (the bidding agents), a policy's name",
}
"""One row per run: ``navcli.compare``'s rows, and :func:`~navcli.analysis.tables.load_runs`'s (with
:data:`RUN_FROM_LOGS`). Besides these, every parameter of the run is a column
``params.<group>.<name>`` (``params.pilot.K``), so runs can be grouped by any of them."""

RUN_FROM_LOGS = {
    "log": "the log's path",
    "poses_path_m": "the path's length recomputed from the log's poses (m), which the summary's must match",
}
"""What a row read from a log holds besides :data:`RUN` (``navcli.compare`` with ``out``;
:func:`~navcli.analysis.tables.load_runs` also keeps the poses' x, y in ``xy``, for plots)."""

PILOT_TABLE = {
    "condition": "the condition: the scenario and perception, and whatever else tells it from another "
    "of the same scenario (a time limit, a parameter's value)",
    "scenario": "the scenario's name",
    "perception": "`vision` or `oracle`",
    "pilot": "the pilot's name",
    "runs": "the runs counted (all but the interrupted)",
    "reached": "of those, the runs that reached the target",
    "failed": "the runs counted that did not reach it (errored runs among them)",
    "interrupted": "the runs stopped from outside (Ctrl-C, an observer), left out of the success rate",
    "success_rate": "`reached / runs`",
    "success_ci_low": "the success rate's Wilson 95 % interval, its low end",
    "success_ci_high": "its high end",
    "time_s_mean": "the mean time of the reached runs (s)",
    "time_s_std": "their time's standard deviation (s)",
    "path_cm_mean": "the mean path length of the reached runs (cm)",
    "path_cm_std": "their path length's standard deviation (cm)",
    "collisions_mean": "the mean bumper contacts of the reached runs",
    "collisions_std": "their standard deviation",
    "camera_looks_mean": "the mean images taken in the reached runs",
    "camera_looks_std": "their standard deviation",
    "time_fail_at_limit_mean": "the mean time of every run counted, a failed one at its time limit (s)",
    "collisions_all_mean": "the mean bumper contacts of every run counted",
    "outcome_reached": "the runs counted that reached the target",
    "outcome_blocked": "that ended blocked",
    "outcome_timeout": "that ran out of time",
    "outcome_error": "that ended in error (navcli's or a plugin's failure)",
    "diverting_targets_mean": "the mean diverting targets of every run counted",
    "diverting_0": "the runs counted that needed no diverting target",
    "diverting_1": "that needed one",
    "diverting_2": "that needed two",
    "diverting_3_or_more": "that needed three or more",
}
"""One row per condition and pilot: :func:`~navcli.analysis.tables.pilot_table` (the pilot paper's
Table 1). A mean or deviation of no run (or a deviation of one) is NaN."""

IMPROVEMENTS = {
    "condition": "the condition, as in the pilot table",
    "pilot": "the pilot compared",
    "baseline": "the pilot it is compared with",
    "metric": "`time_s` or `path_cm`",
    "pairs": "the seeds at which both reached the target",
    "improvement_pct": "`100 (baseline - pilot) / baseline` of the metric's means over the pairs (%; "
    "positive: the pilot took less)",
    "ci95_low": "its paired bootstrap 95 % interval, its low end (%)",
    "ci95_high": "its high end (%)",
    "p_value": "the paired sign-flip permutation test's two-sided p-value",
}
"""One row per condition, pilot (other than the baseline) and metric:
:func:`~navcli.analysis.tables.improvements`."""

TABLES = {
    "run": RUN,
    "run_from_logs": RUN_FROM_LOGS,
    "pilot_table": PILOT_TABLE,
    "improvements": IMPROVEMENTS,
}
"""The declarations by the name docs/python-api.md gives each (its ``navcli-columns`` blocks)."""
