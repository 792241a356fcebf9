"""Prescott's beta-coefficient network with fuzzy numbers (notes, section 3; learning-agent paper,
section 3): the Map Manager's memory of where landmarks are relative to each other.

A landmark D seen together with three others A, B, C is encoded by its barycentric coordinates
in their triangle, the beta-vector (eq. 3.1 of the thesis, reconstructed in the notes)::

    D = beta_A A + beta_B B + beta_C C,   beta_A + beta_B + beta_C = 1

Barycentric coordinates do not change under any rotation and translation of the frame, so when
A, B and C are known again from anywhere, ``D' = A' + beta_B (B' - A') + beta_C (C' - A')``
locates D although it is not seen. A *beta-unit* ``ABC/D`` holds one such vector.

Fuzzy extension (the thesis' own operators are not available; ours, as the notes propose):
positions are fuzzy (:class:`navcli.fuzzy.FuzzyPoint`, read as boxes cut by cut) and every
operation is interval arithmetic per alpha-cut (Cramer's rule for the 2 x 2 system in the
triangle's edge vectors). Interval arithmetic is inclusion-monotone, so if the true positions
lie in the supports when D is encoded and when it is recalled, the true position lies in the
recalled support. A triangle whose crisp collinearity ``Col`` is near 1, or whose fuzzy
determinant's support spans 0, is refused (the matrix is singular or may be). Among several
estimates of one landmark the least imprecise (lowest I(l)) is chosen, as Busquets did.

Cost is bounded whatever the length of a run: at most ``units_per_landmark`` units per landmark
are kept (the sharpest), and encoding considers only the landmarks of the image just taken.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from ..fuzzy import ALPHAS, Fuzzy, FuzzyPoint


class Iv:
    """Fuzzy numbers as interval vectors: ``lo[k], hi[k]`` is the cut at ``ALPHAS[k]``.

    Plain tuples of four floats, not numpy arrays: at four elements numpy's call overhead is
    most of an operation's cost (an encode took ~0.8 ms with arrays), and the arithmetic is the
    same IEEE operations, element by element, so the results are the same to the last bit."""

    __slots__ = ("lo", "hi")

    def __init__(self, lo: tuple[float, ...], hi: tuple[float, ...]):
        self.lo, self.hi = lo, hi

    def fuzzy(self) -> Fuzzy:
        return Fuzzy(tuple(zip(self.lo, self.hi)))

    def __add__(self, o: Iv) -> Iv:
        return Iv(tuple([a + b for a, b in zip(self.lo, o.lo)]), tuple([a + b for a, b in zip(self.hi, o.hi)]))

    def __sub__(self, o: Iv) -> Iv:
        return Iv(tuple([a - b for a, b in zip(self.lo, o.hi)]), tuple([a - b for a, b in zip(self.hi, o.lo)]))

    def __mul__(self, o: Iv) -> Iv:
        lo, hi = [], []
        for al, ah, bl, bh in zip(self.lo, self.hi, o.lo, o.hi):
            p = (al * bl, al * bh, ah * bl, ah * bh)
            lo.append(min(p))
            hi.append(max(p))
        return Iv(tuple(lo), tuple(hi))

    def __truediv__(self, o: Iv) -> Iv:
        if o.lo[0] <= 0.0 <= o.hi[0]:
            raise ZeroDivisionError("the divisor's support contains 0")
        return self * Iv(tuple([1.0 / h for h in o.hi]), tuple([1.0 / lo for lo in o.lo]))

    def width(self) -> float:
        """Width of the support."""
        return self.hi[0] - self.lo[0]


def _xy(p: FuzzyPoint) -> tuple[Iv, Iv]:
    """The fuzzy coordinates of ``p`` (:meth:`FuzzyPoint.coords`: each cut's disc in its box), as
    interval vectors directly."""
    x, y, radii = p.x, p.y, p.radii
    return (
        Iv(tuple([x - r for r in radii]), tuple([x + r for r in radii])),
        Iv(tuple([y - r for r in radii]), tuple([y + r for r in radii])),
    )


def collinearity(a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]) -> float:
    """``Col(A, B, C) = 1 - 4 sqrt(3) Area / (a^2 + b^2 + c^2)``: 0 for an equilateral triangle,
    1 for collinear points (the notes' substitute for the thesis' eq. 3.4).

    >>> round(collinearity((0, 0), (1, 0), (0.5, math.sqrt(3) / 2)), 9), collinearity((0, 0), (1, 0), (2, 0))
    (0.0, 1.0)
    """
    area = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2
    s = math.dist(a, b) ** 2 + math.dist(b, c) ** 2 + math.dist(c, a) ** 2
    return 1.0 if s == 0.0 else 1.0 - 4.0 * math.sqrt(3.0) * area / s


@dataclass(frozen=True)
class BetaUnit:
    """``ABC/D``: the fuzzy beta-coefficients of landmark ``target`` in the triangle of ``basis``
    (beta_B and beta_C; beta_A = 1 - beta_B - beta_C is implied by the recall's form)."""

    basis: tuple[str, str, str]
    target: str
    beta_b: Iv
    beta_c: Iv

    @property
    def name(self) -> str:
        return f"{''.join(self.basis) if all(len(k) == 1 for k in self.basis) else '-'.join(self.basis)}/{self.target}"

    @property
    def spread(self) -> float:
        """How imprecise the encoding is (the supports' widths of the two betas)."""
        return self.beta_b.width() + self.beta_c.width()


def encode(
    basis: tuple[str, str, str], target: str, points: dict[str, FuzzyPoint], max_collinearity: float = 0.95
) -> BetaUnit | None:
    """The beta-unit of ``target`` in the triangle ``basis``, from the fuzzy positions ``points``
    (any common frame); ``None`` for a (nearly) collinear triangle or a fuzzy determinant whose
    support spans zero.

    Cramer's rule for ``t = beta_B u + beta_C v``, with ``u = B - A``, ``v = C - A``, ``t = D - A``.
    """
    a, b, c = (points[k] for k in basis)
    if collinearity((a.x, a.y), (b.x, b.y), (c.x, c.y)) > max_collinearity:
        return None
    ax, ay = _xy(a)
    bx, by = _xy(b)
    cx, cy = _xy(c)
    dx, dy = _xy(points[target])
    ux, uy, vx, vy, tx, ty = bx - ax, by - ay, cx - ax, cy - ay, dx - ax, dy - ay
    det = ux * vy - uy * vx
    try:
        beta_b = (tx * vy - ty * vx) / det
        beta_c = (ux * ty - uy * tx) / det
    except ZeroDivisionError:
        return None
    return BetaUnit(basis, target, beta_b, beta_c)


def recall(unit: BetaUnit, points: dict[str, FuzzyPoint]) -> FuzzyPoint:
    """Where ``unit.target`` is, from where its basis is now: ``A' + beta_B (B' - A') + beta_C (C' - A')``."""
    ax, ay = _xy(points[unit.basis[0]])
    bx, by = _xy(points[unit.basis[1]])
    cx, cy = _xy(points[unit.basis[2]])
    x = ax + unit.beta_b * (bx - ax) + unit.beta_c * (cx - ax)
    y = ay + unit.beta_b * (by - ay) + unit.beta_c * (cy - ay)
    return FuzzyPoint.enclosing(_nested(x), _nested(y))


def _nested(v: Iv) -> Fuzzy:
    """Interval arithmetic keeps the cuts nested mathematically; rounding may not, by an ulp."""
    lo, hi = list(v.lo), list(v.hi)
    for k in range(1, len(ALPHAS)):
        lo[k] = max(lo[k], lo[k - 1])
        hi[k] = min(hi[k], hi[k - 1])
        if lo[k] > hi[k]:
            lo[k] = hi[k] = (lo[k] + hi[k]) / 2
    return Iv(tuple(lo), tuple(hi)).fuzzy()


class BetaNetwork:
    """The object-units (landmark ids) and beta-units of the map (see the module docstring)."""

    def __init__(self, units_per_landmark: int = 6, max_collinearity: float = 0.95, basis_candidates: int = 5):
        self.units: dict[str, dict[tuple[str, str, str], BetaUnit]] = {}
        self.units_per_landmark = units_per_landmark
        self.max_collinearity = max_collinearity
        self.basis_candidates = basis_candidates

    @property
    def landmarks(self) -> set[str]:
        """The object-units: every landmark that encodes or is encoded."""
        out = set(self.units)
        for per in self.units.values():
            for basis in per:
                out.update(basis)
        return out

    def __len__(self) -> int:
        return sum(map(len, self.units.values()))

    def learn(self, viewframe: dict[str, FuzzyPoint], targets: set[str] | None = None) -> list[BetaUnit]:
        """Encode landmarks of one viewframe (at least 4, precise enough: the caller's choice),
        each in the least collinear triangle of its sharpest neighbours; keep the sharpest
        ``units_per_landmark`` units per landmark. ``targets`` limits which landmarks are encoded
        (those the image showed); the others serve as bases. Returns the units added."""
        if len(viewframe) < 4:
            return []
        ranked = sorted(viewframe, key=lambda k: viewframe[k].imprecision())
        added = []
        for target in ranked:
            if targets is not None and target not in targets:
                continue
            others = [k for k in ranked if k != target][: self.basis_candidates]
            best = min(
                itertools.combinations(others, 3),
                key=lambda t: collinearity(*((viewframe[k].x, viewframe[k].y) for k in t)),
            )
            a, b, c = sorted(best)
            basis = (a, b, c)
            unit = encode(basis, target, viewframe, self.max_collinearity)
            if unit is None:
                continue
            per = self.units.setdefault(target, {})
            old = per.get(basis)
            if old is not None and old.spread <= unit.spread:
                continue
            per[basis] = unit
            if len(per) > self.units_per_landmark:
                del per[max(per, key=lambda b: per[b].spread)]
            if basis in per:
                added.append(unit)
        return added

    def locate(self, target: str, known: dict[str, FuzzyPoint], tries: int = 3) -> tuple[FuzzyPoint, BetaUnit] | None:
        """The least imprecise recall of ``target`` from the ``tries`` sharpest units whose basis
        is ``known`` now."""
        best = None
        usable = [u for b, u in self.units.get(target, {}).items() if all(k in known for k in b)]
        for unit in sorted(usable, key=lambda u: u.spread)[:tries]:
            p = recall(unit, known)
            if best is None or p.imprecision() < best[0].imprecision():
                best = (p, unit)
        return best
