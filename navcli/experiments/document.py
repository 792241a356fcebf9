"""The document ``navcli reproduce`` writes: headings, paragraphs, tables, lists and images as
blocks, written once as Markdown (``report.md``) and once as HTML (``report.html``), with no
converter between them."""

from __future__ import annotations

import math
from typing import Any, Sequence


class Report:
    """The report as blocks, written once as Markdown and once as HTML (no converter needed)."""

    def __init__(self) -> None:
        self.blocks: list[tuple[str, Any]] = []
        self.errors: list[str] = []
        """Every section's runs that ended in error, a line each: said at the top of the report."""
        self.error_count = 0

    def errored(self, lines: Sequence[str], count: int) -> None:
        """``count`` runs of a section that ended in error, said in ``lines`` (which, how many, why):
        kept for the top of the report; the caller says them in the section's notes too."""
        self.errors += [line for line in lines if line]
        self.error_count += count

    def heading(self, text: str, level: int = 2) -> None:
        self.blocks.append(("h", (level, text)))

    def text(self, text: str) -> None:
        self.blocks.append(("p", text))

    def notes(self, notes: Sequence[str | None]) -> None:
        """What a section's table cannot say (a small sample, in the words of every comparison), if anything."""
        said = [n for n in notes if n]
        if said:
            self.text("Notes:")
            self.bullets(said)

    def table(self, header: list[str], rows: list[list[Any]]) -> None:
        self.blocks.append(("table", (header, [[str(c) for c in r] for r in rows])))

    def image(self, path: str, caption: str) -> None:
        self.blocks.append(("img", (path, caption)))

    def bullets(self, items: list[str]) -> None:
        self.blocks.append(("ul", items))

    def markdown(self) -> str:
        out = []
        for kind, b in self.blocks:
            if kind == "h":
                out.append(f"{'#' * b[0]} {b[1]}")
            elif kind == "p":
                out.append(b)
            elif kind == "table":
                header, rows = b
                out += ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
                out += ["| " + " | ".join(r) + " |" for r in rows]
            elif kind == "ul":
                out += [f"- {item}" for item in b]
            else:
                out.append(f"![{b[1]}]({b[0]})")
            out.append("")
        return "\n".join(out)

    def html(self) -> str:
        import html

        e = html.escape
        from ..analysis.files import MARK

        out = [
            f"<!doctype html>{MARK}<html><head><meta charset='utf-8'><title>navcli reproduce</title><style>"
            "body{font-family:sans-serif;max-width:70em;margin:2em auto}table{border-collapse:collapse}"
            "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}img{max-width:100%}</style></head><body>"
        ]
        for kind, b in self.blocks:
            if kind == "h":
                out.append(f"<h{b[0]}>{e(b[1])}</h{b[0]}>")
            elif kind == "p":
                out.append(f"<p>{e(b)}</p>")
            elif kind == "table":
                header, rows = b
                out.append(
                    "<table><tr>"
                    + "".join(f"<th>{e(h)}</th>" for h in header)
                    + "</tr>"
                    + "".join("<tr>" + "".join(f"<td>{e(c)}</td>" for c in r) + "</tr>" for r in rows)
                    + "</table>"
                )
            elif kind == "ul":
                out.append("<ul>" + "".join(f"<li>{e(item)}</li>" for item in b) + "</ul>")
            else:
                out.append(f"<figure><img src='{e(b[0])}' alt='{e(b[1])}'><figcaption>{e(b[1])}</figcaption></figure>")
        return "\n".join(out + ["</body></html>\n"])


def interval_text(m: float, lo: float, hi: float, sign: bool = False) -> str:
    """``m [lo, hi]``, with one decimal (and a sign for a gain); ``m (no interval)`` without bounds;
    ``-`` for no value at all (no pair, no run).

    >>> interval_text(2.0, 1.0, 3.25), interval_text(-4.0, -9.0, 1.0, sign=True), interval_text(5.0, float("nan"), float("nan"))
    ('2.0 [1.0, 3.2]', '-4.0 [-9.0, +1.0]', '5.0 (no interval)')
    >>> interval_text(float("nan"), float("nan"), float("nan"), sign=True)
    '- (no value)'
    """
    f = "{:+.1f}" if sign else "{:.1f}"
    if not math.isfinite(m):
        return "- (no value)"
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return f.format(m) + " (no interval)"
    return f"{f.format(m)} [{f.format(lo)}, {f.format(hi)}]"
