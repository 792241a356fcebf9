"""How a parameter is declared: once, with its type, unit, range and description. Its checks
(at construction and on every override), ``navcli params``, the JSON Schema of the scenario
format and the reference docs are all read from that one declaration.

A parameter set is a frozen dataclass deriving from :class:`ParamSet`, whose every field is made
by :func:`param`. navcli's own sets (:mod:`navcli.params`) are declared this way, and so are a
plugin's (its ``Params`` class attribute):

>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Gains(ParamSet):
...     gain: float = param(1.5, "1/s", "turn rate per radian of heading error", above=0.0)
...     sectors: int = param(72, "", "sectors of the polar histogram", at_least=8)
...     smooth: bool = param(True, "", "average each turn with the one before")
>>> Gains(gain=2).gain, Gains(smooth=0).smooth
(2.0, False)
>>> Gains(gain=-1.0)
Traceback (most recent call last):
...
navcli.params.declare.ParamError: Gains.gain must be above 0, got -1

The type is the default's: a ``bool`` is a switch (``true``/``false``; 1 and 0 are taken for
them), an ``int`` a whole number, a ``float`` a number, a tuple of floats a list of numbers (with
``intervals``, a fixed count of increasing bounds), a word with ``choices`` one of those words. A number is at least 0 unless its declaration
says otherwise (``at_least``, ``above``, ``at_most``, ``below``; ``at_least=None`` for no lower
bound). Units: ``m``, ``s``, ``rad``, ``m/s`` ..., ``""`` for a pure number.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass
from typing import Any, ClassVar, Iterator, Literal, Mapping

from .. import NavcliError

MAX_LIST = 64
"""The most numbers a list-valued parameter takes (navcli's longest default has 6)."""
DECLARED = "navcli.param"
"""The key of a field's metadata that holds its :class:`Declared`."""
_UNSET: Any = object()

Kind = Literal["switch", "integer", "number", "numbers", "intervals", "choice"]


class ParamError(NavcliError):
    """A parameter named that does not exist, or given a value of the wrong type or outside its
    declared range."""


def _is_number(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool)


@dataclass(frozen=True)
class Declared:
    """One parameter's declaration (made by :func:`param`): its kind, unit, description and range.
    A list's bounds hold for each of its numbers."""

    kind: Kind
    unit: str
    description: str
    at_least: float | None = None
    above: float | None = None
    at_most: float | None = None
    below: float | None = None
    count: int = 0  # intervals: how many bounds (the default's, which the states are built on)
    choices: tuple[str, ...] = ()  # a choice: the words it takes
    course: bool = True  # False: a guard that never changes a run's course, left out of its run id

    def check(self, name: str, value: Any) -> Any:
        """``value`` in this parameter's type (a whole number as ``int``, a switch as ``bool``, a
        list as a tuple of floats, a choice as one of its words), or :class:`ParamError` naming
        ``name`` and saying why not."""
        if self.kind == "choice":
            if value not in self.choices:
                raise ParamError(f"{name} is one of {', '.join(self.choices)}, got {value!r}"[:300])
            return value
        if self.kind == "switch":
            if isinstance(value, bool):
                return value
            if _is_number(value) and value in (0, 1):
                return bool(value)
            raise ParamError(f"{name} is a switch: expects true or false (or 1, 0), got {value!r}"[:300])
        if self.kind in ("numbers", "intervals"):
            if (
                not isinstance(value, (list, tuple))
                or len(value) > MAX_LIST
                or not all(_is_number(v) and math.isfinite(v) for v in value)
            ):
                raise ParamError(f"{name} expects a list of at most {MAX_LIST} finite numbers, got {value!r}"[:300])
            out = tuple(float(v) for v in value)
            if self.kind == "intervals" and (len(out) != self.count or any(b <= a for a, b in zip(out, out[1:]))):
                raise ParamError(
                    f"{name} must be {self.count} increasing numbers (the bounds of {self.count + 1} "
                    f"intervals), got {list(out)}"
                )
            for v in out:
                self._within(name, v)
            return out
        if isinstance(value, str):
            raise ParamError(f"{name}: {value!r} is not a number"[:300])
        if not _is_number(value) or not math.isfinite(value):
            raise ParamError(f"{name} expects a finite number, got {value!r}"[:300])
        if self.kind == "integer":
            if value != int(value):
                raise ParamError(f"{name} expects a whole number, got {value!r}")
            value = int(value)
        else:
            value = float(value)
        self._within(name, value)
        return value

    def _within(self, name: str, v: float) -> None:
        for bound, ok, words in (
            (self.at_least, v >= (self.at_least or 0), "at least"),
            (self.above, v > (self.above or 0), "above"),
            (self.at_most, v <= (self.at_most or 0), "at most"),
            (self.below, v < (self.below or 0), "below"),
        ):
            if bound is not None and not ok:
                raise ParamError(f"{name} must be {words} {bound:g}, got {v:g}")

    @property
    def lower(self) -> tuple[float | None, bool]:
        """The lower bound and whether it is open (``above``), or (None, False) for none."""
        return (self.above, True) if self.above is not None else (self.at_least, False)

    @property
    def upper(self) -> tuple[float | None, bool]:
        """The upper bound and whether it is open (``below``), or (None, False) for none."""
        return (self.below, True) if self.below is not None else (self.at_most, False)

    def range_text(self) -> str:
        """The values an override may take, as ``navcli params`` shows them: ``[0, 1]``,
        ``(0, inf)``, ``whole number in [1, inf)``, ``true or false``, ``3 increasing numbers``.

        >>> Declared("number", "m", "", above=0.0).range_text(), Declared("integer", "", "", 1, at_most=6).range_text()
        ('(0, inf)', 'whole number in [1, 6]')
        """
        if self.kind == "switch":
            return "true or false"
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "intervals":
            return f"{self.count} increasing numbers"
        (lo, lo_open), (hi, hi_open) = self.lower, self.upper
        text = (
            (("(" if lo_open else "[") + f"{lo:g}" if lo is not None else "(-inf")
            + ", "
            + (f"{hi:g}" + (")" if hi_open else "]") if hi is not None else "inf)")
        )
        return {"integer": "whole number in ", "numbers": "numbers each in "}.get(self.kind, "") + text

    def json_schema(self, default: Any) -> dict[str, Any]:
        """This parameter's JSON Schema (draft-07), with its default, unit and description."""
        unit = f" ({self.unit})" if self.unit else ""
        d: dict[str, Any] = {"description": self.description + unit}
        if self.kind == "switch":
            return d | {"type": "boolean", "default": default}
        if self.kind == "choice":
            return d | {"enum": list(self.choices), "default": default}
        bounds: dict[str, Any] = {}
        (lo, lo_open), (hi, hi_open) = self.lower, self.upper
        if lo is not None:
            bounds["exclusiveMinimum" if lo_open else "minimum"] = lo
        if hi is not None:
            bounds["exclusiveMaximum" if hi_open else "maximum"] = hi
        if self.kind in ("numbers", "intervals"):
            n = {"minItems": self.count, "maxItems": self.count} if self.kind == "intervals" else {"maxItems": MAX_LIST}
            return d | {"type": "array", "items": {"type": "number"} | bounds, "default": list(default)} | n
        return d | {"type": "integer" if self.kind == "integer" else "number", "default": default} | bounds


def param(
    default: Any,
    unit: str,
    description: str,
    *,
    at_least: float | None = _UNSET,
    above: float | None = None,
    at_most: float | None = None,
    below: float | None = None,
    intervals: bool = False,
    choices: tuple[str, ...] = (),
    course: bool = True,
) -> Any:
    """A parameter field of a :class:`ParamSet`. A default outside its own range is a mistake of
    the declaration, refused when the class is made.

    Args:
        default: its default value: a number (``float`` or ``int``), a switch (``bool``), a word
            (``str``, with ``choices``) or a tuple of numbers.
        unit: its unit (``"m"``, ``"deg"``, ``"s"``; ``""`` for a pure number).
        description: what it does, in a phrase (``navcli params`` prints it).
        at_least: a number's lowest value (0 unless said otherwise; None: no lower bound).
        above: a lower bound the value must exceed, in place of ``at_least``.
        at_most: its highest value.
        below: an upper bound the value must stay under.
        intervals: a tuple of numbers is a fixed count of increasing bounds (a set of intervals).
        choices: a word's allowed values.
        course: False marks a guard that never changes what a run does (a limit on wall-clock
            time): the run's id leaves it out, so two runs that differ in it alone are one run.

    Returns:
        The dataclass field that declares it.
    """
    if isinstance(default, str) and choices:
        kind: Kind = "choice"
    elif isinstance(default, bool):
        kind = "switch"
    elif isinstance(default, int):
        kind = "integer"
    elif isinstance(default, float):
        kind = "number"
    elif isinstance(default, tuple):
        kind = "intervals" if intervals else "numbers"
    else:
        raise TypeError(
            f"a parameter's default is a bool, an int, a float, a tuple of floats or a word with its "
            f"choices, got {default!r}"
        )
    if at_least is _UNSET:
        at_least = 0.0 if kind in ("integer", "number") and above is None else None
    if kind in ("switch", "choice"):
        at_least = above = at_most = below = None
    d = Declared(
        kind,
        unit,
        " ".join(description.split()),
        at_least,
        above,
        at_most,
        below,
        len(default) if kind == "intervals" else 0,
        tuple(choices),
        course,
    )
    d.check("the default", default)
    return dataclasses.field(default=default, metadata={DECLARED: d})


@dataclass(frozen=True)
class ParamSet:
    """A set of parameters (navcli's robot, pilot, navigation, vision and learning sets, or a
    plugin's own): a frozen dataclass whose every field is declared by :func:`param`. Every value
    is checked against its declaration when the set is made (so ``RobotParams(max_speed=-1)``
    raises :class:`ParamError`), and converted to its declared type."""

    group: ClassVar[str] = ""
    """The name the set's parameters are addressed by (``pilot`` in ``pilot.K``); a plugin's set
    takes its plugin's name."""

    def __post_init__(self) -> None:
        prefix = self.group or type(self).__name__
        for f in dataclasses.fields(self):
            d = f.metadata.get(DECLARED)
            if d is None:
                raise TypeError(
                    f"{type(self).__name__}.{f.name} is not declared: make it with "
                    f"navcli.params.param(default, unit, description, ...)"
                )
            value = getattr(self, f.name)
            checked = d.check(f"{prefix}.{f.name}", value)
            if checked is not value:
                object.__setattr__(self, f.name, checked)

    @classmethod
    def declarations(cls) -> Iterator[tuple[str, Declared, Any]]:
        """Every parameter of the set.

        Yields:
            (name, declaration, default) of each parameter, in declaration order.
        """
        for f in dataclasses.fields(cls):
            yield f.name, f.metadata[DECLARED], f.default

    def to_json(self) -> dict[str, Any]:
        """The set as plain JSON values.

        Returns:
            Each parameter's value by its name (``{"K": 18.0, ...}``), tuples as lists.
        """
        return {
            f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in dataclasses.fields(self)
        }

    def changed(self, name: str, values: Mapping[str, Any]) -> ParamSet:
        """A copy with some values changed, each checked against its declaration.

        Args:
            name: the set's name in messages (``pilot``).
            values: the new values by their parameters' names (``{"K": 30.0}``).

        Returns:
            The copy.

        Raises:
            ParamError: an unknown parameter, or a value its declaration refuses.
        """
        fields = {f.name: f.metadata[DECLARED] for f in dataclasses.fields(self)}
        out = {}
        for key, value in values.items():
            if key not in fields:
                raise ParamError(f"unknown parameter {name}.{key}")
            out[key] = fields[key].check(f"{name}.{key}", value)
        return dataclasses.replace(self, **out)


def suggest(name: str, known: Iterator[str] | list[str]) -> str:
    """`` (did you mean pilot.K?)`` for a mistyped parameter ``name``, or where to find the names."""
    import difflib

    known = list(known)
    close = (
        [k for k in known if k.endswith("." + name)]
        or difflib.get_close_matches(name, known, n=1)
        or [k for k in known if k.lower() == name.lower()]
    )
    return f" (did you mean {close[0]}?)" if close else " (see `navcli params` for the names)"


def parse_override(item: str) -> tuple[str, Any]:
    """``"pilot.K=30"`` -> ``("pilot.K", 30.0)``; a list-valued parameter takes its numbers in
    brackets, comma-separated (``[]`` for none); a switch ``true`` or ``false`` (or 1, 0); any other
    word is kept as it is (a parameter that names a choice, ``vision.walls=known``). The value is
    checked by :meth:`~navcli.params.Params.override`.

    >>> parse_override("navigation.kappa1=0.5"), parse_override("pilot.looks=false")
    (('navigation.kappa1', 0.5), ('pilot.looks', False))
    >>> parse_override("pilot.reflex_look_pans_deg=[-60, 0, 60]"), parse_override("vision.walls=known")
    (('pilot.reflex_look_pans_deg', [-60.0, 0.0, 60.0]), ('vision.walls', 'known'))
    """
    name, sep, value = item.partition("=")
    name, value = name.strip(), value.strip()
    if not sep or not name:
        raise ParamError(f"{item!r}: expected NAME=VALUE, e.g. pilot.K=30")
    if len(value) > 1000:
        raise ParamError(f"{name}: a value of {len(value)} characters is not a parameter's")
    if value.lower() in ("true", "false"):
        return name, value.lower() == "true"
    listed = value.startswith("[") and value.endswith("]")
    parts = [v.strip() for v in value[1:-1].split(",")] if listed else [value]
    if listed and parts == [""]:
        return name, []
    numbers_ = []
    for v in parts:
        try:
            numbers_.append(float(v))
        except ValueError:
            if not listed and v.replace("-", "").replace("_", "").isalnum():
                return name, v  # a word: a choice (the parameter's check says which words it takes)
            raise ParamError(
                f"{item!r}: {v!r} is not a number"
                + ("" if listed else " (a list parameter takes [a, b, ...])" if "," in value else "")
            ) from None
    return name, numbers_ if listed else numbers_[0]
