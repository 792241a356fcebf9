"""The intervals of the tables and the report stay in their quantity's range, and every comparison
warns of a small sample in the same words."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from navcli.analysis.stats import MIN_SAMPLE, bootstrap_mean, small_sample, wilson_interval


@given(st.integers(0, 500), st.integers(1, 500))
def test_a_wilson_interval_lies_in_0_1_and_holds_the_observed_rate(k, n):
    k = min(k, n)
    lo, hi = wilson_interval(k, n)
    assert 0.0 <= lo <= k / n <= hi <= 1.0
    assert hi - lo > 0.0  # never the zero-width interval of a rate of 0/n or n/n


@given(st.lists(st.floats(0.0, 1e4), min_size=2, max_size=40), st.integers(1, 6))
def test_a_bootstrap_interval_lies_within_the_values_and_holds_their_mean(values, n_groups):
    groups = [i % n_groups for i in range(len(values))]
    for g in (None, groups):
        m, lo, hi = bootstrap_mean(values, g)
        assert m == sum(values) / len(values) or math.isclose(m, sum(values) / len(values))
        if g is not None and n_groups == 1:  # one group: its spread is unknown, no interval
            assert math.isnan(lo) and math.isnan(hi)
            continue
        assert min(values) - 1e-9 <= lo <= m + 1e-6 and m - 1e-6 <= hi <= max(values) + 1e-9


def test_a_bootstrap_with_groups_resamples_groups_not_values():
    """Two groups of ten equal values each: resampled as groups, a resample's mean is 1, 2 or 3;
    as values, almost always near 2. The grouped interval is [1, 3], the other far narrower."""
    values, groups = [1.0] * 10 + [3.0] * 10, ["a"] * 10 + ["b"] * 10
    assert bootstrap_mean(values, groups) == (2.0, 1.0, 3.0)
    _, lo, hi = bootstrap_mean(values)
    assert 1.4 < lo < 2.0 < hi < 2.6


def test_the_small_sample_warning_is_one_sentence_for_every_comparison():
    assert small_sample("x", MIN_SAMPLE, "runs") is None
    assert (
        small_sample("x", MIN_SAMPLE - 1, "pairs")
        == f"x: only {MIN_SAMPLE - 1} pairs; with fewer than {MIN_SAMPLE} its 95 % intervals are too uncertain to trust"
    )
