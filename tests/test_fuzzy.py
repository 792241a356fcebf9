"""Fuzzy numbers as alpha-cuts: worked examples and properties."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navcli.fuzzy import ALPHAS, CUT, Fuzzy, FuzzyAngle, FuzzyPoint, imprecision, landmark_imprecision


def test_trapezoid_cuts_are_linear_between_support_and_core():
    f = Fuzzy.trapezoid(1.0, 2.0, 3.0, 5.0)
    assert f.support == (1.0, 5.0) and f.core == (2.0, 3.0)
    assert f.cut(0.7) == pytest.approx((1.7, 3.6))
    assert f.cut(0.5) == pytest.approx((1.5, 4.0))  # between stored levels, interpolated
    assert f.width() == pytest.approx(1.9)  # the 70 % cut, the papers' imprecision
    assert f.centre == 2.5


def test_worked_arithmetic():
    a, b = Fuzzy.triangle(1, 2, 3), Fuzzy.trapezoid(4, 5, 6, 8)
    assert (a + b).support == (5, 11) and (a + b).core == (7, 8)
    assert (b - a).support == (1, 7) and (b - a).core == (3, 4)
    assert (a * b).support == (4, 24) and (a * b).core == (10, 12)
    assert (b / a).support == pytest.approx((4 / 3, 8.0)) and (b / a).core == pytest.approx((2.5, 3.0))
    assert (a * -2).support == (-6, -2)
    assert (3 - a).core == (1, 1)


def test_division_by_an_interval_holding_zero_is_refused():
    with pytest.raises(ZeroDivisionError, match="contains 0"):
        Fuzzy.triangle(1, 2, 3) / Fuzzy.triangle(-1, 1, 2)
    with pytest.raises(ZeroDivisionError):
        Fuzzy.crisp(1.0) / 0.0


def test_angles_wrap_around_pi():
    a = FuzzyAngle.around(math.radians(175), math.radians(10))
    assert a.contains(math.radians(-178))  # 182 degrees, just across the seam
    assert not a.contains(math.radians(-170))
    b = a + math.radians(10)
    assert b.centre == pytest.approx(math.radians(-175))
    assert b.width(0.0) == pytest.approx(math.radians(20))
    lost = FuzzyAngle.around(0.0, 3.0) + FuzzyAngle.around(0.0, 3.0)
    assert lost.width(0.0) == pytest.approx(2 * math.pi) and lost.contains(math.pi)


def test_landmark_imprecision_follows_section_5_1():
    h = FuzzyAngle.around(0.3, 0.5)  # 70 % cut width 0.3
    d = Fuzzy.around(4.0, 1.0)  # 70 % cut width 0.6
    assert landmark_imprecision(h, d) == pytest.approx(0.2 * math.tanh(0.6) + 0.8 * 0.3 / (2 * math.pi))
    assert landmark_imprecision(FuzzyAngle.around(0, 0), Fuzzy.crisp(2.0)) == 0.0


values = st.floats(-50, 50, allow_nan=False)
spreads = st.floats(0, 10, allow_nan=False)


@st.composite
def fuzzies(draw):
    x, s, c = draw(values), draw(spreads), draw(spreads)
    return x, Fuzzy.around(x, s + c, c)


@settings(deadline=None)
@given(fuzzies(), fuzzies(), st.sampled_from(ALPHAS))
def test_true_values_stay_inside_the_cuts_they_were_built_from(fa, fb, alpha):
    (x, a), (y, b) = fa, fb
    for f, v in ((a + b, x + y), (a - b, x - y), (a * b, x * y), (a.scale(-1.5), -1.5 * x)):
        lo, hi = f.cut(alpha)
        assert lo - 1e-9 * (1 + abs(v)) <= v <= hi + 1e-9 * (1 + abs(v))
    lo, hi = b.support
    if lo > 1e-6 or hi < -1e-6:  # divisors well away from zero (a tinier one overflows to infinity)
        lo, hi = (a / b).cut(alpha)
        assert lo - 1e-9 * (1 + abs(x / y)) <= x / y <= hi + 1e-9 * (1 + abs(x / y))


@settings(deadline=None)
@given(fuzzies(), fuzzies(), st.sampled_from(ALPHAS))
def test_widths_add_under_addition_and_subtraction(fa, fb, alpha):
    (_, a), (_, b) = fa, fb
    assert (a + b).width(alpha) == pytest.approx(a.width(alpha) + b.width(alpha), abs=1e-9)
    assert (a - b).width(alpha) == pytest.approx(a.width(alpha) + b.width(alpha), abs=1e-9)


@settings(deadline=None)
@given(fuzzies(), fuzzies())
def test_cuts_stay_nested_through_arithmetic(fa, fb):
    (_, a), (_, b) = fa, fb
    for f in (a + b, a - b, a * b, a.widen(0.3)):
        for (lo, hi), (lo2, hi2) in zip(f.cuts, f.cuts[1:]):
            assert lo <= lo2 <= hi2 <= hi


@settings(deadline=None)
@given(values, values, spreads, st.floats(0, 1))
def test_point_imprecision_is_its_70_cut_read_off_the_disc(x, y, r0, core):
    """FuzzyPoint.imprecision writes radius() and the half-angle out: the same bits as the plain
    definition from radius(CUT) and heading_width(CUT), and close to the fuzzy numbers' widths."""
    d = r0 * (core - 1.0)  # a core of radius core * r0
    p = FuzzyPoint(x, y, tuple(r0 + a * d for a in ALPHAS))
    r = p.radius(CUT)
    assert p.imprecision() == imprecision(p.heading_width(CUT), 2.0 * r)
    if math.hypot(x, y) > r:
        assert p.imprecision() == pytest.approx(landmark_imprecision(p.heading(), p.distance()), abs=1e-9)
