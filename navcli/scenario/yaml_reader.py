"""A bounded YAML reader: the one way navcli reads a YAML file (a scenario, a sweep plan).

What is read is bounded before it is built (size, depth, aliases expanded, value length), only
PyYAML's safe loader is used, and YAML 1.1's surprising numbers (``010``, ``1:30``, ``0x6``) are
refused with what to write instead. :class:`Reader` is the typed access to what was loaded: each
refusal is recorded as a :class:`Problem` naming the file, the line and the field, and reading goes
on so that every problem of a file is shown at once (``navcli validate``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from .. import NavcliError
from ..geometry import Point
from .model import RANGES


# --- Refusals ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Problem:
    file: str
    line: int | None
    field: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{where}: {self.field}: {self.message}" if self.field else f"{where}: {self.message}"


class ScenarioError(NavcliError):
    """A scenario file was refused; ``problems`` lists every reason found."""

    headline = "scenario refused"

    def __init__(self, problems: list[Problem]):
        self.problems = problems
        shown = [str(p) for p in problems[:MAX_PROBLEMS]]
        if len(problems) > MAX_PROBLEMS:
            shown.append(f"... and {len(problems) - MAX_PROBLEMS} more problems in {problems[0].file}")
        super().__init__("\n".join(shown))


# --- Loading -------------------------------------------------------------------------------
# What the loader reads at most, checked before the YAML is built into values (a
# scenario is a few kilobytes; these bounds are hundreds of times that, and each keeps a hostile
# file from costing more than a fraction of a second or a few megabytes).
MAX_BYTES = 256_000
"""Largest scenario file read (bytes)."""
MAX_DEPTH = 32
"""Deepest nesting of mappings and lists (a scenario needs 5)."""
MAX_NODES = 20_000
"""Most values (keys, items, scalars) in the document, every alias counted as what it expands to,
so an alias bomb is refused before it is expanded."""
MAX_SCALAR = 10_000
"""Longest single value (characters)."""
MAX_DIGITS = 30
"""Longest plain number (characters); a longer one cannot be a seed or a size."""
MAX_PROBLEMS = 20
"""Problems printed for one file; the rest are counted."""
_NOT_YAML_CHARS = re.compile("[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f]")
_SURROGATE = re.compile("[\ud800-\udfff]")
_LONG_NUMBER = re.compile(r"^[-+]?[0-9_.,:]+([eE][-+]?[0-9]+)?$")
_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
"""libyaml's safe loader when PyYAML was built with it (about 10x faster, and its nodes keep
their line); PyYAML's pure-Python safe loader otherwise. Both refuse every ``!!python`` tag."""


def read_bounded(path: str | Path, max_bytes: int, what: str, error: type[ScenarioError]) -> str:
    """The UTF-8 text of the file ``path``, read at most ``max_bytes + 1`` bytes (so a FIFO, a
    device or a huge file costs nothing more); refused with ``error`` naming ``what`` is expected
    when it is a folder, missing, unreadable, too large or not UTF-8."""
    p = Path(path)
    try:
        if p.is_dir():
            raise error([Problem(str(p), None, "", f"is a folder, expected {what}")])
        if p.exists() and not p.is_file():
            raise error([Problem(str(p), None, "", f"is not a regular file (a device or a pipe), expected {what}")])
        with p.open("rb") as f:
            data = f.read(max_bytes + 1)
    except FileNotFoundError:
        raise error([Problem(str(p), None, "", "no such file")]) from None
    except OSError as e:
        raise error([Problem(str(p), None, "", f"cannot be read ({e.strerror or e})")]) from None
    if len(data) > max_bytes:
        raise error([Problem(str(p), None, "", f"is larger than {max_bytes:,} bytes; {what} is a few kilobytes")])
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[: e.start].count(b"\n") + 1
        raise error([Problem(str(p), line, "", f"is not UTF-8 text (byte 0x{data[e.start]:02x})")]) from None


def _refuse(source: str, line: int | None, message: str, field: str = "") -> ScenarioError:
    return ScenarioError([Problem(source, line, field, message)])


def _bounded(text: str, source: str) -> None:
    """Refuse, before anything is built, a text that breaks one of the bounds above: characters
    YAML forbids, too deep, too many values (aliases expanded), an alias to itself, a value too
    long. One pass over the parser's events: linear in the file, whatever its aliases.

    libyaml has limits of its own: from PyYAML 6.0.4 its scanner refuses about 1,000 levels of
    flow nesting while it looks ahead, before our depth check has seen the events. So when
    libyaml refuses a text, what it read up to its error is read again by PyYAML's pure-Python
    parser, which streams the events: where one of our bounds is broken there, it is reported in
    our words; else libyaml's error is (the cut text's own end is no error of the file)."""
    if len(text) > MAX_BYTES:
        raise _refuse(source, None, f"is larger than {MAX_BYTES:,} characters; a scenario is a few kilobytes")
    bad = _NOT_YAML_CHARS.search(text)
    if bad:
        line = text.count("\n", 0, bad.start()) + 1
        raise _refuse(source, line, f"holds the character U+{ord(bad.group()):04X}, which a YAML file may not hold")
    try:
        _walk_events(_Loader(text), source)
    except yaml.YAMLError as e:
        if _Loader is not yaml.SafeLoader:
            mark = getattr(e, "problem_mark", None) or getattr(e, "context_mark", None)
            read = text[: mark.index + 1] if mark is not None and mark.index is not None else text
            try:
                _walk_events(yaml.SafeLoader(read), source)
            except yaml.YAMLError:
                pass
        if isinstance(e, yaml.MarkedYAMLError):
            raise _yaml_problem(e, source) from None
        raise _refuse(source, None, f"not valid YAML: {e}") from None


def _walk_events(loader: Any, source: str) -> None:
    """The bound pass of :func:`_bounded` with one parser; a bound broken raises
    :class:`ScenarioError`, the parser's own refusal its ``YAMLError``."""
    try:
        depth = nodes = 0
        sizes: dict[str, int] = {}  # anchor -> values it stands for
        open_: list[tuple[str | None, int]] = []  # collections being read: (anchor, nodes before it)
        while loader.check_event():
            ev = loader.get_event()
            line = ev.start_mark.line + 1 if ev.start_mark else None
            if isinstance(ev, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
                depth += 1
                if depth > MAX_DEPTH:
                    raise _refuse(source, line, f"is nested more than {MAX_DEPTH} levels deep")
                open_.append((ev.anchor, nodes))
                nodes += 1
            elif isinstance(ev, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                depth -= 1
                anchor, before = open_.pop()
                if anchor is not None:
                    sizes[anchor] = nodes - before
            elif isinstance(ev, yaml.ScalarEvent):
                if len(ev.value) > MAX_SCALAR:
                    raise _refuse(
                        source, line, f"holds a value of {len(ev.value):,} characters (at most {MAX_SCALAR:,})"
                    )
                if not ev.style and len(ev.value) > MAX_DIGITS and _LONG_NUMBER.match(ev.value):
                    raise _refuse(
                        source, line, f"holds a number of {len(ev.value)} characters, too large for any field"
                    )
                nodes += 1
                if ev.anchor is not None:
                    sizes[ev.anchor] = 1
            elif isinstance(ev, yaml.AliasEvent):
                if ev.anchor not in sizes:
                    inside = any(a == ev.anchor for a, _ in open_)
                    raise _refuse(
                        source,
                        line,
                        f"the alias *{ev.anchor} "
                        + (
                            "refers to the value that holds it (a loop)"
                            if inside
                            else "names no anchor defined before it"
                        ),
                    )
                nodes += sizes[ev.anchor]
            if nodes > MAX_NODES:
                raise _refuse(source, line, f"holds more than {MAX_NODES:,} values (aliases expanded)")
    finally:
        loader.dispose()


def _yaml_problem(e: yaml.MarkedYAMLError, source: str) -> ScenarioError:
    mark = e.problem_mark or e.context_mark
    line = mark.line + 1 if mark else None
    what = e.problem or e.context or "malformed"
    if e.problem and e.context and e.context_mark and e.context_mark.line + 1 != line:
        what += f" ({e.context} that began on line {e.context_mark.line + 1})"  # an unclosed [ or { is found at the end
    return _refuse(source, line, f"not valid YAML: {what}")


def parse_yaml(text: str, source: str) -> tuple[Any, dict[tuple, int]]:
    """Safe-load ``text`` once it is known to be bounded, keeping the line of every key and item
    (1-based)."""
    _bounded(text, source)
    root, own, data = _compose(text, source)
    if root is None:
        raise ScenarioError([Problem(source, None, "", "the file is empty (expected a scenario mapping)")])
    if not isinstance(root, yaml.MappingNode):
        kind = "a list" if isinstance(root, yaml.SequenceNode) else "a single value"
        raise ScenarioError(
            [
                Problem(
                    source,
                    root.start_mark.line + 1,
                    "",
                    f"the file holds {kind}, expected a mapping of scenario fields",
                )
            ]
        )
    walk = _LineWalk(source, own, data, root)
    walk.node(root, ())
    if walk.problems:
        raise ScenarioError(walk.problems)
    return data, walk.lines


def _compose(text: str, source: str) -> tuple[yaml.Node | None, set[tuple[int, int]], Any]:
    """The document's root node, its own keys (:func:`_own_keys`) and the data loaded from it;
    YAML the loader refuses is a :class:`ScenarioError`."""
    loader = _Loader(text)
    try:
        root = loader.get_single_node()
        own = _own_keys(root)  # before construction, which merges `<<` keys into the mappings in place
        data = loader.construct_document(root) if root is not None else None
    except yaml.MarkedYAMLError as e:
        raise _yaml_problem(e, source) from None
    except yaml.YAMLError as e:
        raise _refuse(source, None, f"not valid YAML: {e}") from None
    except ValueError as e:  # a value the constructor cannot build (a date out of range ...)
        raise _refuse(source, None, f"not valid YAML: {e}") from None
    finally:
        loader.dispose()
    return root, own, data


class _LineWalk:
    """One walk over the node tree: the line of every key and item (``lines``, by path), and the
    problems the data cannot show: keys that are not names, keys written twice, YAML 1.1 numbers."""

    def __init__(self, source: str, own: set[tuple[int, int]], data: Any, root: yaml.Node) -> None:
        self.source, self.own, self.data = source, own, data
        self.lines: dict[tuple, int] = {(): root.start_mark.line + 1}
        self.problems: list[Problem] = []

    def node(self, node: yaml.Node, path: tuple) -> None:
        if isinstance(node, yaml.MappingNode):
            self.mapping(node, path)
        elif isinstance(node, yaml.SequenceNode):
            for i, v in enumerate(node.value):
                self.lines[path + (i,)] = v.start_mark.line + 1
                self.node(v, path + (i,))
        elif isinstance(node, yaml.ScalarNode) and not node.style and node.tag in _NUMBER_TAGS:
            value = self.data_at(path)
            hint = _yaml11_number(node.value, value) if isinstance(value, (int, float)) else ""
            if hint:
                self.problems.append(Problem(self.source, node.start_mark.line + 1, _dotted(path), hint))

    def mapping(self, node: yaml.MappingNode, path: tuple) -> None:
        source, own = self.source, self.own
        seen: set = set()
        for k, v in node.value:
            key = k.value
            if not isinstance(key, str) or k.tag != "tag:yaml.org,2002:str":  # a list, a number, ~, true ...
                shown = f" ({key!r} is read as {k.tag.rsplit(':', 1)[-1]})" if isinstance(key, str) else ""
                self.problems.append(
                    Problem(source, k.start_mark.line + 1, _dotted(path), f"a key must be a name{shown}")
                )
                continue
            if key in seen and (id(node), id(k)) in own:  # written twice; a key a merge (<<) gave may be overridden
                self.problems.append(
                    Problem(source, k.start_mark.line + 1, _dotted(path + (key,)), "appears twice in the same mapping")
                )
            if (id(node), id(k)) in own:
                seen.add(key)
            self.lines[path + (key,)] = k.start_mark.line + 1
            self.node(v, path + (key,))

    def data_at(self, path: tuple) -> Any:
        """The loaded value at ``path``, or None where the data is not shaped as the nodes (an
        ``!!omap``, a set ...: refused by the reader's types)."""
        v: Any = self.data
        for k in path:
            try:
                v = v[k]
            except (KeyError, IndexError, TypeError):
                return None
        return v


def _own_keys(root: yaml.Node | None) -> set[tuple[int, int]]:
    """(mapping, key) of the keys written in each mapping itself (not brought by a ``<<`` merge),
    by identity (a merge shares the key nodes of the mapping it copies)."""
    own: set[tuple[int, int]] = set()
    seen: set[int] = set()
    todo = [root] if root is not None else []
    while todo:
        node = todo.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                if k.tag != "tag:yaml.org,2002:merge":
                    own.add((id(node), id(k)))
                todo += [k, v]
        elif isinstance(node, yaml.SequenceNode):
            todo += node.value
    return own


_NUMBER_TAGS = ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")
_PLAIN_NUMBER = re.compile(
    r"^[-+]?(0|[1-9][0-9]*)$|^[-+]?([0-9]+\.[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$"
    r"|^[-+]?\.(inf|Inf|INF)$|^\.(nan|NaN|NAN)$"
)
"""The numbers YAML 1.1 and 1.2 read alike: decimal integers without a leading zero, decimal
fractions, infinities and NaN (the last two refused later by the fields' ranges)."""


def _yaml11_number(text: str, value: Any) -> str:
    """Why a plain number written ``text`` is refused, or "": YAML 1.1 (PyYAML's) reads ``010`` as 8
    (octal), ``1:30`` as 90 (base 60), ``0x6`` as 6 and ``6_0`` as 60, where YAML 1.2 and every
    reader of today would read something else or refuse; a scenario must mean one thing (our
    design), so such a number is refused with what to write instead."""
    if _PLAIN_NUMBER.match(text):
        return ""
    t = text.lstrip("+-")
    if ":" in t:
        why = f"YAML 1.1 reads {text} as a base-60 number ({value:g})"
    elif t[:2].lower() in ("0x", "0o", "0b"):
        why = f"{text} is written in base {dict(x=16, o=8, b=2)[t[1].lower()]} ({value:g})"
    elif "_" in t:
        why = f"YAML 1.1 ignores the _ of {text} ({value:g})"
    elif t[:1] == "0" and t[1:2].isdigit():
        why = f"YAML 1.1 reads {text} as octal ({value:g}), YAML 1.2 as {t.lstrip('0') or '0'}"
    else:
        why = f"{text} is not a plain decimal number"
    return f"{why}: write the number plainly in decimal, e.g. {value:g}, or quote it if it is text"


def _dotted(path: tuple) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _number_hint(v: Any) -> str:
    """The YAML 1.1 pitfall: ``1e-3`` (no point, or no sign in the exponent) is text, not a number."""
    if isinstance(v, str):
        try:
            float(v.replace("_", ""))
        except ValueError:
            return ""
        if v.strip().lower() in ("nan", "inf", "-inf", "+inf", "infinity", "-infinity"):
            return ""
        if "e" in v.lower():
            return (
                "; YAML 1.1 reads a number written like 1e-3 as text: write it with a point and a signed "
                "exponent, 1.0e-3 or 1.0e+3 (or plainly, 0.001)"
            )
        if v.strip().lstrip("+-")[:1] == "0":
            return f"; write it in decimal without a leading zero ({float(v.replace('_', '')):g}), unquoted"
    return ""


def type_name(v: Any) -> str:
    if v is None:
        return "nothing"
    if isinstance(v, bool):
        return f"a boolean ({str(v).lower()})"
    if isinstance(v, (int, float)):
        return f"a number ({v})"
    if isinstance(v, str):
        return f"text ({v!r})"
    if isinstance(v, list):
        return "a list"
    if isinstance(v, dict):
        return "a mapping"
    return type(v).__name__


class Invalid(Exception):
    """Raised inside the reader to abandon one field; the problem is already recorded."""


class Reader:
    """Typed access to the loaded YAML that records a :class:`Problem` per refusal."""

    def __init__(self, source: str, lines: dict[tuple, int]):
        self.source = source
        self.lines = lines
        self.problems: list[Problem] = []

    # -- recording
    def fail(self, path: tuple, message: str) -> Invalid:
        p = path
        while p not in self.lines and p:
            p = p[:-1]
        self.problems.append(Problem(self.source, self.lines.get(p), _dotted(path), message))
        return Invalid()

    def guard(self, fn, *args, default=None):
        """Run one field's reader; on refusal keep going with ``default`` so all problems show."""
        try:
            return fn(*args)
        except Invalid:
            return default

    # -- typed getters
    def mapping(self, v: Any, path: tuple, required: tuple[str, ...], optional: tuple[str, ...]) -> dict:
        if not isinstance(v, dict):
            raise self.fail(path, f"expected a mapping, found {type_name(v)}")
        for k in v:
            if k not in required and k not in optional:
                allowed = ", ".join(required + optional)
                raise self.fail(path + (k,), f"unknown field {k!r} (expected one of: {allowed})")
        for k in required:
            if k not in v:
                raise self.fail(path, f"missing required field {k!r}")
        return v

    def number(self, v: Any, path: tuple, rng: str | None = None) -> float:
        """A finite number within ``RANGES[rng]``."""
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.fail(path, f"expected a number, found {type_name(v)}{_number_hint(v)}")
        try:
            f = float(v)
        except OverflowError:
            raise self.fail(path, f"expected a number of sensible size, found one of {len(str(v))} digits") from None
        if not math.isfinite(f):
            raise self.fail(path, f"expected a finite number, found {v}")
        problem = RANGES[rng].problem(f) if rng else None
        if problem:
            raise self.fail(path, problem)
        return f

    def integer(self, v: Any, path: tuple, rng: str) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(path, f"expected a whole number, found {type_name(v)}")
        r = RANGES[rng]
        if not r.lo <= v <= r.hi:
            raise self.fail(path, f"must be a whole number from {r.lo} to {r.hi} (2**64 - 1), found {v}")
        return v

    def text(self, v: Any, path: tuple) -> str:
        if not isinstance(v, str):
            raise self.fail(path, f"expected text, found {type_name(v)}")
        if _CONTROL.search(v) or _SURROGATE.search(v):
            raise self.fail(path, f"holds a control character or an unpaired surrogate ({v[:40]!r})")
        return v

    def point(self, v: Any, path: tuple) -> Point:
        if not isinstance(v, list) or len(v) != 2:
            raise self.fail(path, f"expected a point [x, y] in metres, found {type_name(v)}")
        return (self.number(v[0], path + (0,), "point"), self.number(v[1], path + (1,), "point"))

    def opt(self, m: dict, key: str, path: tuple, getter, default, **kw):
        return getter(m[key], path + (key,), **kw) if key in m else default
