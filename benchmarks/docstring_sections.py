"""How many of navcli's public functions have a docstring with an Args or Returns section (Google
style, as Sphinx's napoleon renders them; a NumPy-style ``Parameters`` or ``Returns`` heading counts
too), and how many have every section they need.

    python benchmarks/docstring_sections.py            # the whole package, then the API reference's
    python benchmarks/docstring_sections.py --list     # and each public function without a section

*Public* here: a function or method defined at the top level of a module of ``navcli/``, or in a
class there, whose name, whose class's name and whose module path have no part that starts with an
underscore (``__init__.py`` aside), and that is not a dunder method; the command line's modules
(``navcli/cli/``, whose functions are documented by ``--help``) are counted apart. *Complete*: an
``Args:`` section if it takes an argument (beyond ``self``/``cls``), and a ``Returns:`` (or
``Yields:``) section if it is annotated to return something other than ``None``; a property needs
neither. *The API reference*: the functions and methods of the objects docs/reference/api.md
documents (``navcli.api``, the plugin-facing classes, ``navcli.envs``). *The exported API*: the
functions, and the methods of the classes, that ``navcli.__all__``, ``navcli.analysis.__all__``
and ``navcli.envs.__all__`` name.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import re
from pathlib import Path
from typing import Iterator, NamedTuple

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "navcli"
ARGS = re.compile(r"^\s*(Args|Arguments|Parameters)\s*:?\s*$", re.M)
RETURNS = re.compile(r"^\s*(Returns|Yields)\s*:?\s*$", re.M)
REFERENCE = ROOT / "docs" / "reference" / "api.md"


class Function(NamedTuple):
    module: str
    qualname: str
    has_args: bool
    has_returns: bool
    needs_args: bool
    needs_returns: bool

    @property
    def any_section(self) -> bool:
        return self.has_args or self.has_returns

    @property
    def complete(self) -> bool:
        return (self.has_args or not self.needs_args) and (self.has_returns or not self.needs_returns)


def _module(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _public(name: str) -> bool:
    return not name.startswith("_")


def _describe(module: str, qualname: str, fn: ast.FunctionDef | ast.AsyncFunctionDef, method: bool) -> Function:
    doc = ast.get_docstring(fn) or ""
    args = [a.arg for a in fn.args.posonlyargs + fn.args.args + fn.args.kwonlyargs]
    if method and args and args[0] in ("self", "cls"):
        args = args[1:]
    args += [a.arg for a in (fn.args.vararg, fn.args.kwarg) if a is not None]
    is_property = any(isinstance(d, ast.Name) and d.id in ("property", "cached_property") for d in fn.decorator_list)
    returns = fn.returns is not None and not (isinstance(fn.returns, ast.Constant) and fn.returns.value is None)
    return Function(
        module,
        qualname,
        bool(ARGS.search(doc)),
        bool(RETURNS.search(doc)),
        bool(args) and not is_property,
        returns and not is_property,
    )


def functions(path: Path) -> Iterator[Function]:
    module = _module(path)
    if not all(_public(p) for p in module.split(".")):
        return
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and _public(node.name):
            yield _describe(module, node.name, node, method=False)
        elif isinstance(node, ast.ClassDef) and _public(node.name):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and _public(item.name):
                    yield _describe(module, f"{node.name}.{item.name}", item, method=True)


def reference_objects() -> list[str]:
    """The dotted names docs/reference/api.md documents (its autodoc directives and their members)."""
    text = REFERENCE.read_text(encoding="utf-8")
    out = []
    for m in re.finditer(r"^\.\. auto(\w+):: ([\w.]+)\n((?:   :.*\n)*)", text, re.M):
        kind, name, options = m.groups()
        members = re.search(r":members:(.*)", options)
        listed = [x.strip() for x in members.group(1).split(",") if x.strip()] if members else []
        if kind == "module":
            out += [f"{name}.{x}" for x in listed]
        else:
            out.append(name)
    return out


def exported_objects() -> list[str]:
    """The dotted names the package exports: ``navcli.__all__`` (its API for notebooks and plugins),
    ``navcli.analysis.__all__`` and ``navcli.envs.__all__``."""
    out = []
    for module in ("navcli", "navcli.analysis", "navcli.envs"):
        m = importlib.import_module(module)
        out += [f"{module}.{name}" for name in m.__all__ if not name.startswith("__")]
    return out


def in_reference(f: Function, objects: list[str]) -> bool:
    """Is ``f`` one of ``objects`` or a method of one (each found where it is defined, not where it
    is imported: ``navcli.pilot.Pilot`` is ``navcli.pilot.base.Pilot``)?"""
    for name in objects:
        module, _, attr = name.rpartition(".")
        obj = getattr(importlib.import_module(module), attr)
        if not callable(obj):
            continue
        where = (getattr(obj, "__module__", module), getattr(obj, "__qualname__", attr))
        if (f.module, f.qualname) == where or (f.module == where[0] and f.qualname.startswith(where[1] + ".")):
            return True
    return False


def _share(fs: list[Function], what: str) -> str:
    n = len(fs)
    anysec = sum(f.any_section for f in fs)
    complete = sum(f.complete for f in fs)
    return (
        f"{what}: {n} public functions; with an Args or Returns section {anysec} ({100 * anysec / max(n, 1):.0f} %), "
        f"with every section they need {complete} ({100 * complete / max(n, 1):.0f} %)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--list", action="store_true", help="list the public functions missing a section they need")
    a = ap.parse_args()
    every = [f for path in sorted(PACKAGE.rglob("*.py")) for f in functions(path)]
    cli = [f for f in every if f.module.startswith("navcli.cli")]
    package = [f for f in every if not f.module.startswith("navcli.cli")]
    objects = reference_objects()
    reference = [f for f in package if in_reference(f, objects)]
    print(_share(package, "navcli (but navcli.cli)"))
    print(_share(cli, "navcli.cli"))
    print(_share(reference, "the API reference (docs/reference/api.md)"))
    exported = [f for f in package if in_reference(f, exported_objects())]
    print(_share(exported, "the exported API (navcli.__all__, navcli.analysis.__all__, navcli.envs.__all__)"))
    if a.list:
        for f in exported + [f for f in reference + package if f not in exported]:
            if not f.complete:
                print(f"  {f.module}.{f.qualname}")


if __name__ == "__main__":
    main()
