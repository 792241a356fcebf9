"""How a log's chunks are compressed: the choices, declared once (``navcli run --log-compression``,
:func:`navcli.runner.run_mission`'s ``log_compression``), and the default, chosen by measure
(``docs/howto/speed.md``, "How a log is compressed"; ``benchmarks/log_compression.py`` makes its
table). Every choice writes the same messages; every MCAP reader (the ``mcap`` library, Foxglove,
Lichtblick, :mod:`navcli.analysis`) reads each of them.

Standard library only: the command line's help is made from it without importing the writer.
"""

from __future__ import annotations

from typing import Any

COMPRESSIONS: dict[str, tuple[str | None, int]] = {
    "zstd-1": ("zstd", 1),
    "zstd-3": ("zstd", 3),
    "lz4": ("lz4", 0),
    "none": (None, 0),
}
"""Each choice by name: the chunks' compression (an MCAP compression, or None) and its level (0:
the compressor's own default)."""
DEFAULT = "zstd-1"
"""The default (see the module's docstring for why)."""
HELP = (
    f"How the log's chunks are compressed: {', '.join(COMPRESSIONS)} (zstd at a level, LZ4, none). "
    f"Default {DEFAULT}: the smallest log for its time (docs/howto/speed.md)."
)


def refusal(name: Any) -> str | None:
    """What is wrong with ``name`` as a compression's, or None.

    >>> refusal("zstd-1") is None, refusal("gzip")
    (True, "expected one of 'zstd-1', 'zstd-3', 'lz4', 'none', got 'gzip'")
    """
    if isinstance(name, str) and name in COMPRESSIONS:
        return None
    return f"expected one of {', '.join(map(repr, COMPRESSIONS))}, got {name!r}"
