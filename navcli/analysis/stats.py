"""The intervals of navcli's tables and report, each within its quantity's range, and the one
warning every comparison gives when a sample is too small to trust them.

- A rate, a count of successes out of ``n``: the Wilson score interval (:func:`wilson_interval`),
  always inside [0, 1] and sound at 0/n and n/n, where the normal approximation is not.
- A mean: a percentile bootstrap (:func:`bootstrap_mean`), inside the range of the values (a mean
  of counts never gets a negative bound, as a t-interval over a few runs does). Observations that
  come in groups (a start's trials over the runs of ``compare policies``, which share the start)
  are resampled group by group, so correlated trials are not counted as independent.
- Identical reruns are one observation: a verdict (``navcli reproduce``) counts runs
  whose summaries are alike in every number (:data:`navcli.analysis.tables.IDENTITY`: ground-truth
  perception has no noise, so its reruns repeat one run) once, in its interval and its sample size,
  and says how many runs were distinct. The tables of ``compare`` and ``report`` count every run.
- Fewer than :data:`MIN_SAMPLE` observations (runs, pairs, starts): the interval is still given,
  and :func:`small_sample` says, in the same words in every comparison, that it is too uncertain
  to trust.

Numpy only; the draws are seeded, so the same numbers always give the same intervals.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

RESAMPLES = 10_000
"""Bootstrap resamples."""
MIN_SAMPLE = 10
"""Fewer observations than this and a 95 % interval is too uncertain to trust: a
percentile bootstrap of fewer than 10 covers the true mean markedly less often than 95 % of the
time, and the Wilson interval of a rate spans some 30 points or more."""


def wilson_interval(successes: float, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score 95 % interval of a success rate (sound at 0/n and n/n, unlike the normal
    approximation); NaNs for no trial.

    >>> [round(x, 3) for x in wilson_interval(45, 45)]
    [0.921, 1.0]
    >>> [round(x, 3) for x in wilson_interval(0, 3)]
    [0.0, 0.562]
    """
    if n == 0:
        return math.nan, math.nan
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    # exactly 0 at 0/n and 1 at n/n, where the formula's rounding may miss them by an ulp
    return (0.0 if successes == 0 else max(0.0, centre - half)), (1.0 if successes == n else min(1.0, centre + half))


def bootstrap_mean(
    values: Sequence[float] | np.ndarray, groups: Sequence | np.ndarray | None = None, seed: int = 0
) -> tuple[float, float, float]:
    """The mean of ``values`` and its percentile bootstrap 95 % interval, resampling whole groups
    (``groups[i]`` names the group of ``values[i]``) or, without groups, single values. NaNs for no
    value or a NaN among them (a metric that does not apply); no interval (NaN bounds) for one
    group, whose spread is unknown.

    Two groups of means 1 and 3, two values each: a resample is both groups once (mean 2), one
    twice (1 or 3), each with probability 1/4, so the 2.5 % and 97.5 % points are 1 and 3:

    >>> bootstrap_mean([0.0, 2.0, 3.0, 3.0], groups=["a", "a", "b", "b"])
    (2.0, 1.0, 3.0)
    >>> bootstrap_mean([4.0])[1:]
    (nan, nan)
    """
    x = np.asarray(values, dtype=float)
    if x.size == 0 or np.isnan(x).any():
        return math.nan, math.nan, math.nan
    mean = float(x.mean())
    if groups is None:
        sums, counts = x, np.ones_like(x)
    else:
        _, index = np.unique(np.asarray(groups), return_inverse=True)
        sums, counts = np.bincount(index, weights=x), np.bincount(index).astype(float)
    k = len(sums)
    if k < 2:
        return mean, math.nan, math.nan
    pick = np.random.default_rng(seed).integers(0, k, size=(RESAMPLES, k))
    means = sums[pick].sum(axis=1) / counts[pick].sum(axis=1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    return mean, float(lo), float(hi)


def small_sample(subject: str, n: int, unit: str) -> str | None:
    """The warning of every comparison (``compare pilots``, ``compare policies``, ``report``,
    ``reproduce``) when ``n`` (``unit``: runs, pairs, starts) is below :data:`MIN_SAMPLE`; None
    otherwise.

    >>> small_sample("hand-coded", 3, "starts")
    'hand-coded: only 3 starts; with fewer than 10 its 95 % intervals are too uncertain to trust'
    """
    if n >= MIN_SAMPLE:
        return None
    return f"{subject}: only {n} {unit}; with fewer than {MIN_SAMPLE} its 95 % intervals are too uncertain to trust"
