"""Every tunable default of navcli, in one place.

The papers' values live here (K = 18, A_t = 50, R_min = 0.40 m, bid cap 0.9 ...). A scenario's
blocks and the command line override them; nothing else in the code base repeats a default.
Units: metres, seconds, radians, unless a name says otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

PILOT_NAMES = ("potential-field", "geometric")
"""The pilots a scenario or ``--pilot`` may name; the first is the default."""

# --- Timing: both rates in one place --------------------------------------------------------
CONTROL_DT = 0.1
"""Seconds between two decisions of the agents (10 Hz), and between two log records."""
PHYSICS_SUBSTEPS = 5
"""Physics steps per control tick: the world steps at CONTROL_DT / PHYSICS_SUBSTEPS (50 Hz)."""
PHYSICS_DT = CONTROL_DT / PHYSICS_SUBSTEPS
PHYSICS_DT_NS = round(PHYSICS_DT * 1e9)


@dataclass(frozen=True)
class RobotDefaults:
    """Body and drive limits of the differential-drive robot (a Pioneer-sized disc)."""

    radius: float = 0.25
    max_speed: float = 0.3  # m/s
    max_accel: float = 0.5  # m/s^2
    max_turn_rate: float = math.radians(90.0)  # rad/s
    max_turn_accel: float = math.radians(180.0)  # rad/s^2


@dataclass(frozen=True)
class PilotParams:
    """Parameters of the Pilot (pilot paper, sections 3.4 and 4)."""

    K: float = 18.0  # eq. 2: repulsion constant
    A_t: float = 50.0  # eq. 5: constant target attraction
    R_min: float = 0.40  # m, radius of the grown obstacles (eq. 3-4)
    bid_cap: float = 0.9  # eq. 9: the Pilot never bids above this
    heading_gain: float = 1.5  # 1/s: turn rate per radian of heading error
    turn_in_place: float = math.radians(45.0)  # above this heading error the robot stops to turn


@dataclass(frozen=True)
class NavigationParams:
    """Parameters of the Navigation system's agents."""

    kappa1: float = 0.5  # Target Tracker: move bid with a perfectly known target (notes, section 2)


@dataclass(frozen=True)
class Defaults:
    """Defaults of the optional scenario blocks (see shared/spec/scenario-format.md)."""

    heading_deg: float = 0.0
    landmark_radius: float = 0.15
    segment_thickness: float = 0.05  # m: the physical width of a linear obstacle
    target_tolerance: float = 0.3
    pilot: str = PILOT_NAMES[0]
    time_limit: float = 900.0
    seed: int = 1
    odometry_noise: float = 0.02
    vision_heading_deg: float = 2.0
    vision_distance: float = 0.05
    camera_fov_deg: float = 60.0
    camera_range: float = 6.0


ROBOT = RobotDefaults()
PILOT = PilotParams()
NAVIGATION = NavigationParams()
DEFAULTS = Defaults()
