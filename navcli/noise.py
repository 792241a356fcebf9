"""Sensor noise: the robot's sensors (odometry, the camera) err by bounded amounts."""

from __future__ import annotations

import numpy as np


def bounded_normals(rng: np.random.Generator, bound: float) -> tuple[float, float]:
    """Two standard normal errors from ``rng``, clipped at ``bound`` deviations (a real sensor's
    errors are bounded). Clipped in Python: ``np.clip`` on two numbers costs more than the draw."""
    a, b = rng.standard_normal(2).tolist()
    return min(max(a, -bound), bound), min(max(b, -bound), bound)
