"""The names pilots and Navigation policies go by, declared once: what a name may hold, navcli's
own names, the forms a value that names one takes, and the ``NAME=REFERENCE`` form by which a user
names a plugin. The registry, the scenario's schema, the command line's help and the API derive
theirs from here.

A value names a pilot (or policy) as

- one of navcli's own (:data:`BUILTIN_PILOTS`, :data:`BUILTIN_POLICIES`);
- an installed package's entry point, by its name;
- ``module:Class`` (a module importable here) or ``path/to/file.py:Class``;
- ``NAME=module:Class`` or ``NAME=path/to/file.py:Class`` (or ``NAME=`` before an installed
  plugin's name): the same plugin, called ``NAME`` in tables, log file names, its parameters
  (``NAME.threshold``) and messages.

Without ``NAME=`` a plugin goes by the value itself: ``/home/me/mypilot.py:MyPilot`` in a table's
pilot column, ``home_me_mypilot.py_MyPilot-seed1-….mcap`` as a log's name.

>>> named("mine=path/to/file.py:MyPilot", "pilot")
('mine', 'path/to/file.py:MyPilot')
>>> named("path/to/file.py:MyPilot", "pilot")
('path/to/file.py:MyPilot', 'path/to/file.py:MyPilot')
>>> label("mine=mypackage.pilots:MyPilot"), label("geometric")
('mine', 'geometric')
>>> navigation_label("agents+mine=path/to/file.py:MyAgent")
'agents+mine'
"""

from __future__ import annotations

import re
from typing import Literal

from .. import NavcliError

Kind = Literal["pilot", "policy"]
GROUPS: dict[Kind, str] = {"pilot": "navcli.pilots", "policy": "navcli.policies"}
"""The entry point group of each kind of plugin."""
WORDS: dict[Kind, str] = {"pilot": "pilot", "policy": "navigation policy"}
"""How messages name each kind."""
NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}")
"""What a plugin may be called (it names runs, log files and its parameters), matched whole: an
installed plugin's entry point, a name given as ``NAME=``, a policy agent's bidder name."""
NAME_RULE = "1 to 64 of A-Z, a-z, 0-9, '_' and '-', the first a letter or a digit"
""":data:`NAME_RE` in words, for messages."""
BUILTIN_PILOTS = ("potential-field", "geometric")
"""navcli's own pilots; the first is the default, and a comparison's default pilots are both, the
pilot paper's baseline (the geometric pilot) last."""
BUILTIN_POLICIES = ("agents", "hand-coded", "learned")
"""navcli's own Navigation policies (``learned:FILE`` names a model; plain ``learned`` the bundled
one); the first is the default."""
BUILTIN: dict[Kind, tuple[str, ...]] = {"pilot": BUILTIN_PILOTS, "policy": BUILTIN_POLICIES}
REFERENCE_RE = re.compile(r"[^\s:]+:[A-Za-z_][A-Za-z0-9_.]*")
"""``module:Class`` or ``path/to/file.py:Class``, matched whole."""
NAMED_RE = re.compile(rf"{NAME_RE.pattern}=(?:{REFERENCE_RE.pattern}|{NAME_RE.pattern})")
"""``NAME=REFERENCE`` (or ``NAME=`` an installed plugin's name), matched whole."""
PILOT_PATTERN = rf"^(?:{NAME_RE.pattern}|{REFERENCE_RE.pattern}|{NAMED_RE.pattern})$"
"""Every form of a plugin pilot's value as one regular expression (the scenario's JSON Schema)."""
PLUGIN_FORMS = (
    "module:Class (a module importable here) or path/to/file.py:Class; "
    "NAME=module:Class or NAME=path/to/file.py:Class calls it NAME in tables and file names"
)
"""How a plugin not installed is named: the help texts' words (:func:`forms`)."""


class UnknownPlugin(NavcliError):
    """A pilot or policy name that is none of navcli's, no installed package's, and no importable
    ``module:Class`` (exit 2: bad input)."""


def forms(kind: Kind) -> str:
    """Every form a value naming a ``kind`` may take, in words (for ``--help``): navcli's own
    names, an installed plugin's, and :data:`PLUGIN_FORMS`."""
    own = ", ".join(BUILTIN_PILOTS) if kind == "pilot" else "agents, hand-coded, learned[:FILE]"
    return f"{own}, an installed plugin's name (entry point {GROUPS[kind]}), {PLUGIN_FORMS}"


def named(value: str, kind: Kind) -> tuple[str, str]:
    """(the name it goes by, the reference that finds it) of a value naming a ``kind``: ``NAME=REF``
    gives ``(NAME, REF)``, any other value ``(value, value)``. A value is in that form when the
    text before its first ``=`` holds no ``:`` and no ``/`` (so ``learned:a=b.npz`` names a file).
    Raises :class:`UnknownPlugin` for a name that breaks :data:`NAME_RULE`, takes one of navcli's
    own names, or is given to one of navcli's own components."""
    name, sep, ref = value.partition("=")
    if not sep or ":" in name or "/" in name:
        return value, value
    what = WORDS[kind]
    if not NAME_RE.fullmatch(name):
        raise UnknownPlugin(f"{value!r}: the name before '=' is {name!r}, but a {what}'s name is {NAME_RULE}")
    if name in BUILTIN[kind]:
        raise UnknownPlugin(f"{value!r}: {name!r} is taken by navcli's own {what}: call the plugin another name")
    ref = ref.strip()
    if not ref:
        raise UnknownPlugin(f"{value!r}: nothing after '=' (NAME=module:Class or NAME=path/to/file.py:Class)")
    if ref.partition(":")[0] in BUILTIN[kind]:
        raise UnknownPlugin(f"{value!r}: {ref!r} is navcli's own {what}, which goes by its own name: name a plugin")
    return name, ref


def label(value: str, kind: Kind = "pilot") -> str:
    """The name a value naming a ``kind`` goes by in tables, file names and messages (see
    :func:`named`)."""
    return named(value, kind)[0]


def navigation_label(value: str) -> str:
    """The name a ``--navigation`` value goes by: each policy's :func:`label`, joined by ``+`` as the
    value joins them (``learned:FILE`` whole)."""
    if value.startswith("learned:"):
        return value
    return "+".join(label(p.strip(), "policy") for p in value.split("+"))
