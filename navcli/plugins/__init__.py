"""Plugins: pilots and Navigation policies of one's own, found by name and run like navcli's own
(:mod:`.registry`), every call into them guarded and what they return checked (:mod:`.boundary`:
their faults are named as theirs), and the checker that tells a plugin's author what it gets
wrong (:mod:`.checker`, which runs missions: the package does not import it, so that the
configuration can import the registry).

The tutorial "Your own pilot" (``docs/tutorials/your-own-pilot.md``) writes a pilot plugin, checks
it and compares it with navcli's pilots; ``examples/vfh-pilot`` is a real one, an installable
package.
"""

from __future__ import annotations

from .registry import (
    BUILTIN_PILOTS,
    BUILTIN_POLICIES,
    GROUPS,
    Component,
    PluginError,
    UnknownPlugin,
    find,
    installed,
    navigation,
    pilot,
)

__all__ = [
    "BUILTIN_PILOTS",
    "BUILTIN_POLICIES",
    "GROUPS",
    "Component",
    "PluginError",
    "UnknownPlugin",
    "find",
    "installed",
    "navigation",
    "pilot",
]
