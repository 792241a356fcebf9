"""The import rules that keep the architecture honest (README, "Where to find it in the code").

Read from the source with ``ast``, so a rule is checked for every module whether or not a test
happens to import it, and once more by importing the agents in a fresh interpreter.
"""

from __future__ import annotations

import ast
import io
import subprocess
import sys
import tokenize
from pathlib import Path

import pytest

from conftest import ROOT

VALUES = {"navcli.beliefs", "navcli.bidding", "navcli.geometry", "navcli.fuzzy", "navcli.params"}
"""Plain values and maths: what an agent may import."""
STDLIB = set(sys.stdlib_module_names)


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every module ``path`` imports (relative imports resolved), at any depth of the file."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module
            found.add(mod)
            found |= {f"{mod}.{a.name}" for a in node.names}  # `from . import recorder` imports a module
    return found


def _modules(*folders: str) -> dict[str, set[str]]:
    return {_module_name(p): _imports(p) for f in folders for p in sorted((ROOT / f).rglob("*.py"))}


MODULES = _modules("navcli")
KNOWN = set(MODULES)


def _who_imports(prefix: str) -> set[str]:
    return {m for m, deps in MODULES.items() if any(d == prefix or d.startswith(prefix + ".") for d in deps)}


def test_the_import_scan_sees_the_package():
    assert {
        "navcli.world",
        "navcli.pilot.potential_field",
        "navcli.navigation.target_tracker",
        "navcli.analysis.logs",
        "navcli.log.format",
    } <= KNOWN
    assert "navcli.beliefs" in MODULES["navcli.pilot.base"]  # relative imports are resolved


def test_only_the_world_imports_pymunk():
    assert _who_imports("pymunk") == {"navcli.world"}


def test_only_the_world_imports_the_servo_in_c():
    """navcli/servo.c drives Chipmunk through the addresses the world hands it: glue of the world's."""
    from navcli.builds import SERVO

    assert (ROOT / "navcli" / f"{SERVO}.c").is_file()
    assert _who_imports(f"navcli.{SERVO}") == {"navcli.world"}


def test_only_the_log_package_writes_logs():
    writers = {
        m
        for m, deps in MODULES.items()
        if any((d == "foxglove" or d.startswith("foxglove.")) and d != "foxglove.layouts" for d in deps)
    }
    assert writers == {"navcli.log.writer", "navcli.log.scenes"}  # the recorder, and the scenes it writes
    assert _who_imports("foxglove.layouts") == {"navcli.log.layout"}  # builds a viewer layout, writes no log
    assert _who_imports("mcap.writer") == {"navcli.log.recover"}  # rewrites a killed run's chunks


def _is_type_checking(node: ast.stmt) -> bool:
    return isinstance(node, ast.If) and (
        isinstance(node.test, ast.Name)
        and node.test.id == "TYPE_CHECKING"
        or isinstance(node.test, ast.Attribute)
        and node.test.attr == "TYPE_CHECKING"
    )


def _run_time_imports(path: Path) -> set[str]:
    """The navcli modules that importing ``path``'s module, or calling any of its functions, can
    import: every import statement at any depth (inside functions too) but those under ``if
    TYPE_CHECKING:``, which never run. ``import a.b.c`` runs the packages ``a`` and ``a.b`` first,
    so they count, except the importer's own packages (already being imported when it runs)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text(), str(path))
    unrun = {id(n) for top in ast.walk(tree) if _is_type_checking(top) for b in top.body for n in ast.walk(b)}
    found = set()
    for node in ast.walk(tree):
        if id(node) in unrun:
            continue
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            parts = package.split(".")
            base = ".".join(parts[: len(parts) - node.level + 1] + [node.module or ""]) if node.level else node.module
            base = base.rstrip(".") if base else ""
            targets = [base] + [f"{base}.{a.name}" for a in node.names]
        else:
            continue
        for target in targets:
            bits = target.split(".")
            found |= {".".join(bits[:i]) for i in range(1, len(bits) + 1)}
    return {m for m in found & KNOWN if m != name and not name.startswith(m + ".")}


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """The cycles of ``graph`` (node -> the nodes it points to): its strongly connected components
    of more than one node, or of one that points to itself (Tarjan's algorithm, iterative), each
    sorted.

    >>> strongly_connected({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}})
    [['a', 'b', 'c']]
    >>> strongly_connected({"a": {"b"}, "b": set(), "c": {"c"}})
    [['c']]
    """
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            nxt = next(edges, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph.get(nxt, ())))))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    m = stack.pop()
                    on_stack.discard(m)
                    component.append(m)
                    if m == node:
                        break
                if len(component) > 1 or node in graph.get(node, ()):
                    found.append(sorted(component))
    return sorted(found)


RUN_TIME = {_module_name(p): _run_time_imports(p) for p in sorted((ROOT / "navcli").rglob("*.py"))}


def test_the_import_graph_counts_imports_inside_functions_and_their_packages():
    assert "navcli.log.writer" in RUN_TIME["navcli.runner"]  # open_log imports the recorder inside it
    assert "navcli.log" in RUN_TIME["navcli.runner"]  # ... and so runs navcli/log/__init__.py first
    assert "navcli.plugins.registry" not in RUN_TIME["navcli.plugins.contract"]  # only under TYPE_CHECKING
    assert "navcli.plugins" not in RUN_TIME["navcli.plugins.registry"]  # its own package is already running


def test_no_import_cycle_among_navcli_modules():
    """Imports run one way: no module imports, at any depth, one that imports it back. The plugin
    registry (names to classes) sits below the configuration, and the checker (it runs missions)
    above the runner, with the commands; a plugin pilot's ``/pilot`` schema is made by the log's
    format, which the registry does not import."""
    assert strongly_connected(RUN_TIME) == []


def test_the_plugin_registry_sits_below_the_configuration():
    low = {"navcli.plugins", "navcli.plugins.registry", "navcli.plugins.contract", "navcli.plugins.boundary"}
    for mod in low:
        above = {d for d in RUN_TIME[mod] if d.startswith(("navcli.config", "navcli.scenario", "navcli.runner"))}
        assert above == set(), mod
    assert not any(d.startswith("navcli.log") for d in RUN_TIME["navcli.plugins.registry"])
    assert RUN_TIME["navcli.plugins.names"] == set()  # the names' rules: the lightest of all (the CLI's help)
    assert "navcli.plugins.checker" not in set().union(*(RUN_TIME[m] for m in RUN_TIME if m != "navcli.cli.plugins"))


FORMAT = "navcli.log.format"
"""The log's format: what the analysis package may import of navcli (besides the package root,
for the root error class, and the API's argument checks)."""
CHECKS = "navcli.checks.arguments"
"""The API's argument checks, which import the standard library and the root error class alone."""


def test_analysis_imports_only_the_format():
    for mod, deps in MODULES.items():
        if not mod.startswith("navcli.analysis"):
            continue
        for dep in deps:
            if dep.split(".")[0] != "navcli" or dep.startswith("navcli.analysis"):
                continue
            assert (
                dep in ("navcli", "navcli.NavcliError", "navcli.log")
                or dep in (FORMAT, CHECKS)
                or dep.startswith((FORMAT + ".", CHECKS + "."))
            ), f"{mod} imports {dep}"


def test_the_format_imports_only_msgspec():
    """The enumerations a log carries (a look's purposes, the Rescuer's states ...) are declared by
    the code that produces them and given to the format's schemas by the recorder
    (``navcli.log.writer.enums``), so the format, and the analysis that reads it, import no navcli."""
    for dep in MODULES[FORMAT]:
        assert dep.split(".")[0] in STDLIB | {"msgspec", "__future__"}, dep


def test_no_private_name_is_imported_across_modules():
    for path in sorted((ROOT / "navcli").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ImportFrom) and node.module != "__future__":
                private = [a.name for a in node.names if a.name.startswith("_") and not a.name.startswith("__")]
                assert not private, f"{path.relative_to(ROOT)} imports {private} from {node.module}"


def test_each_topic_name_is_written_once():
    """A topic's name is a literal only in the format; everything else uses its constant."""
    from navcli.log import format as fmt

    names = {v for k, v in vars(fmt).items() if k.endswith("_TOPIC")}
    assert len(names) == 18  # the fifteen, then /robot/path, /memory/supports, /map/regions
    where: dict[str, list[str]] = {n: [] for n in names}
    for path in sorted((ROOT / "navcli").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                for n in names:  # the name itself, or a path inside its messages ("/bids.motion.pilot")
                    if node.value == n or node.value.startswith(n + "."):
                        where[n].append(str(path.relative_to(ROOT)))
    assert {n: w for n, w in where.items() if w != ["navcli/log/format.py"]} == {}


AGENTS = ("navcli.pilot", "navcli.navigation", "navcli.learning")
"""The packages of agents: the Pilot, the Navigation system's agents, the Learning Agent."""
NOT_AGENTS = {"navcli.learning", "navcli.learning.model_file", "navcli.learning.softmax", "navcli.learning.ppo"}
"""In those packages but no agent: model files on disk, and the package's factory and the sampled
policies' plugins (softmax, ppo) that open them."""


@pytest.mark.parametrize("agent", sorted(m for m in KNOWN if m.startswith(AGENTS) and m not in NOT_AGENTS))
def test_agents_import_only_values_and_maths(agent):
    """An agent sees beliefs and returns bids: it imports values, maths (numpy, scipy) and agents."""
    for dep in MODULES[agent]:
        top = dep.split(".")[0]
        if top == "navcli":
            allowed = (
                any(dep == v or dep.startswith(v + ".") for v in VALUES)
                or dep in ("navcli", "navcli.NavcliError")
                or (
                    dep.startswith(AGENTS)
                    and dep not in NOT_AGENTS
                    and not dep.startswith("navcli.learning.model_file.")
                )
            )
            assert allowed, f"{agent} imports {dep}"
        else:
            assert top in STDLIB or top in ("numpy", "scipy", "__future__", "mypy_extensions"), f"{agent} imports {dep}"


def test_the_agents_include_the_learning_agent():
    assert {
        "navcli.learning.learning_agent",
        "navcli.learning.features",
        "navcli.pilot.potential_field",
        "navcli.navigation.rescuer",
    } <= {m for m in KNOWN if m.startswith(AGENTS)} - NOT_AGENTS


def _is_value(dep: str) -> bool:
    """A value module, a package of them (``navcli.params``), or a name imported from one."""
    return any(dep == v or dep.startswith(v + ".") for v in VALUES)


def test_value_modules_import_only_each_other():
    mods = [m for m in KNOWN if _is_value(m)]
    assert "navcli.params.declare" in mods
    for mod in mods:
        for dep in MODULES[mod]:
            top = dep.split(".")[0]
            assert top in STDLIB or top == "__future__" or _is_value(dep) or dep in ("navcli", "navcli.NavcliError"), (
                f"{mod} imports {dep}"
            )


def test_importing_the_agents_or_analysis_pulls_in_no_simulator():
    code = (
        "import sys, navcli.pilot, navcli.navigation; "
        "bad = [m for m in ('pymunk', 'yaml', 'foxglove', 'navcli.scenario', 'navcli.vision', 'navcli.world') "
        "if m in sys.modules]; [sys.modules.pop(m) for m in list(sys.modules) if m.startswith('navcli')]; "
        "import navcli.analysis.tables, navcli.analysis.render, navcli.analysis.mapplot; "
        "bad += [m for m in sys.modules if m.split('.')[0] in ('pymunk', 'foxglove') or m.startswith('navcli') "
        "and m not in ('navcli', 'navcli.builds', 'navcli.log', 'navcli.log.format', 'navcli.checks', 'navcli.checks.arguments') "
        "and not m.startswith('navcli.analysis')]; "
        "print(bad); sys.exit(1 if bad else 0)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr


def test_the_public_api_is_importable_and_listed():
    import navcli

    assert {"RunSpec", "load_scenario", "run_mission"} <= set(navcli.__all__)  # what the README's API uses
    for name in navcli.__all__:
        assert getattr(navcli, name) is not None, name


MAX_STATEMENTS = 350
"""Logical lines (statements) a module may hold: about the 450 physical lines of the dense layout
this bound was first set in. Statements, not lines: ruff format puts a long call's arguments one to
a line, which changes the count of lines and not what a reader must hold."""
MAX_TOP_LEVEL = 12


def statements(source: str) -> int:
    r"""The logical lines of ``source``: a statement split over several lines counts once; comments
    and blank lines not at all.

    >>> statements("x = f(\n    1,\n    2,\n)\n# a comment\n\nif x:\n    y = 1\n")
    3
    """
    return sum(1 for t in tokenize.generate_tokens(io.StringIO(source).readline) if t.type == tokenize.NEWLINE)


def test_no_module_is_longer_than_its_reader_can_hold():
    long = {
        str(p.relative_to(ROOT)): n
        for p in sorted((ROOT / "navcli").rglob("*.py"))
        if (n := statements(p.read_text())) > MAX_STATEMENTS
    }
    assert long == {}


def test_at_most_twelve_modules_sit_at_the_top_of_the_package():
    """Besides the package's own ``__init__`` and ``__main__``; the rest lives in packages named as
    the papers' systems are (pilot, vision, navigation, learning) and as navcli's own parts are."""
    top = sorted(p.stem for p in (ROOT / "navcli").glob("*.py") if p.stem not in ("__init__", "__main__"))
    assert len(top) <= MAX_TOP_LEVEL, top


def test_ci_runs_the_readmes_test_command():
    """`.ci/run` is the README's test command (with a quiet pip): lint, types, tests."""
    import re

    readme = (ROOT / "README.md").read_text()
    command = re.search(r"```sh\n(python -m pip install -e '\.\[test\]' && [^\n]+)\n```", readme).group(1)
    ci = (ROOT / ".ci" / "run").read_text().strip().splitlines()[-1]
    assert ci == command.replace("pip install -e", "pip install -q -e")
    assert "ruff check" in command and "mypy" in command and "pytest" in command
