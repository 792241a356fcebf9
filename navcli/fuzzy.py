"""Fuzzy numbers held as alpha-cut intervals (learning-agent paper, section 5.1; notes, section 3).

A fuzzy number is stored as its cuts at the fixed levels ``ALPHAS``: one closed interval per
level, nested (a higher level's cut lies inside a lower one's). Arithmetic is interval arithmetic
level by level, the standard alpha-cut form of the extension principle (Dubois-Prade): widths add
under addition and subtraction, products take the extreme products, and division refuses a
divisor whose support contains zero. :class:`FuzzyAngle` adds wrap-around for headings. The
imprecision measures of the papers are the width of the 70 % cut (:meth:`Fuzzy.width`) and the
combined landmark imprecision :func:`landmark_imprecision`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple

ALPHAS = (0.0, 0.3, 0.7, 1.0)
"""The membership levels whose cuts are kept: the support, the two levels of the papers' features, the core."""
CUT = 0.7  # the papers' imprecision is the width of the 70 % alpha-cut
LAMBDA, BETA = 0.2, 1.0  # learning-agent paper, section 5.1: weights of I(l)
TWO_PI = 2.0 * math.pi

Interval = tuple[float, float]


def _wrap(a: float) -> float:
    a = math.fmod(a + math.pi, TWO_PI)
    if a <= 0.0:
        a += TWO_PI
    return a - math.pi


@dataclass(frozen=True)
class Fuzzy:
    """A fuzzy number: ``cuts[k]`` is the interval of membership >= ``ALPHAS[k]``.

    >>> a = Fuzzy.trapezoid(0.0, 1.0, 2.0, 3.0)
    >>> a.support, a.core, round(a.width(0.7), 9)  # the 70 % cut is [0.7, 2.3]
    ((0.0, 3.0), (1.0, 2.0), 1.6)
    >>> round((a + a).width(0.7), 9), (a - a).support  # widths add, also under subtraction
    (3.2, (-3.0, 3.0))
    >>> Fuzzy.crisp(2.0) / Fuzzy.around(0.0, 1.0)
    Traceback (most recent call last):
    ...
    ZeroDivisionError: divisor's support [-1.0, 1.0] contains 0
    """

    cuts: tuple[Interval, ...]

    def __post_init__(self) -> None:
        # One chained comparison checks all (made per sighting, so kept cheap): the bounds nest,
        # lo0 <= lo1 <= ... <= hi1 <= hi0, and are finite (a NaN fails any comparison).
        c = self.cuts
        if len(c) == 4:
            (a0, b0), (a1, b1), (a2, b2), (a3, b3) = c
            if -math.inf < a0 <= a1 <= a2 <= a3 <= b3 <= b2 <= b1 <= b0 < math.inf:
                return
        self._complain()

    def _complain(self) -> None:
        """Raise the error that says what is wrong with the cuts."""
        if len(self.cuts) != len(ALPHAS):
            raise ValueError(f"expected {len(ALPHAS)} cuts, got {len(self.cuts)}")
        for (lo, hi), (lo2, hi2) in zip(self.cuts, self.cuts[1:]):
            if not (lo <= lo2 <= hi2 <= hi):
                raise ValueError(f"cuts are not nested: {self.cuts}")
        for lo, hi in self.cuts:
            if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
                raise ValueError(f"bad cut [{lo}, {hi}]")

    # -- construction
    @classmethod
    def trapezoid(cls, a: float, b: float, c: float, d: float) -> Fuzzy:
        """Support [a, d], core [b, c]; linear in between."""
        if not (a <= b <= c <= d):
            raise ValueError(f"a trapezoid needs a <= b <= c <= d, got {a}, {b}, {c}, {d}")
        # clamped to the core so that rounding can never un-nest the cuts (min and max written out:
        # a comparison is cheaper than the builtins' call, and picks the same float)
        rise, fall = b - a, d - c
        cuts = []
        for al in ALPHAS:
            lo, hi = a + al * rise, d - al * fall
            cuts.append((b if b < lo else lo, c if c > hi else hi))
        return cls(tuple(cuts))

    @classmethod
    def triangle(cls, a: float, m: float, b: float) -> Fuzzy:
        return cls.trapezoid(a, m, m, b)

    @classmethod
    def crisp(cls, x: float) -> Fuzzy:
        return cls.trapezoid(x, x, x, x)

    @classmethod
    def around(cls, x: float, spread: float, core: float = 0.0) -> Fuzzy:
        """Symmetric about ``x``: support ``x +- spread``, core ``x +- core``."""
        return cls.trapezoid(x - spread, x - core, x + core, x + spread)

    # -- reading
    def cut(self, alpha: float) -> Interval:
        """The alpha-cut, interpolated linearly between the stored levels."""
        if not 0.0 <= alpha <= 1.0:
            raise ValueError(f"alpha must lie in [0, 1], got {alpha}")
        for k in range(len(ALPHAS) - 1):
            a0, a1 = ALPHAS[k], ALPHAS[k + 1]
            if alpha <= a1:
                t = (alpha - a0) / (a1 - a0)
                (l0, h0), (l1, h1) = self.cuts[k], self.cuts[k + 1]
                return l0 + t * (l1 - l0), h0 + t * (h1 - h0)
        return self.cuts[-1]

    def width(self, alpha: float = CUT) -> float:
        """Width of the alpha-cut; at 0.7 it is the papers' imprecision measure."""
        lo, hi = self.cut(alpha)
        return hi - lo

    @property
    def support(self) -> Interval:
        return self.cuts[0]

    @property
    def core(self) -> Interval:
        return self.cuts[-1]

    @property
    def centre(self) -> float:
        """The crisp value used for decisions: the middle of the core."""
        lo, hi = self.cuts[-1]
        return (lo + hi) / 2

    def contains(self, x: float, alpha: float = 0.0) -> bool:
        lo, hi = self.cut(alpha)
        return lo <= x <= hi

    # -- arithmetic, level by level
    def _zip(self, other: Fuzzy, f: Callable[[Interval, Interval], Interval]) -> Fuzzy:
        return Fuzzy(tuple(f(a, b) for a, b in zip(self.cuts, other.cuts)))

    def __add__(self, other: Fuzzy | float) -> Fuzzy:
        o = _lift(other)
        return self._zip(o, lambda a, b: (a[0] + b[0], a[1] + b[1]))

    def __radd__(self, other: Fuzzy | float) -> Fuzzy:  # a method, not an alias: mypyc compiles this module
        return self.__add__(other)

    def __neg__(self) -> Fuzzy:
        return Fuzzy(tuple((-hi, -lo) for lo, hi in self.cuts))

    def __sub__(self, other: Fuzzy | float) -> Fuzzy:
        o = _lift(other)
        return self._zip(o, lambda a, b: (a[0] - b[1], a[1] - b[0]))

    def __rsub__(self, other: float) -> Fuzzy:
        return _lift(other) - self

    def __mul__(self, other: Fuzzy | float) -> Fuzzy:
        if not isinstance(other, Fuzzy):
            return self.scale(other)

        def mul(a: Interval, b: Interval) -> Interval:
            p = (a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1])
            return min(p), max(p)

        return self._zip(other, mul)

    def __rmul__(self, other: Fuzzy | float) -> Fuzzy:
        return self.__mul__(other)

    def __truediv__(self, other: Fuzzy | float) -> Fuzzy:
        o = _lift(other)
        lo, hi = o.support
        if lo <= 0.0 <= hi:
            raise ZeroDivisionError(f"divisor's support [{lo}, {hi}] contains 0")
        return self * Fuzzy(tuple((1.0 / hi, 1.0 / lo) for lo, hi in o.cuts))  # the reciprocal

    def scale(self, k: float) -> Fuzzy:
        """Multiply by the crisp number ``k``."""
        return Fuzzy(tuple((min(k * lo, k * hi), max(k * lo, k * hi)) for lo, hi in self.cuts))

    def widen(self, e: float) -> Fuzzy:
        """Add the symmetric triangular error (-e, 0, e): each cut grows by ``e * (1 - alpha)`` a side."""
        return Fuzzy(tuple((lo - e * (1 - al), hi + e * (1 - al)) for (lo, hi), al in zip(self.cuts, ALPHAS)))


def _lift(x: Fuzzy | float) -> Fuzzy:
    return x if isinstance(x, Fuzzy) else Fuzzy.crisp(float(x))


@dataclass(frozen=True)
class FuzzyAngle:
    """A fuzzy heading (rad): cuts as intervals ``[lo, hi]`` around a centre wrapped to (-pi, pi].

    An interval may straddle +-pi; widths are capped at 2 pi (the heading is then unknown).
    Sums and differences add widths, as for :class:`Fuzzy`, and re-wrap the centre.
    """

    value: Fuzzy

    @classmethod
    def around(cls, a: float, spread: float, core: float = 0.0) -> FuzzyAngle:
        return cls(Fuzzy.around(_wrap(a), min(spread, math.pi), min(core, math.pi))).normalised()

    def normalised(self) -> FuzzyAngle:
        """Shift so the centre lies in (-pi, pi]; cap every cut at a full turn."""
        c = self.value.centre
        shift = _wrap(c) - c
        cuts = []
        for lo, hi in self.value.cuts:
            lo, hi = lo + shift, hi + shift
            if hi - lo > TWO_PI:
                mid = (lo + hi) / 2
                lo, hi = mid - math.pi, mid + math.pi
            cuts.append((lo, hi))
        # capping can break nesting only by making an inner cut wider than a capped outer one
        for k in range(len(cuts) - 2, -1, -1):
            lo, hi = cuts[k]
            ilo, ihi = cuts[k + 1]
            cuts[k] = (ilo if ilo < lo else lo, ihi if ihi > hi else hi)  # min, max
        return FuzzyAngle(Fuzzy(tuple(cuts)))

    @property
    def centre(self) -> float:
        return _wrap(self.value.centre)

    def width(self, alpha: float = CUT) -> float:
        return min(self.value.width(alpha), TWO_PI)

    def contains(self, a: float, alpha: float = 0.0) -> bool:
        lo, hi = self.value.cut(alpha)
        if hi - lo >= TWO_PI:
            return True
        return 0.0 <= (a - lo) % TWO_PI <= hi - lo

    def __add__(self, other: FuzzyAngle | Fuzzy | float) -> FuzzyAngle:
        o = other.value if isinstance(other, FuzzyAngle) else other
        return FuzzyAngle(self.value + o).normalised()

    def __sub__(self, other: FuzzyAngle | Fuzzy | float) -> FuzzyAngle:
        o = other.value if isinstance(other, FuzzyAngle) else other
        return FuzzyAngle(self.value - o).normalised()


def landmark_imprecision(heading: FuzzyAngle, distance: Fuzzy) -> float:
    """I(l) of a landmark whose fuzzy heading and distance are given (section 5.1), in [0, 1]."""
    return imprecision(heading.width(CUT), distance.width(CUT))


def imprecision(i_h: float, i_d: float) -> float:
    """``I(l) = lambda * tanh(beta * I_d) + (1 - lambda) * I_h / (2 pi)`` (section 5.1), with
    ``I_h`` (rad) and ``I_d`` (m) the widths of the 70 % cuts, lambda = 0.2, beta = 1.

    >>> imprecision(0.0, 0.0), imprecision(TWO_PI, 0.0)  # crisp; heading unknown
    (0.0, 0.8)
    >>> round(imprecision(math.pi, 1.0), 4)  # 0.2 tanh(1) + 0.8 / 2
    0.5523
    """
    return LAMBDA * math.tanh(BETA * i_d) + (1 - LAMBDA) * min(i_h, TWO_PI) / TWO_PI


class FuzzyPoint(NamedTuple):
    """A fuzzy position as nested discs: a crisp egocentric centre ``(x, y)`` (m) and the radius
    (m) of each cut at ``ALPHAS`` (the support first, the core last; non-increasing).

    It is how the visual memory holds a remembered point and how the Map Manager returns a
    recalled landmark; read as the papers read positions, it gives a fuzzy distance and a fuzzy
    heading, and their 70 % cuts give the imprecision I(l).

    One is made per remembered landmark every tick (a NamedTuple: docs/design.md, "Values made every tick").

    Attributes:
        x: the crisp centre's x (m, egocentric: ahead).
        y: the crisp centre's y (m, egocentric: to the left).
        radii: each cut's radius (m), at the levels of ``ALPHAS``: the support first, the core last.

    >>> p = FuzzyPoint(3.0, 4.0, (1.0, 0.7, 0.3, 0.0))
    >>> p.distance().support, p.distance().core  # 5 m away, +- 1 m
    ((4.0, 6.0), (5.0, 5.0))
    >>> round(p.imprecision(), 4)  # 70 % cut: r = 0.3, so 0.2 tanh(0.6) + 0.8 * 2 asin(0.3 / 5) / 2 pi
    0.1227
    """

    x: float
    y: float
    radii: tuple[float, ...]

    def radius(self, alpha: float) -> float:
        """The cut's radius at ``alpha``, interpolated between the stored levels.

        Args:
            alpha: the membership level, in [0, 1] (0: the support, 1: the core).

        Returns:
            The radius (m).
        """
        k, t = _LEVEL.get(alpha) or _level(alpha)
        r = self.radii
        return r[k] + t * (r[k + 1] - r[k]) if t is not None else r[-1]

    def distance(self) -> Fuzzy:
        """The fuzzy distance to the point from the robot.

        Returns:
            A fuzzy number (m): each cut's interval, the support first.
        """
        d = math.hypot(self.x, self.y)
        return Fuzzy(tuple((max(0.0, d - r), d + r) for r in self.radii))

    def heading(self) -> FuzzyAngle:
        """The fuzzy heading of the point from the robot.

        Returns:
            A fuzzy angle (rad, egocentric: 0 ahead, + left): each cut's interval, the support first.
        """
        d = math.hypot(self.x, self.y)
        h = math.atan2(self.y, self.x)
        return FuzzyAngle(Fuzzy(tuple((h - _half_angle(r, d), h + _half_angle(r, d)) for r in self.radii)))

    def heading_width(self, alpha: float = CUT) -> float:
        """The width of the heading's alpha-cut, read off the disc: ``heading().width(alpha)``
        without building the fuzzy number (a per-tick quantity).

        Args:
            alpha: the membership level (default: the 70 % cut).

        Returns:
            The width (rad).
        """
        return 2.0 * _half_angle(self.radius(alpha), math.hypot(self.x, self.y))

    def imprecision(self) -> float:
        """I(l) (section 5.1) from the 70 % cut: the widths of heading and distance, read off the
        disc directly (what :meth:`heading` and :meth:`distance` give, without building them).

        :meth:`radius` and :func:`_half_angle` are written out, the same operations, as they
        are read for every remembered point twice a second, and for every landmark weighed.

        Returns:
            I(l), in [0, 1].
        """
        x, y, radii = self
        r = radii[_CUT_K] + _CUT_T * (radii[_CUT_K + 1] - radii[_CUT_K])  # self.radius(CUT)
        d = math.hypot(x, y)
        return imprecision(2.0 * (math.pi if r >= d else math.asin(r / d)), 2.0 * r)

    @classmethod
    def enclosing(cls, x: Fuzzy, y: Fuzzy) -> FuzzyPoint:
        """The nested discs that hold the boxes ``x`` x ``y`` cut by cut, centred on the core's
        centre (so a true point inside a box stays inside its disc).

        Args:
            x: the fuzzy x (m).
            y: the fuzzy y (m), with as many cuts.

        Returns:
            The fuzzy point.
        """
        cx, cy = x.centre, y.centre
        radii = []
        for (xlo, xhi), (ylo, yhi) in zip(x.cuts, y.cuts):
            radii.append(math.hypot(max(cx - xlo, xhi - cx), max(cy - ylo, yhi - cy)))
        for k in range(len(radii) - 2, -1, -1):  # rounding must not un-nest them
            radii[k] = max(radii[k], radii[k + 1])
        return cls(cx, cy, tuple(radii))

    def contains(self, p: tuple[float, float], alpha: float = 0.0) -> bool:
        """Whether a point lies in a cut of this fuzzy point.

        Args:
            p: the point ``(x, y)`` (m, egocentric).
            alpha: the cut's level (default: the support).

        Returns:
            True if ``p`` is in the cut's disc.
        """
        return math.hypot(p[0] - self.x, p[1] - self.y) <= self.radius(alpha) + 1e-9


def _level(alpha: float) -> tuple[int, float | None]:
    """Where ``alpha`` lies among ``ALPHAS``: the level ``k`` below it and the fraction ``t`` of the
    way to the next (None above the last), as :meth:`FuzzyPoint.radius` interpolates."""
    for k in range(len(ALPHAS) - 1):
        a0, a1 = ALPHAS[k], ALPHAS[k + 1]
        if alpha <= a1:
            return k, (alpha - a0) / (a1 - a0)
    return len(ALPHAS) - 1, None


_LEVEL = {a: _level(a) for a in (*ALPHAS, CUT)}  # the levels read every tick, looked up once
_CUT_K, _CUT_LEVEL_T = _LEVEL[CUT]  # FuzzyPoint.imprecision's level: between ALPHAS[1] and ALPHAS[2]
assert _CUT_LEVEL_T is not None
_CUT_T: float = _CUT_LEVEL_T


def _half_angle(r: float, d: float) -> float:
    """Half the angle a disc of radius ``r`` at distance ``d`` spans, seen from the origin."""
    return math.pi if r >= d else math.asin(r / d)
