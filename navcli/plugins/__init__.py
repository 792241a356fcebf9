"""Plugins: pilots and Navigation policies of one's own, found by name and run like navcli's own
(:mod:`.registry`), every call into them guarded and what they return checked (:mod:`.boundary`:
their faults are named as theirs), and the checker that tells a plugin's author what it gets
wrong (:mod:`.checker`, which runs missions: the package does not import it, so that the
configuration can import the registry).

A pilot plugin, in full (``examples/vfh-pilot`` is a real one)::

    import math
    from dataclasses import dataclass
    from typing import Annotated

    import msgspec
    from navcli.bidding import Move
    from navcli.params import ParamSet, param
    from navcli.pilot import Avoidance, Pilot

    @dataclass(frozen=True)
    class SwerveParams(ParamSet):
        swerve_deg: float = param(40.0, "deg", "how far to turn from an obstacle ahead", at_most=90.0)

    class SwerveInfo(msgspec.Struct):
        ahead: Annotated[int, msgspec.Meta(description="obstacles within 1 m ahead")]

    class Swerve(Pilot):
        Params = SwerveParams  # --param swerve.swerve_deg=30 (swerve: the name it is installed under)
        Info = SwerveInfo  # its fields in /pilot, which the log's schema then declares
        version = "1.0"

        def avoid(self, beliefs, obstacles, request):
            ahead = [o for o in obstacles if 0 < o.a[0] < 1.0 and abs(o.a[1]) < 0.5]
            if not ahead:
                return Avoidance(None, 0.0, {"ahead": 0})
            turn = math.radians(self.own_params.swerve_deg)
            return Avoidance(Move(turn, self.max_speed), self.params.bid_cap, {"ahead": len(ahead)})

installed with ``[project.entry-points."navcli.pilots"] swerve = "mypackage:Swerve"``, or named
``mypackage:Swerve`` without installing: ``navcli run room.yaml --pilot swerve``.
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
