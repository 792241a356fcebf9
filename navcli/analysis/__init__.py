"""Log analysis for navcli: reads MCAP logs into pandas; never imports the simulator, only the
log's format (:mod:`navcli.log.format`).

Imported lazily (``read_log`` and the rest load pandas on first use), so a module that needs only
:mod:`navcli.analysis.files` does not pay for pandas."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["LogError", "RunLog", "path_length", "read_log"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        value = getattr(importlib.import_module(".logs", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'navcli.analysis' has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
