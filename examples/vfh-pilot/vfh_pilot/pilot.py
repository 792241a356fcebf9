"""``VFHPilot``: the VFH+ obstacle avoidance (:mod:`.histogram`) as a navcli pilot.

What navcli gives a pilot, and how VFH+ uses it (our reading, where the papers speak of sonar):

- **The certainty grid** is made each step from the obstacles the robot knows (its visual memory,
  bumped obstacles included; the room's walls as the camera has seen them), each occupied cell
  ``c* = 1``: the memory already holds what the sensors have confirmed, which VFH's grid builds up
  by counting sonar readings.
- **The frame**: the histogram's sectors are fixed in the odometry frame (VFH+'s world frame), so
  the binary histogram's hysteresis and the previous direction mean the same sectors from one step
  to the next however the robot turned.
- **The target direction** ``k_t`` is the Navigation system's requested heading (it asks to move
  toward the current target, a diverting one while the Rescuer holds one), else the target's.
- **The market**: VFH+ proposes its direction and speed at the Pilot's cap (0.9) whenever they
  differ from the Navigation system's request (by more than one sector, or slower); otherwise it
  proposes nothing and the request is carried out. With no request, or a request to stop, it
  proposes nothing: where to go is the Navigation system's to say. With every sector masked (no
  opening: VFH+ has no direction), it proposes nothing either (ours): the request is then carried
  out as navcli's execution finds safe (the nearest safe heading), and the Rescuer, seeing no
  progress, sets a diverting target; turning on the spot froze the robot for good in a narrow place.
- **The robot's size** ``r_rs`` is its radius, the clearance navcli's execution keeps
  (``pilot.arc_margin``: it refuses a move that comes nearer) and VFH+'s safety distance.
- **The minimum turning radius** of the masked histogram is the arc the robot drives at full
  speed and full turn rate, ``robot.max_speed / robot.max_turn_rate`` (0.19 m at 0.3 m/s, 0.03 m
  at the paper's 5 cm/s).

Reflexes, the look-ahead camera bid and the execution of the winning move are navcli's
(:class:`navcli.pilot.Pilot`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

import msgspec
import numpy as np
from navcli.bidding import Move
from navcli.geometry import wrap_angle
from navcli.params import PILOT, ROBOT, ParamSet, PilotParams, RobotParams, param
from navcli.pilot import Avoidance, Pilot

from . import histogram as vfh


@dataclass(frozen=True)
class VFHParams(ParamSet):
    """VFH+'s parameters: ``--param vfh.<name>=<value>`` (installed under the name ``vfh``)."""

    sector_deg: float = param(
        5.0,
        "deg",
        "alpha: the width of a sector of the polar histogram (VFH+: 5 deg, 72 sectors)",
        above=0.5,
        at_most=45.0,
    )
    cell_m: float = param(0.1, "m", "the certainty grid's cell (VFH: 10 cm)", at_least=0.02, at_most=0.5)
    window_m: float = param(
        1.6,
        "m",
        "the active window's radius, (w_s - 1) / 2 cells (VFH: 33 x 33 cells of 10 cm)",
        above=0.1,
        at_most=10.0,
    )
    a: float = param(
        5.0,
        "",
        "a of m = c*^2 (a - b d^2): a cell's magnitude at the robot; b follows from a - b (window_m)^2 = 1",
        above=1.0,
        at_most=1000.0,
    )
    safety_m: float = param(
        0.05,
        "m",
        "d_s: the distance kept from obstacles beyond the robot's radius and the "
        "clearance navcli's execution keeps (r_rs = robot.radius + pilot.arc_margin + "
        "d_s)",
        at_most=2.0,
    )
    tau_low: float = param(5.0, "", "the binary histogram's low threshold: a sector below it is free")
    tau_high: float = param(
        10.0,
        "",
        """the binary histogram's high threshold: a sector above it is blocked (between
        the two: as the step before). Ours, by measurement (paper-8x8, 6 reruns each perception): a 5 cm fence
        0.3 m away fills a sector with some 15 (three cells of m = 4.9: VFH's sonar counts raise c* where ours
        is 1), so 10/20 let the robot graze fence ends (3 contacts a run with ground truth, 651 s); 5/10 none,
        300 s""",
    )
    wide_sectors: int = param(
        16, "", "s_max: an opening of more sectors than this is wide (VFH+: 16 of 5 deg)", at_least=2, at_most=360
    )
    mu_target: float = param(5.0, "", "mu1: the cost of a candidate's distance (in sectors) to the target direction")
    mu_heading: float = param(2.0, "", "mu2: the cost of its distance to the robot's heading")
    mu_previous: float = param(2.0, "", "mu3: the cost of its distance to the direction chosen the step before")
    slow_density: float = param(
        40.0,
        "",
        "h_m: the density in the direction of travel at which the speed falls to its least (VFH's speed rule)",
        above=0.0,
    )
    min_speed: float = param(0.25, "", "the least speed, a fraction of robot.max_speed", above=0.0, at_most=1.0)
    clip_at_target: bool = param(
        True,
        "",
        """cells farther than the target (by more than r_rs) are left out of the
        histogram (ours: a target within the window's reach of a wall, as paper-8x8's is 0.8 m from two walls, is
        otherwise behind a blocked sector for good); off: VFH+'s window alone""",
    )


class VFHInfo(msgspec.Struct):
    """What VFH+ adds to ``/pilot`` every step."""

    target_sector: Annotated[int, msgspec.Meta(description="k_t: the target direction's sector (odometry frame)")]
    chosen_sector: Annotated[int, msgspec.Meta(description="the sector chosen (odometry frame); -1: none")]
    openings: Annotated[int, msgspec.Meta(description="openings (runs of free sectors) in the masked histogram")]
    candidates: Annotated[int, msgspec.Meta(description="candidate directions of those openings")]
    density_ahead: Annotated[float, msgspec.Meta(description="the primary histogram in the heading's sector")]
    density_max: Annotated[float, msgspec.Meta(description="the primary histogram's largest sector")]
    blocked_sectors: Annotated[int, msgspec.Meta(description="sectors blocked in the masked histogram")]
    target_blocked: Annotated[bool, msgspec.Meta(description="the target direction is blocked in the masked histogram")]


class VFHPilot(Pilot):
    """``--pilot vfh``: VFH+ (see the module docstring; the algorithm in :mod:`vfh_pilot.histogram`)."""

    Params = VFHParams
    Info = VFHInfo

    def __init__(
        self,
        params: PilotParams = PILOT,
        robot: RobotParams = ROBOT,
        *,
        own_params: ParamSet | None = None,
        rng: np.random.Generator | None = None,
    ):
        super().__init__(params, robot, own_params=own_params or VFHParams(), rng=rng)
        p = self.vfh = self.own_params if isinstance(self.own_params, VFHParams) else VFHParams()
        self.n = max(8, round(360.0 / p.sector_deg))
        self.alpha = 2 * math.pi / self.n
        self.cells = vfh.window_cells(p.window_m, p.cell_m)
        self.b = (p.a - 1.0) / (p.window_m * p.window_m)  # a - b R^2 = 1
        # r_rs: the robot grown by the clearance navcli's execution keeps (it refuses a move that comes nearer) and
        # VFH+'s own safety distance (ours: with the robot's radius alone, VFH+ led it where every move was refused)
        self.r_rs = robot.radius + params.arc_margin + p.safety_m
        self.r_turn = robot.max_speed / robot.max_turn_rate
        self.mu = (p.mu_target, p.mu_heading, p.mu_previous)
        self._binary = np.zeros(self.n, dtype=bool)  # the last binary histogram (hysteresis)
        self._previous: int | None = None  # the sector chosen last

    def histograms(self, obstacles, theta: float, reach: float = math.inf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The occupied cells (egocentric), the primary histogram and the masked histogram (True:
        blocked) for the known ``obstacles`` and the heading ``theta`` (odometry frame), counting
        the cells within ``reach`` m only."""
        p = self.vfh
        near = [o for o in obstacles if _distance(o) - o.radius <= min(p.window_m, reach) + p.cell_m]
        if near:
            a = np.array([o.a for o in near], dtype=float)
            b = np.array([o.b for o in near], dtype=float)
            cells = vfh.occupied(self.cells, a, b, np.array([o.radius for o in near]), p.cell_m)
            if reach < p.window_m:
                cells = cells[np.hypot(cells[:, 0], cells[:, 1]) <= reach]
        else:
            cells = self.cells[:0]
        primary = vfh.primary_histogram(cells, theta, self.n, p.a, self.b, self.r_rs)
        self._binary = vfh.binary_histogram(primary, self._binary, p.tau_low, p.tau_high)
        return cells, primary, vfh.masked_histogram(self._binary, cells, theta, self.r_turn, self.r_rs)

    def avoid(self, beliefs, obstacles, request) -> Avoidance:
        p = self.vfh
        theta = beliefs.odometry.theta
        t = beliefs.target
        reach = math.hypot(*t) + self.r_rs if p.clip_at_target and t is not None else math.inf
        cells, primary, masked = self.histograms(obstacles, theta, reach)
        heading = int(vfh.sector_of(theta, self.n))
        wanted = request.heading if request is not None else None
        target = int(vfh.sector_of(theta + wanted, self.n)) if wanted is not None else heading
        runs = vfh.openings(masked)
        cands = vfh.candidates(runs, target, p.wide_sectors, self.n)
        info = {
            "target_sector": target,
            "openings": len(runs),
            "candidates": len(cands),
            "density_ahead": float(primary[heading]),
            "density_max": float(primary.max()),
            "blocked_sectors": int(masked.sum()),
            "target_blocked": bool(masked[target]),
        }
        if request is None or request.speed <= 0.0:
            self._previous = None
            return Avoidance(None, 0.0, info | {"chosen_sector": -1})
        if not cands:  # boxed in: no direction of its own; the request goes to navcli's execution (ours)
            self._previous = None
            return Avoidance(None, 0.0, info | {"chosen_sector": -1})
        chosen = vfh.choose(cands, target, heading, self._previous, self.mu, self.n)
        self._previous = chosen
        turn = wrap_angle(chosen * self.alpha - theta)
        speed = self.max_speed * vfh.speed_factor(float(primary[heading]), p.slow_density, p.min_speed)
        info |= {"chosen_sector": chosen, "turn_deg": math.degrees(turn)}
        agrees = (
            abs(wrap_angle(turn - request.heading)) <= self.alpha and speed >= min(request.speed, self.max_speed) - 1e-9
        )
        if agrees:
            return Avoidance(None, 0.0, info)  # the request is VFH+'s own choice: let it through
        return Avoidance(Move(turn, speed), self.params.bid_cap, info)


def _distance(o) -> float:
    """From the robot (the origin) to the obstacle's segment, m."""
    (ax, ay), (bx, by) = o.a, o.b
    dx, dy = bx - ax, by - ay
    t = 0.0 if dx == dy == 0 else max(0.0, min(1.0, -(ax * dx + ay * dy) / (dx * dx + dy * dy)))
    return math.hypot(ax + t * dx, ay + t * dy)
