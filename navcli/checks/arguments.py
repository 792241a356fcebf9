"""The Python API's arguments, each declared once by its name with what it must be, and checked
at every call of a public function (:func:`checked`) before any work: a wrong one is refused with
an :class:`ArgumentError` naming the function and the argument, never a ``TypeError`` from deep
inside or a value taken silently (``seed=True``, ``time_limit="10"``, a string where a list is
meant, which Python would walk letter by letter).

A check is a function of the value that returns what is wrong with it, in words, or ``None``;
the small ones below are combined into the table of each layer's names (:data:`COMMON` here, the
scenario's and the plan's in :mod:`navcli.api`). Ranges that a value's own class checks (a seed
below 2**64, the time limit's range) are left to it: here the kinds and the counts.

Standard library only: imported with navcli's lightest modules.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import os
from collections.abc import Mapping
from typing import Any, Callable, TypeVar, cast

from .. import NavcliError

Check = Callable[[Any], "str | None"]
F = TypeVar("F", bound=Callable[..., Any])

MAX_JOBS = 256
"""Most local worker processes (each forks the whole of navcli: some 100 MB)."""


class ArgumentError(NavcliError, TypeError):
    """An argument of a public function refused: the message names the function and the
    argument. Also a ``TypeError``, as Python's own refusal of an argument is."""


def shown(value: Any) -> str:
    """A value as a refusal quotes it: its repr, cut short."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def optional(check: Check) -> Check:
    """``check``, or ``None`` (the default: the scenario's, the machine's ...)."""
    return lambda v: None if v is None else check(v)


def flag(v: Any) -> str | None:
    return None if isinstance(v, bool) else "expected True or False"


def whole(least: int, most: int | None = None, what: str = "a whole number") -> Check:
    """An ``int`` (not a bool: ``True`` is no count and no seed) from ``least`` to ``most``."""

    def check(v: Any) -> str | None:
        if isinstance(v, bool):
            return f"expected {what} (an int); a bool is not one"
        if not isinstance(v, numbers.Integral):
            return f"expected {what} (an int), got {type(v).__name__}"
        n = int(v)
        if n < least or (most is not None and n > most):
            return (
                f"expected {what} from {least} to {most}"
                if most is not None
                else f"expected {what} of at least {least}"
            )
        return None

    return check


def real(positive: bool = False) -> Check:
    """A finite ``int`` or ``float`` (not a bool, not a string of digits), above 0 if ``positive``."""

    def check(v: Any) -> str | None:
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            return f"expected a number, got {type(v).__name__}"
        if not math.isfinite(v) or (positive and v <= 0):
            return "expected a finite number" + (" above 0" if positive else "")
        return None

    return check


def text(v: Any) -> str | None:
    """A name: a non-empty ``str``."""
    if not isinstance(v, str):
        return f"expected a name (a str), got {type(v).__name__}"
    return None if v.strip() else "expected a name, got an empty string"


def path(v: Any) -> str | None:
    """A file or folder: a ``str`` or a path (``pathlib.Path``, any ``os.PathLike``), not empty."""
    if not isinstance(v, (str, os.PathLike)):
        return f"expected a path (a str or pathlib.Path), got {type(v).__name__}"
    return None if os.fspath(v) not in ("", b"") else "expected a path, got an empty one"


def instance(*kinds: type, what: str) -> Check:
    """An instance of one of ``kinds`` (classes of the layer that declares the check)."""
    return lambda v: None if isinstance(v, kinds) else f"expected {what}, got {type(v).__name__}"


def either(*checks: Check, what: str) -> Check:
    """A value that one of ``checks`` passes (else ``what`` it should have been)."""

    def check(v: Any) -> str | None:
        if any(c(v) is None for c in checks):
            return None
        return f"expected {what}, got {type(v).__name__}"

    return check


def listing(item: Check, what: str, empty: bool = False) -> Check:
    """A list or tuple (any sequence but a string, which Python would walk letter by letter) of
    ``what``, each passing ``item``; not empty unless ``empty``."""

    def check(v: Any) -> str | None:
        if isinstance(v, (str, bytes, os.PathLike, Mapping)) or not isinstance(v, (list, tuple, range)):
            return f"expected a list of {what}, got {type(v).__name__}" + (
                f" (for one, write [{v!r}])" if isinstance(v, (str, os.PathLike)) else ""
            )
        if not v and not empty:
            return f"expected a list of {what}, got an empty one"
        for i, x in enumerate(v):
            why = item(x)
            if why is not None:
                return f"item {i} ({shown(x)}): {why}"
        return None

    return check


def names_to_values(v: Any) -> str | None:
    """A mapping of dotted parameter names to values (``{"pilot.K": 30}``)."""
    if not isinstance(v, Mapping):
        return f'expected a dict of parameter names to values ({{"pilot.K": 30}}), got {type(v).__name__}'
    bad = next((k for k in v if not isinstance(k, str)), None)
    return None if bad is None else f"a parameter name is a str, got {shown(bad)}"


def function(v: Any) -> str | None:
    return None if callable(v) else f"expected a function, got {type(v).__name__}"


COMMON: dict[str, Check] = {
    "seed": optional(whole(0, 2**64 - 1, "a seed")),
    "pilot": optional(text),
    "perception": optional(text),
    "navigation": optional(text),
    "time_limit": optional(real(positive=True)),
    "params": optional(names_to_values),
    "observers": listing(function, "observers (functions of the mission and its tick)", empty=True),
    "log": optional(path),
    "out": optional(path),
    "overwrite": flag,
    "reruns": whole(1, what="a count of reruns"),
    "jobs": optional(whole(1, MAX_JOBS, "a count of worker processes")),
    "pilots": listing(text, "pilot names"),
    "also": listing(text, "pilot names", empty=True),
}
"""The arguments every layer's functions share, by name."""


def checked(table: Mapping[str, Check], where: str = "navcli") -> Callable[[F], F]:
    """A decorator: every argument a call gives the function is checked by the check ``table``
    holds under its name, before the function runs. A function with an argument the table lacks
    is refused when it is decorated, so no public argument goes unchecked.

    Args:
        table: the check of each argument, by its name.
        where: the module the function is public in, for messages.

    Returns:
        The decorator; the function it returns raises :class:`ArgumentError` on a wrong argument.
    """

    def decorate(fn: F) -> F:
        signature = inspect.signature(fn)
        missing = [n for n in signature.parameters if n not in table]
        if missing:
            raise TypeError(f"{fn.__qualname__}: no check declared for {', '.join(missing)}")
        name = f"{where}.{fn.__name__}"

        @functools.wraps(fn)
        def call(*args: Any, **kwargs: Any) -> Any:
            try:
                given = signature.bind(*args, **kwargs).arguments
            except TypeError as e:
                raise ArgumentError(f"{name}(): {e}") from None
            for arg, value in given.items():
                why = table[arg](value)
                if why is not None:
                    raise ArgumentError(f"{name}(): {arg}={shown(value)}: {why}")
            return fn(*args, **kwargs)

        return cast(F, call)

    return decorate
