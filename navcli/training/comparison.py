"""``navcli compare policies``: the learning paper's Table 1 (section 6) from our own trials.

Every policy runs the same trials: the ``starts`` fixed random starts that ``navcli train``
evaluates on (:data:`~.training.EVAL_SEED`, :func:`~.task.random_starts`), once per run. A run
changes only the missions' seeds (sensor and odometry noise): run 0 uses the starts' own seeds,
exactly the trials of ``navcli train``'s evaluations; run ``r`` >= 1 uses
:func:`~navcli.experiments.compare.rerun_seed` of each start's seed and ``r``. A learned policy is a
fixed model file, so the runs measure how much the noise moves the numbers, not how much
learning varies between training seeds (our design: training is a separate command).

- ``learned[:FILE]``, ``hand-coded`` and the baselines ``all-MB``, ``all-MLL`` ... (one action in
  every state) choose one of the five actions per belief state; their
  trials are :func:`~.training.run_trial`'s, the evaluations' own (an action lasts ``action_s``;
  a trial ends at the target, after ``max_actions`` actions, at the scenario's time limit, or when
  the Rescuer gives up). A model made by Q-learning is a table like any other.
- ``random`` and the **sampled** policies (a Navigation policy plugin that draws the Learning
  Agent's actions from a table of probabilities, :mod:`navcli.learning.sampled`: ``softmax``,
  ``ppo``) run the same trials, each trial's draws from a generator seeded by its start's seed
  (the same trial, the same draws); a sampled policy runs with its parameters' defaults.
- ``agents`` (the hand-tuned bidding agents) choose no actions: their trial is a mission from
  the same start with the same seed, cut ``max_actions`` x ``action_s`` simulated seconds after
  the Rescuer's initial sweep (the most a trial of 500 one-second actions can last; or at the
  scenario's limit if sooner); it has successes and a time per trial, but no reward, action count
  or actions of each kind (n/a in the table).

Each (policy, run) is one job of the execution layer (:mod:`navcli.experiments.executor`) and one
JSON file of its per-trial records, ``<out>/runs/<policy>-run<r>-<key>.json``; ``key`` is a sha256
of everything that decides those trials (the run configuration's ``run_id`` with the policy's
kind, the policy's action table, the run, the starts with their seeds), so a comparison resumes
where it stopped and never reuses the trials of another configuration.

The table: per policy, the successes out of the starts (the mean over the runs) with the Wilson
95 % interval of the success rate over every trial, and the means per trial of reward, actions,
each action and simulated time with a percentile bootstrap 95 % interval that resamples the
starts (:func:`policy_table`); with fewer than :data:`~navcli.analysis.stats.MIN_SAMPLE` starts,
a note says the intervals are too uncertain to trust.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import NavcliError
from ..analysis.files import file_name, write_csv, write_markdown
from ..config import RunSpec
from ..learning.actions import ACTIONS
from .task import Start, random_starts, spec_at

CONSTANT = tuple(f"all-{a}" for a in ACTIONS)  # one action in every state: the baselines all-MB, all-MLL ...
POLICY_KINDS = ("learned", "hand-coded", "agents", "plugin", "sampled") + CONSTANT
DEFAULT_POLICIES = ("learned", "hand-coded", "random", "agents")
METRICS = ("successes", "reward", "actions") + ACTIONS + ("time_s",)
"""The table's columns: successes out of the starts, then means per trial."""

TABLE_FILES = ("policies.csv", "policies.md", "trials.csv")
"""What ``compare policies`` writes into its folder, besides ``runs/`` and :data:`SOURCE_FILE`."""
SOURCE_FILE = "source.json"
"""The comparison's provenance (:func:`navcli.experiments.provenance.record`: its command line, commit,
build and libraries), so that a report that reads its trials (``navcli reproduce``'s optional rows)
can say which command made them."""


class PolicyError(NavcliError):
    """A ``--policy`` that is not one of ``learned[:FILE]``, ``hand-coded``, ``agents``."""


@dataclass(frozen=True)
class Policy:
    """One row of the table: ``label`` as given (``learned:models/q.npz``; a plugin's ``NAME`` of
    ``NAME=module:Class``), its ``kind``, its action per belief state (int8 bytes; None for
    ``agents``) and what it is (``about``)."""

    label: str
    kind: str
    table: bytes | None
    about: str
    value: str = ""  # the --policy value, where it goes by another name (a plugin's NAME=module:Class)
    probabilities: bytes | None = None  # a sampled policy's (float64, a row of actions per belief state)

    @property
    def navigation(self) -> str:
        """The ``--navigation`` value that runs it (a plugin's)."""
        return self.value or self.label

    def actions(self) -> np.ndarray:
        """The action per belief state (not for ``agents``, which has none)."""
        if self.table is None:
            raise ValueError(f"the policy {self.label} has no table of actions")
        return np.frombuffer(self.table, dtype=np.int8).astype(np.int64)


def parse_policy(text: str) -> Policy:
    """The policy named by a ``--policy`` value; raises :class:`PolicyError`, or
    :class:`~.model_file.ModelError` for a model file that cannot be used. A Navigation policy
    plugin (or ``agents+NAME``) runs as ``agents`` does: missions, no actions."""
    from ..plugins import UnknownPlugin, navigation
    from ..plugins.names import navigation_label

    if text == "random":
        return Policy(text, "random", None, "a uniform random action at every choice (seeded by each trial's start)")
    if text in CONSTANT:
        from ..learning.features import N_STATES

        action = ACTIONS.index(text[4:])
        return Policy(text, text, np.full(N_STATES, action, dtype=np.int8).tobytes(), f"{text[4:]} in every state")
    try:
        found = navigation(text)
    except UnknownPlugin as e:
        raise PolicyError(
            f"unknown policy {text!r} (expected learned, learned:FILE, hand-coded, agents, random, one action "
            f"everywhere: {', '.join(CONSTANT)}, or a Navigation policy plugin: {e})"
        ) from None
    if len(found) == 1 and hasattr(found[0].cls, "probabilities"):  # navcli.learning.sampled: draws actions
        cls = found[0].cls
        p = cls.probabilities(None)
        return Policy(navigation_label(text), "sampled", None, cls.describe(None), text, p.astype(np.float64).tobytes())
    if any(not c.builtin for c in found):
        return Policy(
            navigation_label(text),
            "plugin",
            None,
            " and ".join(c.label for c in found if not c.builtin)
            + (" beside the bidding agents" if len(found) > 1 else ""),
            text,
        )
    kind, file = found[0].name.partition(":")[0], found[0].argument
    if kind == "agents":
        return Policy(text, kind, None, "the Navigation system's bidding agents")
    if kind == "hand-coded":
        from .trainer import hand_coded_table

        return Policy(text, kind, hand_coded_table().astype(np.int8).tobytes(), "section 6's hand-coded policy")
    from ..learning import model_file

    arrays, meta = model_file.load(Path(file) if file else model_file.BUNDLED)
    about = (
        f"{'the bundled model: ' if not file else ''}{meta.get('algorithm', 'unknown algorithm')}, "
        f"{meta.get('trials', '?')} trials on {meta.get('scenario', '?')}, seed {meta.get('seed', '?')}"
    )
    return Policy(text, kind, arrays["policy"].astype(np.int8).tobytes(), about)


@dataclass(frozen=True)
class Job:
    """The trials of one policy in one run (a whole configuration, carried to the worker)."""

    spec: RunSpec
    policy: Policy
    run: int
    starts: tuple[Start, ...]
    key: str
    path: str


def run_starts(starts: list[Start], run: int) -> tuple[Start, ...]:
    """The starts of run ``run``: the same places and headings, the seeds of the run."""
    from ..experiments.compare import rerun_seed

    if run == 0:
        return tuple(starts)
    return tuple(dataclasses.replace(s, seed=rerun_seed(s.seed, run)) for s in starts)


def job_key(spec: RunSpec, policy: Policy, run: int, starts: tuple[Start, ...]) -> str:
    """sha256 (hex) of what decides a job's trials (see the module docstring)."""
    table = hashlib.sha256(policy.table).hexdigest() if policy.table is not None else None
    if policy.probabilities is not None:  # the draws' table and stream
        from ..learning.sampled import SAMPLE_STREAM

        table = f"sampled {hashlib.sha256(policy.probabilities).hexdigest()} {SAMPLE_STREAM}"
    if policy.kind == "random":  # the Learning Agent told each action, as a table's, and the draws' stream
        from .trainer import RANDOM_STREAM

        nav, table = "learned", f"random {RANDOM_STREAM}"
    else:
        nav = (
            "learned"
            if policy.kind in CONSTANT
            else policy.navigation
            if policy.kind in ("plugin", "sampled")
            else policy.kind
        )
    # (a constant table is a table like a learned one's, in the key too; a plugin's identity is in the run id)
    blob = json.dumps(
        [spec.replace(navigation=nav).run_id, table, run, [dataclasses.asdict(s) for s in starts]], sort_keys=True
    )
    return hashlib.sha256(blob.encode()).hexdigest()


def plan(spec: RunSpec, policies: list[Policy], runs: int, starts: int, out: Path) -> list[Job]:
    """Every (policy, run) of a comparison, run by run (so that an interrupted comparison has
    whole runs of every policy)."""
    from .trainer import EVAL_SEED

    base = random_starts(spec, starts, EVAL_SEED)
    jobs = []
    for r in range(runs):
        st = run_starts(base, r)
        for p in policies:
            key = job_key(spec, p, r, st)
            jobs.append(
                Job(spec, p, r, st, key, str(out / "runs" / f"{file_name(p.label, 'policy')}-run{r}-{key[:12]}.json"))
            )
    return jobs


def done_trials(job: Job) -> list[dict] | None:
    """The trials of ``job`` already on disk (same key, every start), else None."""
    try:
        d = json.loads(Path(job.path).read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(d, dict) or d.get("key") != job.key or len(d.get("trials", ())) != len(job.starts):
        return None
    return d["trials"]


def _record(
    i: int,
    start: Start,
    outcome: str,
    time_s: float,
    actions: int | None = None,
    reward: float | None = None,
    counts: tuple[int, ...] | None = None,
) -> dict:
    rec = {
        "start": i,
        "x": start.x,
        "y": start.y,
        "heading": start.heading,
        "seed": start.seed,
        "outcome": outcome,
        "success": outcome == "reached",
        "time_s": time_s,
        "actions": actions,
        "reward": reward,
    }
    rec.update({name: (counts[k] if counts is not None else None) for k, name in enumerate(ACTIONS)})
    return rec


def run_trials(job: Job) -> list[dict]:
    """The trials of ``job``, one record per start (in this process)."""
    spec, p = job.spec, job.spec.params.learning
    out = []
    if job.policy.table is None and job.policy.kind not in (
        "random",
        "sampled",
    ):  # the bidding agents, or a plugin's: missions
        from ..mission import Mission
        from ..runner import advance

        nav = job.policy.navigation if job.policy.kind == "plugin" else "agents"
        base = spec.replace(navigation=nav)  # the same task as the policies' (task.py)
        for i, st in enumerate(job.starts):
            m = Mission(spec_at(base, st), snapshots=False, explain=False)
            advance(m, until=lambda m: m.ticks > 0 and not m.navigation.sweeping)  # as NavigationTask.reset
            end = m.time + p.max_actions * p.action_s  # the learned policies' time after their sweep, at most
            advance(m, until=_past(end))
            out.append(_record(i, st, m.outcome or "timeout", m.time))
        return out
    from .task import NavigationTask
    from ..learning.learning_agent import table_policy
    from .trainer import run_trial

    task = NavigationTask(spec)
    table = None if job.policy.table is None else table_policy(job.policy.actions())
    for i, st in enumerate(job.starts):
        r = run_trial(task, st, table or _chooser(job.policy, st))
        assert task.mission is not None  # the trial's
        out.append(_record(i, st, r.outcome, task.mission.time, r.actions, r.reward, r.counts))
    return out


def _chooser(policy: Policy, start: Start) -> Callable[[int], int]:
    """The uniform random policy's, or a sampled policy's draws, of the trial from ``start``."""
    from .trainer import random_policy

    if policy.probabilities is None:
        return random_policy(start)
    from ..learning.features import N_STATES
    from ..learning.sampled import trial_sampler

    p = np.frombuffer(policy.probabilities, dtype=np.float64).reshape(N_STATES, len(ACTIONS))
    return trial_sampler(p, start.seed)


def _past(end: float) -> Callable[[Any], bool]:
    """The test that a mission's time has reached ``end`` (s)."""
    return lambda m: m.time >= end - 1e-9


def run_job(job: Job) -> dict:
    """A job's result (in a worker process, or in this one); never raises: ``error`` says what went wrong."""
    try:
        trials = run_trials(job)
    except Exception as e:
        return {"key": job.key, "error": f"{type(e).__name__}: {e}"}
    return {
        "key": job.key,
        "policy": job.policy.label,
        "about": job.policy.about,
        "run": job.run,
        "scenario": job.spec.scenario.name,
        "scenario_sha256": job.spec.scenario.sha256,
        "trials": trials,
    }


@dataclass(frozen=True)
class Result:
    job: Job
    trials: list[dict] | None  # None: the job raised
    ran: bool  # False: its trials were on disk already
    error: str = ""


def run_all(jobs: list[Job], ex, on_done: Callable[[Result], None] | None = None) -> list[Result]:
    """Run the jobs whose trials are not on disk on the executor ``ex`` (:mod:`navcli.experiments.executor`),
    writing each job's JSON as it finishes; results in the jobs' order. Ctrl-C or SIGTERM stops
    the workers and is re-raised; finished jobs stay on disk."""
    from ..experiments.executor import run_each

    results: dict[int, Result] = {}

    def keep(i: int, r: Result) -> None:
        results[i] = r
        if on_done:
            on_done(r)

    todo = []
    for i, j in enumerate(jobs):
        trials = done_trials(j)
        if trials is None:
            todo.append(i)
        else:
            keep(i, Result(j, trials, ran=False))

    def finished(k: int, f) -> None:
        i = todo[k]
        d = f.result()
        if "error" in d:
            keep(i, Result(jobs[i], None, ran=True, error=d["error"]))
            return
        path = Path(jobs[i].path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(json.dumps(d, indent=1) + "\n")
        tmp.replace(path)
        keep(i, Result(jobs[i], d["trials"], ran=True))

    run_each(run_job, [jobs[i] for i in todo], ex, finished)
    return [results[i] for i in range(len(jobs)) if i in results]


# --- the table -----------------------------------------------------------------------------------
def trials_frame(results: list[Result]):
    """Every trial as a row (policy, run, start, outcome, reward, actions, MB ... MVT, time_s, ...)."""
    import pandas as pd

    rows = [
        {"policy": r.job.policy.label, "run": r.job.run} | t for r in results if r.trials is not None for t in r.trials
    ]
    cols = [
        "policy",
        "run",
        "start",
        "x",
        "y",
        "heading",
        "seed",
        "outcome",
        "success",
        "actions",
        "reward",
        *ACTIONS,
        "time_s",
    ]
    return pd.DataFrame(rows, columns=cols)


def per_run(trials):
    """One row per (policy, run): successes and the means per trial of the other metrics."""
    t = trials.copy()
    for c in ("actions", "reward", *ACTIONS):
        t[c] = t[c].astype(float)  # None (agents) -> NaN
    g = t.groupby(["policy", "run"], sort=False)
    out = g[["reward", "actions", *ACTIONS, "time_s"]].mean(numeric_only=False)
    out.insert(0, "successes", g["success"].sum().astype(int))
    out.insert(1, "starts", g.size())
    return out.reset_index()


def policy_table(trials, about: dict[str, str] | None = None):
    """Table 1: per policy (in order of appearance), each of :data:`METRICS` with its 95 % interval
    (``_lo``, ``_hi``), the runs and the starts. ``successes``: per run (the mean over the runs), its
    interval the Wilson interval of the success rate over every trial, scaled to the starts; the
    others: means per trial, their intervals a percentile bootstrap that resamples the starts (a
    start's trials over the runs share it; :mod:`navcli.analysis.stats`). Each stays in its range."""
    import pandas as pd

    from ..analysis.stats import bootstrap_mean, wilson_interval

    runs = per_run(trials)
    rows = []
    for policy, g in runs.groupby("policy", sort=False):
        t = trials[trials["policy"] == policy]
        starts = int(g["starts"].iloc[0])
        row: dict[str, Any] = {
            "policy": policy,
            "about": (about or {}).get(policy, ""),
            "runs": len(g),
            "starts": starts,
        }
        k, n = int(t["success"].sum()), len(t)
        lo, hi = wilson_interval(k, n)
        row["successes"], row["successes_lo"], row["successes_hi"] = (starts * x for x in (k / n, lo, hi))
        for m in METRICS[1:]:
            row[m], row[f"{m}_lo"], row[f"{m}_hi"] = bootstrap_mean(t[m].to_numpy(dtype=float), t["start"].to_numpy())
        rows.append(row)
    return pd.DataFrame(rows)


def notes(table, scenario: str = "") -> list[str]:
    """What the table cannot say: too few starts for its intervals (the words of every comparison)."""
    from ..analysis.stats import small_sample

    starts = int(table["starts"].min()) if len(table) else 0
    note = small_sample(f"the policies{' on ' + scenario if scenario else ''}", starts, "starts")
    return [note] if note else []


_DIGITS = {"successes": 1, "reward": 1, "actions": 2, "time_s": 1} | {a: 2 for a in ACTIONS}


def _cell(r, m: str) -> str:
    v, lo, hi = getattr(r, m), getattr(r, f"{m}_lo"), getattr(r, f"{m}_hi")
    if math.isnan(v):
        return "n/a"
    d = _DIGITS[m]
    return f"{v:.{d}f}" if math.isnan(lo) else f"{v:.{d}f} [{lo:.{d}f}, {hi:.{d}f}]"


def markdown(table, scenario: str = "", errors: list[str] | None = None) -> str:
    """The table as Markdown, in the paper's layout, with what the numbers are; ``errors`` (runs
    that raised, a line per policy) among its notes."""
    starts = int(table["starts"].max()) if len(table) else 0
    runs = int(table["runs"].max()) if len(table) else 0
    head = ["policy", f"successes (of {starts})", "reward / trial", "actions / trial", *ACTIONS, "time / trial (s)"]
    lines = [
        f"### Policies{' on ' + scenario if scenario else ''}",
        "",
        "| " + " | ".join(head) + " |",
        "| --- |" + " ---: |" * (len(head) - 1),
    ]
    for r in table.itertuples():
        lines.append(f"| {r.policy} | " + " | ".join(_cell(r, m) for m in METRICS) + " |")
    lines += [
        "",
        f"{runs} run(s) of the same {starts} starts (a run changes the missions' seeds). Successes per run, "
        "in brackets the Wilson 95 % interval of the success rate over every trial, in starts; reward, "
        "actions, the count of each action and time are means per trial, failures included, in brackets a "
        "bootstrap 95 % interval that resamples the starts; n/a: the policy chooses no actions.",
        "",
    ]
    lines += [f"- {r.policy}: {r.about}" for r in table.itertuples() if r.about] + [""]
    remarks = notes(table, scenario) + (errors or [])
    if remarks:
        lines += ["Notes:", ""] + [f"- {n}" for n in remarks] + [""]
    return "\n".join(lines)


def failures(results: list[Result], where: str = "") -> dict[str, str]:
    """Per policy with runs that raised: a line saying how many of its runs, and why."""
    from ..analysis.tables import why

    out = {}
    for policy in dict.fromkeys(r.job.policy.label for r in results):
        runs = [r for r in results if r.job.policy.label == policy]
        bad = [r.error for r in runs if r.trials is None]
        if bad:
            out[policy] = (
                f"{where + ', ' if where else ''}{policy}: {len(bad)} of {len(runs)} runs ended in error: {why(bad)}"
            )
    return out


def write_table(results: list[Result], out: Path, scenario: str = "") -> dict[str, Path]:
    """``policies.csv``, ``policies.md`` and ``trials.csv`` (every trial) into ``out``; runs that
    raised have no trials, and the notes say how many and why."""
    out.mkdir(parents=True, exist_ok=True)
    trials = trials_frame(results)
    about = {r.job.policy.label: r.job.policy.about for r in results if r.trials is not None}
    table = policy_table(trials, about)
    files = dict(zip(("table", "markdown", "trials"), (out / f for f in TABLE_FILES)))
    write_csv(files["table"], table)
    write_csv(files["trials"], trials)
    write_markdown(files["markdown"], markdown(table, scenario, list(failures(results).values())))
    return files


def write_source(out: Path, argv: list[str]) -> Path:
    """:data:`SOURCE_FILE` into ``out``: the provenance of a comparison made by the command ``argv``."""
    from ..experiments.provenance import record
    from ..outputs import write_text

    path = out / SOURCE_FILE
    write_text(path, json.dumps(record(argv), indent=1) + "\n")
    return path
