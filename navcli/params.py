"""Every tunable default of navcli, in one place.

The papers' values live here (K = 18, A_t = 50, R_min = 0.40 m, bid cap 0.9 ...). A scenario's
blocks and the command line override them; nothing else in the code base repeats a default.
Units: metres, seconds, radians, unless a name says otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

NOISE_BOUND = 3.0
"""Sensor errors (odometry, camera) are drawn from normals clipped at this many standard deviations:
physical sensors have bounded errors, and the fuzzy supports of the visual memory rely on the bound."""

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
    distress_gain: float = 1.5  # section 5: the offending obstacle's force x 1.5 when IN_DISTRESS
    corridor_margin: float = 0.40  # m: section 3.3, the safe corridor keeps this far from the line's ends
    # Section 3.5: reflexes and backward motion
    backward_turn: float = math.radians(160.0)  # turns larger than this are driven backwards...
    max_backward: float = 0.6  # m: ...while the distance driven backwards stays under this
    reflex_stop_s: float = 0.5  # s standing still after a bump
    reflex_look_pans_deg: tuple[float, ...] = (-60.0, 0.0, 60.0)  # looks around after a bump
    backup_distance: float = 0.30  # m backed up after a bump
    backup_speed: float = 0.15  # m/s
    reflex_phase_limit_s: float = 4.0  # s: a reflex phase that cannot finish (backed into something) is given up
    # Section 2, eq. 1: the look-ahead camera bid (d_l / d_m) ** s
    look_d_max: float = 1.0  # m: d_m, the longest drive without looking ahead
    look_exponent: float = 2.0  # s
    # Geometric pilot (the baseline of Table 1)
    geometric_lookahead: float = 1.0  # m beyond the grown obstacle at which it starts to steer


@dataclass(frozen=True)
class NavigationParams:
    """Parameters of the Navigation system's agents."""

    # Target Tracker (notes, section 2, with the thesis' GA-tuned values for cluster C1, Table 5.2)
    kappa1: float = 0.314  # move bid with a precisely known target
    alpha: float = 1.731  # how fast that bid falls with the target's imprecision I_a
    kappa2: float = 0.493  # the look bid's peak
    beta: float = 2.03  # I_a = (eps / 2 pi) ** beta, eps the width of the heading's 70 % cut
    I_a_bar: float = 0.386  # I_a at which the look bid peaks (the Rescuer's threshold)


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
    camera_pan_limit_deg: float = 100.0  # the pan unit turns this far either side of ahead
    camera_pan_speed_deg: float = 90.0  # deg/s
    camera_look_time: float = 0.3  # s of image processing per look, the camera busy meanwhile
    perception: str = "vision"  # vision | oracle (ground truth, for experiments isolating the pilot)


PERCEPTIONS = ("vision", "oracle")


@dataclass(frozen=True)
class VisionParams:
    """The camera's measurement model and the visual memory (notes, sections 1 and 3)."""

    noise_bound: float = NOISE_BOUND  # sensor errors are bounded at this many standard deviations
    heading_floor: float = math.radians(0.5)  # rad: the fuzzy heading's least half-spread (a pixel or so)
    distance_floor: float = 0.02  # m: the fuzzy distance's least half-spread
    walk_bound: float = 4.0  # the per-tick odometry errors' random walk is bounded at this many deviations
    odometry_floor: float = 0.005  # relative: odometry error the memory allows for even without noise
    bump_radius: float = 0.10  # m: support radius of an obstacle found by the bumpers
    forget_above: float = 0.35  # I(l) above which an object is forgotten
    forget_every: int = 5  # ticks between two sweeps of the memory for what has become too imprecise
    draw_every: int = 5  # ticks between two /memory/scene updates


ROBOT = RobotDefaults()
PILOT = PilotParams()
NAVIGATION = NavigationParams()
VISION = VisionParams()
DEFAULTS = Defaults()
