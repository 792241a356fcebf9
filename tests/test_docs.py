"""The documentation: the site builds with warnings as errors from a clean folder, every command and
snippet in it runs (docs/contributing.md, "The documentation", states the rules), the README's quick
start runs, and the README stays a five-minute read."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from conftest import ROOT

DOCS = ROOT / "docs"
FENCE = re.compile(r"^```([\w{}-]*)[^\n]*\n(.*?)^```", re.S | re.M)
LINKED = ("scenarios", "plans", "examples", "docs")  # what a page's commands see of the repository
MAX_NOT_RUN = 13  # ```sh blocks: few, each with its reason
CAPTION = re.compile(r"\A:caption: ([\w.-]+)\n\n?")  # a {code-block} of a file, captioned with its name
PILOT_TUTORIAL = "docs/tutorials/your-own-pilot.md"  # run by its own test, which checks what it made


def _pages() -> list[Path]:
    pages = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts and "results" not in p.parts)
    return [ROOT / "README.md"] + [p for p in pages if p.name != "python-api.md"]  # tests/test_api.py runs that one


def _blocks(page: Path) -> list[tuple[str, str, str]]:
    """(language, body, the text before the block) of each fenced block of a page, in order."""
    text = page.read_text(encoding="utf-8")
    return [(m.group(1), m.group(2), text[: m.start()]) for m in FENCE.finditer(text)]


def _commands(body: str) -> list[tuple[str, int]]:
    """A console block's commands, each with the exit code its trailing comment states (0 if none)."""
    out = []
    for line in body.splitlines():
        if line.startswith("$ "):
            code = re.search(r"#\s*exits (\d+)", line)
            out.append((line[2:], int(code.group(1)) if code else 0))
    return out


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("html")
    r = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS), str(out)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    return out


def test_the_site_builds_with_warnings_as_errors(built):
    for page in (
        "index",
        "reference/cli",
        "reference/params",
        "reference/api",
        "results/index",
        "changelog",
        "references",
        "concepts/pilot",
        "tutorials/first-mission",
    ):
        assert (built / f"{page}.html").is_file(), page


def test_the_references_are_made_from_the_code(built):
    import typer

    from navcli.cli import app
    from navcli.params import Params

    cli = (built / "reference" / "cli.html").read_text(encoding="utf-8")
    root = typer.main.get_command(app)
    for name, cmd in root.commands.items():
        assert f"navcli {name}" in cli, name
        for p in getattr(cmd, "params", []):
            for opt in p.opts if p.param_type_name == "option" else []:
                assert opt in cli, (name, opt)
    params = (built / "reference" / "params.html").read_text(encoding="utf-8")
    names = [n for n, _, _ in Params().declarations()]
    assert len(names) > 50 and all(
        f'<code class="docutils literal notranslate"><span class="pre">{n}</span>' in params for n in names
    )
    api = (built / "reference" / "api.html").read_text(encoding="utf-8")
    assert all(f'id="navcli.api.{f}"' in api for f in ("run", "compare", "sweep"))
    for plugin_facing in ("beliefs.Beliefs", "beliefs.KnownObstacle", "bidding.Move", "pilot.Pilot", "pilot.Avoidance"):
        assert f'id="navcli.{plugin_facing}"' in api, plugin_facing
    assert all(f'id="navcli.beliefs.KnownObstacle.{f}"' in api for f in ("a", "b", "radius"))
    assert all(f'id="navcli.pilot.Pilot.{f}"' in api for f in ("max_speed", "own_params", "params", "robot"))
    from navcli.analysis.columns import TABLES

    tour = (built / "python-api.html").read_text(encoding="utf-8")
    for columns in TABLES.values():
        assert all(f'<span class="pre">{c}</span>' in tour for c in columns)


def test_every_block_is_run_or_says_why_not():
    not_run = 0
    for page in _pages():
        for lang, body, before in _blocks(page):
            if lang in ("sh", "bash", "shell"):
                paragraph = before.rstrip().rsplit("\n\n", 1)[-1].lower()
                is_setup = page.name == "README.md" and body.startswith("python -m pip install -e ")
                assert is_setup or "not run by the tests" in paragraph, (
                    f"{page}: a {lang} block with no reason: {body[:60]}"
                )
                not_run += not is_setup
            else:
                assert lang in (
                    "console",
                    "python",
                    "text",
                    "yaml",
                    "{eval-rst}",
                    "{code-block}",
                    "{toctree}",
                    "{literalinclude}",
                    "{include}",
                    "{navcli-cli}",
                    "{navcli-params}",
                    "{navcli-references}",
                    "",
                ), (page, lang)
                if lang == "console":
                    assert _commands(body), f"{page}: a console block with no $ command"
                if lang == "{code-block}":  # the runner writes it to the file its caption names
                    assert CAPTION.match(body), f"{page}: a code-block with no file's name as :caption:"
    assert 0 < not_run <= MAX_NOT_RUN


def _run_page(page: str, tmp_path: Path, monkeypatch) -> None:
    """A page's blocks in order, in the empty folder ``tmp_path`` that sees the repository's
    scenarios, plans, examples and docs: its commands run, its Python blocks share one namespace,
    and a code-block captioned with a file's name is added to that file there (a file written in
    several blocks is the blocks in order)."""
    import matplotlib

    matplotlib.use("Agg")
    for name in LINKED:
        os.symlink(ROOT / name, tmp_path / name)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", list(sys.path))  # the registry adds the current folder: this page's only
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    namespace: dict = {"__name__": "__docs__"}
    for i, (lang, body, _) in enumerate(_blocks(ROOT / page)):
        if lang == "console":
            for command, expected in _commands(body):
                r = subprocess.run(
                    ["bash", "-c", command],
                    capture_output=True,
                    text=True,
                    env=env,
                    cwd=tmp_path,
                    stdin=subprocess.DEVNULL,
                    timeout=300,
                )
                if r.returncode != expected:
                    raise AssertionError(
                        f"{page}: `{command}` exited {r.returncode}:\n{r.stdout[-1500:]}{r.stderr[-1500:]}"
                    )
        elif lang == "python":
            exec(compile(body, f"{page} block {i + 1}", "exec"), namespace)
        elif lang == "{code-block}" and (m := CAPTION.match(body)):
            with open(tmp_path / m.group(1), "a", encoding="utf-8") as f:
                f.write(body[m.end() :] + "\n\n")
    for name in LINKED:  # nothing written into the repository through the links
        assert (tmp_path / name).is_symlink()
    # a page's modules (swerve.py) forgotten: other tests use those names
    for name, module in list(sys.modules.items()):
        if Path(getattr(module, "__file__", None) or "/").resolve().is_relative_to(tmp_path.resolve()):
            del sys.modules[name]


@pytest.mark.parametrize(
    "page",
    [
        str(p.relative_to(ROOT))
        for p in _pages()
        if any(lang in ("console", "python") for lang, _, _ in _blocks(p))
        and str(p.relative_to(ROOT)) != PILOT_TUTORIAL
    ],
)
def test_every_command_and_snippet_of_a_page_runs(page, tmp_path, monkeypatch):
    _run_page(page, tmp_path, monkeypatch)


def test_the_pilot_tutorial_writes_checks_and_compares_a_short_pilot_under_its_own_name(tmp_path, monkeypatch):
    """The tutorial's pilot is its page's code, short; the page's commands check it, run it and
    compare it under the name the page gives it, which the table and the files then use."""
    _run_page(PILOT_TUTORIAL, tmp_path, monkeypatch)
    code = (tmp_path / "swerve.py").read_text(encoding="utf-8").splitlines()
    assert 25 <= sum(bool(line.strip()) for line in code) <= 35  # about thirty lines, blank ones aside
    runs = pd.read_csv(tmp_path / "cmp" / "runs.csv")
    assert sorted(set(runs["pilot"])) == ["geometric", "mine"] and len(runs) == 4  # 2 pilots x 2 seeds
    assert set(pd.read_csv(tmp_path / "cmp" / "table.csv")["pilot"]) == {"geometric", "mine"}
    written = [p.name for p in (tmp_path / "cmp").rglob("*") if p.is_file()]
    assert any(n.startswith("mine") for n in written) and not any("swerve" in n for n in written), written


def test_the_readme_is_a_five_minute_read():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.encode()) <= 12_000
    for link in re.findall(r"\]\((docs/[^)#]+)", readme):
        assert (ROOT / link).exists(), link
    picture = re.search(r"!\[[^]]*\]\((docs/[^)]+\.png)\)", readme).group(1)
    assert (ROOT / picture).stat().st_size < 150_000


def test_the_readmes_results_and_the_results_page_are_made_from_the_checked_in_report(make_results):
    page, table = make_results.render()
    assert (DOCS / "results" / "index.md").read_text(encoding="utf-8") == page
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert make_results.between_markers(readme) == table


def test_the_results_page_is_not_older_than_the_code_it_reports(make_results):
    """The page's report must be of a commit no later commit changes ``navcli/`` after (but its
    documentation files), made from committed sources; `python docs/make_results.py --check` says
    why not and the command that remakes it."""
    from navcli.experiments.provenance import checkout

    if not checkout(ROOT):
        pytest.skip("not a git checkout: the report's commit cannot be checked")
    problems = make_results.check()
    assert not problems, "docs/results is stale:\n" + "\n".join(problems)


def test_the_page_names_the_recorded_command_with_its_folder_as_dir(make_results, tmp_path, monkeypatch):
    import json

    run = tmp_path / "run dir"  # a space: the command is quoted as a shell would need it
    source = {
        "command": ["navcli", "reproduce", "all", "--out", str(run), "--jobs", "2"],
        "commit": "0123456789abcdef0123456789abcdef01234567",
        "commit_date": "2026-12-06",
        "dir": str(run),
    }
    monkeypatch.setattr(make_results, "KEPT", tmp_path)
    (tmp_path / "source.json").write_text(json.dumps(source))
    (tmp_path / "report.md").write_text(f"# navcli reproduce\n\nLogs: {run}/table1\n")
    page, _ = make_results.render()
    assert "Made by `navcli reproduce all --out DIR --jobs 2` at commit `0123456` (2026-12-06)" in page
    assert "Logs: DIR/table1" in page
