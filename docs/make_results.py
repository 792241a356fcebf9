"""The results page (docs/results/index.md) and the README's table of what reproduces, made from a
``navcli reproduce`` report, never pasted.

    python docs/make_results.py DIR --command "navcli reproduce --quick --out DIR"

copies ``DIR/report.md`` to ``docs/results/report/report.md`` with the command that made it and the
commit checked out (``source.json``), then writes the page and the README's table from that copy.
``python docs/make_results.py`` alone remakes them from the copy checked in; tests/test_docs.py
checks that what is checked in is what this script makes.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
from pathlib import Path

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
    """What reproduces, by experiment: the report's verdicts counted (agrees / does not / no verdict)."""
    lines = ["| experiment | agrees | does not agree | no verdict |", "| --- | ---: | ---: | ---: |"]
    for title, rows in _sections(report):
        verdicts = [r["agreement"] for r in rows if "agreement" in r]
        if not verdicts:
            continue
        agree = sum(v == "agrees" for v in verdicts)
        disagree = sum(v.startswith("does not agree") for v in verdicts)
        lines.append(f"| {title} | {agree} | {disagree} | {len(verdicts) - agree - disagree} |")
    return "\n".join(lines) + "\n"


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
                + f"Made by `{source['command']}` at commit `{source['commit']}` ({source['date']}), and turned into this page "
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", nargs="?", type=Path, help="a `navcli reproduce --out` folder to take the report from")
    ap.add_argument("--command", help="the command that made it (stated on the page)")
    a = ap.parse_args()
    if a.dir is not None:
        if not a.command:
            ap.error("--command: say which command made the report")
        KEPT.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(a.dir / "report.md", KEPT / "report.md")
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.strip()
        date = subprocess.run(
            ["git", "log", "-1", "--format=%cs"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.strip()
        source = {"command": a.command, "commit": commit, "date": date, "dir": str(a.dir.resolve())}
        (KEPT / "source.json").write_text(json.dumps(source, indent=1) + "\n", encoding="utf-8")
    write()


if __name__ == "__main__":
    main()
