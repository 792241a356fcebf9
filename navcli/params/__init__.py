"""Every tunable number of navcli, in one place.

The papers' values live here (K = 18, A_t = 50, R_min = 0.40 m, bid cap 0.9 ...). A scenario's
blocks and the command line override them; nothing else in the code base repeats a default.

The five parameter sets of a run (robot, pilot, navigation, vision, learning), and the sets of
the plugins it uses, travel as one :class:`Params`, addressed by dotted names (``pilot.K``) from
``--param``, plans and the log's metadata. Each parameter is declared once, with its type, unit,
range and description (:func:`~navcli.params.declare.param`): a value outside its range is
refused by name wherever it is made, and ``navcli params``, the scenario format's JSON Schema and
the reference docs read the same declaration."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, ClassVar, Iterator, Mapping

from .declare import MAX_LIST, Declared, ParamError, ParamSet, param, parse_override, suggest

__all__ = [
    "CLUSTERS",
    "CONTROL_DT",
    "LEARNING",
    "MAX_LIST",
    "NAVIGATION",
    "NAVIGATION_C2",
    "PILOT",
    "ROBOT",
    "VISION",
    "Declared",
    "LearningParams",
    "NavigationParams",
    "ParamError",
    "ParamSet",
    "Params",
    "PilotParams",
    "RobotParams",
    "VisionParams",
    "param",
    "parse_override",
]

NOISE_BOUND = 3.0
"""Sensor errors (odometry, camera) are drawn from normals clipped at this many standard deviations:
physical sensors have bounded errors, and the fuzzy supports of the visual memory rely on the bound."""

PERCEPTIONS = ("vision", "oracle")
"""What the agents may know: the camera and visual memory (default), or ground truth. (Pilots and
Navigation policies are found by name: :mod:`navcli.plugins`.)"""

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


@dataclass(frozen=True)
class RobotParams(ParamSet):
    """Body and drive limits of the differential-drive robot (a Pioneer-sized disc); a scenario's
    ``robot:`` block sets ``radius`` and ``max_speed``."""

    group: ClassVar[str] = "robot"

    radius: float = param(0.25, "m", "the robot's radius (a disc)", at_least=0.05, at_most=1.0)
    max_speed: float = param(
        0.3, "m/s", "full speed; the physics step holds walls up to 2 m/s (tests/test_world.py)", above=0.0, at_most=2.0
    )
    max_accel: float = param(0.5, "m/s^2", "the drive's acceleration limit", above=0.0)
    max_turn_rate: float = param(math.radians(90.0), "rad/s", "the fastest turn (90 deg/s)", above=0.0)
    max_turn_accel: float = param(
        math.radians(180.0), "rad/s^2", "the turn's acceleration limit (180 deg/s^2)", above=0.0
    )
    slip_noise: float = param(
        0.1,
        "",
        """how far each wheel's executed speed may stray from its command, as a fraction: every
        physics step each wheel's speed is multiplied by its own factor drawn uniformly from
        [1 - slip_noise, 1 + slip_noise] (Webots' DifferentialWheels ``slipNoise``, whose default
        0.1 this is); 0 executes the command exactly""",
        at_most=0.5,
    )
    decision_limit_s: float = param(
        5.0,
        "s",
        """wall-clock seconds a plugin's code (a plugin pilot's, a plugin Navigation policy's) may
        take for one call; one that takes longer ends its run as error, its log closed (navcli's own
        pilots and agents are not timed; the clock never enters the log or a normal run's course)""",
        above=0.0,
        at_most=3600.0,
        course=False,
    )

    def time_to_drive(self, metres: float) -> float:
        """Seconds the robot takes to drive ``metres`` at full speed: how the windows that are
        about progress (the Rescuer's blocked window and diverting timeout, the Pilot's stall
        watch) become times, so a slow robot is given the time its distance takes.

        >>> RobotParams(max_speed=0.05).time_to_drive(12.0)
        240.0
        """
        return metres / self.max_speed


PILOT_CEILING = 0.9
"""No bid of the Pilot, for the wheels or the camera, exceeds this (pilot paper, eq. 9's 0.9; the
architecture: the Pilot's "bids never exceed 0.9"), so that another system can always overrule it:
the most ``pilot.bid_cap`` and ``pilot.look_cap`` may be."""


@dataclass(frozen=True)
class PilotParams(ParamSet):
    """Parameters of the Pilot (pilot paper, sections 3.4 and 4); a scenario's ``pilot:`` block
    sets ``K``, ``A_t`` and ``R_min``."""

    group: ClassVar[str] = "pilot"

    K: float = param(18.0, "force units x m^2", "eq. 2: the repulsion constant", at_most=1000.0)
    A_t: float = param(50.0, "force units", "eq. 5: the target's constant attraction", at_most=1000.0)
    R_min: float = param(
        0.40, "m", "eq. 3-4: the prohibited area's radius beyond an obstacle's surface", at_least=0.01, at_most=5.0
    )
    bid_cap: float = param(PILOT_CEILING, "", "eq. 9: the Pilot's motion bid never above this", at_most=PILOT_CEILING)
    heading_gain: float = param(1.5, "1/s", "turn rate per radian of heading error")
    drive_while_turning: bool = param(
        True,
        "",
        """how a winning move is executed (section 4: "the Pilot executes
        the turn of the winning bid"): on, the speed and the turn commanded together, as a Pioneer's velocity and
        heading commands do (our reading of the paper); off, stop to turn above turn_in_place, slow by cos(error)
        below""",
    )
    arc_margin: float = param(
        0.1, "m", "clearance the body keeps along the arc of a large turn driven at speed (see Pilot._arc_clear)"
    )
    safe_execution: bool = param(
        True,
        "",
        "moves are executed only if safe (section 2, see Pilot._path_clear); off: as they come",
    )
    nearest_safe: bool = param(
        True,
        "",
        """a request not safe, with no own move that drives, is replaced by the
        nearest safe heading (15 deg steps); off: turned on the spot (where the robot can stand still for good,
        facing its target past a landmark)""",
    )
    turn_in_place: float = param(
        math.radians(45.0),
        "rad",
        "above this heading error the robot stops to turn (drive_while_turning off), or checks the turn's arc (on)",
    )
    distress_gain: float = param(
        1.5, "", "section 5: each offending obstacle's force is multiplied by this when IN_DISTRESS"
    )
    distress_from_nearest: bool = param(
        True,
        "",
        """a linear obstacle IN_DISTRESS pushes from its nearest point
        (our design: from its centre, section 3.2, a corner of two fences is a sink); off: from its centre there
        too""",
    )
    blocked_report_m: float = param(
        0.0,
        "m",
        """the field leading away from the target, a long obstacle its
        strongest push, while the robot could drive this far and got along the obstacle less than a third of it:
        the Pilot reports the obstacle as one it cannot easily avoid (the thesis' blocked situation); 0: no report
        (the default: measured, it helps behind long fences and costs paper-8x8 runs; README, trap rooms)""",
    )
    wall_window: float = param(1.0, "m", "a room wall acts as the stretch this long nearest the robot", above=0.0)
    line_window: float = param(
        3.0,
        "m",
        "a linear obstacle longer than this acts as the stretch this long nearest the robot (the paper's are shorter)",
        above=0.0,
    )
    corridor_margin: float = param(0.40, "m", "section 3.3: the safe corridor keeps this far from the line's ends")
    backward_turn: float = param(
        math.radians(160.0),
        "rad",
        "section 3.5: turns larger than this are driven backwards (turning the complement) ...",
        at_most=math.pi,
    )
    max_backward: float = param(0.6, "m", "... while the total distance driven backwards that way stays under this")
    reflex_stop_s: float = param(0.5, "s", "section 3.5: standing still after a bump")
    reflex_look_pans_deg: tuple[float, ...] = param(
        (-60.0, 0.0, 60.0),
        "deg",
        "section 3.5: the looks around after a bump (pans from ahead)",
        at_least=-180.0,
        at_most=180.0,
    )
    backup_distance: float = param(0.30, "m", "section 3.5: backed up after a bump")
    backup_speed: float = param(
        0.15, "m/s", "section 3.5: the speed of that backing up (at most robot.max_speed)", above=0.0
    )
    reflex_phase_limit_s: float = param(
        4.0,
        "s",
        """a reflex phase that cannot finish (the camera kept busy) is
        given up after this; the backup phase is given at least twice the time backing up takes at the speed it is
        driven (backed into something)""",
        above=0.0,
    )
    stall_window_m: float = param(
        0.6,
        "m",
        """no silent stall (our design): pushing without moving starts the
        reflex too, judged over the time it takes to drive this far at robot.max_speed (0.6 m: 2 s at 0.3 m/s)""",
        above=0.0,
    )
    stall_min_distance: float = param(0.1, "m", "commanded in that window before a stall can be called", above=0.0)
    stall_progress: float = param(
        0.2, "", "a stall: less than this fraction of the commanded distance moved", at_most=1.0
    )
    look_d_max: float = param(1.0, "m", "eq. 1: d_m, the longest drive without looking ahead", above=0.0)
    look_exponent: float = param(2.0, "", "eq. 1: s, the look-ahead bid's exponent", above=0.0)
    look_cap: float = param(
        1.0,
        "",
        """eq. 1's bid never above this: 1, eq. 1 as written (d_m is "the maximum distance
        allowed to travel without looking ahead", so the bid reaches 1 there); 0.9 (PILOT_CEILING, the architecture's
        ceiling of the Pilot's bids) lets the Risk Manager's searches, bid above 0.9 while the risk is
        high (always, in a room without landmarks), keep the Pilot from ever looking ahead""",
        at_most=1.0,
    )
    look_ahead_cone: float = param(math.radians(30.0), "rad", "a look this close to straight ahead resets d_l of eq. 1")
    looks: bool = param(
        True,
        "",
        """the Pilot bids for the camera (eq. 1's look-ahead, a reflex's looks around);
        off: never (the learning paper's task: the camera is the Learning Agent's; the Pilot still avoids what the
        memory holds)""",
    )
    geometric_lookahead: float = param(
        1.0, "m", "the geometric pilot starts to steer this far beyond the prohibited area"
    )
    geometric_clearance: float = param(
        0.05, "m", "the geometric pilot's tangents pass this far outside the prohibited area"
    )
    geometric_side_memory: float = param(
        0.5, "m", "driven with the way clear before the geometric pilot forgets the side it chose to pass on"
    )


@dataclass(frozen=True)
class NavigationParams(ParamSet):
    """Parameters of the Navigation system's agents (learning-agent paper section 3; notes,
    sections 1-4). The bidding parameters default to the thesis' GA-tuned values for task cluster
    C1 (targets reachable without obstacles, Table 5.2); :data:`NAVIGATION_C2` holds cluster C2's
    (targets behind obstacles). The rest is our design, each with its reason."""

    group: ClassVar[str] = "navigation"

    kappa1: float = param(0.314, "", "Target Tracker: its move bid with a precisely known target", at_most=1.0)
    alpha: float = param(1.731, "", "Target Tracker: how fast that bid falls with the target's imprecision I_a")
    kappa2: float = param(0.493, "", "Target Tracker: the look bid's peak", at_most=1.0)
    beta: float = param(
        2.03, "", "Target Tracker: I_a = (eps / 2 pi) ** beta, eps the width of the heading's 70 % cut", above=0.0
    )
    I_a_bar: float = param(
        0.386,
        "",
        "Target Tracker: I_a at which the look bid peaks; above it the Rescuer takes over",
        above=0.0,
        below=1.0,
    )
    kappa: float = param(
        0.355,
        "",
        "Distance Estimator: its bid kappa * tanh(I_d / d), I_d the width (m) of the "
        "target distance's 70 % cut, d its distance",
        at_most=1.0,
    )
    gamma_A: float = param(0.240, "", "Risk Manager: R = 1 - min(1, q_A (|A|/6)^gamma_A + q_B (|B|/6)^gamma_B)")
    gamma_B: float = param(0.521, "", "Risk Manager: the exponent of the known landmarks' term")
    gamma_R: float = param(0.054, "", "Risk Manager: its look bid R^gamma_R", above=0.0)
    R_bar: float = param(0.215, "", "Risk Manager: it bids only when R > R_bar", at_most=1.0)
    ahead_deg: float = param(
        90.0, "deg", "Risk Manager: landmarks within this bearing are ahead (set A)", above=0.0, at_most=180.0
    )
    communicator_window_s: float = param(
        0.2, "s", "the Communicator collects bids over this window; a later bid replaces an earlier one"
    )
    rescuer_bid: float = param(
        1.0, "", "the Rescuer's stop, look and turn bids: an emergency, above every other bid", at_most=1.0
    )
    blocked_window_m: float = param(
        12.0,
        "m",
        """no progress toward the target while the robot could drive this
        far at robot.max_speed: blocked (our design, a distance: a slow robot is never blocked for being slow; 12 m
        is the 40 s this window had at 0.3 m/s)""",
        above=0.0,
    )
    blocked_progress: float = param(0.5, "m", "closer to the target that counts as progress", above=0.0)
    stall_rule: bool = param(
        True,
        "",
        """the short no-progress rule: the robot moved less than stall_progress net
        over the stall window is blocked (a potential field caught in a minimum, swinging between two obstacles
        without a bump); off: only the long window of blocked_window_m""",
    )
    stall_window_s: float = param(
        20.0, "s", "the stall window: at least this long, or stall_window_m at robot.max_speed", above=0.0
    )
    stall_window_m: float = param(
        1.5,
        "m",
        "the stall window: as long as the robot takes to drive this far at robot.max_speed (30 s at 5 cm/s)",
        above=0.0,
    )
    stall_approach: float = param(
        2.0,
        "",
        """and blocked when, over this many stall windows, the robot came less than
        stall_progress closer to its target (led away round and round); 0: the net displacement alone""",
    )
    stall_progress: float = param(
        0.3, "m", "less net displacement than this over the stall window: no progress", above=0.0
    )
    blocked_bumps: int = param(3, "", "or this many bumps within the blocked window: blocked", at_least=1)
    diverting_timeout_m: float = param(
        27.0,
        "m",
        "a diverting target not crossed while the robot could drive this far has failed (90 s at 0.3 m/s)",
        above=0.0,
    )
    max_diverting_failures: int = param(0, "", "failed diverting targets that end the mission; 0: no count does")
    gives_up: bool = param(
        False,
        "",
        """on: the Rescuer ends the mission blocked when the map shows no way out twice
        (or max_diverting_failures is reached); off: it turns by a random angle and asks the map again, as the
        thesis' Rescuer does with no diverting target, until the time limit""",
    )
    random_turn_deg: float = param(
        120.0, "deg", "with no diverting target: turn by up to this much", above=0.0, at_most=180.0
    )
    explore_m: float = param(
        3.0,
        "m",
        """exploring (no diverting target): turn away from the target (within half
        random_turn_deg), drive up to this far looking around until a new landmark is seen, then scan (our design:
        what hides the landmarks from where the robot is blocked is a long obstacle, about 3 m in the papers'
        rooms); 0: turn and scan in place""",
    )
    turn_when_here: bool = param(
        True,
        "",
        """blocked with the target in the robot's own region (the map's way is
        straight): turn by a random angle within random_turn_deg, as the thesis' Rescuer with no diverting target;
        off: explore (turn away, drive explore_m, look around)""",
    )
    sight_ends_way: bool = param(
        True,
        "",
        """once a diverting target is crossed, a target in sight (no known long
        obstacle across the straight way) is headed for directly; off: the map is asked for the way's next step all
        the same""",
    )
    scan_pans_deg: tuple[float, ...] = param(
        (-90.0, -45.0, 0.0, 45.0, 90.0),
        "deg",
        "the looks of a scan (the initial sweep, a lost target)",
        at_least=-180.0,
        at_most=180.0,
    )
    initial_sweep: bool = param(True, "", "the Rescuer's initial sweep (thesis node 81); off: none (short experiments)")
    rescuer_looks: bool = param(
        True,
        "",
        """the Rescuer looks (the initial sweep, a lost target's scans, looking
        around to explore); off: never, and a lost target is left to the agents (the learning paper's task, where
        the camera is the Learning Agent's)""",
    )
    blocked_ends: bool = param(
        False, "", "the first blocked situation ends the mission blocked (the learning paper's trials)"
    )
    blocked_no_progress: bool = param(
        True,
        "",
        """no progress toward a known target within the blocked window is a blocked situation; off:
        it is not, and only bumps and the Pilot's report block the robot (the learning paper's task: "blocked
        by the landmarks or by the wall"; its trials go on, bounded by their 500 actions)""",
    )
    reach_confident: bool = param(
        False,
        "",
        """the target counts as reached only when the robot is also confident
        of it ("and is confident that it has reached the target"): the 70 % cut of its belief of the target wholly
        within reach; off: the body alone""",
    )
    reach_imprecision: float = param(
        0.0,
        "",
        "> 0: and the belief's I(t) (the learning paper's I(l)) below this (a stricter reading, for the sensitivity)",
        at_most=1.0,
    )
    map_encode_imprecision: float = param(
        0.25, "", "Map Manager: landmarks at most this imprecise are encoded", above=0.0, at_most=1.0
    )
    map_units_per_landmark: int = param(6, "", "Map Manager: beta-units kept per landmark (the sharpest)", at_least=1)
    map_recall_every: int = param(
        5, "ticks", "Map Manager: between two recalls of a landmark from the network", at_least=1
    )
    map_draw_every: int = param(
        100,
        "ticks",
        """between two /map/scene updates, and the last tick (10 s; our
        design: the map changes slowly, and its snapshot triangulates the landmarks, which every 2 s cost some
        40 us a tick; see DRAW_PERIOD)""",
        at_least=1,
    )
    virtual_distance: float = param(10.0, "m", "Map Manager: virtual landmarks beyond the hull edges", above=0.0)
    blocked_cost: float = param(1000.0, "", "Map Manager: the cost of a region arc known to be blocked", above=1.0)
    seen_closed_cost: float = param(
        100.0,
        "",
        """Map Manager: the cost of an arc a remembered long obstacle was seen across
        (one the memory no longer holds): a way worse than any open one, cleared when the robot sees both its
        landmarks with no known obstacle across; 0: a block for good, which can close the robot in""",
    )
    dead_end_radius: float = param(
        1.0,
        "m",
        """Map Manager: an edge whose middle lies this near the middle of a failed
        diverting target's edge passes by that dead end and costs seen_closed_cost (blocked_cost when that is 0);
        0: failed edges matched by their ends only""",
    )
    diverting_in_sight: bool = param(
        True,
        "",
        "the diverting target is the farthest edge of the way the robot sees straight; off: the first",
    )
    diverting_seen_whole: bool = param(
        False,
        "",
        """in sight means the edge's middle half seen whole (sight lines to its middle
        and quarter points clear, no obstacle's end between: never an edge beyond a wall's end); off: its middle
        alone (measured: as fast or faster in the trap rooms and slanted-8x8, 5 reruns)""",
    )


@dataclass(frozen=True)
class VisionParams(ParamSet):
    """The camera's measurement model and the visual memory (notes, sections 1 and 3)."""

    group: ClassVar[str] = "vision"

    noise_bound: float = param(
        NOISE_BOUND, "standard deviations", "sensor errors are bounded at this many standard deviations", above=0.0
    )
    told_target: bool = param(True, "", "the robot is told where the target is at the start; off: it must see it")
    routines: bool = param(
        True,
        "",
        "a look registers only what the routine of its purpose finds "
        "(vision/routines.py), no look no image; off: every image registers all in view",
    )
    line_objects: bool = param(
        True,
        "",
        "a fence or wall is one object, its ends fused end by end "
        "(vision/visual_memory.py); off: view-cut pieces re-joined by geometry",
    )
    walls: str = param(
        "seen",
        "",
        "how the robot knows the room's walls (vision/perception.py): seen (as lines, "
        "like fences), known (from the start) or felt (by the bumpers only)",
        choices=("seen", "known", "felt"),
    )
    heading_floor: float = param(math.radians(0.5), "rad", "the fuzzy heading's least half-spread (a pixel or so)")
    distance_floor: float = param(0.02, "m", "the fuzzy distance's least half-spread")
    walk_bound: float = param(
        4.0, "standard deviations", "the per-tick odometry errors' random walk is bounded at this many deviations"
    )
    odometry_floor: float = param(0.005, "", "relative odometry error the memory allows for even without noise")
    bump_radius: float = param(0.10, "m", "support radius of an obstacle found by the bumpers", above=0.0)
    bump_merge: float = param(1.0, "m", "a bump this near another bump or a landmark joins it in a long obstacle")
    bump_lines: str = param(
        "one-object",
        "",
        """which bumps join into a long obstacle (vision/visual_memory.py): one-object, only
        two felt on one object as far as the robot can tell (the line between them clear of the robot's body
        where it stood at each bump, the robot on one side of it at both; a bump on a remembered line or point
        confirms it instead of drawing another); near, any two within bump_merge (which draws lines through the
        robot's own body, and one line four times)""",
        choices=("one-object", "near"),
    )
    fence_rigid: bool = param(
        False,
        "",
        """on: a fence is one object: when a sighting of one of its ends, sharper than the
        memory and within it, corrects that end and not the other, the other end is moved with it, its support grown
        by the move (vision/visual_memory.py); off: each end corrected on its own (a fence's line may drift and tilt;
        on, 20 seeds of the five trap rooms reached 195/200 with 3.9 contacts a run, off 198/200 with 2.7)""",
    )
    line_join_gap: float = param(
        0.5, "m", "stretches of a fence or wall seen apart are one only if they overlap or are this near"
    )
    forget_above: float = param(
        0.35, "", "I(l) above which a landmark or the target is forgotten", above=0.0, at_most=1.0
    )
    forget_line_by_one_end: bool = param(
        False,
        "",
        """on: a linear obstacle (or wall) is forgotten when one end is
        above forget_above (the near end of a fence the robot drives along blurs first, and the whole fence goes
        with it); off: when both are""",
    )
    forget_every: int = param(
        5, "ticks", "between two sweeps of the memory for what has become too imprecise", at_least=1
    )
    draw_every: int = param(
        30,
        "ticks",
        """between two /memory/scene updates, and the last tick (3 s; our design:
        drawn once a second it cost some 40 us a tick; each drawing stays where it was in the world, see
        DRAW_PERIOD)""",
        at_least=1,
    )


@dataclass(frozen=True)
class LearningParams(ParamSet):
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
      seen an end, values only fall, which the greedy policy avoids; the simpler task, ``paper_task`` 0,
      is meant with 0.99); ``backups`` k = 20 per real step and
      ``threshold`` 1e-3 (the notes' starting points for 980 states, rewards of size 1-10);
      ``explore`` 29: an action tried fewer times than this in a state is preferred there
      (Moore & Atkeson's exploration of rarely tried actions, locally). How many tries is
      enough the papers do not say; ours: enough to see, at 95 %, a way out taken one try in
      ten, 0.9 ** 29 < 0.05. One in ten is what the start state offers, "nothing known": only
      MLL leaves it, 10 % of 631 tries in a training of landmarks-12; every other action loops
      back. With too few tries an action whose tries all looped is judged a loop; where every
      action is, the undiscounted model sees no way out, its values sink together, and the
      cheapest loop, MB, wins for good (MB takes no image, so it never finds one): at 2, a
      training of seed 5 ran 500 MB a trial from its second trial on. ``--param
      learning.explore=2`` gives that setting.
    - **Q-learning** (the model-free baseline): ``q_alpha`` 0.1, ``q_epsilon`` 0.1, the usual
      textbook values.
    """

    group: ClassVar[str] = "learning"

    distance_bounds: tuple[float, ...] = param(
        (0.9, 1.5, 3.0, 5.0), "m", "the target distance D(t)'s interval bounds (5 intervals)", intervals=True
    )
    imprecision_bounds: tuple[float, ...] = param(
        (0.02, 0.04, 0.07, 0.1, 0.15, 0.25),
        "",
        "the target imprecision I(t)'s interval bounds (7 intervals)",
        intervals=True,
    )
    count_bounds: tuple[float, ...] = param(
        (0.34, 0.67, 1.0), "", "the landmark count C-bar's interval bounds (4 intervals)", intervals=True
    )
    landmark_bounds: tuple[float, ...] = param(
        (0.2, 0.35, 0.5, 0.65, 0.8, 0.95),
        "",
        "the landmark imprecision I-bar's interval bounds (7 intervals)",
        intervals=True,
    )
    action_s: float = param(1.0, "s", "one action lasts this long", above=0.0)
    max_actions: int = param(500, "", "actions before a trial ends (the paper's 500)", at_least=1)
    bid: float = param(0.5, "", "the Learning Agent's bids for the wheels and the camera", above=0.0, at_most=1.0)
    gamma: float = param(1.0, "", "Prioritized Sweeping's discount", above=0.0, at_most=1.0)
    backups: int = param(20, "", "k: Prioritized Sweeping's backups per real step")
    threshold: float = param(1e-3, "", "priorities at or below this are not queued", above=0.0)
    explore: int = param(29, "", "tries of each action in a state before it is judged on its values")
    q_alpha: float = param(0.1, "", "Q-learning's step size", above=0.0, at_most=1.0)
    q_epsilon: float = param(0.1, "", "Q-learning's exploration rate", at_most=1.0)
    paper_task: bool = param(
        True,
        "",
        "train, compare policies and the env run the paper's task (training/task.py); off: a simpler task (training/task.py)",
    )
    first_sighting: bool = param(
        False,
        "",
        "the paper's task: the robot starts with the image of the target a look "
        "from its start would give; off: it knows nothing (section 5.1)",
    )
    pace: bool = param(
        True,
        "",
        "a lost target: each action aims at pi fixed in the odometry frame when it starts, 180 degrees "
        "from the last, driven as a reversal (section 5.3's pacing; learning_agent.py); off: re-aimed "
        "at pi in the robot's frame every tick",
    )
    blocked_terminal: bool = param(
        False,
        "",
        "a blocked ending is an end state of value 0 for the learner (navcli "
        "before); off: a cut, as at max_actions (training/task.py)",
    )


ROBOT = RobotParams()
PILOT = PilotParams()
NAVIGATION = NavigationParams()
NAVIGATION_C2 = dataclasses.replace(
    NAVIGATION,
    alpha=1.231,
    beta=2.12,
    kappa1=1.0,
    kappa2=0.564,
    kappa=0.178,
    gamma_A=1.377,
    gamma_B=4.39,
    gamma_R=0.707,
    I_a_bar=0.871,
    R_bar=0.906,
)
"""The thesis' GA-tuned bidding parameters for task cluster C2 (targets behind obstacles, Table 5.2)."""
CLUSTERS = {"C1": NAVIGATION, "C2": NAVIGATION_C2}
VISION = VisionParams()
LEARNING = LearningParams()


@dataclass(frozen=True)
class Params:
    """The parameter sets of one run: navcli's five, and ``plugins``, the sets of the plugins it
    may use, by the plugins' names (``(("vfh", VFHParams(...)),)``); see the module docstring.

    >>> p = Params().override({"pilot.K": 30, "navigation.kappa1": 0.5, "pilot.looks": 0})
    >>> p.pilot.K, p.navigation.kappa1, p.pilot.A_t, p.pilot.looks
    (30.0, 0.5, 50.0, False)
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
    plugins: tuple[tuple[str, ParamSet], ...] = ()

    GROUPS = ("robot", "pilot", "navigation", "vision", "learning")

    def sets(self) -> dict[str, ParamSet]:
        """Every parameter set by its name.

        Returns:
            navcli's five sets, then the plugins', by their names (``pilot``, ``vfh``).
        """
        return {g: getattr(self, g) for g in self.GROUPS} | dict(self.plugins)

    def to_json(self) -> dict[str, dict[str, Any]]:
        """navcli's five sets as plain JSON values. A plugin's set is written with its plugin
        (:meth:`navcli.config.RunSpec.to_json`).

        Returns:
            ``{"pilot": {"K": 18.0, ...}, ...}``, tuples as lists.
        """
        return {g: getattr(self, g).to_json() for g in self.GROUPS}

    @classmethod
    def from_json(cls, d: Mapping[str, Mapping[str, Any]]) -> Params:
        """The inverse of :meth:`to_json`.

        Args:
            d: navcli's sets as :meth:`to_json` writes them.

        Returns:
            The parameters.

        Raises:
            ParamError: an unknown name, or a value its declaration refuses, as for overrides.
        """
        return cls().override({f"{g}.{k}": v for g, block in d.items() for k, v in block.items()})

    def flat(self) -> dict[str, Any]:
        """Every parameter by its dotted name.

        Returns:
            ``{"pilot.K": 18.0, ...}``, plugins' parameters too.
        """
        return {f"{g}.{k}": v for g, s in self.sets().items() for k, v in s.to_json().items()}

    def declarations(self) -> Iterator[tuple[str, Declared, Any]]:
        """Every parameter with its declaration.

        Yields:
            (dotted name, declaration, value) of each parameter, navcli's then the plugins'.
        """
        for g, s in self.sets().items():
            for k, d, _ in s.declarations():
                yield f"{g}.{k}", d, getattr(s, k)

    def with_plugin(self, name: str, values: ParamSet) -> Params:
        """A copy holding a plugin's parameter set (replacing any it held).

        Args:
            name: the plugin's name, which its parameters go by (``vfh`` in ``vfh.tau_high``).
            values: its parameter set.

        Returns:
            The copy.

        Raises:
            ParamError: a name that is one of navcli's sets', holds a dot, or is empty.
        """
        if name in self.GROUPS or "." in name or not name:
            raise ParamError(
                f"{name!r} cannot name a plugin's parameters (navcli's own sets: {', '.join(self.GROUPS)})"
            )
        rest = tuple((n, s) for n, s in self.plugins if n != name)
        return dataclasses.replace(self, plugins=tuple(sorted(rest + ((name, values),), key=lambda p: p[0])))

    def plugin(self, name: str) -> ParamSet | None:
        """A plugin's parameter set.

        Args:
            name: the plugin's name, which its parameters go by.

        Returns:
            Its set, or None if these parameters hold none.
        """
        return dict(self.plugins).get(name)

    def override(self, changes: Mapping[str, Any]) -> Params:
        """A copy with some parameters changed, each checked against its declaration.

        Args:
            changes: the new values by their dotted names (``{"pilot.K": 30}``).

        Returns:
            The copy.

        Raises:
            ParamError: an unknown name (with the nearest known one), or a value its declaration
                refuses.
        """
        sets = self.sets()
        groups: dict[str, dict[str, Any]] = {}
        for name, value in changes.items():
            group, _, key = name.partition(".")
            target = sets.get(group)
            if target is None or key not in {f.name for f in dataclasses.fields(target)}:
                raise ParamError(f"unknown parameter {name!r}{suggest(name, list(self.flat()))}")
            groups.setdefault(group, {})[key] = value
        own: dict[str, Any] = {}
        out = self
        for group, values in groups.items():
            changed = sets[group].changed(group, values)
            if group in self.GROUPS:
                own[group] = changed
            else:
                out = out.with_plugin(group, changed)
        return dataclasses.replace(out, **own)
