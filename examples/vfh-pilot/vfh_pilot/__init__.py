"""A third pilot for navcli, shipped as a plugin: the Vector Field Histogram, VFH+ (Ulrich &
Borenstein 1998, after Borenstein & Koren 1991). Installed, navcli finds it by the entry point
``navcli.pilots: vfh``: ``navcli compare pilots scenarios/paper-8x8.yaml --pilots vfh,potential-field,geometric``.
"""

from __future__ import annotations

from .pilot import VFHInfo, VFHParams, VFHPilot

__version__ = "0.1.0"
__all__ = ["VFHInfo", "VFHParams", "VFHPilot", "__version__"]
