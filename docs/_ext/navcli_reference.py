"""The reference pages made from the code at build time, so they cannot drift from it.

Two directives for MyST pages:

- ``{navcli-cli}``: every command of the ``navcli`` typer app, with its usage, what it does and
  each argument and option as ``navcli COMMAND --help`` shows it (typer 0.28 carries its own copy
  of click, so sphinx-click cannot read the app; this walks the same objects ``--help`` prints);
- ``{navcli-params}``: every parameter, as ``navcli params --markdown`` prints it (the same
  function), from the declarations in ``navcli/params/``;
- ``{navcli-references}``: the papers' references, from ``CITATION.cff``;
- ``{navcli-columns} TABLE``: the columns of one of the tables of runs the Python API returns,
  each with what it holds, from their declarations (``navcli/analysis/columns.py``).

Each renders Markdown and parses it in place, so headings join the page's table of contents.
"""

from __future__ import annotations

import re
from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective


def _escape(text: str) -> str:
    """Help text as Markdown: its backquoted names kept as code, anything else that Markdown would
    read as markup (``<path>``, ``*``, ``_``, a table's ``|``) escaped."""
    out = []
    for i, piece in enumerate(re.split(r"(`[^`]*`)", text)):
        out.append(piece if i % 2 else re.sub(r"([\\<>*_|\[\]#])", r"\\\1", piece))
    return "".join(out)


def _paragraphs(help_text: str) -> list[str]:
    """A docstring's paragraphs, each joined into one line (click's ``\\b`` markers dropped)."""
    paras = re.split(r"\n\s*\n", (help_text or "").strip())
    return [" ".join(line.strip() for line in p.splitlines() if line.strip() != "\b") for p in paras if p.strip()]


def cli_markdown(level: int = 2) -> str:
    """Every command of the ``navcli`` app, depth first, in the order ``navcli --help`` lists them."""
    import typer

    from navcli.cli import app

    root = typer.main.get_command(app)
    lines: list[str] = []

    def visit(cmd: Any, ctx: Any, depth: int) -> None:
        sub = getattr(cmd, "commands", None)
        if depth:
            lines.append(f"{'#' * (level + depth - 1)} {ctx.command_path}\n")
        lines.append(f"```text\n{cmd.get_usage(ctx).strip()}\n```\n")
        lines.extend(_escape(p) + "\n" for p in _paragraphs(cmd.help or ""))
        lines.extend(_escape(p) + "\n" for p in _paragraphs(getattr(cmd, "epilog", None) or ""))
        records = [
            (kind, r)
            for kind in ("argument", "option")
            for p in cmd.params
            if p.param_type_name == kind and (r := p.get_help_record(ctx))
        ]
        if records:
            for kind, (names, text) in records:
                lines.append(f"- `{names}` ({kind}): {_escape(text)}")
            lines.append("")
        for name in sub or {}:
            child = sub[name]
            visit(child, child.make_context(name, [], parent=ctx, resilient_parsing=True), depth + 1)

    visit(root, root.make_context("navcli", [], resilient_parsing=True), 0)
    return "\n".join(lines)


def params_markdown() -> str:
    """navcli's own parameters with their defaults (a plugin's own: ``navcli params --pilot NAME``)."""
    from navcli.cli.run import params_markdown as table
    from navcli.params import Params

    return table(Params())


def references_markdown() -> str:
    """The papers' references as ``CITATION.cff`` holds them (the one place they are written)."""
    from pathlib import Path

    import yaml

    cff = yaml.safe_load((Path(__file__).resolve().parents[2] / "CITATION.cff").read_text(encoding="utf-8"))
    lines = []
    for ref in cff["references"]:
        names = [f"{a['given-names']} {a['family-names']}" for a in ref["authors"]]
        where = ref.get("collection-title") or ref["conference"]["name"]
        parts = [
            ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0],
            f'"{ref["title"]}"',
            f"*{_escape(where)}*",
        ]
        if "volume" in ref:
            parts.append(f"volume {ref['volume']}")
        parts += [ref["publisher"]["name"], str(ref["year"])]
        lines.append("- " + ", ".join(parts) + (f", <{ref['url']}>" if "url" in ref else "") + ".")
    return "\n".join(lines) + "\n"


def columns_markdown(table: str) -> str:
    """The columns of ``table`` (a name of :data:`navcli.analysis.columns.TABLES`), one item each."""
    from navcli.analysis.columns import TABLES

    return "\n".join(f"- `{name}`: {_escape(what)}" for name, what in TABLES[table].items()) + "\n"


class _Generated(SphinxDirective):
    has_content = False
    make: Any = None

    def run(self) -> list[nodes.Node]:
        text = type(self).make()
        container = nodes.section() if "\n#" in "\n" + text else nodes.container()
        self.state.nested_parse(
            StringList(text.splitlines(), source="<generated>"), self.content_offset, container, match_titles=True
        )
        return list(container.children)


class CliDirective(_Generated):
    make = staticmethod(cli_markdown)


class ParamsDirective(_Generated):
    make = staticmethod(params_markdown)


class ReferencesDirective(_Generated):
    make = staticmethod(references_markdown)


class ColumnsDirective(SphinxDirective):
    has_content = False
    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        container = nodes.container()
        text = columns_markdown(self.arguments[0])
        self.state.nested_parse(StringList(text.splitlines(), source="<generated>"), self.content_offset, container)
        return list(container.children)


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_directive("navcli-cli", CliDirective)
    app.add_directive("navcli-params", ParamsDirective)
    app.add_directive("navcli-references", ReferencesDirective)
    app.add_directive("navcli-columns", ColumnsDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
