"""The Pilot: the only system that moves the robot (pilot paper, sections 2-4).

Every tick the Pilot (1) proposes its own motion with a bid (obstacle avoidance, reflexes) and
its look-ahead camera bid, and (2) executes whichever motion bid won the arbiter: its own or the
Navigation system's. This module holds what every pilot shares:

- **execution** of a winning :class:`Move` (section 4: "the Pilot executes the turn of the
  winning bid"): the speed and the turn commanded together, by default, as a Pioneer's velocity
  and heading commands are (``pilot.drive_while_turning``; 0 stops to turn above
  ``turn_in_place``), with the section 3.5 rule that a turn larger than 160 degrees is driven
  backwards (turning the complement) while the total distance driven backwards that way stays
  under ``max_backward``; and the section 2 rule that the Pilot implements the Navigation
  system's requests "if they are safe" (our reading, :meth:`Pilot._path_clear`): a request whose
  turn and stopping distance would bring the body within ``arc_margin`` of a known obstacle is
  replaced by the Pilot's own move, and any large turn (above ``turn_in_place``) whose arc at
  speed would is made on the spot;
- **reflexes** (section 3.5): on a bumper hit, stop, look around, back up ``backup_distance``
  (drive forward from a contact behind), then recompute with the obstacle that was hit (which
  the visual memory now holds); the same reflex when the robot stalls, pushing without moving
  (over the time it takes to drive ``stall_window_m`` at full speed, so a slow robot is not
  taken for a stalled one);
- the **look-ahead camera bid** (eq. 1): ``(d_l / d_m) ** s``, at most ``look_cap`` (1: eq. 1 as
  written). ``d_m`` is "the maximum distance allowed to travel without looking ahead", so the bid
  reaches 1 there and the Pilot's look wins the camera (ties go to the Pilot). The 0.9 of eq. 9
  caps the Pilot's motion bid, so that another system may overrule its driving; capping the look
  with it too (``look_cap`` 0.9) lets the Risk Manager's looks, bid above 0.9
  whenever the risk passes ``R_bar``, keep the Pilot from ever looking ahead, which matters where
  only a look for obstacles finds obstacles (:mod:`navcli.vision.routines`): on paper-8x8 the
  geometric pilot takes 480 s with the cap, 270 s without (10 seeds). So the look is the one bid of
  the Pilot that may pass :data:`navcli.params.PILOT_CEILING`; ``look_cap`` 0.9 honours the
  ceiling.

The avoidance strategies subclass :class:`Pilot` and implement :meth:`Pilot.avoid`:
:mod:`navcli.pilot.potential_field` (the paper's pilot) and :mod:`navcli.pilot.geometric` (the
baseline). Everything the Pilot learns comes in its :class:`~navcli.beliefs.Beliefs` (the memory's
obstacles, odometry, the image taken last tick, the bumps of last tick) and the Navigation
system's request; everything it decides goes out in its :class:`PilotOutput` and wheel command.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any, ClassVar, Final

import numpy as np
from mypy_extensions import mypyc_attr

from ..beliefs import Beliefs, Bump, KnownObstacle
from ..bidding import SYSTEMS, Bid, Look, Move, looked_at
from ..geometry import Pose, distance_to_segment, motion_between, wrap_angle
from ..params import CONTROL_DT, PILOT, ROBOT, ParamSet, PilotParams, RobotParams


class Avoidance:
    """An avoidance strategy's proposal: the move, its bid, and the quantities that explain it
    (what :meth:`Pilot.avoid` returns). Made every tick: a plain class with its own ``__init__``,
    which the compiled build makes native (docs/design.md, "Values made every tick"); it compares
    by its fields, which are not reassigned.

    Attributes:
        move: the move it proposes (heading in rad, speed in m/s, at most the pilot's
            ``max_speed``), or None for none: the Navigation system's request is carried out.
        bid: its bid for the wheels, in [0, ``params.bid_cap``]; 0 offers nothing, as None does.
        info: the quantities behind it, logged on ``/pilot`` each tick: keys among ``/pilot``'s
            fields (navcli's and the class's ``Info``'s), each value of its field's type, a number
            a finite ``float`` or ``int`` (a numpy scalar is not one: ``float(x)`` makes one).
        arrows: force vectors drawn in ``/robot/scene``, egocentric: ``(name, fx, fy)``.
    """

    def __init__(
        self,
        move: Move | None,
        bid: float,
        info: dict[str, Any],
        arrows: list[tuple[str, float, float]] | None = None,
    ) -> None:
        self.move: Final = move
        self.bid: Final = bid
        self.info: Final = info
        self.arrows: Final[list[tuple[str, float, float]]] = [] if arrows is None else arrows

    def _values(self) -> tuple[object, ...]:
        return (self.move, self.bid, self.info, self.arrows)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Avoidance) and self._values() == other._values()

    def __repr__(self) -> str:
        return f"Avoidance(move={self.move!r}, bid={self.bid!r}, info={self.info!r}, arrows={self.arrows!r})"


class PilotOutput:
    """What the pilot decided this tick, and why.

    ``bids`` go to the arbiter; ``info`` is the JSON-ready explanation logged on ``/pilot``
    (forces, turn angle, IN_DISTRESS, mode); ``arrows`` are egocentric force vectors
    ``(name, fx, fy)`` drawn in ``/robot/scene``; ``events`` are reports to the Navigation system;
    ``obstacles`` what the pilot avoided this tick, egocentric; ``blocked_by`` the long obstacle
    reported to the Navigation system as not easily avoided. A plain class, as :class:`Avoidance`.
    """

    def __init__(
        self,
        bids: list[Bid],
        info: dict[str, Any],
        arrows: list[tuple[str, float, float]] | None = None,
        events: list[str] | None = None,
        obstacles: tuple[KnownObstacle, ...] = (),
        blocked_by: str | None = None,
    ) -> None:
        self.bids: Final = bids
        self.info: Final = info
        self.arrows: Final[list[tuple[str, float, float]]] = [] if arrows is None else arrows
        self.events: Final[list[str]] = [] if events is None else events
        self.obstacles: Final = obstacles
        self.blocked_by: Final = blocked_by

    def _values(self) -> tuple[object, ...]:
        return (self.bids, self.info, self.arrows, self.events, self.obstacles, self.blocked_by)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, PilotOutput) and self._values() == other._values()

    def __repr__(self) -> str:
        return "PilotOutput" + repr(self._values())


MODES = ("avoid", "idle", "reflex")
"""What a pilot does in a tick, as ``/pilot.mode`` says: proposes a move of its own, proposes none (the
Navigation system's request is carried out), or runs a reflex (section 3.5, after a bump or a stall)."""
PHASES = ("stop", "look", "backup", "done")
"""The phases of a reflex (section 3.5), as ``/pilot.phase`` says."""
SAFE_STEP = math.radians(15.0)  # rad between the headings :meth:`Pilot._nearest_safe` tries
SAFE_STEPS = 12  # each way: up to a half turn
LOOK_AHEAD = Look(0.0, "obstacles")  # the look-ahead of eq. 1 (a value: one serves every tick)
BIDDER = SYSTEMS[0]  # the name the Pilot's bids go by, navcli's: never a plugin's own attribute
MAX_STALL_WINDOW_S = 30.0  # s: the stall watch's longest window (0.6 m takes 60 s at 1 cm/s)


@mypyc_attr(allow_interpreted_subclasses=True)  # compiled (navcli.builds); plugins subclass it
class Pilot:
    """Shared pilot machinery (see the module docstring); ``avoid`` proposes nothing here.

    A pilot of one's own subclasses this and implements :meth:`avoid` (the tutorial "Your own
    pilot" builds one); navcli makes it with the run's parameters, and it keeps them as
    attributes it may read in :meth:`avoid`.

    Args:
        params: navcli's pilot parameters (``pilot.*``).
        robot: the robot's parameters (``robot.*``).
        own_params: an instance of the class's ``Params`` with the run's overrides; None without one.
        rng: the run's generator for plugins, seeded from the run's seed.

    Attributes:
        params: navcli's pilot parameters (``pilot.*`` in the parameters' reference), such as
            ``params.bid_cap``, the highest bid a pilot's move may have (0.9, eq. 9).
        robot: the robot's parameters (``robot.*``): ``robot.radius`` (m), ``robot.max_speed``
            (m/s) ...
        max_speed: the fastest a move may drive (m/s): ``robot.max_speed``.
        own_params: the plugin's own parameters (an instance of its class's ``Params``, a
            :class:`~navcli.params.ParamSet`, with the run's overrides: ``--param NAME.x=...``),
            or None without a ``Params``.
        rng: the run's generator for plugins: draw from it, never from a global one, so that the
            same seed gives the same run (None outside a run).
    """

    name = "pilot"  # the system's name; its bids go by BIDDER, whatever a subclass sets here
    Params: ClassVar[type[ParamSet] | None] = None
    """A plugin's own parameters (a :class:`~navcli.params.ParamSet` dataclass), or None."""
    Info: ClassVar[Any] = None
    """A plugin's ``msgspec.Struct`` of the fields its :meth:`avoid` adds to ``/pilot``, or None."""

    def __init__(
        self,
        params: PilotParams = PILOT,
        robot: RobotParams = ROBOT,
        *,
        own_params: ParamSet | None = None,
        rng: np.random.Generator | None = None,
    ):
        self.own_params = own_params
        self.rng = rng
        self.params = params
        self.max_speed = robot.max_speed
        self.robot = robot
        self.backup_speed = min(params.backup_speed, robot.max_speed)  # m/s: the reflex backs up at most at full speed
        # s: a slow robot backs up slowly, so its backup phase is given twice the time backing up takes
        self._backup_limit_s = max(params.reflex_phase_limit_s, 2.0 * params.backup_distance / self.backup_speed)
        self.backward = 0.0  # m commanded backwards by section 3.5's backward turns, in total
        self.since_look = 0.0  # d_l of eq. 1, metres
        self.travelled = 0.0  # metres driven (by odometry), forwards and backwards, outside reflexes
        self._reflex: list[tuple[str, float]] = []  # pending reflex phases (name, amount)
        self._reflex_progress = 0.0
        self._reflex_dir = -1.0  # the reflex backs up (-1) or, from a contact behind, drives forward (+1)
        self._phase_ticks = 0  # ticks spent in the current reflex phase
        self._events: list[str] = []
        # what the avoidance finds blocking, for how many ticks, and where (odometry) that began, with
        # the obstacle's direction there: (x, y, ux, uy)
        self._blocking: tuple[str | None, int, tuple[float, float, float, float] | None] = (None, 0, None)
        self._last_odom: Pose | None = None
        self._obstacles: tuple[KnownObstacle, ...] = ()
        self._own: Move | None = None
        self._last_v = 0.0  # the forward speed last commanded, m/s
        self._drive_v = 0.0  # the speed the drive can have reached, at its acceleration limit, m/s
        self._drivable_m = 0.0  # and the metres it could cover with the last command
        # s; at most MAX_STALL_WINDOW_S, so a crawling robot's window stays a few hundred ticks
        self.stall_window_s = min(robot.time_to_drive(params.stall_window_m), MAX_STALL_WINDOW_S)
        self._report_s = robot.time_to_drive(params.blocked_report_m)  # s: see _report
        window = max(1, round(self.stall_window_s / CONTROL_DT))
        self._commanded: deque[float] = deque(maxlen=window)  # m commanded per tick, over the stall window
        self._moved: deque[float] = deque(maxlen=window)  # m measured per tick, over the stall window
        # build the explanation (``/pilot``'s fields, the force arrows), which only a log or an observer
        # reads; without it ``info`` holds only what decisions read (``blocked_by``): Mission sets it
        self.explains = True

    # -- to be provided by the strategies
    def avoid(self, beliefs: Beliefs, obstacles: tuple[KnownObstacle, ...], request: Move | None) -> Avoidance:
        """The strategy's own move this tick (outside reflexes); here, none. A plugin's is called
        through :mod:`navcli.plugins.boundary`, which checks what it returns.

        Args:
            beliefs: what the robot believes (egocentric: x ahead, y to the left); ``beliefs.target``
                is the current target, a diverting one while the Rescuer holds one.
            obstacles: the obstacles the robot knows (its visual memory, bumped ones included):
                ``beliefs.obstacles``.
            request: the Navigation system's motion request, or None.

        Returns:
            The proposal: a :class:`~navcli.bidding.Move` (heading in rad, speed at most
            :attr:`max_speed`) with a bid in [0, ``params.bid_cap``] (0 or no move: the request is
            carried out, when it is safe), and ``info``, the quantities behind it for ``/pilot``
            (its fields, or the class's ``Info``'s), every number a finite ``float`` or ``int``.
        """
        return Avoidance(None, 0.0, {})

    # -- per tick
    def decide(self, beliefs: Beliefs, request: Move | None = None) -> PilotOutput:
        """The pilot's bids for this tick; ``request`` is the Navigation system's motion request."""
        if beliefs.looked is not None:
            self._looked(beliefs.looked)
        self._bumped(beliefs.bumps)
        self._track(beliefs.odometry)
        self._watch_for_stall(beliefs.touching)
        events, self._events = self._events, []
        obstacles = beliefs.obstacles  # the visual memory, bumped obstacles included
        self._obstacles = obstacles  # what the execution's swept-arc check (``drive``) tests against
        look = self.look_bid()
        if self._reflex:
            self._blocking = (None, 0, None)
            self._own = None  # no move of its own to carry out instead: an unsafe request turns on the spot
            return self._reflex_output(look, events, obstacles)
        a = self.avoid(beliefs, obstacles, request)
        self._own = a.move  # what the execution carries out instead of a request that is not safe
        bids = [Bid(BIDDER, "camera", LOOK_AHEAD, look)] if look > 0 else []
        offers = a.move is not None and a.bid > 0.0  # a bid of 0 is not offered: it would drive a silent robot
        info = (
            {"mode": "avoid" if offers else "idle", "bid": a.bid, "look_bid": look} | a.info
            if self.explains
            else a.info
        )
        if offers and a.move is not None:
            bids.insert(0, Bid(BIDDER, "motion", a.move, a.bid))
        return PilotOutput(
            bids, info, a.arrows, events, obstacles, self._report(a.info.get("blocked_by"), beliefs.odometry, obstacles)
        )

    def _report(self, blocked: str | None, odom: Pose, obstacles: tuple[KnownObstacle, ...]) -> str | None:
        """The long obstacle to report as not easily avoided (our reading of the thesis' blocked
        situation): the one the avoidance has found blocking, in a row, for as long as the robot
        takes to drive ``blocked_report_m`` at full speed, while it got along the obstacle less
        than a third of that: held in front of it, going back and forth toward it and away. A
        robot rounding the obstacle's end, led away from its target for a while, moves along it
        and is not reported."""
        key, ticks, since = self._blocking
        if blocked is None or self.params.blocked_report_m == 0.0:
            self._blocking = (None, 0, None)
            return None
        if blocked != key:
            o = next(o for o in obstacles if o.key == blocked)
            along = odom.theta + math.atan2(o.b[1] - o.a[1], o.b[0] - o.a[0])  # its direction, odometry frame
            ticks, since = 0, (odom.x, odom.y, math.cos(along), math.sin(along))
        ticks += 1
        if ticks * CONTROL_DT >= self._report_s - 1e-9:
            self._blocking = (None, 0, None)  # a new report takes another window
            assert since is not None  # set when the obstacle was first found blocking
            x, y, ux, uy = since
            held = abs((odom.x - x) * ux + (odom.y - y) * uy) < self.params.blocked_report_m / 3
            return blocked if held else None
        self._blocking = (blocked, ticks, since)
        return None

    def look_bid(self) -> float:
        """Eq. 1: ``(d_l / d_m) ** s``, never above ``look_cap``; 0 without ``looks``.

        Returns:
            The Pilot's bid for a look ahead, in [0, ``look_cap``].
        """
        p = self.params
        if not p.looks:
            return 0.0
        return min(p.look_cap, float((self.since_look / p.look_d_max) ** p.look_exponent))

    def _looked(self, look: Look) -> None:
        """Vision carried out ``look``; a look for obstacles near ahead resets d_l of eq. 1 (a look
        another agent won for another purpose did not look for obstacles)."""
        if look.purpose in ("obstacles", "everything") and abs(look.pan) < self.params.look_ahead_cone:
            self.since_look = 0.0
        if self._reflex and self._reflex[0][0] == "look":
            pans = self.params.reflex_look_pans_deg
            want = Look(math.radians(pans[min(int(self._reflex_progress), len(pans) - 1)]), "obstacles")
            if looked_at(look, want):  # an image someone else asked for is not its look
                self._reflex_progress += 1

    def _track(self, odom: Pose) -> None:
        """What the pilot keeps from its odometry: the distance since the last look ahead, a
        reflex's progress, and the commanded-against-measured motion the stall watch compares."""
        last, self._last_odom = self._last_odom, odom
        if last is None:
            return
        ds, _ = motion_between(last, odom)
        self.since_look += abs(ds)
        if self._reflex:
            if self._reflex[0][0] == "backup":
                self._reflex_progress += ds * self._reflex_dir
            self._forget_motion()  # a reflex that cannot move is given up by its phase limit instead
        else:
            self.travelled += abs(ds)
            self._commanded.append(self._drivable_m)
            self._moved.append(abs(ds))

    # -- reflexes (section 3.5) and the stall watch (our design)
    def _bumped(self, bumps: tuple[Bump, ...]) -> None:
        """Bumper contacts that began last tick: start the reflex, away from the contact.

        The obstacle that was hit goes to the visual memory (perception hears of the bumps too),
        so the recomputed forces include it. A contact behind the robot (it backed into
        something) is escaped forwards; the paper's reflex backs up from a contact ahead."""
        if bumps:
            behind = abs(bumps[0].bearing) > math.pi / 2
            self._start_reflex(
                +1.0 if behind else -1.0,
                f"reflex: bumper hit at bearing {math.degrees(bumps[0].bearing):.0f} deg; "
                f"stopping, looking around, {'driving forward' if behind else 'backing up'}",
            )

    def _watch_for_stall(self, touching: bool) -> None:
        """No silent stall (our design; the paper's reflex fires on a new bump only, and a contact
        that lasts is no new bump): when, over the last ``stall_window_s`` (the time to drive
        ``stall_window_m`` at full speed), the pilot commanded at
        least ``stall_min_distance`` of driving but odometry measured less than ``stall_progress``
        of it, the robot is pushing against something (or wedged): the reflex starts, escaping
        opposite to the way the robot was pushing."""
        p = self.params
        if self._reflex or len(self._moved) < (self._moved.maxlen or 1):
            return
        commanded = sum(self._commanded)
        moved = sum(self._moved)
        if commanded >= p.stall_min_distance and moved < p.stall_progress * commanded:
            self._start_reflex(
                +1.0 if self._last_v < 0 else -1.0,
                f"reflex: stalled ({'bumper pressed, ' if touching else ''}commanded {commanded:.2f} m "
                f"in {self.stall_window_s:g} s, moved {moved:.2f} m)",
            )

    def _forget_motion(self) -> None:
        self._commanded.clear()
        self._moved.clear()

    def _start_reflex(self, direction: float, message: str) -> None:
        p = self.params
        self._reflex = [
            ("stop", p.reflex_stop_s),
            ("look", float(len(p.reflex_look_pans_deg))),
            ("backup", p.backup_distance),
        ]
        if not p.looks:
            del self._reflex[1]  # no looks around: the camera is not the Pilot's
        self._reflex_progress = 0.0
        self._reflex_dir = direction
        self._phase_ticks = 0
        self._forget_motion()
        self._events.append(message)

    def _reflex_output(self, look: float, events: list[str], obstacles: tuple[KnownObstacle, ...]) -> PilotOutput:
        p = self.params
        while self._reflex and (
            self._reflex_progress >= self._reflex[0][1] - 1e-9
            or self._phase_ticks * CONTROL_DT >= self._phase_limit(self._reflex[0][0])
        ):
            self._reflex.pop(0)  # done, or given up (backing into something, the camera kept busy)
            self._reflex_progress = 0.0
            self._phase_ticks = 0
        self._phase_ticks += 1
        if not self._reflex:
            events.append("reflex done: recomputing with the obstacle that was hit")
            return PilotOutput([], self._reflex_info("done", 0.0, look), [], events, obstacles)
        phase = self._reflex[0][0]
        if phase == "stop":
            self._reflex_progress += CONTROL_DT  # this tick is spent standing still
        speed = self._reflex_dir * self.backup_speed if phase == "backup" else 0.0
        bids = [Bid(BIDDER, "motion", Move(0.0, speed), p.bid_cap)]
        if phase == "look":
            pan = math.radians(p.reflex_look_pans_deg[int(self._reflex_progress)])
            bids.append(Bid(BIDDER, "camera", Look(pan, "obstacles"), p.bid_cap))
        elif look > 0:
            bids.append(Bid(BIDDER, "camera", LOOK_AHEAD, look))
        return PilotOutput(bids, self._reflex_info(phase, p.bid_cap, look), [], events, obstacles)

    def _reflex_info(self, phase: str, bid: float, look: float) -> dict[str, Any]:
        """``/pilot``'s fields in a reflex; none unexplained."""
        return {"mode": "reflex", "phase": phase, "bid": bid, "look_bid": look} if self.explains else {}

    def _phase_limit(self, phase: str) -> float:
        """Seconds after which a reflex phase that cannot finish is given up."""
        return self._backup_limit_s if phase == "backup" else self.params.reflex_phase_limit_s

    # -- execution
    def execute(self, winner: Bid | None) -> tuple[float, float]:
        """Wheel command (v m/s, omega rad/s) that carries out the winning motion bid.

        Section 3.5: a turn larger than ``backward_turn`` is driven backwards, turning the
        complement, while the total distance commanded backwards this way stays under
        ``max_backward`` (the paper's "total distance covered backwards"; counted as commanded, so
        pushing blind against something spends it too).

        Args:
            winner: the bid that won the wheels, the Pilot's or the Navigation system's (None: no bid).

        Returns:
            The wheel command: forward speed (m/s) and turn rate (rad/s).
        """
        v, omega = 0.0, 0.0
        if winner is not None and isinstance(winner.action, Move):
            move = winner.action
            p = self.params
            backward = abs(move.heading) > p.backward_turn and move.speed > 0 and self.backward < p.max_backward
            if backward:
                move = Move(wrap_angle(move.heading - math.pi), -move.speed)  # back up, turn the complement
            v, omega = self.drive(move, requested=winner.bidder != BIDDER)
            if backward and v < 0.0:  # (the Pilot's own move, carried out instead, may go forwards)
                self.backward += -v * CONTROL_DT
        self._last_v = v
        self._drivable_m = self._drivable(v)
        return v, omega

    def _drivable(self, v: float) -> float:
        """Metres the drive can cover this tick when commanded ``v``: it reaches a new speed at most
        at ``max_accel``, as :meth:`navcli.world.World.step` limits it (over the whole tick here,
        step by step there: the same speed at the tick's end). Our design: the stall watch compares
        motion with this, not with the bare command, so a robot starting from a standstill, which
        lags its command, is not stalled."""
        a = self.robot.max_accel * CONTROL_DT
        before = self._drive_v
        self._drive_v = before + max(-a, min(a, v - before))
        return abs(before + self._drive_v) / 2 * CONTROL_DT

    def _path_clear(self, v: float, omega: float, err: float, ahead: float = 0.0, samples: int = 6) -> bool:
        """Does driving at ``v`` (m/s) while turning at ``omega`` (rad/s) until the heading error
        ``err`` (rad) is gone, and then ``ahead`` metres straight on, keep the body clear of every
        known obstacle by ``arc_margin``?

        Our design, the paper's Pilot implementing a motion "if it is safe" (section 2): a large
        turn at speed sweeps an arc of radius v / omega (0.19 m at 0.3 m/s and 90 deg/s), which
        beside a fence swings the robot into it; and the Navigation system's request to head for
        a target behind a fence drives straight into it. Tested at ``samples`` points of the arc
        (the last where the turn ends) and two of the straight run, egocentric (the robot at the
        origin heading along x)."""
        obstacles = self._obstacles
        if not obstacles:
            return True
        r = v / omega if omega else 0.0
        phi_end = omega * abs(err / omega) if omega else 0.0
        points = (
            [
                (r * math.sin(phi_end * k / samples), r * (1.0 - math.cos(phi_end * k / samples)))
                for k in range(1, samples + 1)
            ]
            if omega
            else [(0.0, 0.0)]
        )
        if ahead:
            ex, ey = points[-1]
            h = err if omega else 0.0
            step = math.copysign(ahead, v) / 2
            points += [(ex + step * k * math.cos(h), ey + step * k * math.sin(h)) for k in (1, 2)]
        clear = self.robot.radius + self.params.arc_margin
        for p in points:
            for o in obstacles:
                d = math.hypot(p[0] - o.a[0], p[1] - o.a[1]) if o.a == o.b else distance_to_segment(p, o.a, o.b)
                if d - o.radius < clear:
                    return False
        return True

    def _stopping(self, v: float) -> float:
        """Metres the robot covers at ``v`` before it can stand: a tick's reaction and the braking
        at ``max_accel`` (0.12 m at 0.3 m/s and 0.5 m/s^2)."""
        return v * v / (2.0 * self.robot.max_accel) + abs(v) * CONTROL_DT

    def drive(self, move: Move, requested: bool = False, instead: bool = True) -> tuple[float, float]:
        """Heading servo: turn toward ``move.heading`` at ``heading_gain`` per radian of error.

        With ``drive_while_turning`` (the default) the move's speed is commanded as it is, with the
        turn: the paper's Pilot "executes the turn of the winning bid" and sets a speed (section
        3.5 sets it negative for the largest turns), and states no stop to turn; a Pioneer is
        driven this way, by a velocity and a heading command that its controller carries out
        together. Without it (0), the robot stops to turn above ``turn_in_place`` and slows by
        cos(error) below (navcli's execution before, kept as an option: it makes every large turn
        cost time at any speed). Either way, with ``safe_execution``, a ``requested`` move (the
        Navigation system's) whose path is not clear (:meth:`_path_clear`, with the stopping
        distance) is replaced by the Pilot's own move, if ``instead`` and it has one and that one
        drives, else by the nearest heading whose path is clear (:meth:`_nearest_safe`), else
        turned on the spot; any move of its own turning more than ``turn_in_place`` whose arc is
        not clear is turned on the spot.

        Args:
            move: the move to carry out.
            requested: the move is the Navigation system's (checked with the stopping distance).
            instead: an unsafe requested move may be replaced by the Pilot's own move.

        Returns:
            The wheel command: forward speed (m/s) and turn rate (rad/s).
        """
        err = move.heading
        v, omega = self._servo(err, move.speed)
        check = self.params.safe_execution and (abs(err) > self.params.turn_in_place or requested)
        if v and check and not self._path_clear(v, omega, err, self._stopping(v) if requested else 0.0):
            if requested and instead:  # the paper's "if they are safe": else
                if self._own is not None:
                    own = self.drive(self._own, instead=False)  # the Pilot's own move
                    if own[0]:
                        return own
                safe = self._nearest_safe(move) if self.params.nearest_safe else None  # or the nearest safe heading
                if safe is not None:
                    return safe
            return 0.0, omega  # turning on the spot is always safe
        return v, omega

    def _servo(self, err: float, speed: float, slow: bool = True) -> tuple[float, float]:
        """The command for a heading error ``err`` (rad) at ``speed`` (m/s): the turn at
        ``heading_gain`` per radian, within the turn-rate limit; the speed as it is with
        ``drive_while_turning``, else none above ``turn_in_place`` and, with ``slow``, times
        cos(err) below."""
        p, max_w = self.params, self.robot.max_turn_rate
        omega = max(-max_w, min(max_w, p.heading_gain * err))
        if p.drive_while_turning:
            return speed, omega
        if abs(err) > p.turn_in_place:
            return 0.0, omega
        return (speed * math.cos(err) if slow else speed), omega

    def _nearest_safe(self, move: Move) -> tuple[float, float] | None:
        """The command toward the heading nearest the requested ``move``'s whose path, with the
        stopping distance, is clear (headings ``SAFE_STEP`` apart, each way, up to a half turn;
        one to turn to on the spot first, without ``drive_while_turning``), or None (our design:
        a robot whose request and own move were both unsafe stood still for good, facing its
        target past a landmark it would have grazed; a mobile robot's controller takes the
        admissible heading nearest the one wanted)."""
        for k in range(1, SAFE_STEPS + 1):
            for side in (1.0, -1.0):
                err = wrap_angle(move.heading + side * k * SAFE_STEP)
                v, omega = self._servo(err, move.speed, slow=False)
                if not v:
                    return 0.0, omega
                if self._path_clear(v, omega, err, self._stopping(v)):
                    return v, omega
        return None
