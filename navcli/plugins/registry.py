"""Pilots and navigation policies found by name: navcli's own, the entry points of installed
packages, and ``module:Class``.

A name is looked up in this order (as Gymnasium finds environments, and IR-SIM its behaviours):

1. **navcli's own**: the pilots ``potential-field`` and ``geometric``; the policies ``agents`` (the
   Navigation system's bidding agents), ``hand-coded`` and ``learned[:FILE]`` (the Learning Agent);
2. **an installed package's entry point** in the group ``navcli.pilots`` or ``navcli.policies``::

       [project.entry-points."navcli.pilots"]
       vfh = "vfh_pilot:VFHPilot"

3. **``module:Class``** (or ``path/to/file.py:Class``): the module is imported from the installed
   packages, then from the current folder.

``NAME=`` before an installed plugin's name, ``module:Class`` or ``path/to/file.py:Class`` finds the
same plugin under the name ``NAME`` (:mod:`.names` declares the names' rules).

A pilot is a subclass of :class:`navcli.pilot.Pilot`; a policy is a Navigation agent (the
:class:`navcli.navigation.Agent` protocol: a ``name`` and ``bid(situation) -> list[Bid]``), made
with an :class:`~navcli.navigation.situation.AgentSetup`. Either may declare ``Params`` (a
:class:`~navcli.params.ParamSet`: its parameters, addressed as ``<its name>.<parameter>``),
``version`` (else its package's version, else a hash of its module's source) and, for a pilot,
``Info`` (a ``msgspec.Struct``: the fields it adds to ``/pilot`` every tick).

A plugin's identity (name, version, origin) is part of its runs' configuration and so of their
run id; an exception raised in its code, a wrong return or a hung decision is reported as the
plugin's (:class:`PluginError`, exit 1; :mod:`.boundary` guards every call into it), never as
navcli's.

A plugin named by its file is imported under a private module name (``navcli_plugin_<hash of its
path>``), and again when the file changes; one imported as a module whose source has changed since
is refused (:func:`locate`).
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.metadata
import importlib.util
import inspect
import sys
import traceback
from dataclasses import dataclass, replace
from pathlib import Path
from types import TracebackType
from typing import Any, Iterable, Sequence

from .. import NavcliError, __version__
from .names import (
    BUILTIN_PILOTS,
    BUILTIN_POLICIES,
    GROUPS,
    NAME_RE,
    NAME_RULE,
    WORDS,
    Kind,
    UnknownPlugin,
    named,
)

HINT = "NAVCLI_DEBUG=1 shows the traceback"


class PluginError(NavcliError):
    """A plugin's own code failed: it cannot be imported or made, or it raised while running, or
    it broke its contract (exit 1: not bad input, and not a bug of navcli's)."""

    exit_code = 1


@dataclass(frozen=True)
class Component:
    """A pilot or a policy, found: its ``kind``, the ``name`` it goes by (the value it was asked
    by, or the ``NAME`` of ``NAME=REFERENCE``: :mod:`.names`), its class (``cls``; None for
    navcli's ``agents``), where it came from (``origin``: ``navcli``, ``entry point vfh =
    vfh_pilot:VFHPilot of vfh-pilot 0.1.0``, ``module mypilot``) and its ``version``.
    ``argument`` is what follows ``learned:``; ``asked`` the whole value it was asked by."""

    kind: Kind
    name: str
    cls: Any
    origin: str
    version: str
    argument: str = ""
    source: tuple[str, str] | None = None  # (file, sha256) of the module defining cls, when it was loaded
    reference: str = ""  # the value it was asked by, where a NAME= gave it another name

    @property
    def asked(self) -> str:
        """The value that finds it again (``mine=path/to/file.py:Class``): for hints and reruns."""
        return self.reference or self.name

    @property
    def builtin(self) -> bool:
        """One of navcli's own."""
        return self.origin == "navcli"

    @property
    def label(self) -> str:
        """How messages name it: ``the pilot plugin 'vfh' (vfh-pilot 0.1.0)``."""
        return f"the {WORDS[self.kind]} plugin {self.name!r} ({self.origin}, version {self.version})"

    @property
    def group(self) -> str:
        """The name its parameters go by (``vfh`` in ``vfh.threshold``): an installed plugin's name,
        the ``NAME`` of ``NAME=REFERENCE``, or, for ``module:Class``, the class's name."""
        return self.name.rpartition(":")[2].rpartition(".")[2] if ":" in self.name else self.name

    @property
    def params_class(self) -> Any:
        """Its parameter set's class (a :class:`~navcli.params.ParamSet`), or None."""
        return getattr(self.cls, "Params", None) if not self.builtin else None

    @property
    def info_class(self) -> Any:
        """A pilot's ``Info``: the ``msgspec.Struct`` of the fields it adds to ``/pilot``, or None."""
        return getattr(self.cls, "Info", None) if not self.builtin else None

    def identity(self) -> dict[str, str]:
        """What names it in a run's configuration (and so in its run id)."""
        return {"name": self.name, "version": self.version, "origin": self.origin}

    def owns(self, module: str) -> bool:
        """Is ``module`` (a module's ``__name__``) part of this plugin's code?"""
        if self.builtin or self.cls is None:
            return False
        root = self.cls.__module__.split(".")[0]
        return module == root or module.startswith(root + ".")


def _navcli(kind: Kind, name: str) -> Component | None:
    """navcli's own component of that name (``learned:FILE`` too), or None."""
    base, sep, arg = name.partition(":")
    if kind == "pilot" and name in BUILTIN_PILOTS:
        from ..pilot import GeometricPilot, PotentialFieldPilot

        cls = {"potential-field": PotentialFieldPilot, "geometric": GeometricPilot}[name]
        return Component(kind, name, cls, "navcli", __version__)
    if kind == "policy" and sep and base in BUILTIN_POLICIES and base != "learned":
        raise UnknownPlugin(f"unknown navigation policy {name!r}: {base} takes no :argument (only learned:FILE does)")
    if kind == "policy" and (name in BUILTIN_POLICIES or (base == "learned" and sep)):
        if base == "learned" and sep and not arg.strip():
            raise UnknownPlugin(f"{name!r} names no model file (learned:FILE, or plain learned for the bundled one)")
        return Component(kind, name, None, "navcli", __version__, arg)
    return None


@functools.lru_cache(maxsize=None)
def entry_points(kind: Kind) -> dict[str, tuple[importlib.metadata.EntryPoint, ...]]:
    """The installed packages' entry points of ``kind``, by name (looked up once per process)."""
    found: dict[str, tuple[importlib.metadata.EntryPoint, ...]] = {}
    for ep in importlib.metadata.entry_points(group=GROUPS[kind]):
        found[ep.name] = found.get(ep.name, ()) + (ep,)
    return found


def _distribution(ep: importlib.metadata.EntryPoint) -> tuple[str, str]:
    dist = ep.dist
    return (dist.name, dist.version) if dist is not None else ("an unknown package", "0")


def _from_entry_point(kind: Kind, name: str, eps: tuple[importlib.metadata.EntryPoint, ...]) -> Component:
    if len(eps) > 1:
        owners = ", ".join(f"{d} {v}" for d, v in map(_distribution, eps))
        raise UnknownPlugin(
            f"the {kind} {name!r} is declared by several installed packages ({owners}): uninstall all but one"
        )
    ep = eps[0]
    dist, version = _distribution(ep)
    origin = f"entry point {ep.name} = {ep.value} of {dist} {version}"
    if kind == "pilot" and name in BUILTIN_PILOTS or kind == "policy" and name in BUILTIN_POLICIES:
        raise UnknownPlugin(f"{origin} takes the name of navcli's own {kind} {name!r}: rename it")
    if not NAME_RE.fullmatch(name):
        raise UnknownPlugin(f"{origin}: a plugin's name is {NAME_RULE}")
    try:
        cls = ep.load()
    except Exception as e:
        raise failed(Component(kind, name, None, origin, version), e, "cannot be loaded") from e
    return Component(kind, name, cls, origin, str(getattr(cls, "version", None) or version), source=_source_stamp(cls))


_FILE_MODULES: dict[Path, tuple[str, Any]] = {}
"""The modules of the plugin files loaded in this process, by resolved path: (sha256 of the
source they were made from, module)."""


def _private_name(path: Path) -> str:
    """The module name a plugin file is loaded under: its own, so that ``numpy.py:Shadow`` replaces
    no module of that name, and two files of the same name in two folders are two modules."""
    return "navcli_plugin_" + hashlib.sha256(str(path).encode()).hexdigest()[:16]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _module_file(spec: str) -> Any:
    """The module of ``path/to/file.py``, imported under a private name (:func:`_private_name`),
    and imported again when the file has changed since (the name then holds the new module)."""
    path = Path(spec)
    if not path.is_file():
        raise UnknownPlugin(f"{spec}: no such file")
    path = path.resolve()
    digest = _digest(path)
    known = _FILE_MODULES.get(path)
    if known is not None and known[0] == digest:
        return known[1]
    name = _private_name(path)
    loader = importlib.util.spec_from_file_location(name, path)
    assert loader is not None and loader.loader is not None  # a .py file has a loader
    module = importlib.util.module_from_spec(loader)
    sys.modules[name] = module  # so its classes pickle by reference into forked workers
    try:
        loader.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    _FILE_MODULES[path] = (digest, module)
    return module


def _source_stamp(cls: Any) -> tuple[str, str] | None:
    """(file, sha256 of its source) of the module that defines ``cls``, or None."""
    try:
        path = Path(inspect.getfile(sys.modules[cls.__module__])).resolve()
        return str(path), _digest(path)
    except (KeyError, TypeError, OSError, AttributeError):
        return None


def _version_of(cls: Any, module: Any) -> str:
    """``cls.version``, its module's ``__version__``, its package's version, or the sha256 of its
    module's source (so an edited plugin is another version, and its runs get other run ids)."""
    given = getattr(cls, "version", None) or getattr(module, "__version__", None)
    if given:
        return str(given)
    top = module.__name__.split(".")[0]
    for dist in importlib.metadata.packages_distributions().get(top, []):
        try:
            return importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            continue
    try:
        source = Path(inspect.getfile(module)).read_bytes()
    except (TypeError, OSError):
        return "unknown"
    return "sha256:" + hashlib.sha256(source).hexdigest()[:16]


def _from_module(kind: Kind, name: str) -> Component:
    """``module:Class`` or ``path/to/file.py:Class``."""
    module_name, _, attr = name.rpartition(":")
    if not module_name or not attr.isidentifier() and not all(p.isidentifier() for p in attr.split(".")):
        raise UnknownPlugin(f"{name!r}: expected module:Class (e.g. mypackage.pilots:MyPilot)")
    is_file = module_name.endswith(".py") or "/" in module_name
    origin = f"module {module_name}"
    try:
        if is_file:
            module = _module_file(module_name)
        else:
            here = str(Path.cwd())
            if here not in sys.path:
                sys.path.append(here)  # after the installed packages: the current folder shadows none of them
            module = importlib.import_module(module_name)
    except ModuleNotFoundError as e:
        if e.name and (module_name == e.name or module_name.startswith(e.name + ".")):
            raise UnknownPlugin(
                f"{name!r}: no module {e.name!r} among the installed packages or in the current folder"
            ) from None
        raise failed(Component(kind, name, None, origin, "unknown"), e, "cannot be imported") from e
    except UnknownPlugin:
        raise
    except Exception as e:
        raise failed(Component(kind, name, None, origin, "unknown"), e, "cannot be imported") from e
    obj: Any = module
    for part in attr.split("."):
        obj = getattr(obj, part, None)
        if obj is None:
            raise UnknownPlugin(f"{name!r}: the module {module_name} has no {attr}")
    return Component(kind, name, obj, origin, _version_of(obj, module), source=_source_stamp(obj))


def find(kind: Kind, name: str) -> Component:
    """The pilot or policy called ``name`` (see the module docstring), checked to be of its kind;
    raises :class:`UnknownPlugin` (exit 2), or :class:`PluginError` (exit 1) for one that is found
    but cannot be loaded or is no pilot (no policy), or whose source changed since this process
    loaded it and cannot be loaded again (:func:`locate`)."""
    c = _found(kind, _named(kind, name), _file_digest(kind, name))
    _unchanged(c)
    return c


@functools.lru_cache(maxsize=None)
def _found(kind: Kind, name: str, digest: str) -> Component:
    from .contract import contract_problems  # msgspec, numpy: not imported by the command line's start

    c = _located(kind, name, digest)
    problems = contract_problems(c)
    if problems:  # an installed package that is broken is its fault; a module:Class that is no pilot, the name's
        error = PluginError if c.origin.startswith("entry point") else UnknownPlugin
        raise error(
            f"{c.label} is no {kind}: {problems[0]}"
            + (f" (and {len(problems) - 1} more problems)" if len(problems) > 1 else "")
            + f"; `navcli plugins check {kind} {name}` lists what it gets wrong"
        )
    return c


def locate(kind: Kind, name: str) -> Component:
    """The component called ``name``, loaded but not yet checked against its kind's contract
    (:func:`find` checks it). Found once per process and kept, by name; a plugin named by its file
    (``path/to/file.py:Class``) by its file's content too, so an edited file is loaded again. Any
    other plugin whose module's source has changed since it was loaded raises
    :class:`PluginError`: Python cannot load a module again in place (``importlib.reload`` leaves
    its package's other modules and every reference to the old classes as they were)."""
    c = _located(kind, _named(kind, name), _file_digest(kind, name))
    _unchanged(c)
    return c


def clear_caches() -> None:
    """Forget every plugin found (the next lookup finds it again): for tests."""
    for cache in (_found, _located, entry_points):
        cache.cache_clear()
    _FILE_MODULES.clear()


def _named(kind: Kind, name: object) -> str:
    if not isinstance(name, str) or not name.strip():
        raise UnknownPlugin(f"a {WORDS[kind]} is named by a non-empty name, got {name!r}")
    return name


def _file_digest(kind: Kind, name: str) -> str:
    """The sha256 of the file of a ``path/to/file.py:Class`` name ('' for any other name, or a file
    that cannot be read: the lookup says why)."""
    module_name, sep, _ = named(name, kind)[1].rpartition(":")
    if not sep or not (module_name.endswith(".py") or "/" in module_name):
        return ""
    try:
        return _digest(Path(module_name).resolve())
    except OSError:
        return ""


def _unchanged(c: Component) -> None:
    """Refuse a plugin whose module's source changed after it was loaded (see :func:`locate`)."""
    if c.source is None:
        return
    file, digest = c.source
    try:
        now = _digest(Path(file))
    except OSError:
        return  # gone: the code loaded is all there is
    if now != digest:
        raise PluginError(
            f"{c.label}: its source {file} has changed since this process loaded it, and Python cannot load a "
            f"module again in place; navcli loads a plugin named by its file (path/to/file.py:Class) again when "
            f"the file changes: name it so, or start a new process to run the edited plugin"
        )


@functools.lru_cache(maxsize=None)
def _located(kind: Kind, name: str, digest: str) -> Component:
    """:func:`locate`'s lookup, kept by name and file digest."""
    called, reference = named(name, kind)
    if called != reference:
        return replace(_located(kind, reference, digest), name=called, reference=name)
    own = _navcli(kind, name)
    if own is not None:
        return own
    eps = entry_points(kind)
    if name in eps:
        return _from_entry_point(kind, name, eps[name])
    if ":" in name:
        return _from_module(kind, name)
    ours = ", ".join(BUILTIN_PILOTS if kind == "pilot" else BUILTIN_POLICIES + ("learned:FILE",))
    installed = ", ".join(sorted(eps)) or "none"
    example = "mypackage.pilots:MyPilot" if kind == "pilot" else "mypackage.policies:MyPolicy"
    raise UnknownPlugin(
        f"unknown {WORDS[kind]} {name!r}: not one of navcli's ({ours}), not an entry point "
        f"{GROUPS[kind]} of an installed package (installed: {installed}), and not "
        f"module:Class (e.g. {example})"
    )


def pilot(name: str) -> Component:
    """The pilot called ``name`` (see :func:`find`)."""
    return find("pilot", name)


def navigation(value: str) -> tuple[Component, ...]:
    """The policies of a ``--navigation`` value: one name, or several joined by ``+`` to bid side by
    side (``agents+my-agent``: navcli's bidding agents and a plugin's); ``hand-coded`` and
    ``learned[:FILE]`` replace the agents, so they stand alone.

    >>> [c.name for c in navigation("agents")]
    ['agents']
    """
    if not isinstance(value, str) or not value.strip():
        raise UnknownPlugin(f"a navigation policy is named by a non-empty name, got {value!r}")
    parts = [p.strip() for p in value.split("+")] if not value.startswith("learned:") else [value]
    if any(not p for p in parts):
        raise UnknownPlugin(f"{value!r}: an empty name between '+'")
    comps = tuple(find("policy", p) for p in parts)
    _distinct([c.name for c in comps], value)
    if len(comps) > 1 and any(c.builtin and c.name != "agents" for c in comps):
        raise UnknownPlugin(f"{value!r}: hand-coded and learned replace the bidding agents; they stand alone")
    return comps


def pilots(values: Sequence[str], what: str = "the pilots") -> tuple[Component, ...]:
    """The pilots of a comparison (``--pilots``, ``navcli.compare``'s ``pilots``, a plan's), each
    found, no two going by one name: a table's rows and the log files are by name."""
    comps = tuple(pilot(v) for v in values)
    _distinct([c.name for c in comps], what)
    return comps


def _distinct(names: list[str], what: str) -> None:
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise UnknownPlugin(f"{what}: {', '.join(map(repr, twice))} named twice (each would be the same runs)")


def installed(kind: Kind) -> list[Component | tuple[str, str]]:
    """navcli's own components of ``kind`` and every installed package's, each found (or, for one
    that cannot be, its name and why)."""
    out: list[Component | tuple[str, str]] = [
        find(kind, n) for n in (BUILTIN_PILOTS if kind == "pilot" else BUILTIN_POLICIES)
    ]
    for name in sorted(entry_points(kind)):
        try:
            out.append(find(kind, name))
        except NavcliError as e:
            out.append((name, str(e)))
    return out


BLAME = "The fault is the plugin's, not navcli's"  # how every plugin fault ends: the checker cuts it there


def failed(c: Component, e: BaseException, doing: str = "raised", at: Any = None) -> PluginError:
    """The :class:`PluginError` saying that ``c``'s code ``doing`` (``raised``, ``cannot be
    loaded`` ...) ``e``, where in its code, and what to do: one line. Where: the innermost frame
    of the traceback in the plugin's own files; without one (a call its signature refused, a
    mypyc-compiled check of what it returned), the definition of ``at``, the plugin's function
    navcli called."""
    what = f"{type(e).__name__}: {e}".strip().splitlines()[0][:300] if str(e) else type(e).__name__
    return PluginError(
        f"{c.label} {doing}: {what}{_location(c, e, at)}. {BLAME}: "
        f"`navcli plugins check {c.kind} {c.asked}` tests it against navcli's contract; {HINT}"
    )


def _location(c: Component, e: BaseException, at: Any) -> str:
    """`` at file.py:LINE in function`` (see :func:`failed`), or ''."""
    frames = traceback.extract_tb(e.__traceback__) if e.__traceback__ is not None else []
    if c.cls is None:  # its module could not be imported: the innermost frame is the import's
        if isinstance(e, SyntaxError) and e.filename and e.lineno:
            return f" at {Path(e.filename).name}:{e.lineno}"
        return f" at {Path(frames[-1].filename).name}:{frames[-1].lineno} in {frames[-1].name}" if frames else ""
    root = _root(c)
    mine = [f for f in frames if root is not None and _inside(f.filename, root)]
    if mine:
        return f" at {Path(mine[-1].filename).name}:{mine[-1].lineno} in {mine[-1].name}"
    where = definition(at) if at is not None else ""
    return f" calling {getattr(at, '__name__', 'it')}() (defined at {where})" if where else ""


def _inside(filename: str, root: Path) -> bool:
    try:
        return Path(filename).resolve().is_relative_to(root)
    except (OSError, ValueError):
        return False


def definition(fn: Any) -> str:
    """``file.py:LINE`` where the function (or method; for a class, its ``__init__``) ``fn`` is
    defined, or ''."""
    fn = vars(fn).get("__init__", fn) if isinstance(fn, type) else fn
    code = getattr(inspect.unwrap(getattr(fn, "__func__", fn)), "__code__", None)
    return f"{Path(code.co_filename).name}:{code.co_firstlineno}" if code is not None else ""


def _root(c: Component) -> Path | None:
    """The folder (a package) or file (a module) of ``c``'s code (a class of navcli's own named as
    ``module:Class``: its module's file, never the whole of navcli)."""
    top = c.cls.__module__.split(".")[0] if c.cls is not None else ""
    module = sys.modules.get(c.cls.__module__ if top == "navcli" else top) if c.cls is not None else None
    file = getattr(module, "__file__", None)
    if not file:
        return None
    p = Path(file).resolve()
    return p.parent if p.name == "__init__.py" else p


def blame(e: BaseException, components: Iterable[Component]) -> Component | None:
    """The plugin among ``components`` whose code ``e`` was raised in, or passed through (the
    traceback's frames, from the innermost out), or None: navcli's own code raised it."""
    plugins = [c for c in components if not c.builtin and c.cls is not None]
    if not plugins:
        return None
    tb: TracebackType | None = e.__traceback__
    frames = []
    while tb is not None:
        frames.append(tb.tb_frame.f_globals.get("__name__", ""))
        tb = tb.tb_next
    for module in reversed(frames):
        for c in plugins:
            if c.owns(module):
                return c
    return None


def with_params(params: Any, components: Iterable[Component]) -> Any:
    """``params`` (a :class:`~navcli.params.Params`) holding the parameter set of each plugin of
    ``components`` that declares one: its defaults, where ``params`` holds none yet."""
    for c in components:
        if c.params_class is not None and params.plugin(c.group) is None:
            params = params.with_plugin(c.group, c.params_class())
    return params
