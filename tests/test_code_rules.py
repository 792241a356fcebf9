"""Rules of the code that no linter states: how long a function may be, and that the code and docs
speak of what the code does, never of the issue that changed it."""

from __future__ import annotations

import ast
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "navcli"
MAX_LINES = 100
"""A function's length in lines, its signature and docstring included, past which no reader holds it."""
EXEMPT: set[str] = set()
"""Functions let past :data:`MAX_LINES` by name (``path:function``): none."""


def _is_command(f: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """A typer command (``@app.command()``): its signature is its list of options."""
    return any(
        isinstance(d, ast.Call) and isinstance(d.func, ast.Attribute) and d.func.attr == "command"
        for d in f.decorator_list
    )


def _length(f: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """Lines from the ``def`` to the last line, or from the first line of the body for a command."""
    start = f.body[0].lineno if _is_command(f) else f.lineno
    return (f.end_lineno or f.lineno) - start + 1


def long_functions(root: Path) -> list[str]:
    """``path:name (lines)`` of every function under ``root`` longer than :data:`MAX_LINES`."""
    found = []
    for path in sorted(root.rglob("*.py")):
        where = path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else path.as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and _length(node) > MAX_LINES:
                found.append(f"{where}:{node.name} ({_length(node)} lines)")
    return found


def test_no_function_in_the_package_is_longer_than_a_reader_can_hold():
    assert [f for f in long_functions(PACKAGE) if f.split(" (")[0] not in EXEMPT] == []


def test_the_length_check_finds_a_long_function_and_spares_a_commands_signature(tmp_path):
    body = "".join(f"    x{i} = {i}\n" for i in range(MAX_LINES))
    options = "".join(f"    o{i}: int = {i},\n" for i in range(MAX_LINES))
    (tmp_path / "m.py").write_text(
        f"def long():\n{body}\n\ndef short():\n{body[: -len(body.splitlines()[-1]) - 1]}\n\n"
        f"@app.command()\ndef cmd(\n{options}):\n    pass\n",
        encoding="utf-8",
    )
    assert long_functions(tmp_path) == [f"{(tmp_path / 'm.py').as_posix()}:long ({MAX_LINES + 1} lines)"]


ISSUE_NUMBER = re.compile(r"\b(?:issues?|pull requests?|PR) ?#? ?\d+", re.IGNORECASE)
"""A reference to a tracker's entry by number ("issue 22", "Issue #7", "PR 3"): history, which the
code's comments and docs do not carry (the commit log does)."""
TEXT = (".py", ".md", ".rst", ".txt", ".yaml", ".yml", ".toml", ".cfg", ".html")


def _tracked_text_files() -> list[Path]:
    """The repository's text files under navcli/, docs/ and tests/, and its top-level documents."""
    out = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard", "navcli", "docs", "tests", "README.md", "CHANGELOG.md"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return [ROOT / p for p in out.splitlines() if p.endswith(TEXT) and (ROOT / p).is_file()]


def issue_numbers(paths: list[Path]) -> list[str]:
    """``path:line: text`` of every line of ``paths`` that cites an issue by number."""
    found = []
    for path in paths:
        for i, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if ISSUE_NUMBER.search(line):
                found.append(f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}:{i}: {line.strip()}")
    return found


def test_no_code_or_doc_cites_an_issue_number():
    files = [p for p in _tracked_text_files() if p != Path(__file__).resolve()]
    assert any(p.name == "rescuer.py" for p in files) and any(p.suffix == ".md" for p in files)  # it reads them
    assert issue_numbers(files) == []


def test_the_scan_finds_an_issue_number_in_its_usual_spellings(tmp_path):
    cited = ["# issue 22's rule", "see Issue #7", "(issues 3 and 4)", "PR 12 made it", "pull request #5"]
    clean = ["the issue of a periodical", "an issue: 3 runs errored", "# a PRNG seeded 42", "tissue 3"]
    f = tmp_path / "m.py"
    f.write_text("\n".join(cited + clean) + "\n", encoding="utf-8")
    assert [line.split(": ", 1)[1] for line in issue_numbers([f])] == cited
