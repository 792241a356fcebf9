"""``navcli train``: the Learning Agent's training (learning-agent paper, section 6).

Trials run one after another from seeded random starts (trial ``i`` of seed ``N`` always starts at
the same place), each until the target is reached, ``max_actions`` actions, or the Rescuer gives
up; the learner (Prioritized Sweeping, or Q-learning for the model-free baseline) learns from
every action. Every ``eval_every`` trials its greedy policy runs the same fixed test starts
(:data:`EVAL_SEED`, whatever the training seed), in worker processes while training goes on
(``workers=1``: in this process, between trials); the hand-coded policy runs them once for its
level. The model is saved after every evaluation, with the learning curve so far, so an
interrupted training resumes from its file (``--resume``). A test start whose last greedy trial
the new greedy policy would repeat exactly (the same action in every state it visited) is not run
again: its result is taken over (:class:`EvaluationMemo`; the curve is the same to the last bit).

Resuming gives what the uninterrupted training would have, bit for bit (arrays, curve, trials CSV):
the file holds, beside the learner's arrays, the state of its random generator (``learner_rng``)
and the policies of the evaluations still running at the save (``pending_evaluations``), run again
on resume; trial ``i``'s start depends on the seed and ``i`` alone, and the trials after the save
are run again (their rows of the trials CSV dropped first). A training to ``N`` trials interrupted
with its model saved at ``n`` is completed by ``--resume FILE --trials N`` (the total, the same command). Ctrl-C and SIGTERM
stop it alike (the workers stopped, the trials CSV closed), never in the middle of a save.

What each training trial did is a row of ``<model>-trials.csv`` (where it started, its outcome,
actions, reward and the count of each action), written as it ends; with ``log="full"`` every
tick of every training trial is also recorded, one MCAP log per trial in ``<model>-trials/``
(readable by ``analysis`` and Foxglove like a ``navcli run`` log; 10-25 kB a simulated second).
Evaluation trials run without logs.
"""

from __future__ import annotations

import csv
import itertools
import math
import time
from concurrent.futures import Future
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..config import RunSpec
from ..outputs import atomic
from ..signals import deferred
from ..learning.actions import ACTIONS
from ..learning.features import N_STATES, check_bounds
from ..learning.model_file import curve_paths, trials_paths
from .task import NavigationTask, Start, random_starts
from .trials import RANDOM_STREAM as RANDOM_STREAM, TrialResult as TrialResult, eval_job
from .trials import evaluate as evaluate, hand_coded_table as hand_coded_table
from .trials import random_policy as random_policy, run_trial as run_trial

ALGORITHMS = ("prioritized-sweeping", "q-learning")
EVAL_SEED = 99
"""The test starts come from this seed, the same for every training run (the paper: "the same set
of 99 starting locations was employed in each testing period")."""


def make_learner(algorithm: str, spec: RunSpec, seed: int):
    from ..learning.prioritized_sweeping import PrioritizedSweeping
    from ..learning.q_learning import QLearning

    p = spec.params.learning
    rng = np.random.default_rng([seed, 1])
    if algorithm == "prioritized-sweeping":
        return PrioritizedSweeping(
            N_STATES,
            len(ACTIONS),
            gamma=p.gamma,
            backups=p.backups,
            threshold=p.threshold,
            explore=p.explore,
            optimistic=0.0,
            rng=rng,
        )
    if algorithm == "q-learning":
        return QLearning(N_STATES, len(ACTIONS), alpha=p.q_alpha, gamma=p.gamma, epsilon=p.q_epsilon, rng=rng)
    raise ValueError(f"unknown algorithm {algorithm!r} (expected one of: {', '.join(ALGORITHMS)})")


@dataclass
class Point:
    """One evaluation of the learning curve."""

    trials: int
    successes: int
    reward: float  # mean per trial
    actions: float  # mean per trial


@dataclass
class Training:
    """What ``navcli train`` did: the curve, the hand-coded level, and where its time went (s)."""

    algorithm: str
    seed: int
    trials: int
    curve: list[Point] = field(default_factory=list)
    hand_coded: int | None = None  # the hand-coded policy's successes of the test starts
    hand_coded_reward: float | None = None  # and its mean reward per trial
    random: int | None = None  # the uniform random policy's successes of the test starts
    random_reward: float | None = None  # and its mean reward per trial
    train_s: float = 0.0  # wall time in training trials (this process)
    eval_s: float = 0.0  # summed wall time of the evaluations (worker processes beside training; this one if workers=1)
    eval_trials: int = 0  # the evaluation trials run (in eval_s)
    eval_reused: int = 0  # and those a greedy policy would have repeated, taken from an earlier evaluation
    wall_s: float = 0.0
    outcomes: dict[str, int] = field(default_factory=dict)
    end: int = 0  # the trials this training goes to (those of the file resumed and the new ones)
    saved_at_start: int | None = None  # the trials of the file resumed
    saved: int | None = None  # the trials of the model file last saved (or resumed), None before any
    saved_in: Path | None = None  # that file


class EvaluationMemo:
    """The last greedy trial from each test start, to be reused (our design). A trial is a
    function of its start and of the actions chosen in the belief states it visits: its mission is
    seeded by the start alone, and a table policy's choice depends on the state alone. A later
    greedy policy that chooses the same actions in every state the trial visited therefore runs
    the same trial, to the last bit, and its result is taken instead of running it again.

    >>> memo = EvaluationMemo()
    >>> memo.remember(0, np.array([1, 2, 3]), TrialResult("reached", 2, (1, 1, 0), visited=(0, 2)))
    >>> memo.reusable(0, np.array([1, 0, 3])).outcome  # state 1 was never visited
    'reached'
    >>> memo.reusable(0, np.array([1, 2, 4])) is None  # state 2 was: another trial
    True
    """

    def __init__(self) -> None:
        self._last: dict[int, tuple[np.ndarray, np.ndarray, TrialResult]] = {}  # start: states, actions, result

    def remember(self, start: int, policy: np.ndarray, result: TrialResult) -> None:
        """``result``, the trial of ``policy`` from test start number ``start``."""
        states = np.array(result.visited, dtype=np.int64)
        self._last[start] = (states, policy[states], result)

    def reusable(self, start: int, policy: np.ndarray) -> TrialResult | None:
        """The remembered trial from ``start`` if ``policy`` would run it again, else None."""
        last = self._last.get(start)
        if last is None or not np.array_equal(policy[last[0]], last[1]):
            return None
        return last[2]


@dataclass
class _Batch:
    """Some test starts of an evaluation (their numbers), run in a job (``future``) or ``reused``."""

    starts: list[int]
    future: Future | None = None
    reused: list[TrialResult] | None = None

    def done(self) -> bool:
        return self.future is None or self.future.done()


LOGS = ("summary", "full")
"""What training records of its trials: a row each (``summary``), or also every tick (``full``)."""
TRIAL_COLUMNS = ("trial", "x", "y", "heading_deg", "seed", "outcome", "actions", "reward", *ACTIONS)


def _trials_csv(path: Path, keep: int, source: Path | None = None):
    """The trials CSV opened for writing, with the rows of trials before ``keep`` kept from ``source``
    (by default ``path`` itself; a resumed training runs the later ones again: they came after the
    model's last save). The kept rows are written to a new file that then replaces ``path``, so an
    interruption meanwhile loses none of them."""
    source = source or path
    rows = []
    if keep and source.exists():
        with source.open(newline="") as f:  # at most the header and ``keep`` rows are read
            rows = list(itertools.islice(csv.reader(f), keep + 1))[1:]
        rows = [r for r in rows if r and r[0].isdigit() and int(r[0]) < keep]
    with atomic(path) as tmp, tmp.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(TRIAL_COLUMNS)
        w.writerows(rows)
    f = path.open("a", newline="")
    return f, csv.writer(f)


def _resumed_policy(resume: Path, p) -> tuple[int, np.ndarray]:
    """A pending evaluation of a model file (``{"trials": n, "policy": [action per state]}``)."""
    from ..learning.model_file import ModelError

    try:
        n, policy = int(p["trials"]), np.array(p["policy"], dtype=np.int64)
    except (TypeError, KeyError, ValueError, OverflowError):
        policy = None
    if policy is None or policy.shape != (N_STATES,) or policy.min() < 0 or policy.max() >= len(ACTIONS):
        raise ModelError(
            f"{resume}: a pending evaluation of its metadata is not a policy of {len(ACTIONS)} "
            f"actions for each of {N_STATES} states"
        )
    return n, policy.astype(np.int8)


def train(  # noqa: PLR0913 (the train command's options, each keyword-only)
    spec: RunSpec,
    *,
    trials: int = 2000,
    eval_every: int = 100,
    eval_starts: int = 99,
    seed: int = 1,
    algorithm: str = "prioritized-sweeping",
    out: Path,
    resume: Path | None = None,
    workers: int = 2,
    log: str = "summary",
    on_trial: Callable[[int, TrialResult, Training], None] | None = None,
) -> Training:
    """Train to ``trials`` trials in all (see the module docstring): a resumed training goes on
    from the trials of its file to that total (our design: what a user asks for is the model's size,
    and the same command completes an interrupted training). Writes ``out`` (.npz + .json),
    ``out``-curve.csv and -curve.png, ``out``-trials.csv, and with ``log="full"`` the folder
    ``out``-trials/ of trial logs."""
    if log not in LOGS:
        raise ValueError(f"unknown log {log!r} (expected one of: {', '.join(LOGS)})")
    check_bounds(spec.params.learning)
    learner = make_learner(algorithm, spec, seed)
    result = Training(algorithm, seed, 0)
    resumed: list[tuple[int, np.ndarray]] = []  # the evaluations the file resumed had not finished
    if resume is not None:
        resumed = _resume(resume, learner, result, spec, trials, eval_every, eval_starts)
    run = _Run(spec, learner, result, out, eval_every, eval_starts, workers)
    t_start = time.perf_counter()
    from ..experiments.executor import executor, interruptible

    result.end = trials  # what a stop says the training goes to, wherever it comes
    try:
        with interruptible():  # Ctrl-C and SIGTERM alike, from the first trial to the last file written
            with executor(workers) as pool:  # stopped cleanly on Ctrl-C or SIGTERM, like compare's
                run.evals.begin(pool, learner.greedy_policy(), resumed)
                run.trials(pool, trials, resume, log, on_trial)
                run.evals.harvest(True)
            result.curve.sort(key=lambda p: p.trials)
            result.wall_s = time.perf_counter() - t_start
            run.save()
            write_curve(result, out)
    except KeyboardInterrupt as e:  # Ctrl-C, or SIGTERM (Terminated): the caller can say how far it got
        e.training = result  # type: ignore[attr-defined]  # what the CLI says of how far it got
        raise
    return result


def _resume(
    resume: Path,
    learner,
    result: Training,
    spec: RunSpec,
    trials: int,
    eval_every: int,
    eval_starts: int,
) -> list[tuple[int, np.ndarray]]:
    """Load the training saved in ``resume`` into ``learner`` and ``result``, refusing a file this
    training cannot go on from; returns the evaluations it had not finished."""
    from ..learning import model_file

    arrays, meta = model_file.load(resume)
    _check_resumable(resume, meta, result.algorithm, spec, trials, eval_every, eval_starts)
    learner.load_arrays(arrays)
    result.seed = int(meta["seed"])
    result.trials = result.saved = result.saved_at_start = int(meta["trials"])
    result.saved_in = resume
    if "learner_rng" in meta:  # the generator goes on where it was at the save
        try:
            learner.rng.bit_generator.state = meta["learner_rng"]
        except (TypeError, KeyError, ValueError) as e:
            raise model_file.ModelError(f"{resume}: its learner's random state is not usable ({e})") from None
    else:  # a file of an older navcli: resumed, but not as its training would have gone on
        learner.rng = np.random.default_rng([result.seed, 1, result.trials])
    result.curve = [Point(**p) for p in meta.get("curve", [])]
    result.hand_coded = meta.get("hand_coded")
    result.hand_coded_reward = meta.get("hand_coded_reward")
    result.random, result.random_reward = meta.get("random"), meta.get("random_reward")
    result.outcomes = dict(meta.get("outcomes", {}))
    return [_resumed_policy(resume, p) for p in meta.get("pending_evaluations", [])]


def _check_resumable(
    resume: Path, meta: dict, algorithm: str, spec: RunSpec, trials: int, eval_every: int, eval_starts: int
) -> None:
    """Refuse (ModelError) a model file this training cannot go on from."""
    from ..learning.model_file import ModelError

    if "seed" not in meta or "trials" not in meta:
        raise ModelError(f"{resume}: not saved by a training (no seed or trials); cannot resume it")
    if meta.get("algorithm") != algorithm or meta.get("scenario_sha256") != spec.scenario.sha256:
        raise ModelError(
            f"{resume}: made by {meta.get('algorithm')} on another scenario or "
            f"with another algorithm; cannot resume it here"
        )
    differ = [
        f"--{k.replace('_', '-')} {meta[k]}"
        for k, v in (("eval_every", eval_every), ("eval_starts", eval_starts))
        if k in meta and meta[k] != v
    ]
    if differ:  # its curve would mix evaluations of two kinds
        raise ModelError(f"{resume}: was trained with {' and '.join(differ)}; resume it with the same")
    if int(meta["trials"]) >= trials:
        raise ModelError(
            f"{resume}: already holds {meta['trials']} trials; --trials is the total to "
            f"reach: give more than {meta['trials']}"
        )


class _Evaluations:
    """The evaluations of a training on its fixed test starts: the greedy policy's, in ``chunks``
    jobs each, running beside the training, and the hand-coded and random policies' levels once."""

    def __init__(self, spec: RunSpec, result: Training, eval_starts: int, chunks: int):
        self.spec, self.result, self.chunks = spec, result, chunks
        self.test = random_starts(spec, eval_starts, EVAL_SEED)
        self.pending: list[tuple[int, np.ndarray, list[_Batch]]] = []  # evaluations running: trials, policy, batches
        self.hand: list[_Batch] = []
        self.rand: list[_Batch] = []
        self.memo = EvaluationMemo()  # the greedy policy's last trial from each test start

    def begin(self, pool, untrained: np.ndarray, resumed: list[tuple[int, np.ndarray]]) -> None:
        """The levels not yet known, the ``untrained`` greedy policy (a new training) and the
        evaluations a resumed file had not finished, submitted in the order of an uninterrupted run."""
        if self.result.hand_coded is None:
            self.hand = self.submit(pool, hand_coded_table())
        if self.result.random is None:
            self.rand = self.submit(pool, None)
        if self.result.trials == 0:  # the untrained policy: the curve's first point
            self.later(pool, 0, untrained)
        for n, policy in resumed:  # before anything new: the curve in the order of an uninterrupted run
            self.later(pool, n, policy)

    def submit(self, pool, policy: np.ndarray | None, reuse: bool = False) -> list[_Batch]:
        """``policy`` from the test starts, in ``chunks`` jobs; with ``reuse``, a start whose last
        greedy trial the policy would repeat (:class:`EvaluationMemo`) is not run again."""
        again: dict[int, TrialResult] = {}
        if reuse and policy is not None:
            for i in range(len(self.test)):
                if (r := self.memo.reusable(i, policy)) is not None:
                    again[i] = r
        todo = [i for i in range(len(self.test)) if i not in again]
        batches = [_Batch(list(again), reused=list(again.values()))] if again else []
        for k in range(self.chunks):
            if todo[k :: self.chunks]:
                starts = todo[k :: self.chunks]
                job = pool.submit(eval_job, self.spec, policy, [self.test[i] for i in starts])
                batches.append(_Batch(starts, job))
        return batches

    def collect(self, batches: list[_Batch], policy: np.ndarray | None = None) -> list[TrialResult]:
        """The results of ``batches`` in the test starts' order; a greedy ``policy``'s are remembered."""
        got: dict[int, TrialResult] = {}
        for b in batches:
            if b.future is None:
                rs = b.reused or []
                self.result.eval_reused += len(rs)
            else:
                rs, dt = b.future.result()
                self.result.eval_s += dt
                self.result.eval_trials += len(rs)
                if policy is not None:
                    for i, r in zip(b.starts, rs):
                        self.memo.remember(i, policy, r)
            got.update(zip(b.starts, rs))
        return [got[i] for i in sorted(got)]

    def harvest(self, block: bool) -> None:
        """The evaluations finished (all, waiting for them, with ``block``) into the result."""
        result = self.result
        while self.pending and (block or all(b.done() for b in self.pending[0][2])):
            n, policy, batches = self.pending.pop(0)
            rs = self.collect(batches, policy)
            result.curve.append(Point(n, _successes(rs), _mean_reward(rs), float(np.mean([r.actions for r in rs]))))
        if self.hand and (block or all(b.done() for b in self.hand)):
            hs = self.collect(self.hand)
            result.hand_coded, result.hand_coded_reward = _successes(hs), _mean_reward(hs)
            self.hand.clear()
        if self.rand and (block or all(b.done() for b in self.rand)):
            rs = self.collect(self.rand)
            result.random, result.random_reward = _successes(rs), _mean_reward(rs)
            self.rand.clear()

    def later(self, pool, n: int, policy: np.ndarray) -> None:
        """The greedy ``policy`` after ``n`` trials, submitted to run beside the training."""
        self.harvest(False)  # the evaluations done so far, first: what they ran may be reused
        self.pending.append((n, policy, self.submit(pool, policy, reuse=True)))


def _successes(rs: list[TrialResult]) -> int:
    return sum(r.success for r in rs)


def _mean_reward(rs: list[TrialResult]) -> float:
    return float(np.mean([r.reward for r in rs]))


class _Run:
    """One training under way: its learner, its result, its evaluations and its model file."""

    def __init__(
        self, spec: RunSpec, learner, result: Training, out: Path, eval_every: int, eval_starts: int, workers: int
    ):
        self.spec, self.learner, self.result, self.out = spec, learner, result, out
        self.eval_every, self.eval_starts = eval_every, eval_starts
        self.evals = _Evaluations(spec, result, eval_starts, max(1, workers))
        self.task = NavigationTask(spec.replace(navigation="learned"))  # what a trial log's summary says drove it

    def trials(
        self,
        pool,
        end: int,
        resume: Path | None,
        log: str,
        on_trial: Callable[[int, TrialResult, Training], None] | None,
    ) -> None:
        """The training trials up to ``end``, each a row of the trials CSV; the greedy policy
        evaluated every ``eval_every`` trials and the model saved then."""
        result = self.result
        result.end = end
        csv_path, log_dir = trials_paths(self.out)
        self.out.parent.mkdir(parents=True, exist_ok=True)
        if log == "full":
            log_dir.mkdir(parents=True, exist_ok=True)
        kept = trials_paths(resume)[0] if resume is not None else None  # the rows before its save
        rows, writer = _trials_csv(csv_path, result.trials, kept)
        with rows:
            while result.trials < end:
                i = result.trials
                start, r = self.trial(i, log_dir / f"trial-{i:05d}.mcap" if log == "full" else None)
                writer.writerow(_trial_row(i, start, r))
                rows.flush()
                if result.trials % self.eval_every == 0 or result.trials == end:
                    self.evals.later(pool, result.trials, self.learner.greedy_policy())
                    if result.trials < end:  # the last save waits for the last evaluations (train)
                        self.save()
                if on_trial:
                    on_trial(i, r, result)

    def trial(self, i: int, log: Path | None) -> tuple[Start, TrialResult]:
        """Training trial ``i`` (its start from the seed and ``i`` alone), learnt from and counted."""
        result = self.result
        start = random_starts(self.spec, 1, np.random.SeedSequence([result.seed, i]).generate_state(1)[0])[0]
        t0 = time.perf_counter()
        try:
            r = run_trial(self.task, start, self.learner.act, self.learner.observe, log=log)
        finally:
            self.task.close("interrupted", "training stopped")  # a trial's log is never left half-written
        result.train_s += time.perf_counter() - t0
        result.trials += 1
        result.outcomes[r.outcome] = result.outcomes.get(r.outcome, 0) + 1
        return start, r

    def save(self) -> None:
        """The model as it is between trials, with what a resume needs to go on as if never stopped."""
        from ..learning import model_file

        result, spec = self.result, self.spec
        meta = {
            "algorithm": result.algorithm,
            "scenario": spec.scenario.name,
            "scenario_sha256": spec.scenario.sha256,
            "seed": result.seed,
            "trials": result.trials,
            "eval_every": self.eval_every,
            "eval_starts": self.eval_starts,
            "eval_seed": EVAL_SEED,
            "params": spec.params.to_json(),
            "curve": [asdict(p) for p in result.curve],
            "hand_coded": result.hand_coded,
            "hand_coded_reward": result.hand_coded_reward,
            "random": result.random,
            "random_reward": result.random_reward,
            "outcomes": result.outcomes,
            "learner_rng": self.learner.rng.bit_generator.state,
            "pending_evaluations": [{"trials": n, "policy": p.tolist()} for n, p, _ in self.evals.pending],
        }
        with deferred():
            model_file.save(self.out, self.learner, meta)
            result.saved, result.saved_in = result.trials, self.out


def _trial_row(i: int, start: Start, r: TrialResult) -> list:
    """Trial ``i``'s row of the trials CSV (:data:`TRIAL_COLUMNS`)."""
    return [
        i,
        f"{start.x:.3f}",
        f"{start.y:.3f}",
        f"{math.degrees(start.heading):.1f}",
        start.seed,
        r.outcome,
        r.actions,
        f"{r.reward:g}",
        *r.counts,
    ]


def write_curve(result: Training, out: Path) -> None:
    """The learning curve (the paper's Figure 3) as CSV and PNG beside ``out`` (:func:`curve_paths`)."""
    csv_path, png_path = curve_paths(out)
    with atomic(csv_path) as tmp, tmp.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(
            [
                "trials",
                "successes",
                "reward_per_trial",
                "actions_per_trial",
                "hand_coded_successes",
                "hand_coded_reward_per_trial",
                "random_successes",
                "random_reward_per_trial",
            ]
        )
        hc_reward = "" if result.hand_coded_reward is None else f"{result.hand_coded_reward:.2f}"
        r_reward = "" if result.random_reward is None else f"{result.random_reward:.2f}"
        for p in result.curve:
            w.writerow(
                [
                    p.trials,
                    p.successes,
                    f"{p.reward:.2f}",
                    f"{p.actions:.2f}",
                    result.hand_coded,
                    hc_reward,
                    result.random,
                    r_reward,
                ]
            )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    trials = [p.trials for p in result.curve]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    # the hand-coded level is drawn over the learned curve, dashed and in a colour of its own, so it
    # shows where the two meet (they often do: 95 against 97 of 99)
    ax.plot(
        trials,
        [p.successes for p in result.curve],
        "o-",
        color="tab:blue",
        zorder=2,
        label=f"learned ({result.algorithm})",
    )
    for level, colour, name in ((result.hand_coded, "tab:orange", "hand-coded"), (result.random, "tab:gray", "random")):
        if level is not None:
            ax.axhline(level, color=colour, ls="--", lw=2, zorder=3, label=f"{name} ({level})")
    top = max([p.successes for p in result.curve] + [result.hand_coded or 0, result.random or 0, 1])
    ax.set_xlabel("training trials")
    ax.set_ylabel("successful test trials")
    ax.set_ylim(0, top * 1.1 + 1)
    ax.set_title("Successes of the test starts (Figure 3)")
    ax.legend(loc="lower right")
    # where successes do not separate the policies, their cost does: reward per test trial
    ax2.plot(
        trials,
        [p.reward for p in result.curve],
        "o-",
        color="tab:blue",
        zorder=2,
        label=f"learned ({result.algorithm})",
    )
    for reward, colour, name in (
        (result.hand_coded_reward, "tab:orange", "hand-coded"),
        (result.random_reward, "tab:gray", "random"),
    ):
        if reward is not None:
            ax2.axhline(reward, color=colour, ls="--", lw=2, zorder=3, label=f"{name} ({reward:.0f})")
    ax2.set_xlabel("training trials")
    ax2.set_ylabel("reward per test trial (higher is cheaper)")
    ax2.set_title("Reward per trial of the test starts")
    ax2.legend(loc="best")
    fig.tight_layout()
    with atomic(png_path) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
