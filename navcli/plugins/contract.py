"""The quick look every plugin lookup takes at a class, before it is run: of its kind, its
``Params`` a :class:`~navcli.params.ParamSet` made with its defaults, its ``Info`` a
``msgspec.Struct`` that extends ``/pilot`` in a schema the viewers read. What running it shows is
the checker's (:mod:`.checker`), which runs missions and so sits above the registry."""

from __future__ import annotations

import dataclasses
import sys
from importlib.machinery import EXTENSION_SUFFIXES
from typing import TYPE_CHECKING

import msgspec

from .. import NavcliError
from ..log.format import json_schema, plugin_pilot_message, viewer_problems
from ..params import ParamSet
from ..pilot import Pilot

if TYPE_CHECKING:
    from .registry import Component


def _params_problems(c: Component) -> list[str]:
    P = c.params_class
    if P is None:
        return []
    if not (isinstance(P, type) and issubclass(P, ParamSet) and dataclasses.is_dataclass(P)):
        return ["its Params is not a frozen dataclass deriving from navcli.params.ParamSet"]
    try:
        P()
    except (TypeError, NavcliError) as e:
        return [f"its Params cannot be made with its defaults: {e}"]
    return []


def _info_problems(c: Component) -> list[str]:
    info = c.info_class
    if info is None:
        return []
    if not (isinstance(info, type) and issubclass(info, msgspec.Struct)):
        return ["its Info is not a msgspec.Struct (the fields it adds to /pilot, each typed)"]
    try:
        schema = json_schema(plugin_pilot_message(c))
    except (ValueError, TypeError) as e:
        return [f"its Info cannot extend /pilot: {e}"]
    return [f"its Info's schema would be refused by the viewers: {p}" for p in viewer_problems(schema)]


def contract_problems(c: Component) -> list[str]:
    """What is wrong with ``c``'s class itself (not yet run): of the wrong kind, or its ``Params``
    or ``Info`` malformed. Empty when nothing is."""
    if c.builtin:
        return []
    cls = c.cls
    if c.kind == "pilot":
        if not (isinstance(cls, type) and issubclass(cls, Pilot)):
            return [f"{cls!r} is not a subclass of navcli.pilot.Pilot (a pilot implements Pilot.avoid)"]
        compiled = _compiled_bases(cls, Pilot)
        if compiled:
            return [
                f"it subclasses {compiled[0]}, which this build of navcli compiles (navcli.BUILD), and a Python "
                f"class cannot subclass a compiled one but navcli.pilot.Pilot: subclass Pilot, and call one of "
                f"{compiled[0].rpartition('.')[2]} from its avoid"
            ]
    elif not callable(cls) or not callable(getattr(cls, "bid", None)):
        return [f"{cls!r} is no Navigation agent: it needs bid(situation) -> list[Bid] (navcli.navigation.Agent)"]
    if getattr(cls, "version", None) is not None and not isinstance(cls.version, str):
        return [f"its version is {cls.version!r}, not text"]
    return _params_problems(c) + (_info_problems(c) if c.kind == "pilot" else [])


def _compiled_bases(cls: type, allowed: type) -> list[str]:
    """The classes of navcli's that ``cls`` derives from and this build compiles (mypyc: no Python
    class derives from one, but ``allowed``, which is marked to let them)."""
    out = []
    for base in cls.__mro__[1:]:
        if base is allowed or not base.__module__.startswith("navcli."):
            continue
        file = getattr(sys.modules.get(base.__module__), "__file__", None) or ""
        if file.endswith(tuple(EXTENSION_SUFFIXES)):
            out.append(f"{base.__module__}.{base.__qualname__}")
    return out
