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
LOOK_TIME = 0.5
"""Seconds the camera is busy with one look (pan and image processing)."""
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
    distress_gain: float = 1.5  # section 5: the offending obstacle's force x 1.5 when IN_DISTRESS
    corridor_margin: float = 0.40  # m: section 3.3, the safe corridor keeps this far from the line's ends
    # Section 3.5: reflexes and backward motion
    backward_turn: float = math.radians(160.0)  # turns larger than this are driven backwards...
    max_backward: float = 0.6  # m: ...while the distance driven backwards stays under this
    reflex_stop_s: float = 0.5  # s standing still after a bump
    reflex_look_pans_deg: tuple[float, ...] = (-60.0, 0.0, 60.0)  # looks around after a bump
    backup_distance: float = 0.30  # m backed up after a bump
    backup_speed: float = 0.15  # m/s
    bump_obstacle_radius: float = 0.05  # m: a bumped, unseen obstacle is remembered as a point this big
    # Section 2, eq. 1: the look-ahead camera bid (d_l / d_m) ** s
    look_d_max: float = 1.0  # m: d_m, the longest drive without looking ahead
    look_exponent: float = 2.0  # s
    # Geometric pilot (the baseline of Table 1)
    geometric_lookahead: float = 1.0  # m beyond the grown obstacle at which it starts to steer


@dataclass(frozen=True)
class NavigationParams:
    """Parameters of the Navigation system's agents."""

    kappa1: float = 0.314  # Target Tracker: move bid with a precisely known target (notes, Table 5.2, C1)
    alpha: float = 1.731  # Target Tracker: how fast that bid falls with the target's imprecision (C1)


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
