"""Pilots and Navigation policies of one's own: ``plugins list``, ``plugins check``."""

from __future__ import annotations

from typing import Annotated

import typer

from ..plugins.names import PLUGIN_FORMS
from .common import app
from .errors import EXIT_INTERNAL, say

plugins_app = typer.Typer(
    help="Pilots and Navigation policies: navcli's own and installed plugins.", no_args_is_help=True
)
app.add_typer(plugins_app, name="plugins")

KindArgument = Annotated[str, typer.Argument(metavar="KIND", help="pilot or policy.")]


def _kind(kind: str) -> str:
    from ..config import ConfigError

    if kind not in ("pilot", "policy"):
        raise ConfigError(f"KIND: {kind!r} is not pilot or policy")
    return kind


@plugins_app.command("list")
def list_plugins() -> None:
    """Every pilot and Navigation policy a name can give: navcli's own and the installed packages'
    (entry points navcli.pilots, navcli.policies), with version, origin and parameters. A plugin
    not installed is named as module:Class or path/to/file.py:Class, NAME=module:Class or
    NAME=path/to/file.py:Class to call it NAME."""
    from ..plugins import GROUPS, installed

    for kind in GROUPS:
        for c in installed(kind):
            if isinstance(c, tuple):
                typer.echo(f"{kind:7s} {c[0]:24s} cannot be used: {c[1]}")
                continue
            own = c.params_class
            params = f"; parameters {', '.join(f'{c.group}.{n}' for n, _, _ in own.declarations())}" if own else ""
            typer.echo(f"{kind:7s} {c.name:24s} {c.version:12s} {c.origin}{params}")


@plugins_app.command("check")
def check_plugin(
    kind: KindArgument,
    name: Annotated[str, typer.Argument(metavar="NAME", help=f"An installed plugin's name, {PLUGIN_FORMS}.")],
) -> None:
    """Tell a plugin's author what their class gets wrong (in the spirit of Gymnasium's
    env_checker): its kind and declarations, its output in a handful of situations against
    navcli's contract and its /pilot messages against their schema, its determinism, and short
    missions with each perception. Exit 0 when it passes, 1 with the list of problems."""
    from ..plugins import UnknownPlugin
    from ..plugins.checker import check

    problems = check(_kind(kind), name)  # type: ignore[arg-type]
    if problems and problems[0].startswith("unknown "):  # not found: bad input
        raise UnknownPlugin(problems[0])
    if problems:
        for p in problems:
            say(f"problem: {p}")
        say(f"{name}: {len(problems)} problem(s)")
        raise typer.Exit(EXIT_INTERNAL)
    typer.echo(f"{name}: passes navcli's checks of a {kind}")
