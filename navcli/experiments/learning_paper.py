"""The learning paper's experiments in ``navcli reproduce learning``: its Table 1 on three rooms
(:func:`policies`) and its Figure 3 over several trainings (:func:`figure3`), beside its numbers.

- **Table 1**: the learned policy (the model bundled with navcli, trained on ``landmarks-12``),
  the hand-coded policy of section 6 and a uniform random policy (our baseline: the paper has
  none; a policy that does not tell its actions apart must lose if the table means anything),
  from the same fixed starts, ``policy_runs`` runs (the paper's five test runs: only the
  simulator's seed differs); the bidding agents too on the training room. On ``landmarks-12``
  (the paper's kind of room, the one training used), ``landmarks-hall`` (a hall whose landmarks
  hide the target from much of the floor) and ``landmarks-drawn`` (drawn at random before any
  run: a room training never saw). The paper's numbers stand beside the training room's rows.
- **Figure 3**: ``train_seeds`` trainings of ``train_trials`` trials (seeds 1, 2, ...), run in
  parallel worker processes, each evaluated every ``eval_every`` trials on the same fixed starts;
  the figure shows each, their mean and their range, with the hand-coded and random policies'
  levels. Seed 1's training is the bundled model's (``navcli train landmarks-12 --trials 2000
  --seed 1``): the section says whether its model file is the bundled one, byte for byte.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..analysis.stats import wilson_interval
from ..learning.actions import ACTIONS
from .document import Report, interval_text

TRAINING_ROOM = "landmarks-12"
POLICY_ROOMS = (TRAINING_ROOM, "landmarks-hall", "landmarks-drawn")
POLICIES = ("learned", "hand-coded", "random")
PAPER_STARTS = 99  # the learning paper's test starts
PAPER_POLICIES: dict[str, dict[str, float]] = {
    "learned": {
        "successes": 84,
        "reward": -336,
        "actions": 49.95,
        "MB": 11.41,
        "MLL": 21.43,
        "MOT": 6.52,
        "MVL": 4.97,
        "MVT": 5.61,
    },
    "hand-coded": {
        "successes": 24,
        "reward": -858,
        "actions": 153.33,
        "MB": 4.94,
        "MLL": 7.32,
        "MOT": 18.59,
        "MVL": 121.96,
        "MVT": 0.52,
    },
}
"""The learning paper's Table 1 (section 6: 84 and 24 successes of 99 after 2,000 trials)."""
PAPER_FIGURE3 = "the learned policy ahead of the hand-coded one from 99 trials on; 84 of 99 after 2,000"


def policies(report: Report, s: Any, out: Path, ex, verdict, scenario, conditions) -> None:
    """Table 1 on each room of ``s.policy_rooms`` (the report's ``verdict``, ``scenario`` loader and
    ``conditions`` writer are the caller's)."""
    from ..analysis.files import write_csv
    from ..training.comparison import failures, notes, parse_policy, plan, policy_table, run_all, trials_frame
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
        where, keys = out / room, {j.key for j in jobs[room]}
        mine = [r for r in results if r.job.key in keys]
        failed = failures(mine, room)
        report.errored(
            [f"Learning paper, Table 1: {line}" for line in failed.values()], sum(r.trials is None for r in mine)
        )
        trials = trials_frame([r for r in mine if r.trials is not None])
        write_csv(where / "trials.csv", trials)
        table = policy_table(trials).set_index("policy")
        trained = "the room it was trained on" if room == TRAINING_ROOM else "a room training never saw"
        report.heading(f"Learning paper, Table 1 on {room} ({trained})")
        report.text(
            f"{s.policy_runs} run(s) of {s.policy_starts} fixed starts (the paper: 5 of 99); learned = the "
            "model bundled with navcli (Prioritized Sweeping, trained on landmarks-12); random = a uniform "
            "random action at every choice (our baseline). Successes scaled to 99 starts, with the Wilson 95 % "
            "interval of the rate over every trial; reward, actions and each action's count: means per trial "
            "with a bootstrap 95 % interval that resamples the starts. "
            + (
                "The paper's numbers beside (its own room); "
                if room == TRAINING_ROOM
                else "The paper has no numbers for this room; "
            )
            + f"every trial: {where / 'trials.csv'}. Successes' intervals count a start's trials that repeat "
            "identically over the runs once; a policy with runs that ended in error gets no verdict."
        )
        rows = []
        for policy in names:
            if policy not in table.index:  # every run of it failed: said, not hidden
                rows.append([policy, "-", "-", "no trial finished (see the runs' errors)", "no verdict"])
                continue
            bad = sum(r.trials is None for r in mine if r.job.policy.label == policy)
            paper_row = PAPER_POLICIES.get(policy, {}) if room == TRAINING_ROOM else {}
            for metric in ("successes", "reward", "actions", *ACTIONS):
                if policy == "agents" and metric not in ("successes",):
                    continue  # the bidding agents choose no actions
                scale = PAPER_STARTS / s.policy_starts if metric == "successes" else 1.0
                m, lo, hi = (table.loc[policy, k] * scale for k in (metric, f"{metric}_lo", f"{metric}_hi"))
                if metric == "successes":  # the rate's interval over the distinct trials
                    lo, hi = (PAPER_STARTS * x for x in _distinct_rate(trials[trials["policy"] == policy]))
                paper = paper_row.get(metric, math.nan)
                if math.isnan(paper):  # no number in the paper: no verdict
                    rows.append([policy, metric, "-", interval_text(m, lo, hi), ""])
                    continue
                p_lo, p_hi = (
                    (PAPER_STARTS * x for x in wilson_interval(round(paper), PAPER_STARTS))
                    if metric == "successes"
                    else (paper, paper)
                )
                shown = (
                    f"{paper:g} of {PAPER_STARTS} [{p_lo:.1f}, {p_hi:.1f}]" if metric == "successes" else f"{paper:g}"
                )
                rows.append(
                    [
                        policy,
                        metric,
                        shown,
                        interval_text(m, lo, hi),
                        verdict((lo, hi), (p_lo, p_hi), s.policy_starts, "starts", errored=bad),
                    ]
                )
        report.table(["policy", "quantity", "the paper", "navcli [95 % CI]", "agreement"], rows)
        report.notes(notes(table.reset_index(), room) + list(failed.values()))
        report.text(endings(trials))
        conditions(report, where, [spec])


TRIAL_IDENTITY = ("start", "outcome", "success", "actions", "reward", *ACTIONS, "time_s")
"""What makes two trials of a policy the same result: a start's trial repeated alike in every
number over the runs counts once in a verdict (the runs change only the missions' seeds)."""


def _distinct_rate(trials) -> tuple[float, float]:
    """The Wilson 95 % interval of a policy's success rate over its distinct trials (:data:`TRIAL_IDENTITY`)."""
    d = trials[~trials[list(TRIAL_IDENTITY)].astype(str).duplicated()]
    return wilson_interval(int(d["success"].sum()), len(d))


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
