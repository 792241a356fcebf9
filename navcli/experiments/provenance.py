"""Where a report's numbers come from: the command that made them, the commit and whether the
working tree differed from it, the build and every library's version (``navcli reproduce``'s
``source.json`` and the top of its report), and whether a report is older than the code it
reports (:func:`stale`, the check of the results page: ``python docs/make_results.py --check``).

What a report *depends on* (:data:`SOURCES`): every file under ``navcli/`` (the code,
the bundled scenarios and the bundled model) but its documentation files (:data:`DOCS_ONLY`), which
change no number. The report records a digest of each of them as they were (:func:`digests`), and
any difference makes it stale, whatever the change (a docstring edit too: a change is not read for
what it does). The digests need no history, so a shallow clone checks as well as a full one; the
commits since the report's own are named where the history has them. The environment (the build,
the libraries' versions, Python) is recorded beside them, not checked: it is not in the repository.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import platform
import re
import subprocess
from pathlib import Path
from typing import Any, Sequence

ROOT = Path(__file__).resolve().parents[2]
"""The checkout navcli runs from, when it runs from one (an editable install)."""
DOCS_ONLY = ("*.md", "*.rst", "*.txt")
"""Files under ``navcli/`` that change no number."""
SOURCES = ("navcli",) + tuple(f":(exclude,glob)navcli/**/{pattern}" for pattern in DOCS_ONLY)
"""What a report depends on, as a git pathspec: ``navcli/`` but its documentation files."""
UNKNOWN = "unknown"


def git(root: Path, *args: str, strip: bool = True) -> str | None:
    """``git -C root ARGS``' output (stripped); None when git, the checkout or the object is missing."""
    try:
        r = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, timeout=60)
    except OSError:
        return None
    if r.returncode != 0:
        return None
    return r.stdout.strip() if strip else r.stdout


def checkout(root: Path = ROOT) -> bool:
    """Whether ``root`` is the top of a git checkout (not a folder inside another repository, as
    site-packages inside a user's project would be)."""
    top = git(root, "rev-parse", "--show-toplevel")
    return top is not None and Path(top).resolve() == root.resolve()


def libraries() -> dict[str, str]:
    """Python's version and that of every library navcli needs (its distribution's requirements
    without an extra), by distribution name."""
    out = {"python": platform.python_version()}
    try:
        required = importlib.metadata.requires("navcli") or []
    except importlib.metadata.PackageNotFoundError:  # run from a source tree never installed
        required = []
    for req in required:
        if "extra ==" in req:
            continue
        name = re.split(r"[\s<>=!~;\[(]", req, maxsplit=1)[0]
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def digests(root: Path = ROOT) -> dict[str, str]:
    """Each tracked file of :data:`SOURCES` in ``root``'s working tree (a git checkout: its callers
    ask :func:`checkout` first), by path, with the sha256 of its bytes (16 hex digits)."""
    listed = git(root, "ls-files", "-z", "--", *SOURCES, strip=False)
    paths = sorted(p for p in (listed or "").split("\0") if p)
    return {p: hashlib.sha256((root / p).read_bytes()).hexdigest()[:16] for p in paths if (root / p).is_file()}


def changed(recorded: dict[str, str], now: dict[str, str]) -> list[str]:
    """The files that differ between two :func:`digests`: changed, added or removed.

    >>> changed({"navcli/a.py": "1", "navcli/b.py": "2"}, {"navcli/a.py": "1", "navcli/b.py": "3", "navcli/c.py": "4"})
    ['navcli/b.py (changed)', 'navcli/c.py (added)']
    """
    out = [f"{p} (changed)" for p in sorted(recorded.keys() & now.keys()) if recorded[p] != now[p]]
    out += [f"{p} (added)" for p in sorted(now.keys() - recorded.keys())]
    return out + [f"{p} (removed)" for p in sorted(recorded.keys() - now.keys())]


def record(command: Sequence[str] | None, root: Path = ROOT) -> dict[str, Any]:
    """The provenance of a report made now by ``command`` (argv; None: called from Python with
    settings no command line gives): navcli's version and build, the commit (full hash; ``unknown``
    outside a checkout), ``dirty`` (tracked files differ from the commit) and ``dirty_sources``
    (which of :data:`SOURCES` differ, untracked ones too), and :func:`libraries`."""
    from .. import BUILD, __version__

    here = checkout(root)
    commit = (git(root, "rev-parse", "HEAD") if here else None) or UNKNOWN
    tracked = git(root, "status", "--porcelain", "--untracked-files=no") if here else None
    sources = (
        git(root, "status", "--porcelain", "--untracked-files=normal", "--", *SOURCES, strip=False) if here else None
    )
    return {
        "command": list(command) if command is not None else None,
        "navcli_version": __version__,
        "build": BUILD,
        "commit": commit,
        "commit_date": (git(root, "log", "-1", "--format=%cs", commit) if commit != UNKNOWN else None) or UNKNOWN,
        "dirty": bool(tracked) if tracked is not None else None,
        "dirty_sources": sorted(line[3:] for line in (sources or "").splitlines()),
        "libraries": libraries(),
        "sources": digests(root) if here else {},
    }


def describe(source: dict[str, Any]) -> str:
    """The provenance in a sentence, for the top of a report."""
    import shlex

    command = source.get("command")
    made = f"Made by `{shlex.join(command)}`" if command else "Made from Python (no command line gives its settings)"
    if source.get("dirty") is None:
        tree = "outside a git checkout"
    elif source.get("dirty_sources"):
        tree = f"with uncommitted changes to {', '.join(source['dirty_sources'])}"
    else:
        tree = "its sources as committed" + (" (other files changed)" if source.get("dirty") else "")
    libs = ", ".join(f"{k} {v}" for k, v in source.get("libraries", {}).items())
    return (
        f"{made} at commit {source.get('commit', UNKNOWN)} ({source.get('commit_date', UNKNOWN)}), {tree}; "
        f"navcli {source.get('navcli_version', UNKNOWN)}, the {source.get('build', UNKNOWN)} build; {libs}."
    )


def stale(source: dict[str, Any], root: Path = ROOT) -> list[str]:
    """Why a report of provenance ``source`` (:func:`record`) no longer stands for the code in
    ``root``, a line each; empty when it does. Stale: it records no build or no digests of its
    sources, it was made from uncommitted changes to :data:`SOURCES`, or a file of them differs
    now from what it recorded (the commits since its own named where the history has them)."""
    if not checkout(root):
        return [f"{root} is not a git checkout: the report's sources cannot be checked"]
    out = []
    if source.get("dirty_sources"):
        out.append(f"the report was made from uncommitted changes to {', '.join(source['dirty_sources'])}")
    if "build" not in source or "sources" not in source:
        out.append(
            "the report records no build or no digests of its sources (its source.json lacks 'build' or 'sources')"
        )
        return out
    differ = changed(source["sources"], digests(root))
    if differ:
        more = f" and {len(differ) - 5} more" if len(differ) > 5 else ""
        out.append(f"{len(differ)} file(s) of navcli/ differ from the report's: {', '.join(differ[:5])}{more}")
        commit = str(source.get("commit", UNKNOWN))
        later = git(root, "log", "--format=%h %s", f"{commit}..HEAD", "--", *SOURCES)
        if later:
            commits = later.splitlines()
            out.append(f"{len(commits)} commit(s) since the report's commit {commit[:12]}, the latest: {commits[0]}")
    return out
