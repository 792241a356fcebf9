"""navcli's build: the hot modules of a control tick compiled with mypyc, where it can be done.

``pyproject.toml`` holds everything else (setuptools reads it first); this file only adds the
compiled modules. They are C extensions built from the same ``.py`` files, which stay the
reference: ``NAVCLI_PURE=1`` runs them instead (``navcli/__init__.py``), and the tests compare the
two builds' runs (``tests/test_builds.py``).

The pure-Python install is what any machine gets where the build cannot be done: without mypyc
(it ships with mypy, a build requirement), without a working C compiler, or with
``NAVCLI_PURE_BUILD=1``. The build then says so once, on stderr (``pip install -v`` shows it), and
installs the ``.py`` files alone: never an error.
"""

from __future__ import annotations

import os
import runpy
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

# navcli/builds/__init__.py holds the list of the compiled modules (read here without importing navcli)
BUILD = runpy.run_path(os.path.join(os.path.dirname(os.path.abspath(__file__)), "navcli", "builds", "__init__.py"))
COMPILED = [f"navcli/{m.replace('.', '/')}.py" for m in BUILD["MODULES"]]


# setup.py runs once per step of an install; only the steps that build say what they build
BUILDING = any(a in ("build", "build_ext", "bdist_wheel", "editable_wheel", "develop", "install") for a in sys.argv[1:])


def pure(why: str) -> None:
    print(
        f"navcli: {why}: installing pure Python (correct, slower; see docs/howto/speed.md, 'The compiled build')",
        file=sys.stderr,
    )


class OptionalBuildExt(build_ext):
    """build_ext that falls back to pure Python when compiling fails (no C compiler, no headers):
    what it built is removed, so no module is left half compiled."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as e:  # distutils' CompileError, LinkError, PlatformError, an OSError ...
            for ext in self.extensions:
                for path in {
                    self.get_ext_fullpath(ext.name),
                    os.path.join(*ext.name.split(".")) + os.path.splitext(self.get_ext_filename(ext.name))[1],
                }:
                    if os.path.isfile(path):
                        os.remove(path)
            first = str(e).splitlines()[0] if str(e) else ""
            pure(f"the C build failed ({type(e).__name__}: {first})")


def servo() -> Extension:
    """The wheels' velocity servo in C (navcli/servo.c), part of the compiled build. sin and cos
    stay the C library's own functions, as Python's math calls them: never fused into one sincos
    call, which need not round alike on every C library."""
    flags = [] if os.name == "nt" else ["-fno-builtin-sin", "-fno-builtin-cos"]
    return Extension(f"navcli.{BUILD['SERVO']}", ["navcli/servo.c"], extra_compile_args=flags)


def extensions() -> list:
    if not BUILDING:
        return []  # metadata, requirements: no compiling, and nothing said
    if os.environ.get("NAVCLI_PURE_BUILD", "") not in ("", "0"):
        pure("NAVCLI_PURE_BUILD is set")
        return []
    try:
        from mypyc.build import mypycify
    except ImportError:
        pure("mypyc (part of mypy) is not available")
        return []
    try:
        # -ffp-contract=off: no fused multiply-add, so every float operation rounds as CPython's does
        # (GCC contracts a*b+c by default where the CPU has FMA, and the runs would differ in the last bits)
        os.environ["CFLAGS"] = (os.environ.get("CFLAGS", "") + " -ffp-contract=off").strip()
        # mypy's notes (an unchecked untyped function elsewhere) would stop mypyc: they are not errors
        return [
            *mypycify(
                ["--disable-error-code=annotation-unchecked", *COMPILED],
                opt_level="3",
                group_name=f"navcli.{BUILD['GROUP']}",
            ),
            servo(),
        ]
    except (Exception, SystemExit) as e:  # mypyc refused the code (it exits): still an install
        pure(f"mypyc could not compile ({type(e).__name__}: {e})")
        return []


setup(ext_modules=extensions(), cmdclass={"build_ext": OptionalBuildExt})
