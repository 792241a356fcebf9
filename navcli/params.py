"""Every tunable number of navcli, in one place.

The papers' values live here (K = 18, A_t = 50, R_min = 0.40 m, bid cap 0.9 ...). A scenario's
blocks and the command line override them; nothing else in the code base repeats a default.
Units: metres, seconds, radians, unless a name says otherwise.

The five parameter sets of a run (robot, pilot, navigation, vision, learning) travel as one
:class:`Params`, addressed by dotted names (``pilot.K``) from ``--param``, plans and the log's
metadata; each field declares its range, and an override outside it is refused by name."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from . import NavcliError

NOISE_BOUND = 3.0
"""Sensor errors (odometry, camera) are drawn from normals clipped at this many standard deviations:
physical sensors have bounded errors, and the fuzzy supports of the visual memory rely on the bound."""

PILOT_NAMES = ("potential-field", "geometric")
"""The pilots a scenario or ``--pilot`` may name; the first is the default."""
PERCEPTIONS = ("vision", "oracle")
"""What the agents may know: the camera and visual memory (default), or ground truth."""
NAVIGATIONS = ("agents", "hand-coded", "learned")
"""Who chooses the Navigation system's moves and looks: its bidding agents (default), the hand-coded
policy or the Learning Agent (``learned:FILE`` names a model; plain ``learned`` the bundled one)."""

# --- Timing: both rates in one place --------------------------------------------------------
CONTROL_DT = 0.1
"""Seconds between two decisions of the agents (10 Hz), and between two log records."""
PHYSICS_SUBSTEPS = 5
"""Physics steps per control tick: the world steps at CONTROL_DT / PHYSICS_SUBSTEPS (50 Hz)."""
PHYSICS_DT = CONTROL_DT / PHYSICS_SUBSTEPS
PHYSICS_DT_NS = round(PHYSICS_DT * 1e9)
COLLISION_SLOP = 0.001  # m: how far the physics lets two bodies overlap (pymunk's default, 0.1, is in pixels)
SCENE_REFRESH = 1.0
"""Seconds between two publications of the log's state topics (the arena, the robot's body, the
camera's field of view): a viewer that seeks, or joins a live run late, shows them within this time."""
DRAW_PERIOD = 1.0
"""Seconds between two drawings of the Pilot's decorations in ``/robot/scene`` (force arrows, grown
obstacles); the forces themselves are in ``/pilot`` every tick (docs/design.md, "Drawing rates")."""


def _p(default: Any, *, at_least: float | None = 0.0, above: float | None = None,
       at_most: float | None = None, below: float | None = None) -> Any:
    """A parameter field with the range an override must respect (checked by :meth:`Params.override`)."""
    return field(default=default, metadata={"at_least": at_least, "above": above, "at_most": at_most, "below": below})


def _choice(default: str, choices: tuple[str, ...]) -> Any:  # a parameter that names one of choices
    return field(default=default, metadata={"choices": choices})


def _intervals(default: tuple[float, ...]) -> Any:
    """Interval bounds of a feature (the Learning Agent's states): an override keeps their count,
    which the table of states is built on, and their increasing order."""
    return field(default=default, metadata={"intervals": True})


@dataclass(frozen=True)
class RobotParams:
    """Body and drive limits of the differential-drive robot (a Pioneer-sized disc); a scenario's
    ``robot:`` block sets ``radius`` and ``max_speed``."""

    radius: float = _p(0.25, at_least=0.05, at_most=1.0)  # m
    max_speed: float = _p(0.3, above=0.0, at_most=2.0)  # m/s; the physics step holds walls up to 2 m/s (tests/test_world.py)
    max_accel: float = _p(0.5, above=0.0)  # m/s^2
    max_turn_rate: float = _p(math.radians(90.0), above=0.0)  # rad/s
    max_turn_accel: float = _p(math.radians(180.0), above=0.0)  # rad/s^2

    def time_to_drive(self, metres: float) -> float:
        """Seconds the robot takes to drive ``metres`` at full speed: how the windows that are
        about progress (the Rescuer's blocked window and diverting timeout, the Pilot's stall
        watch) become times, so a slow robot is given the time its distance takes.

        >>> RobotParams(max_speed=0.05).time_to_drive(12.0)
        240.0
        """
        return metres / self.max_speed


@dataclass(frozen=True)
class PilotParams:
    """Parameters of the Pilot (pilot paper, sections 3.4 and 4); a scenario's ``pilot:`` block
    sets ``K``, ``A_t`` and ``R_min``."""

    K: float = _p(18.0, at_most=1000.0)  # eq. 2: repulsion constant
    A_t: float = _p(50.0, at_most=1000.0)  # eq. 5: constant target attraction
    R_min: float = _p(0.40, at_least=0.01, at_most=5.0)  # m, radius of the grown obstacles (eq. 3-4)
    bid_cap: float = _p(0.9, at_most=1.0)  # eq. 9: the Pilot never bids above this
    heading_gain: float = _p(1.5)  # 1/s: turn rate per radian of heading error
    # How a winning move is executed (section 4: "the Pilot executes the turn of the winning bid"):
    # 1, the speed and the turn commanded together, as a Pioneer's velocity and heading commands do
    # (the default, our reading of the paper); 0, stop to turn above turn_in_place, slow by cos(error) below
    drive_while_turning: int = _p(1, at_most=1)
    # m: clearance the body keeps along the arc of a large turn driven at speed (see Pilot._arc_clear)
    arc_margin: float = _p(0.1, at_least=0.0)
    # 1: moves are executed only if safe (section 2, see Pilot._path_clear); 0: as they come (navcli before)
    safe_execution: int = _p(1, at_most=1)
    # 1: a request not safe, and no own move that drives, is replaced by the nearest safe heading (15 deg steps);
    # 0: turned on the spot (navcli before: it could stand still for good, facing its target past a landmark)
    nearest_safe: int = _p(1, at_most=1)
    # above this heading error the robot stops to turn (drive_while_turning 0), or checks the turn's arc (1)
    turn_in_place: float = _p(math.radians(45.0))
    distress_gain: float = _p(1.5)  # section 5: each offending obstacle's force x 1.5 when IN_DISTRESS
    # 1: a linear obstacle IN_DISTRESS pushes from its nearest point (our design: from its centre, section 3.2,
    # a corner of two fences is a sink); 0: from its centre there too (navcli before)
    distress_from_nearest: int = _p(1, at_most=1)
    # m: the field leading away from the target, a long obstacle its strongest push, while the robot
    # could drive this far and got along the obstacle less than a third of it: the Pilot reports the
    # obstacle as one it cannot easily avoid (the thesis' blocked situation); 0: no report (the
    # default: measured, it helps behind long fences and costs paper-8x8 runs; README, trap rooms)
    blocked_report_m: float = _p(0.0)
    wall_window: float = _p(1.0, above=0.0)  # m: a room wall acts as the stretch this long nearest the robot
    # m: a linear obstacle longer than this acts as the stretch this long nearest the robot (the paper's are shorter)
    line_window: float = _p(3.0, above=0.0)
    corridor_margin: float = _p(0.40)  # m: section 3.3, the safe corridor keeps this far from the line's ends
    # Section 3.5: reflexes and backward motion
    backward_turn: float = _p(math.radians(160.0), at_most=math.pi)  # turns larger than this are driven backwards...
    max_backward: float = _p(0.6)  # m: ...while the total distance driven backwards that way stays under this
    reflex_stop_s: float = _p(0.5)  # s standing still after a bump
    reflex_look_pans_deg: tuple[float, ...] = (-60.0, 0.0, 60.0)  # looks around after a bump
    backup_distance: float = _p(0.30)  # m backed up after a bump
    backup_speed: float = _p(0.15, above=0.0)  # m/s
    # s: a reflex phase that cannot finish (the camera kept busy) is given up; the backup phase is given
    # at least twice the time backing up takes at the speed it is driven (backed into something)
    reflex_phase_limit_s: float = _p(4.0, above=0.0)
    # No silent stall (our design): pushing without moving starts the reflex too. The window is a
    # distance: the time it takes to drive it at robot.max_speed (0.6 m: 2 s at 0.3 m/s)
    stall_window_m: float = _p(0.6, above=0.0)  # m of driving at full speed over which commanded and measured motion are compared
    stall_min_distance: float = _p(0.1, above=0.0)  # m commanded in that window before a stall can be called
    stall_progress: float = _p(0.2, at_most=1.0)  # a stall: less than this fraction of the commanded distance moved
    # Section 2, eq. 1: the look-ahead camera bid (d_l / d_m) ** s
    look_d_max: float = _p(1.0, above=0.0)  # m: d_m, the longest drive without looking ahead
    look_exponent: float = _p(2.0, above=0.0)  # s
    # eq. 1's bid never above this: 1, eq. 1 as written (d_m is "the maximum distance allowed to travel without
    # looking ahead", so the bid reaches 1 there); 0.9 (navcli before: the cap of eq. 9's motion bid)
    look_cap: float = _p(1.0, at_most=1.0)
    look_ahead_cone: float = _p(math.radians(30.0))  # rad: a look this close to straight ahead resets d_l
    # 1: the Pilot bids for the camera (eq. 1's look-ahead, a reflex's looks around); 0: never (the learning
    # paper's task: the camera is the Learning Agent's; the Pilot still avoids what the memory holds)
    looks: int = _p(1, at_most=1)
    # Geometric pilot (the baseline of Table 1)
    geometric_lookahead: float = _p(1.0)  # m beyond the prohibited area at which it starts to steer
    geometric_clearance: float = _p(0.05)  # m: its tangents pass this far outside the prohibited area
    geometric_side_memory: float = _p(0.5)  # m driven with the way clear before the side chosen to pass is forgotten


@dataclass(frozen=True)
class NavigationParams:
    """Parameters of the Navigation system's agents (learning-agent paper section 3; notes,
    sections 1-4). The bidding parameters default to the thesis' GA-tuned values for task cluster
    C1 (targets reachable without obstacles, Table 5.2); :data:`NAVIGATION_C2` holds cluster C2's
    (targets behind obstacles). The rest is our design, each with its reason."""

    # Target Tracker (notes, section 2)
    kappa1: float = _p(0.314, at_most=1.0)  # move bid with a precisely known target
    alpha: float = _p(1.731)  # how fast that bid falls with the target's imprecision I_a
    kappa2: float = _p(0.493, at_most=1.0)  # the look bid's peak
    beta: float = _p(2.03, above=0.0)  # I_a = (eps / 2 pi) ** beta, eps the width of the heading's 70 % cut
    I_a_bar: float = _p(0.386, above=0.0, below=1.0)  # I_a at which the look bid peaks; above it the Rescuer takes over
    # Distance Estimator: kappa * tanh(I_d / d), I_d the width (m) of the target distance's 70 % cut, d its distance
    kappa: float = _p(0.355, at_most=1.0)
    # Risk Manager: R = 1 - min(1, q_A (|A|/6)^gamma_A + q_B (|B|/6)^gamma_B); look bid R^gamma_R when R > R_bar
    gamma_A: float = _p(0.240)
    gamma_B: float = _p(0.521)
    gamma_R: float = _p(0.054, above=0.0)
    R_bar: float = _p(0.215, at_most=1.0)
    ahead_deg: float = _p(90.0, above=0.0, at_most=180.0)  # landmarks within this bearing are "ahead" (set A)
    # Communicator (notes, section 1): bids are collected over this window; a later bid replaces an earlier one
    communicator_window_s: float = _p(0.2)
    # Rescuer (notes, section 2): blocked, lost, diverting targets
    rescuer_bid: float = _p(1.0, at_most=1.0)  # its stop, look and turn bids: an emergency, above every other bid
    # The Rescuer's windows are distances, each the time it takes to drive it at robot.max_speed (our design: a slow
    # robot is never blocked for being slow; 12 m and 27 m are the 40 s and 90 s these windows had at 0.3 m/s)
    blocked_window_m: float = _p(12.0, above=0.0)  # no progress toward the target while it could drive this far: blocked
    blocked_progress: float = _p(0.5, above=0.0)  # m closer to the target that counts as progress
    blocked_bumps: int = _p(3, at_least=1)  # or this many bumps within the blocked window: blocked
    diverting_timeout_m: float = _p(27.0, above=0.0)  # a diverting target not crossed while it could drive this far has failed
    max_diverting_failures: int = _p(0, at_least=0)  # failed diverting targets that end the mission; 0: no count does
    gives_up: int = _p(1, at_most=1)  # 0: the Rescuer never ends a mission (long benchmarks, tests that need a long run)
    random_turn_deg: float = _p(120.0, above=0.0, at_most=180.0)  # with no diverting target: turn by up to this much
    # exploring (no diverting target): turn away from the target (within half random_turn_deg), drive up to this far
    # looking around until a new landmark is seen, then scan (our design: what hides the landmarks from where the
    # robot is blocked is a long obstacle, about 3 m in the papers' rooms); 0: turn and scan in place (navcli before)
    explore_m: float = _p(3.0, at_least=0.0)
    # 1: once a diverting target is crossed, a target in sight (no known long obstacle across the straight way)
    # is headed for directly; 0: the map is asked for the way's next step all the same (navcli before)
    sight_ends_way: int = _p(1, at_most=1)
    scan_pans_deg: tuple[float, ...] = (-90.0, -45.0, 0.0, 45.0, 90.0)  # the looks of a scan (initial sweep, lost)
    initial_sweep: int = _p(1, at_most=1)  # 1: the Rescuer's initial sweep (thesis node 81); 0: none (short experiments)
    # 1: the Rescuer looks (the initial sweep, a lost target's scans, looking around to explore); 0: never, and a
    # lost target is left to the agents (the learning paper's task, where the camera is the Learning Agent's)
    rescuer_looks: int = _p(1, at_most=1)
    blocked_ends: int = _p(0, at_most=1)  # 1: the first blocked situation ends the mission "blocked" (the learning paper's trials)
    # 1: the target counts as reached only when the robot is also confident of it ("and is confident that it
    # has reached the target"): the 70 % cut of its belief of the target wholly within reach; 0: the body alone
    reach_confident: int = _p(0, at_most=1)
    # > 0: and the belief's I(t) (the learning paper's I(l)) below this (a stricter reading, for the sensitivity)
    reach_imprecision: float = _p(0.0, at_most=1.0)
    # Map Manager (notes, sections 3-4)
    map_encode_imprecision: float = _p(0.25, above=0.0, at_most=1.0)  # landmarks at most this imprecise are encoded
    map_units_per_landmark: int = _p(6, at_least=1)  # beta-units kept per landmark (the sharpest)
    map_recall_every: int = _p(5, at_least=1)  # ticks between two recalls of a landmark from the network
    # ticks between two /map/scene updates, and the last tick (10 s; our design: the map changes slowly,
    # and its snapshot triangulates the landmarks, which every 2 s cost some 40 µs a tick; see DRAW_PERIOD)
    map_draw_every: int = _p(100, at_least=1)
    virtual_distance: float = _p(10.0, above=0.0)  # m: virtual landmarks beyond the hull edges
    blocked_cost: float = _p(1000.0, above=1.0)  # cost of a region arc known to be blocked
    # 1: the diverting target is the farthest edge of the way the robot sees straight; 0: the first (navcli before)
    diverting_in_sight: int = _p(1, at_most=1)


@dataclass(frozen=True)
class VisionParams:
    """The camera's measurement model and the visual memory (notes, sections 1 and 3)."""

    noise_bound: float = _p(NOISE_BOUND, above=0.0)  # sensor errors are bounded at this many standard deviations
    told_target: int = _p(1, at_most=1)  # 1: the robot is told where the target is at the start; 0: it must see it
    # 1: a look registers only what the routine of its purpose finds (vision/routines.py), no look no image;
    routines: int = _p(1, at_most=1)  # 0: every image registers all in view (navcli before)
    # 1: a fence or wall is one object, its ends fused end by end (vision/visual_memory.py);
    line_objects: int = _p(1, at_most=1)  # 0: view-cut pieces re-joined by geometry (navcli before)
    walls: str = _choice("seen", ("seen", "known", "felt"))  # how the robot knows the room's walls (vision/perception.py)
    heading_floor: float = _p(math.radians(0.5))  # rad: the fuzzy heading's least half-spread (a pixel or so)
    distance_floor: float = _p(0.02)  # m: the fuzzy distance's least half-spread
    walk_bound: float = _p(4.0)  # the per-tick odometry errors' random walk is bounded at this many deviations
    odometry_floor: float = _p(0.005)  # relative: odometry error the memory allows for even without noise
    bump_radius: float = _p(0.10, above=0.0)  # m: support radius of an obstacle found by the bumpers
    bump_merge: float = _p(1.0)  # m: a bump this near another bump or a landmark joins it in a long obstacle
    line_join_gap: float = _p(0.5)  # m: stretches of a fence or wall seen apart are one only if they overlap or are this near
    forget_above: float = _p(0.35, above=0.0, at_most=1.0)  # I(l) above which a landmark or the target is forgotten
    # 0: a linear obstacle (or wall) is forgotten when both its ends are above forget_above; 1: when one is
    # (navcli before: the near end of a fence the robot drives along blurs first, and the fence went with it)
    forget_line_by_one_end: int = _p(0, at_most=1)
    forget_every: int = _p(5, at_least=1)  # ticks between two sweeps of the memory for what has become too imprecise
    # ticks between two /memory/scene updates, and the last tick (3 s; our design: drawn once a second it
    # cost some 40 µs a tick; each drawing stays where it was in the world, see DRAW_PERIOD)
    draw_every: int = _p(30, at_least=1)


@dataclass(frozen=True)
class LearningParams:
    """The Learning Agent (learning-agent paper, sections 4-6): its belief-state features, its
    actions and Prioritized Sweeping. The paper gives the number of intervals of each feature
    (5, 7, 4, 7: 980 states), the actions and their rewards; the interval bounds, how long one
    action lasts and the learner's settings are our design, each with its reason:

    - **Target distance** D(t) (m, the centre of the fuzzy distance): bounds 0.9, 1.5, 3, 5. The
      robot has reached landmark T within 0.7 m of its centre (tolerance 0.3 + landmark 0.15 +
      robot 0.25), so the first interval is "at the target, one action away"; the others double
      roughly, so that one action (0.3 m at full speed) changes the interval often near the
      target and the far intervals still part a 8 m room (the paper's "state-action deviation"
      worry: an action must often change the state).
    - **Target imprecision** I(t) (the paper's I(l) of the target's fuzzy position): bounds 0.02,
      0.04, 0.07, 0.1, 0.15, 0.25. The camera's 5 % distance error dominates: a fresh sighting
      gives about 0.02 at 1 m and 0.1 at 4-5 m; odometry blurs it as the robot drives; the visual
      memory forgets above 0.35; the last interval also holds a lost target (I = 1).
    - **Landmark count** C-bar (the mean of N(s) = min(4, |L(s)|) over the six sectors): bounds
      0.34, 0.67, 1.0, i.e. up to 2, 4, 6 or more known landmarks spread one to a sector; 12
      landmarks in the paper's room (11 besides the target) keep C-bar below 2.
    - **Landmark imprecision** I-bar (the mean over the six sectors of the mean I(l) of Best(4,
      L(s))): an empty sector counts as 1, the imprecision of a landmark whose place is unknown
      (I(l) = 1 for a heading spread of 2 pi and an infinite distance spread), so the paper's
      1/6 sum stays defined. Bounds 0.2, 0.35, 0.5, 0.65, 0.8, 0.95: each empty sector adds
      1/6, so the intervals follow how many sectors are blank, and within them how sharp the rest is.
    - **Action length** ``action_s`` = 1 s (10 control ticks): long enough for the camera to pan
      and take two or three images (0.3 s of processing each), and for the robot to drive 0.3 m,
      so the features can change; 500 actions (the paper's trial limit) are then 500 s, a little
      more than the scenario's own time limit.
    - **bid**: the Learning Agent bids this for the wheels and the camera: above the Pilot's quiet
      bids (its look-ahead look, eq. 1, early on) and below its danger bids (up to 0.9), so the
      Pilot still overrules when it must; the Rescuer's 1.0 overrules both.
    - **Prioritized Sweeping**: ``gamma`` 1 (the paper's objective, the total reward: every
      trial ends, at the target, blocked, or cut at 500 actions; where the model has never
      seen an end, values only fall, which the greedy policy avoids; navcli's first task used
      0.99); ``backups`` k = 20 per real step and
      ``threshold`` 1e-3 (the notes' starting points for 980 states, rewards of size 1-10);
      ``explore`` 2: an action tried fewer times than this in a state is preferred there
      (Moore & Atkeson's exploration of rarely tried actions, locally).
    - **Q-learning** (the model-free baseline): ``q_alpha`` 0.1, ``q_epsilon`` 0.1, the usual
      textbook values.
    """

    distance_bounds: tuple[float, ...] = _intervals((0.9, 1.5, 3.0, 5.0))  # m: 5 intervals
    imprecision_bounds: tuple[float, ...] = _intervals((0.02, 0.04, 0.07, 0.1, 0.15, 0.25))  # I(t): 7 intervals
    count_bounds: tuple[float, ...] = _intervals((0.34, 0.67, 1.0))  # C-bar: 4 intervals
    landmark_bounds: tuple[float, ...] = _intervals((0.2, 0.35, 0.5, 0.65, 0.8, 0.95))  # I-bar: 7 intervals
    action_s: float = _p(1.0, above=0.0)  # s one action lasts
    max_actions: int = _p(500, at_least=1)  # actions before a trial ends (the paper's 500)
    bid: float = _p(0.5, above=0.0, at_most=1.0)  # its bids for the wheels and the camera
    gamma: float = _p(1.0, above=0.0, at_most=1.0)
    backups: int = _p(20, at_least=0)  # k: backups per real step
    threshold: float = _p(1e-3, above=0.0)  # priorities at or below this are not queued
    explore: int = _p(2, at_least=0)  # tries of each action in a state before it is judged on its values
    q_alpha: float = _p(0.1, above=0.0, at_most=1.0)  # Q-learning's step size
    q_epsilon: float = _p(0.1, at_most=1.0)  # Q-learning's exploration rate
    paper_task: int = _p(1, at_most=1)  # 1: train, compare policies and the env run the paper's task (training/task.py)


@dataclass(frozen=True)
class Defaults:
    """Defaults of the optional scenario blocks other than the parameter sets (the scenario format)."""

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
    perception: str = PERCEPTIONS[0]


ROBOT = RobotParams()
PILOT = PilotParams()
NAVIGATION = NavigationParams()
NAVIGATION_C2 = dataclasses.replace(NAVIGATION, alpha=1.231, beta=2.12, kappa1=1.0, kappa2=0.564, kappa=0.178,
                                    gamma_A=1.377, gamma_B=4.39, gamma_R=0.707, I_a_bar=0.871, R_bar=0.906)
"""The thesis' GA-tuned bidding parameters for task cluster C2 (targets behind obstacles, Table 5.2)."""
CLUSTERS = {"C1": NAVIGATION, "C2": NAVIGATION_C2}
VISION = VisionParams()
LEARNING = LearningParams()
DEFAULTS = Defaults()


class ParamError(NavcliError):
    """An override names no parameter, or gives it a value outside its range."""


@dataclass(frozen=True)
class Params:
    """The five parameter sets of one run; see the module docstring for the dotted names.

    >>> p = Params().override({"pilot.K": 30, "navigation.kappa1": 0.5})
    >>> p.pilot.K, p.navigation.kappa1, p.pilot.A_t
    (30.0, 0.5, 50.0)
    >>> try:
    ...     Params().override({"pilot.k": 1})
    ... except ParamError as e:
    ...     print(e)
    unknown parameter 'pilot.k' (did you mean pilot.K?)
    """

    robot: RobotParams = ROBOT
    pilot: PilotParams = PILOT
    navigation: NavigationParams = NAVIGATION
    vision: VisionParams = VISION
    learning: LearningParams = LEARNING

    GROUPS = ("robot", "pilot", "navigation", "vision", "learning")

    def to_json(self) -> dict[str, dict[str, Any]]:
        """``{"pilot": {"K": 18.0, ...}, ...}``: plain JSON values (tuples as lists)."""
        return {g: {k: list(v) if isinstance(v, tuple) else v for k, v in dataclasses.asdict(getattr(self, g)).items()}
                for g in self.GROUPS}

    @classmethod
    def from_json(cls, d: Mapping[str, Mapping[str, Any]]) -> Params:
        """The inverse of :meth:`to_json` (unknown names refused, as for overrides)."""
        return cls().override({f"{g}.{k}": v for g, block in d.items() for k, v in block.items()})

    def flat(self) -> dict[str, Any]:
        """Every parameter by its dotted name."""
        return {f"{g}.{k}": v for g, block in self.to_json().items() for k, v in block.items()}

    def override(self, changes: Mapping[str, Any]) -> Params:
        """A copy with ``changes`` (dotted name -> value) applied; raises :class:`ParamError`."""
        groups: dict[str, dict[str, Any]] = {}
        for name, value in changes.items():
            group, _, key = name.partition(".")
            target = getattr(self, group, None) if group in self.GROUPS else None
            fields = {f.name: f for f in dataclasses.fields(target)} if target is not None else {}
            if key not in fields:
                raise ParamError(f"unknown parameter {name!r}{_suggest(name, self.flat())}")
            groups.setdefault(group, {})[key] = _checked(name, fields[key], value)
        return dataclasses.replace(self, **{g: dataclasses.replace(getattr(self, g), **kw) for g, kw in groups.items()})


MAX_LIST = 64
"""The most numbers a list-valued parameter takes (its longest default has 6)."""


def _checked(name: str, f: dataclasses.Field, value: Any) -> Any:
    """``value`` converted to the field's type and checked against its declared range."""
    choices = f.metadata.get("choices")
    if choices is not None:
        if value not in choices:
            raise ParamError(f"{name} is one of {', '.join(choices)}, got {value!r}"[:300])
        return value
    if isinstance(f.default, tuple):
        if (not isinstance(value, (list, tuple)) or len(value) > MAX_LIST
                or not all(_is_number(v) and math.isfinite(v) for v in value)):
            raise ParamError(f"{name} expects a list of at most {MAX_LIST} finite numbers, got {value!r}"[:300])
        value = tuple(float(v) for v in value)
        n = len(f.default)
        if f.metadata.get("intervals") and (len(value) != n or any(b <= a for a, b in zip(value, value[1:]))):
            raise ParamError(f"{name} must be {n} increasing numbers (the bounds of {n + 1} intervals), "
                             f"got {list(value)}")
        return value
    if isinstance(value, str):
        raise ParamError(f"{name}: {value!r} is not a number")
    if not _is_number(value) or not math.isfinite(value):
        raise ParamError(f"{name} expects a finite number, got {value!r}")
    if isinstance(f.default, int):
        if value != int(value):
            raise ParamError(f"{name} expects a whole number, got {value!r}")
        value = int(value)
    else:
        value = float(value)
    m = f.metadata
    for bound, ok, words in (("at_least", lambda v, b: v >= b, "at least"), ("above", lambda v, b: v > b, "above"),
                             ("at_most", lambda v, b: v <= b, "at most"), ("below", lambda v, b: v < b, "below")):
        b = m.get(bound)
        if b is not None and not ok(value, b):
            raise ParamError(f"{name} must be {words} {b:g}, got {value:g}")
    return value


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _suggest(name: str, known: Mapping[str, Any]) -> str:
    import difflib

    close = ([k for k in known if k.endswith("." + name)] or difflib.get_close_matches(name, known, n=1)
             or [k for k in known if k.lower() == name.lower()])
    return f" (did you mean {close[0]}?)" if close else " (see `navcli params` for the names)"
