"""The learning paper's experiments in ``navcli reproduce learning``: its Table 1 on four rooms
(:func:`policies`) and its Figure 3 over several trainings (:func:`figure3`), beside its numbers.

- **Table 1**: the policies of :data:`POLICIES` (the learned policy: the model bundled with
  navcli, trained on ``landmarks-12``; the hand-coded policy of section 6; a uniform random policy,
  our baseline: the paper has none, and in a task whose features alias many situations into one
  belief state a stochastic policy can beat the best deterministic one, so a learned policy is
  judged against it), from the same fixed starts, ``policy_runs`` runs (the paper's five test
  runs: only the simulator's seed differs); the bidding agents too on the training room. Optional
  rows (:data:`OPTIONAL_POLICIES`: a policy that needs more installed than navcli's tests do) are
  read from the folder their own ``navcli compare policies`` command wrote, with that command; a
  room without them says so. On the rooms of :data:`ROOMS`. Per policy: successes (the mean over
  the runs), reward, actions and each action's count per trial with 95 % intervals, how every
  trial ended (:data:`ENDINGS`: at the action limit, blocked, ...; the trials of a run that ended
  in error counted too), and the verdict against the random policy (:func:`against_random`: it
  beats random only where the 95 % intervals do not overlap). The paper's numbers stand beside the
  training room's rows, judged by the report's rule.
- **Figure 3**: ``train_seeds`` trainings of ``train_trials`` trials (seeds 1, 2, ...), run in
  parallel worker processes, each evaluated every ``eval_every`` trials on the same fixed starts;
  the figure shows each, their mean and their range, with the hand-coded and random policies'
  levels, and a table says of each training when it passed the hand-coded policy and its lowest
  evaluation after :data:`SETTLED` trials. Seed 1's training is the bundled model's (``navcli
  train landmarks-12 --trials 2000 --seed 1``): the section says whether its model file is the
  bundled one, byte for byte.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..analysis.stats import wilson_interval
from ..learning.actions import ACTIONS
from .document import Report, interval_text
from .optional_rows import EXTRA, OptionalRow, optional_text, optional_trials

TRAINING_ROOM = "landmarks-12"
ROOMS: dict[str, str] = {
    TRAINING_ROOM: "the room it was trained on",
    "landmarks-hall": "a hall whose landmarks hide the target from much of the floor; a room training never saw",
    "landmarks-drawn": "drawn at random before any run; a room training never saw",
    "landmarks-drawn-b": "drawn at random before any run and held out from all design; a room training never saw",
}
"""Table 1's rooms, with what each is."""
POLICY_ROOMS = tuple(ROOMS)
POLICIES = ("learned", "hand-coded", "random", "softmax", "ppo")
"""The policies Table 1 runs on every room (``compare policies`` names); more rows: more names."""
OPTIONAL_POLICIES: tuple[OptionalRow, ...] = (OptionalRow("sb3-ppo", "navcli[rl] (Stable-Baselines3 and torch)"),)
"""Rows of Table 1 run by their own command where what they need is installed (:mod:`.optional_rows`)."""
BASELINE = "random"
"""The policy every other is judged against (:func:`against_random`)."""
PAPER_ACTIONS = ("MB", "MOT", "MVT", "MVL", "MLL")
"""The actions in the order of the paper's Table 1."""
assert sorted(PAPER_ACTIONS) == sorted(ACTIONS)
PAPER_STARTS = 99  # the learning paper's test starts
PAPER_POLICIES: dict[str, dict[str, float]] = {
    "learned": {
        "successes": 84,
        "reward": -336,
        "actions": 49.95,
        "MB": 11.41,
        "MOT": 6.52,
        "MVT": 5.61,
        "MVL": 4.97,
        "MLL": 21.43,
    },
    "hand-coded": {
        "successes": 24,
        "reward": -858,
        "actions": 153.33,
        "MB": 4.94,
        "MOT": 18.59,
        "MVT": 0.52,
        "MVL": 121.96,
        "MLL": 7.32,
    },
}
"""The learning paper's Table 1 (section 6: 84 and 24 successes of 99 after 2,000 trials)."""
PAPER_FIGURE3 = "the learned policy ahead of the hand-coded one from 99 trials on; 84 of 99 after 2,000"


def policies(report: Report, s: Any, out: Path, ex, verdict, scenario, conditions) -> None:
    """Table 1 on each room of ``s.policy_rooms`` (the report's ``verdict``, ``scenario`` loader and
    ``conditions`` writer are the caller's): every policy of :data:`POLICIES` run here, and the
    rows of :data:`OPTIONAL_POLICIES` read from the folders their own commands wrote."""
    from ..training.comparison import parse_policy, plan, run_all
    from ..training.task import task_spec

    rooms = {
        room: (task_spec(scenario(room)), POLICIES + (("agents",) if room == TRAINING_ROOM else ()))
        for room in s.policy_rooms
    }
    jobs = {
        room: plan(spec, [parse_policy(p) for p in names], s.policy_runs, s.policy_starts, out / room)
        for room, (spec, names) in rooms.items()
    }
    for room in rooms:
        (out / room / "runs").mkdir(parents=True, exist_ok=True)
    # every room's runs in one pool: no room's tail waits
    results = run_all([j for js in jobs.values() for j in js], ex)
    for room, (spec, names) in rooms.items():
        keys = {j.key for j in jobs[room]}
        _room_section(report, s, out / room, room, spec, names, [r for r in results if r.job.key in keys], verdict)
        conditions(report, out / room, [spec])


def _room_section(report: Report, s: Any, where: Path, room: str, spec, names, mine: list, verdict) -> None:
    """Table 1 on ``room`` from its runs ``mine`` and the optional rows found under ``where``: the
    table (the paper's rows beside on the training room), the endings with the verdicts against
    random, and the paper's numbers judged."""
    import pandas as pd

    from ..analysis.files import write_csv
    from ..analysis.stats import small_sample
    from ..training.comparison import failures, trials_frame

    failed = failures(mine, room)
    report.errored(
        [f"Learning paper, Table 1: {line}" for line in failed.values()], sum(r.trials is None for r in mine)
    )
    errored = {p: sum(r.trials is None for r in mine if r.job.policy.label == p) for p in names}
    found = {
        row.policy: optional_trials(where / EXTRA / row.policy, row.policy, spec, s.policy_runs, s.policy_starts)
        for row in OPTIONAL_POLICIES
    }
    extra = {p: f for p, f in found.items() if f.trials is not None}
    trials = pd.concat(
        [trials_frame([r for r in mine if r.trials is not None]), *(f.trials for f in extra.values())],
        ignore_index=True,
    )
    write_csv(where / "trials.csv", trials)
    limit = spec.params.learning.max_actions
    rows = [
        policy_row(trials[trials["policy"] == p], p, s.policy_runs, n, s.policy_starts, limit)
        for p, n in [*errored.items(), *((p, f.missing) for p, f in extra.items())]
    ]
    report.heading(f"Learning paper, Table 1 on {room} ({ROOMS[room]})")
    report.text(_about(s, room, where, limit))
    paper = PAPER_POLICIES if room == TRAINING_ROOM else {}
    report.table(*table1(rows, paper, [p for p in found if p not in extra], s.policy_starts))
    report.table(*endings_table(rows, limit))
    learned = next((r for r in rows if r.policy == "learned"), None)
    if learned is not None and learned.finished:
        report.text(
            'The paper: "the Learning Agent never terminates because of the 500-step limit"; navcli\'s learned '
            f"policy: {learned.endings['limit']} of its {learned.finished} trials at the {limit}-action limit."
        )
    if paper:
        report.table(*paper_verdicts(rows, paper, verdict))
    remarks = [small_sample(f"the policies on {room}", s.policy_starts, "starts")]
    remarks += [optional_text(row, found[row.policy], room, s, where) for row in OPTIONAL_POLICIES]
    report.notes(remarks + other_endings(trials, limit) + list(failed.values()))
    report.text(endings(trials))


def _about(s: Any, room: str, where: Path, limit: int) -> str:
    """What the room's tables are, in words."""
    return (
        f"{s.policy_runs} run(s) of {s.policy_starts} fixed starts (the paper: 5 of 99); learned = the model "
        "bundled with navcli (Prioritized Sweeping, trained on landmarks-12); random = a uniform random action at "
        "every choice (our baseline: the paper has none). Successes: the mean over the runs, in brackets the Wilson "
        "95 % interval of that rate with the starts as the sample (the runs repeat the same starts, so they do not "
        "multiply it), then the runs' lowest and highest; reward, actions and each action's count (in the paper's "
        "order): means per trial, in brackets a bootstrap 95 % interval that resamples the starts. "
        + (
            "The paper's numbers in the rows under navcli's. "
            if room == TRAINING_ROOM
            else "The paper has no numbers for this room. "
        )
        + f"How every trial ended: reached, at the {limit}-action limit, blocked, any other ending (named in the "
        "notes), and the trials of runs that ended in error, so that each row's counts sum to its runs x starts. "
        "Against random (successes, reward): a policy beats random where its 95 % interval lies wholly above "
        "random's, random does better where random's lies wholly above, else random does as well; a row with "
        f"runs that ended in error gets no verdict. Every trial: {where / 'trials.csv'}."
    )


@dataclass(frozen=True)
class PolicyRow:
    """A policy's numbers on one room (:func:`policy_row`)."""

    policy: str
    runs: int
    errored: int  # of the runs: ended in error, or (an optional row) not found
    starts: int
    successes: tuple[float, float, float]  # mean per run, the 95 % interval (in starts)
    run_range: tuple[int, int]  # the runs' fewest and most successes
    means: dict[str, tuple[float, float, float]]  # per trial, with its 95 % interval: reward, actions, each action
    endings: dict[str, int]  # trials by ENDINGS

    @property
    def finished(self) -> int:
        """The trials of the runs that did not end in error."""
        return sum(n for k, n in self.endings.items() if k != "errored")


ENDINGS = ("reached", "limit", "blocked", "other", "errored")
"""How a trial of Table 1 ended (:func:`ending`); ``errored``: the trials of a run that ended in error."""


def ending(outcome: str, actions: float, max_actions: int) -> str:
    """The kind of ending of :data:`ENDINGS` of a trial with ``outcome`` after ``actions`` actions
    (NaN: the bidding agents, which choose none, whose ``timeout`` is their cut at the action
    limit's time).

    >>> [ending(o, a, 500) for o, a in (("reached", 500), ("timeout", 500), ("blocked", 12), ("timeout", 40))]
    ['reached', 'limit', 'blocked', 'other']
    >>> ending("timeout", float("nan"), 500), ending("blocked", float("nan"), 500)
    ('limit', 'blocked')
    """
    if outcome == "reached":
        return "reached"
    if (actions >= max_actions) if math.isfinite(actions) else outcome == "timeout":
        return "limit"
    return "blocked" if outcome == "blocked" else "other"


def _endings_of(trials, max_actions: int) -> list[str]:
    return [ending(str(o), float(a), max_actions) for o, a in zip(trials["outcome"], trials["actions"].astype(float))]


def policy_row(trials, policy: str, runs: int, errored: int, starts: int, max_actions: int) -> PolicyRow:
    """A policy's row from its finished ``trials`` (every run's; ``errored`` of its ``runs`` runs
    have none): successes per run with the Wilson interval of their mean rate over the ``starts``
    (the runs repeat the same starts, so the sample is the starts), the runs' range; the means per
    trial with a bootstrap interval resampling the starts; each ending counted.

    >>> import pandas as pd
    >>> t = pd.DataFrame({"run": [0, 0, 1, 1], "start": [0, 1, 0, 1], "success": [True, False, True, True],
    ...     "outcome": ["reached", "timeout", "reached", "reached"], "actions": [10, 500, 12, 14],
    ...     "reward": [-10.0, -500.0, -12.0, -14.0], "MB": 1, "MLL": 2, "MOT": 3, "MVL": 4, "MVT": 0})
    >>> r = policy_row(t, "p", 3, 1, 2, 500)
    >>> r.successes[0], r.run_range, r.endings, r.finished
    (1.5, (1, 2), {'reached': 3, 'limit': 1, 'blocked': 0, 'other': 0, 'errored': 2}, 4)
    """
    from ..analysis.stats import bootstrap_mean, wilson_interval

    per_run = trials.groupby("run")["success"].sum().astype(int) if len(trials) else None
    if per_run is not None and len(per_run):
        mean = float(per_run.mean())
        lo, hi = wilson_interval(mean, starts)
        successes, run_range = (mean, starts * lo, starts * hi), (int(per_run.min()), int(per_run.max()))
    else:
        successes, run_range = (math.nan, math.nan, math.nan), (0, 0)
    means = {
        m: bootstrap_mean(trials[m].to_numpy(dtype=float), trials["start"].to_numpy())
        if len(trials)
        else (math.nan,) * 3
        for m in ("reward", "actions", *ACTIONS)
    }
    kinds = _endings_of(trials, max_actions)
    counts = {k: kinds.count(k) for k in ENDINGS}
    counts["errored"] = errored * starts
    return PolicyRow(policy, runs, errored, starts, successes, run_range, means, counts)


def against_random(mine: tuple[float, float], random: tuple[float, float], n: int, errored: int = 0) -> str:
    """A policy against the uniform random one in a quantity where more is better, from their 95 %
    intervals ``mine`` and ``random`` (low, high) over ``n`` starts: it beats random only where the
    intervals do not overlap with its own above; ``errored`` runs behind either: no verdict.

    >>> against_random((60.0, 70.0), (40.0, 59.0), 99), against_random((60.0, 70.0), (65.0, 80.0), 99)
    ('beats random', 'random does as well')
    >>> against_random((-900.0, -700.0), (-200.0, -150.0), 99), against_random((60.0, 70.0), (40.0, 59.0), 3)
    ('random does better', 'too few starts to judge (3; 10 needed)')
    >>> against_random((60.0, 70.0), (40.0, 59.0), 99, errored=2)
    'no verdict: 2 runs ended in error'
    """
    from ..analysis.stats import MIN_SAMPLE
    from ..analysis.tables import errored_verdict

    if errored:
        return errored_verdict(errored)
    if n < MIN_SAMPLE:
        return f"too few starts to judge ({n}; {MIN_SAMPLE} needed)"
    if not all(math.isfinite(x) for x in (*mine, *random)):
        return "no interval"
    if mine[0] > random[1]:
        return "beats random"
    if mine[1] < random[0]:
        return "random does better"
    return "random does as well"


AGAINST_RANDOM = ("beats random", "random does as well", "random does better")
"""The verdicts of :func:`against_random` that judge (the others say why there is none)."""
NOT_JUDGED = ("(the baseline)", "n/a")
"""A cell against random that is no verdict: the random row itself, a quantity the policy has not."""


def _cell(m: tuple[float, float, float], digits: int = 1) -> str:
    if not math.isfinite(m[0]):
        return "n/a"
    if not (math.isfinite(m[1]) and math.isfinite(m[2])):
        return f"{m[0]:.{digits}f}"
    return f"{m[0]:.{digits}f} [{m[1]:.{digits}f}, {m[2]:.{digits}f}]"


def table1(
    rows: list[PolicyRow], paper: dict[str, dict[str, float]], absent: list[str], starts: int
) -> tuple[list[str], list[list[str]]]:
    """Table 1 in the paper's layout (its action columns in its order, :data:`PAPER_ACTIONS`):
    a row per policy, the paper's own under it where ``paper`` has it; an ``absent`` optional
    row said as not run."""
    head = [
        "policy",
        f"successes of {starts} [95 % CI] (runs' range)",
        "reward / trial [95 % CI]",
        "actions / trial [95 % CI]",
        *PAPER_ACTIONS,
    ]
    out = []
    for r in rows:
        if r.finished == 0:
            out.append([r.policy, "no trial finished (see the notes)"] + ["-"] * (len(head) - 2))
            continue
        low, high = r.run_range
        spread = f" ({low}-{high})" if r.runs - r.errored > 1 else " (1 run)"
        out.append(
            [r.policy, _cell(r.successes) + spread]
            + [_cell(r.means[m]) for m in ("reward", "actions")]
            + [_cell(r.means[a], 2) for a in PAPER_ACTIONS]
        )
        if r.policy in paper:
            p = paper[r.policy]
            out.append(
                [f"{r.policy}: the paper", f"{p['successes']:g} of {PAPER_STARTS}"]
                + [f"{p[m]:g}" for m in ("reward", "actions", *PAPER_ACTIONS)]
            )
    out += [[f"{p} (optional)", "not run here (see the notes)"] + ["-"] * (len(head) - 2) for p in absent]
    return head, out


def endings_table(rows: list[PolicyRow], max_actions: int) -> tuple[list[str], list[list[str]]]:
    """How each policy's trials ended (:data:`ENDINGS`, summing to its runs x starts) and its
    verdicts against the uniform random policy (:func:`against_random`) in successes and reward."""
    head = [
        "policy",
        "runs (ended in error)",
        "trials",
        "reached",
        f"at the {max_actions}-action limit",
        "blocked",
        "other endings",
        "errored",
        "successes against random",
        "reward against random",
    ]
    base = next((r for r in rows if r.policy == BASELINE and r.finished), None)
    out = []
    for r in rows:
        judged = []
        for m in ("successes", "reward"):
            if r.policy == BASELINE:
                judged.append(NOT_JUDGED[0])
            elif base is None:
                judged.append("no verdict: no random row")
            elif not math.isfinite(r.means["reward"][0]) and m == "reward":
                judged.append(NOT_JUDGED[1])  # the bidding agents: no reward
            else:
                mine, theirs = (r.successes, base.successes) if m == "successes" else (r.means[m], base.means[m])
                judged.append(against_random(mine[1:], theirs[1:], r.starts, r.errored + base.errored))
        out.append(
            [r.policy, f"{r.runs} ({r.errored})", str(r.runs * r.starts)]
            + [str(r.endings[k]) for k in ENDINGS]
            + judged
        )
    return head, out


def paper_verdicts(
    rows: list[PolicyRow], paper: dict[str, dict[str, float]], verdict
) -> tuple[list[str], list[list[str]]]:
    """The paper's numbers judged (the report's ``verdict``): each of its quantities of each of its
    policies against navcli's interval; successes scaled to the paper's 99 starts."""
    head = ["policy", "quantity", "the paper", "navcli [95 % CI]", "agreement"]
    out = []
    for r in rows:
        if r.policy not in paper or r.finished == 0:
            continue
        scale = PAPER_STARTS / r.starts
        for metric in ("successes", "reward", "actions", *PAPER_ACTIONS):
            have = paper[r.policy].get(metric)
            if have is None:
                continue
            m, lo, hi = (x * scale for x in r.successes) if metric == "successes" else r.means[metric]
            if metric == "successes":
                p_lo, p_hi = (PAPER_STARTS * x for x in wilson_interval(round(have), PAPER_STARTS))
                shown = f"{have:g} of {PAPER_STARTS} [{p_lo:.1f}, {p_hi:.1f}]"
            else:
                p_lo, p_hi, shown = have, have, f"{have:g}"
            out.append(
                [
                    r.policy,
                    metric,
                    shown,
                    interval_text(m, lo, hi),
                    verdict((lo, hi), (p_lo, p_hi), r.starts, "starts", errored=r.errored),
                ]
            )
    return head, out


OTHER_ENDINGS = {"timeout": "the scenario's time limit, before the action limit"}
"""What an ending Table 1 counts as ``other`` means, where its outcome's name does not say it."""


def other_endings(trials, max_actions: int) -> list[str]:
    """A note per policy whose trials ended otherwise than :data:`ENDINGS` names: how, and how many.

    >>> import pandas as pd
    >>> t = pd.DataFrame({"policy": ["a", "a", "b"], "outcome": ["timeout", "reached", "interrupted"], "actions": [40, 12, 3]})
    >>> print("\\n".join(other_endings(t, 500)))
    a: 1 trial ended otherwise: timeout (1; the scenario's time limit, before the action limit)
    b: 1 trial ended otherwise: interrupted (1)
    """
    out = []
    for policy, t in trials.groupby("policy", sort=False):
        other = t[[k == "other" for k in _endings_of(t, max_actions)]]
        if len(other):
            named = ", ".join(
                f"{o} ({n}{'; ' + OTHER_ENDINGS[o] if o in OTHER_ENDINGS else ''})"
                for o, n in other["outcome"].value_counts(sort=False).items()
            )
            out.append(f"{policy}: {len(other)} trial{'s' if len(other) != 1 else ''} ended otherwise: {named}")
    return out


def endings(trials) -> str:
    """How each policy's trials ended, and what the trials cut at the action limit cost it: a
    policy that loops in one state pays most of its reward there (below: 2500 of 2600, 96 %).

    >>> import pandas as pd
    >>> t = pd.DataFrame({"policy": ["a", "a", "a", "b"], "outcome": ["reached", "timeout", "blocked", "reached"],
    ...                   "reward": [-50.0, -2500.0, -50.0, -20.0]})
    >>> endings(t)
    'How the trials ended: a: 1 reached, 1 blocked, 1 cut at the action limit (96 % of its reward; -50.0 a trial without them); b: 1 reached.'
    """
    parts = []
    for policy, t in trials.groupby("policy", sort=False):
        n = t["outcome"].value_counts()
        said = [
            f"{n[k]} {word}"
            for k, word in (("reached", "reached"), ("blocked", "blocked"), ("timeout", "cut at the action limit"))
            if n.get(k, 0)
        ]
        cut = t[t["outcome"] == "timeout"]
        if len(cut) and t["reward"].notna().all() and t["reward"].sum() != 0:
            rest = t[t["outcome"] != "timeout"]["reward"]
            said[-1] += f" ({100 * cut['reward'].sum() / t['reward'].sum():.0f} % of its reward" + (
                f"; {rest.mean():.1f} a trial without them)" if len(rest) else ")"
            )
        parts.append(f"{policy}: {', '.join(said)}")
    return "How the trials ended: " + "; ".join(parts) + "."


def _train_one(job: tuple) -> dict:
    """One training of Figure 3 (in a worker process): its curve and levels, from its model file."""
    from ..learning import model_file
    from ..training.trainer import train

    spec, seed, trials, every, starts, model = job
    have = int(model_file.load(model)[1].get("trials", 0)) if model.exists() else 0
    if have < trials:
        train(
            spec,
            trials=trials,
            eval_every=every,
            eval_starts=starts,
            seed=seed,
            out=model,
            resume=model if have else None,
            workers=1,
        )
    return model_file.load(model)[1]


def start_figure3(s: Any, out: Path, ex, scenario) -> tuple[list[Path], dict]:
    """Submit Figure 3's ``s.train_seeds`` trainings to ``ex`` now (the reproduction's longest runs:
    started before every other section's, they do not hold the pool's tail alone); their model
    files and futures, for :func:`figure3`."""
    from ..training.task import task_spec
    from .executor import submit_all

    spec = task_spec(scenario(TRAINING_ROOM))
    out.mkdir(parents=True, exist_ok=True)
    models = [
        out / f"model-seed{k}-{s.train_trials}-every{s.eval_every}-on{s.eval_starts}.npz"
        for k in range(1, s.train_seeds + 1)
    ]  # one per size and seed: resumed only by it
    jobs = [(spec, k, s.train_trials, s.eval_every, s.eval_starts, m) for k, m in enumerate(models, 1)]
    return models, submit_all(_train_one, jobs, ex)


def figure3(report: Report, s: Any, out: Path, ex, started: tuple[list[Path], dict], scenario, conditions) -> None:
    """Figure 3 over the trainings :func:`start_figure3` started on ``ex``."""
    from ..learning import model_file
    from ..training.task import task_spec
    from .executor import collect
    from .figures import learning_curves

    spec = task_spec(scenario(TRAINING_ROOM))
    models, futures = started
    results: list[dict] = [{}] * len(models)
    errors: dict[int, str] = {}

    def done(i: int, f) -> None:
        try:
            results[i] = f.result()
        except Exception as e:  # a training that raised: counted and said, the others drawn
            errors[i + 1] = f"{type(e).__name__}: {e}"

    collect(futures, ex, done)
    report.heading("Learning paper, Figure 3: learning curves of several trainings")
    if errors:
        from ..analysis.tables import why

        line = (
            f"{len(errors)} of {len(models)} trainings ended in error (seeds {', '.join(map(str, sorted(errors)))}): "
        )
        report.errored([f"Figure 3: {line}{why(list(errors.values()))}"], len(errors))
        report.notes([line + why(list(errors.values()))])
    metas = [m for m in results if m]
    if not metas:
        report.text("No training finished: no figure.")
        return
    png = learning_curves(metas, out / "figure3.png")
    hand, rand = metas[0].get("hand_coded"), metas[0].get("random")
    passed = [m["seed"] for m in metas if hand is not None and any(p["successes"] > hand for p in m["curve"])]
    zero = [m["seed"] for m in metas if any(p["trials"] >= 500 and p["successes"] == 0 for p in m["curve"])]
    finals = [m["curve"][-1]["successes"] for m in metas]
    seeds = [int(m["seed"]) for m in metas]
    named = (
        f"1-{len(seeds)}" if len(seeds) > 1 and seeds == list(range(1, len(seeds) + 1)) else ", ".join(map(str, seeds))
    )
    report.text(
        f"{len(metas)} training{'s' if len(metas) != 1 else ''} of {s.train_trials} trials on {TRAINING_ROOM} (seeds {named}, in "
        f"parallel workers), the greedy policy evaluated every {s.eval_every} trials on {s.eval_starts} "
        f"fixed starts. The paper: {PAPER_FIGURE3}. navcli: after {s.train_trials} trials "
        f"{min(finals)} to {max(finals)} of {s.eval_starts} (mean {sum(finals) / len(finals):.1f}); the "
        f"hand-coded policy {hand}, the random policy {rand}. Trainings whose test successes passed the "
        f"hand-coded policy's: {len(passed)} of {len(metas)}"
        + (f" (seeds {', '.join(map(str, passed))})" if passed else "")
        + f"; evaluations at 0 after 500 trials: {len(zero)}"
        + (f" (seeds {', '.join(map(str, zero))})" if zero else "")
        + "."
    )
    if hand is not None:
        report.table(*seeds_table(metas, hand, s.train_trials))
    bundled = model_file.BUNDLED
    if (s.train_trials, s.eval_every, s.eval_starts) == (2000, 100, 99) and bundled.exists() and 1 not in errors:
        same = all(
            a.read_bytes() == b.read_bytes()
            for a, b in ((models[0], bundled), (models[0].with_suffix(".json"), bundled.with_suffix(".json")))
        )
        report.text(
            f"Seed 1's model is {'byte for byte' if same else 'NOT'} the model bundled with navcli ({bundled.name})."
        )
    conditions(report, out, [spec])
    report.image(
        str(png.relative_to(out.parent)),
        "successes of the test starts against training trials, "
        "each training, their mean and range, with the hand-coded and random levels",
    )
    report.text(f"The models, their curves and every training trial: {out}.")


SETTLED = 300
"""Training trials after which an evaluation of Figure 3's trainings should no longer fall below the hand-coded policy's."""


def seeds_table(metas: list[dict], hand: float, trials: int) -> tuple[list[str], list[list[str]]]:
    """Figure 3's trainings a row each (from their models' metadata): successes at the end, the
    first evaluation above the hand-coded policy's ``hand``, the lowest after :data:`SETTLED`
    trials, and whether each passed the hand-coded policy within its ``trials`` and stayed at or
    above it after :data:`SETTLED`.

    >>> m = {"seed": 1, "curve": [{"trials": t, "successes": k} for t, k in ((100, 20), (200, 50), (400, 40))]}
    >>> seeds_table([m], 45.0, 400)[1]
    [['1', '40', '200', '40 (at 400)', 'met', 'not met (40 at 400 below 45)']]
    """
    head = [
        "seed",
        f"successes after {trials} trials",
        "first evaluation above hand-coded (trials)",
        f"lowest after {SETTLED} trials",
        f"target: passes hand-coded within {trials} trials",
        f"target: none below hand-coded after {SETTLED} trials",
    ]
    rows = []
    for m in metas:
        curve = m["curve"]
        above = next((p["trials"] for p in curve if p["successes"] > hand), None)
        late = [p for p in curve if p["trials"] > SETTLED]
        low = min(late, key=lambda p: p["successes"]) if late else None
        rows.append(
            [
                str(m["seed"]),
                f"{curve[-1]['successes']:g}",
                f"{above}" if above is not None else "never",
                f"{low['successes']:g} (at {low['trials']})" if low else "-",
                "met" if above is not None else "not met",
                "no evaluation after it"
                if low is None
                else "met"
                if low["successes"] >= hand
                else f"not met ({low['successes']:g} at {low['trials']} below {hand:g})",
            ]
        )
    return head, rows
