"""The results page (docs/results/index.md) and the README's table of what reproduces, made from a
``navcli reproduce`` report, never pasted.

    python docs/make_results.py DIR

copies ``DIR/report.md`` and ``DIR/source.json`` (the report's provenance, as ``navcli reproduce``
wrote it: its command line, commit, build and libraries) to ``docs/results/report/``, then writes
the page and the README's table from that copy. ``python docs/make_results.py`` alone remakes them
from the copy checked in; tests/test_docs.py checks that what is checked in is what this script
makes. ``python docs/make_results.py --check`` exits 1, saying why and the command that remakes
it, when the report checked in is older than the code it reports
(:func:`navcli.experiments.provenance.stale`: a commit after the report's changes ``navcli/``
outside its documentation files, or the report was made from uncommitted changes); a test runs it.
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import shutil
import sys
from pathlib import Path

from navcli.experiments.learning_paper import AGAINST_RANDOM as RANDOM
from navcli.experiments.learning_paper import NOT_JUDGED

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
KEPT = DOCS / "results" / "report"
PAGE = DOCS / "results" / "index.md"
START, END = "<!-- results: made by docs/make_results.py -->", "<!-- end of results -->"


def _sections(report: str) -> list[tuple[str, list[dict[str, str]]]]:
    """Each ``##`` section of a report with the rows of its tables (a dict per row, by header)."""
    out: list[tuple[str, list[dict[str, str]]]] = []
    header: list[str] | None = None
    for line in report.splitlines():
        if line.startswith("## "):
            out.append((line[3:].strip(), []))
            header = None
        elif line.startswith("|") and out:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if header is None:
                header = cells
            elif not all(set(c) <= {"-", ":"} for c in cells):
                out[-1][1].append(dict(zip(header, cells)))
        else:
            header = None
    return out


def summary_table(report: str) -> str:
    """What reproduces, by experiment: the report's verdicts counted (agrees / does not / no verdict);
    then, where the report holds targets (columns named ``target ...``), each section's targets
    counted (met / not met / no verdict); then, where it judges policies against the uniform random
    one (columns named ``... against random``), each section's verdicts counted (each of
    navcli.experiments.learning_paper.AGAINST_RANDOM, or none)."""
    lines = ["| experiment | agrees | does not agree | no verdict |", "| --- | ---: | ---: | ---: |"]
    targets = ["", "| targets of | met | not met | no verdict |", "| --- | ---: | ---: | ---: |"]
    random = ["", "| against uniform random | " + " | ".join(RANDOM) + " | no verdict |", "| --- |" + " ---: |" * 4]
    for title, rows in _sections(report):
        judged = [v for r in rows for k, v in r.items() if k.endswith("against random") and v not in NOT_JUDGED]
        if judged:
            counts = [sum(v == w for v in judged) for w in RANDOM]
            random.append(f"| {title} | " + " | ".join(map(str, counts)) + f" | {len(judged) - sum(counts)} |")
        verdicts = [r["agreement"] for r in rows if "agreement" in r]
        if verdicts:
            agree = sum(v == "agrees" for v in verdicts)
            disagree = sum(v.startswith("does not agree") for v in verdicts)
            lines.append(f"| {title} | {agree} | {disagree} | {len(verdicts) - agree - disagree} |")
        aims = [v for r in rows for k, v in r.items() if k.startswith("target")]
        if aims:
            met, missed = sum(v == "met" for v in aims), sum(v.startswith("not met") for v in aims)
            targets.append(f"| {title} | {met} | {missed} | {len(aims) - met - missed} |")
    return "\n".join(lines + (targets if len(targets) > 3 else []) + (random if len(random) > 3 else [])) + "\n"


def command(source: dict) -> str:
    """The command that made the kept report, its folder written ``DIR``."""
    argv = source["command"]
    if argv is None:
        return "navcli.experiments.reproduce.reproduce (from Python)"
    if isinstance(argv, str):  # a report whose command is a line of text, not argv
        return argv.replace(source["dir"], "DIR")
    return shlex.join(a.replace(source["dir"], "DIR") for a in argv)


def render() -> tuple[str, str]:
    """(the results page, the README's table) from the report kept in docs/results/report/."""
    source = json.loads((KEPT / "source.json").read_text(encoding="utf-8"))
    report = (KEPT / "report.md").read_text(encoding="utf-8")
    quick = "QUICK RUN" in report
    report = report.replace(source["dir"], "DIR")  # the folder it was written to, as the command names it
    body = [line for line in report.splitlines() if not line.startswith(("# ", "<!--"))]
    body = [re.sub(r"^!\[([^]]*)\]\([^)]*\)$", r"(Figure not kept here: \1.)", line) for line in body]
    table = summary_table(report)
    page = (
        "\n".join(
            [
                "# Results",
                "",
                (
                    "This is the **quick reproduction** (`--quick`: few reruns, to check the machinery; its intervals are "
                    "wide and its verdicts are not the reproduction's). "
                    if quick
                    else ""
                )
                + f"Made by `{command(source)}` at commit `{source['commit'][:7]}` "
                f"({source.get('commit_date') or source['date']}), and turned into this page "
                "by `python docs/make_results.py`; nothing here is typed by hand. How each experiment is built: "
                "[reproducing both papers](../tutorials/reproducing.md).",
                "",
                "## What reproduces",
                "",
                table,
                *body,
            ]
        ).rstrip()
        + "\n"
    )
    return page, table


def between_markers(readme: str) -> str:
    """The table between the README's markers."""
    return readme.split(START, 1)[1].split(END, 1)[0].strip("\n") + "\n"


def write() -> None:
    page, table = render()
    PAGE.write_text(page, encoding="utf-8")
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    head, rest = readme.split(START, 1)
    readme = head + START + "\n" + table + rest[rest.index(END) :]
    (ROOT / "README.md").write_text(readme, encoding="utf-8")


def check() -> list[str]:
    """Why the kept report no longer stands for the code checked out, with the command that remakes
    it; empty when it stands."""
    from navcli.experiments.provenance import stale

    source = json.loads((KEPT / "source.json").read_text(encoding="utf-8"))
    problems = stale(source, ROOT)
    if problems:
        problems.append(
            f"remake it: {command(source)} && python docs/make_results.py DIR (DIR: a new folder; then commit "
            "docs/results/ and README.md)"
        )
    return problems


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", nargs="?", type=Path, help="a `navcli reproduce --out` folder to take the report from")
    ap.add_argument("--check", action="store_true", help="exit 1 when the kept report is older than its code")
    a = ap.parse_args()
    if a.check:
        problems = check()
        for line in problems:
            print(f"docs/results is stale: {line}", file=sys.stderr)
        sys.exit(1 if problems else 0)
    if a.dir is not None:
        if not (a.dir / "source.json").is_file():
            ap.error(f"{a.dir}: no source.json (a report of `navcli reproduce`, which records its provenance there)")
        KEPT.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(a.dir / "report.md", KEPT / "report.md")
        shutil.copyfile(a.dir / "source.json", KEPT / "source.json")
    write()


if __name__ == "__main__":
    main()
