"""The Rescuer: recovers from blocked situations and from losing the target (notes, section 2;
thesis nodes 43 and 79-81).

What the thesis says, and how we do it:

- **Initial sweep** at the start: stop and look around (the pans of ``scan_pans_deg``).
- **Lost** (``I_a > I_a_bar``): stop and scan. Our design: a scan that leaves the target lost is
  followed by a turn of a random angle (the pan unit cannot look behind) and another scan; after
  ``LOST_SCANS`` such scans the Rescuer asks the Map Manager for a way toward where the target is
  believed to be (its belief's centre), as when blocked: what hides a target is most often a long
  obstacle, and scanning on where the robot stands shows it nothing new (inside a U of fences,
  a robot that only scans does so until it gives up). No failure is counted.
- **Blocked**: the robot makes no progress toward its target (``blocked_progress`` metres closer
  within the blocked window), or it hits something ``blocked_bumps`` times within that window
  (the Pilot's report of an obstacle it cannot easily avoid), or it **stalls** (``stall_rule``,
  our design): its net displacement over the last ``W`` seconds, ``W = max(stall_window_s,
  stall_window_m / robot.max_speed)`` (20 s, 1.5 m: 30 s at 5 cm/s), is less than
  ``stall_progress`` (0.3 m). Net displacement bounds how much closer the robot came to any
  target, whatever path it drove: a potential field in a minimum, swinging between a box and a
  post with its turn flipping each decision, drives on and never bumps, but stays where it was,
  and the long window (12 m: 240 s at 5 cm/s) would leave it there for minutes. It also stalls
  when over ``stall_approach`` (2) stall windows it came less than ``stall_progress`` closer to
  its current target, whatever its displacement (a field that leads it away along a wall). The pilot
  paper's diverting targets are there "to escape from a difficult or blocked position". The
  stall window restarts at every change of state (the sweep, scans, turns and drives out are
  deliberate), every new target and every bump (the Pilot's reflex stops and looks around). The Rescuer asks the Map Manager for
  a **diverting target**, a pair of landmarks to pass between, and broadcasts it as the current
  target (the Pilot crosses it through its safe corridor). When it is crossed the original target
  is restored. If none can be computed, the Rescuer **explores** (our design, after MLL): it
  turns to a random heading within half of ``random_turn_deg`` of the one away from the target,
  drives up to ``explore_m`` that way looking around until it sees a landmark it did not know
  (what hides the landmarks from where it is blocked is a long obstacle; they are back the way
  it came), scans for landmarks, then, blocked again, asks again with what was learned; this is
  no failure. When the map has none because the target lies in the robot's own region (its way
  is straight; ``turn_when_here``), the Rescuer only turns by a random angle, as the thesis'
  Rescuer does with no diverting target: driving away would only lengthen the way, and the turn
  takes a potential field out of its minimum (a lost target is explored for: what hides it is
  most often a long obstacle). Once a diverting target is crossed, the original target in sight (no known long
  obstacle across the straight way to it, ``sight_ends_way``) ends the way. If one is not crossed within
  the diverting timeout (or the robot is blocked again on the way), its edge is reported blocked
  to the Map Manager and another is asked for. So is the edge of one that was crossed when the
  robot is next blocked before anything else happened (our design: crossing it leads nowhere, and
  asking again would only send the robot back and forth across it).
  One abandoned for bumps is followed by a drive out (exploring, above) before the map, told of the
  failure with that request, is asked again from where the robot then is (ours: a robot caught
  between a landmark and a wall is led back into the pocket by each next way, 10-31 contacts).
- **Windows in distance** (ours): the blocked window and the diverting timeout are given as
  distances (``blocked_window_m``, ``diverting_timeout_m``) and last as long as the robot takes
  to drive them at full speed (:meth:`~navcli.params.RobotParams.time_to_drive`), and at least
  ``MIN_WINDOW_S``: progress is about distance, so a robot at 5 cm/s is given six times the
  seconds of one at 30 cm/s, and is never declared blocked for being slow.
- **The learning paper's task** (``rescuer_looks`` 0, ``blocked_ends`` 1): no looks at all (no
  sweep, no scans: the camera is the Learning Agent's; a lost target is left to it), and the
  first blocked situation ends the mission ``blocked`` (its trials "terminate ... if the robot
  is blocked"). "The robot can be blocked by the landmarks or by the wall": ``blocked_bumps``
  bumps within the blocked window, or the Pilot's report of an obstacle it cannot easily avoid,
  end it. No progress toward the target within the window is no blocked situation there
  (``blocked_no_progress`` off in that task's preset): nothing stops the robot, and such a trial
  runs on, to the target, a blocked situation or its 500 actions; on, it ends it ``blocked``
  too. The stall rule, a rescue of the potential field, is not applied to its trials.
- **Never giving up** (``gives_up`` off, the default): only a diverting target tried and failed
  is a failure, and nothing ends the mission before its time limit. Where the map shows no way
  out of the robot's regions (every edge out closed by known obstacles) again after the robot
  has looked around once more with no diverting target crossed in between, the thesis' Rescuer,
  with no diverting target to compute, turns by a random angle and asks again: so does this one,
  by an angle drawn uniformly within ``random_turn_deg`` from the Navigation system's generator,
  then asks the map at once; with still none, the other agents drive on from the new heading,
  and the next blocked situation asks anew (exploring first). ``gives_up`` on ends
  the mission ``blocked`` there instead, with the reason in the outcome and the events; with it,
  ``max_diverting_failures`` set to 3 ends it at the third failure (which ends many runs in
  rooms with a way out), and bounds the looks around in a row that the map answers with no
  diverting target.

The state machine (:meth:`Rescuer.decide`) is a phase per state: the sweep, a turn, a drive out,
a look around, a lost target's scans, and normal (following a diverting target, watching for
being blocked), each answering for the tick or handing over to the next. The windows that say
the robot is blocked are kept by :class:`~.progress.Progress`; the scans and turns are
:class:`~.scanning.Scanning`'s.

The Rescuer bids ``rescuer_bid`` (1.0, our design: its actions are the emergencies of the
Navigation system, and a stop is always safe) to stop while it sweeps or scans, to look at each
pan, and to turn; it is heard first, so it wins ties. Random angles come from the run's seeded
generator.
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from ..bidding import Bid, Look, Move, looked_at
from ..geometry import ORIGIN, Point, Pose, midpoint, segments_intersect, wrap_angle
from ..params import NAVIGATION, ROBOT, NavigationParams, RobotParams
from .progress import MIN_WINDOW_S, Progress
from .scanning import STOP, Scanning
from .regions import Crossing, Edge, NoCrossing, ends
from .situation import Situation

Ask = Callable[[Edge | None], Crossing | NoCrossing | None]
"""The Rescuer's question to the Map Manager: ``ask(failed_edge)`` (see :meth:`Rescuer.decide`)."""
LOST_SCANS = 3  # scans (each followed by a random turn) before the map is asked for a way toward a lost target
STATES = ("sweep", "normal", "lost", "turn", "drive", "explore")
"""The Rescuer's states, as ``/navigation.rescuer`` says: its initial sweep, normal (no rescue), scanning
for a lost target, turning (a random angle, or away from the target to explore), driving out to explore,
exploring (looking around for landmarks it did not know)."""


class Rescue(NamedTuple):
    """The Rescuer's decision this tick: its bids, the diverting target (egocentric line, left end
    first) if one is set, events ``(level, message)``, and a reason to end the mission as blocked.
    (A NamedTuple, made every tick: see :class:`~.situation.Situation`.)"""

    bids: tuple[Bid, ...] = ()
    diverting: tuple[Point, Point] | None = None
    events: tuple[tuple[str, str], ...] = ()
    give_up: str | None = None


def _in_sight(s: Situation) -> bool:
    """Is the original target in sight on the map: known, and no known long obstacle (no wall of
    the room) across the straight way to it?"""
    aim = s.aim
    return aim is not None and not any(
        segments_intersect(ORIGIN, aim, o.a, o.b) for o in s.beliefs.obstacles if not o.is_point and not o.wall
    )


class Rescuer(Scanning):
    name = "rescuer"

    def __init__(
        self, params: NavigationParams = NAVIGATION, rng: np.random.Generator | None = None, robot: RobotParams = ROBOT
    ):
        self.params = params
        self.progress = Progress(params, robot)
        self.timeout_s = max(robot.time_to_drive(params.diverting_timeout_m), MIN_WINDOW_S)  # the diverting timeout, s
        self.speed = robot.max_speed
        self.drive_s = 2.0 * robot.time_to_drive(params.explore_m)  # the longest an exploring drive lasts, s
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.state = "sweep" if params.initial_sweep and params.rescuer_looks else "normal"
        self._scan = 0  # index into scan_pans_deg
        self._turn_to: float | None = None  # odometry-frame heading to turn to
        self._scan_after_turn = False  # exploring: the turn is followed by a drive and a scan for landmarks
        self._ask_after_turn = False  # not giving up: the random turn is followed by a request to the map
        self._drive_from: Pose | None = None  # exploring: where the drive began (odometry frame)
        self._drive_since = 0.0
        self._drive_known = 0  # landmarks known when it began: it ends when something new is seen
        self._trapped = False  # the map showed no way out at the last request: explored once since
        self._explorations = 0  # looks around in a row that the map answered with no diverting target
        self._crossing: Crossing | None = None
        self._last_crossed: Edge | None = None  # the edge of the last diverting target crossed
        self._untold: Edge | None = None  # a failed edge the map is told of with the next request
        self._lost_scans = 0  # scans in a row that did not find the lost target
        self._crossing_world: tuple[Point, Point] | None = None  # its ends in the odometry frame
        self._crossing_since = 0.0
        self._side: float | None = None  # which side of the diverting line the robot is on
        self.failures = 0
        self.tried: list[tuple[Point, Point, str]] = []  # each diverting line ended (odometry frame) and how
        self.diverting_targets = 0

    # -- the state machine
    def decide(self, s: Situation, ask: Ask) -> Rescue:
        """``ask(failed_edge)`` tells the Map Manager of the edge of a failed diverting target (if
        any) and asks it for a diverting target toward the original target (or why there is none).

        Each state's phase either answers for this tick or hands over to the next (a turn ends in
        a drive, a drive in a look around, a look around in normal)."""
        events: list[tuple[str, str]] = []
        self.progress.count_bumps(s)
        if s.I_a <= self.params.I_a_bar:
            self._lost_scans = 0  # found again, in whatever state: the next loss starts its scans afresh
        for phase in (self._sweep_phase, self._turn_phase, self._drive_phase, self._explore_phase, self._lost_phase):
            out = phase(s, events, ask)
            if out is not None:
                return out
        if (
            self.state == "normal"
            and self._crossing is None
            and s.I_a > self.params.I_a_bar
            and self.params.rescuer_looks
        ):
            self.state, self._scan = "lost", 0
            events.append(("warning", f"target lost (I_a = {s.I_a:.2f} > {self.params.I_a_bar:g}): stopping to scan"))
            return Rescue(self._scan_bids(), events=tuple(events))
        return self._normal_phase(s, events, ask)

    def _sweep_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """The initial sweep: look at each pan, then normal."""
        return self._scan_then_normal(s, events, "initial sweep done") if self.state == "sweep" else None

    def _turn_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """Turning to ``_turn_to``; then a drive out (exploring), a look around, a new request to
        the map (after the random turn that replaces giving up), or normal."""
        if self.state != "turn":
            return None
        b = s.beliefs
        assert self._turn_to is not None  # set by the turn's start
        err = wrap_angle(self._turn_to - b.odometry.theta)
        if abs(err) > math.radians(10.0):
            return Rescue((Bid(self.name, "motion", Move(err, 0.0), self.params.rescuer_bid),), events=tuple(events))
        if self._ask_after_turn:
            # the thesis' Rescuer with no diverting target: turn by a random angle and ask again;
            # with still none, the other agents drive on from the new heading, and the next
            # blocked situation asks anew (exploring first: a robot pinned against the wall
            # opposite its target drove into that wall again and again)
            self._ask_after_turn = False
            self._enter("normal", s)
            again = ask(None)
            if isinstance(again, Crossing):
                return self._divert(again, s, events)
            events.append(("info", "turned; still no diverting target: going on"))
            return Rescue(events=tuple(events))
        if not self._scan_after_turn:
            self._enter("normal", s)
            return None
        self._scan_after_turn = False
        if self.params.explore_m > 0:
            self._enter("drive", s)
            self._drive_from, self._drive_since, self._drive_known = b.odometry, s.time, len(s.landmarks)
        elif self.params.rescuer_looks:
            self._enter("explore", s)
            return Rescue(self._scan_bids(), events=tuple(events))
        else:
            self._enter("normal", s)
        return None

    def _drive_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """Exploring: drive away, looking around, until ``explore_m`` is driven, something is
        bumped or seen new, the Pilot reports a long obstacle, or the drive takes too long."""
        if self.state != "drive":
            return None
        b = s.beliefs
        o, start = b.odometry, self._drive_from
        assert start is not None  # set by the drive's start
        driven = math.hypot(o.x - start.x, o.y - start.y)
        if (
            driven < self.params.explore_m
            and not b.bumps
            and len(s.landmarks) <= self._drive_known
            and b.pilot_blocked is None
            and s.time - self._drive_since < self.drive_s
        ):
            pans = self.params.scan_pans_deg  # looking around on the way for landmarks, a pan an image
            if looked_at(b.looked, Look(math.radians(pans[self._scan % len(pans)]), "search")):
                self._scan += 1
            v = self.params.rescuer_bid
            bids: tuple[Bid, ...] = (Bid(self.name, "motion", Move(wrap_angle(start.theta - o.theta), self.speed), v),)
            if self.params.rescuer_looks:
                bids += (Bid(self.name, "camera", Look(math.radians(pans[self._scan % len(pans)]), "search"), v),)
            return Rescue(bids, events=tuple(events))
        events.append(("info", f"explored {driven:.1f} m away from the target"))
        self._enter("explore" if self.params.rescuer_looks else "normal", s)
        return None

    def _explore_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """Exploring: look around for landmarks, then normal."""
        if self.state != "explore":
            return None
        return self._scan_then_normal(s, events, f"looked around: {len(s.landmarks)} landmarks in view or remembered")

    def _scan_then_normal(self, s: Situation, events: list[tuple[str, str]], done: str) -> Rescue | None:
        """A scan: look at each pan, then normal, saying ``done``."""
        if not self._scanned(s.beliefs.looked):
            return Rescue(self._scan_bids(), events=tuple(events))
        self._enter("normal", s)
        events.append(("info", done))
        return None

    def _lost_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """The target lost: scan, turn by a random angle, scan again; after ``LOST_SCANS`` scans,
        ask the map for a way toward where the target is believed to be."""
        if self.state != "lost":
            return None
        if s.I_a <= self.params.I_a_bar:
            self._lost_scans = 0
            self._enter("normal", s)
            events.append(("info", f"target found again (I_a = {s.I_a:.2f})"))
            return None
        if not self._scanned(s.beliefs.looked):
            return Rescue(self._scan_bids(), events=tuple(events))
        self._lost_scans += 1
        if self._lost_scans >= LOST_SCANS:
            # scanning here again shows nothing new past the long obstacle that most often hides the
            # target (module docstring, "Lost"); no failure is counted
            self._lost_scans = 0
            self._enter("normal", s)
            events.append(
                (
                    "warning",
                    f"target not found in {LOST_SCANS} scans: asking the map for a way toward where it is believed to be",
                )
            )
            return self._request(s, events, ask, lost=True)
        self._start_turn(s.beliefs.odometry, events, "target still lost after a scan")
        return Rescue(events=tuple(events))

    def _normal_phase(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue:
        """No rescue under way: follow a diverting target until crossed, and watch for being blocked."""
        line = self._diverting_line(s)
        if line is not None and self._crossed(line):
            step = self._on_crossed(s, events, ask)
            if step is not None:
                return step
            line = None
        why = self._blocked(s, line)
        if why is None:
            return Rescue((), line, tuple(events))
        if self.params.blocked_ends:
            return self._end(why, events)
        return self._on_blocked(s, why, events, ask)

    def _on_crossed(self, s: Situation, events: list[tuple[str, str]], ask: Ask) -> Rescue | None:
        """The diverting target was crossed: its way's next step, if the map gives one (a Rescue),
        or back to the original target (None)."""
        crossed = self._crossing
        assert crossed is not None  # a diverting line is that of a crossing
        self._clear_crossing(s, "crossed")
        self._trapped = False  # a way out was found: the map's "no way out" before it is old news
        # the next step of the way, from the region the robot is in; with the target in sight the
        # regions' way may still go round, through virtual landmarks' regions: sight_ends_way ends it
        after = None if self.params.sight_ends_way and _in_sight(s) else ask(None)
        if isinstance(after, Crossing) and after.edge != crossed.edge:
            since = self._crossing_since
            self._set_crossing(after, s)  # the same diverting target's way, one step on: not counted again,
            self._crossing_since = since  # and its timeout runs on: the way as a whole must be done in time
            events.append(
                (
                    "info",
                    f"diverting target crossed between {crossed.left} and {crossed.right}; "
                    f"next: cross between {after.left} (left) and {after.right} (right)",
                )
            )
            return Rescue((), self._diverting_line(s), tuple(events))
        events.append(
            (
                "info",
                f"diverting target crossed between {crossed.left} and {crossed.right}: back to the original target",
            )
        )
        self._last_crossed = crossed.edge
        return None

    def _on_blocked(self, s: Situation, why: str, events: list[tuple[str, str]], ask: Ask) -> Rescue:
        """Blocked for ``why``: another way if the Pilot sees the way closed; else count the
        failed diverting target (held, or crossed and leading nowhere) and ask for a new one."""
        caught = self.progress.caught()  # (before the abandoned crossing clears them)
        tried = self._crossing.edge if self._crossing is not None else self._last_crossed
        if tried is not None and s.beliefs.pilot_blocked is not None:
            # the Pilot sees a long obstacle across the way: the map, which knows it now, may lead
            # another way, and that is no failure of the way tried (only a way driven and failed
            # counts, by bumps, no progress or time; a way seen to be closed was not driven)
            again = ask(None)
            if isinstance(again, Crossing) and again.edge != tried:
                end_u, end_v = ends(tried)
                events.append(
                    ("info", f"blocked ({why}) on the way across {end_u}-{end_v}: the map now leads another way")
                )
                self._clear_crossing(s, "replaced: the way seen closed")
                self._last_crossed = None
                return self._divert(again, s, events)
        abandoned = self._count_failure(s, why, events)
        if self.params.gives_up and 0 < self.params.max_diverting_failures <= self.failures:
            return self._give_up(f"{self.failures} diverting targets failed", events, s)
        if abandoned is not None and caught:
            # caught where it stands, a way asked from here leads back in (module docstring): drive out
            # first; the map hears of the failure with the next request, when blocked again
            self._untold = abandoned
            self._explore(s, events, "caught by bumps")
            return Rescue(events=tuple(events))
        return self._request(s, events, ask, abandoned)

    def _count_failure(self, s: Situation, why: str, events: list[tuple[str, str]]) -> Edge | None:
        """The edge of the diverting target that failed, if one did: the one held (abandoned), or
        the last one crossed, which led nowhere; counted in ``failures``."""
        if self._crossing is not None:
            self.failures += 1
            c = self._crossing
            events.append(
                (
                    "warning",
                    f"diverting target between {c.left} and {c.right} abandoned ({why}; {self.failures} failed)",
                )
            )
            self._clear_crossing(s, "abandoned")
            return c.edge
        events.append(("warning", f"blocked: {why}"))
        if self._last_crossed is None:
            return None
        self.failures += 1  # the last diverting target was crossed but led nowhere
        abandoned, self._last_crossed = self._last_crossed, None
        if self.tried and self.tried[-1][2] == "crossed":
            self.tried[-1] = (*self.tried[-1][:2], "crossed, led nowhere")
        end_u, end_v = ends(abandoned)
        events.append(("warning", f"crossing between {end_u} and {end_v} led nowhere ({self.failures} failed)"))
        return abandoned

    def _request(
        self,
        s: Situation,
        events: list[tuple[str, str]],
        ask: Ask,
        abandoned: Edge | None = None,
        lost: bool = False,
    ) -> Rescue:
        """Ask the map for a diverting target (telling it of the ``abandoned`` edge, if any) and set
        it; with none, turn (the target in the robot's region, unless it is ``lost``: what hides
        it is then most often a long obstacle), explore, or give up when the map still shows no
        way out."""
        untold, self._untold = self._untold, None
        if untold is not None and abandoned is not None:
            ask(untold)  # two failures to tell (rare): the first one's answer is not the robot's way now
        crossing = ask(abandoned if abandoned is not None else untold)
        if crossing is None or isinstance(crossing, NoCrossing):
            why = crossing.why if crossing is not None else "the map gives none"
            trapped = crossing is not None and crossing.trapped
            if trapped and self._trapped:  # no way out, still, after looking around for one
                return self._give_up(f"no way out: {why}", events, s)
            self._trapped = trapped
            if crossing is not None and crossing.here and self.params.turn_when_here and not lost:
                # the thesis' Rescuer with no diverting target: a random turn; the map knows the way
                # is straight, so driving away from the target to explore would only lengthen it
                self._turn(s, events, f"no diverting target ({why})")
                return Rescue(events=tuple(events))
            self._explorations += 1
            if (
                self.params.gives_up and 0 < self.params.max_diverting_failures < self._explorations
            ):  # looking around bounded as failures are
                return self._give_up(
                    f"the map gives no diverting target after {self._explorations - 1} looks around ({why})", events, s
                )
            self._explore(s, events, f"no diverting target ({why})")
            return Rescue(events=tuple(events))
        return self._divert(crossing, s, events)

    def _explore(self, s: Situation, events: list[tuple[str, str]], why: str) -> None:
        """Turn away from the target, then drive and look around (see the module docstring)."""
        self._turn(s, events, f"{why}; exploring", away=s.aim)
        self._scan_after_turn = True

    def _divert(self, crossing: Crossing, s: Situation, events: list[tuple[str, str]]) -> Rescue:
        """Set ``crossing`` as the diverting target, with one stop (the thesis' Rescuer wins one
        stop bid per request)."""
        self._explorations = 0
        self._set_crossing(crossing, s)
        self.diverting_targets += 1
        events.append(
            ("info", f"diverting target set: cross between {crossing.left} (left) and {crossing.right} (right)")
        )
        stop = Bid(self.name, "motion", STOP, self.params.rescuer_bid)
        return Rescue((stop,), self._diverting_line(s), tuple(events))

    def _give_up(self, why: str, events: list[tuple[str, str]], s: Situation) -> Rescue:
        """With ``gives_up``, end the mission as ``blocked`` for ``why``; without (the default),
        turn by a random angle and ask the map again once turned (the thesis' Rescuer with no
        diverting target), so the robot goes on until the time limit."""
        if self.params.gives_up:
            return self._end(why, events)
        self._trapped, self._explorations = False, 0
        self._turn(s, events, f"{why}; not giving up")
        self._ask_after_turn = True
        return Rescue(events=tuple(events))

    def _end(self, why: str, events: list[tuple[str, str]]) -> Rescue:
        """End the mission as ``blocked`` for ``why``, said in the events too."""
        events.append(("error", f"giving up: {why}"))
        return Rescue(events=tuple(events), give_up=why)

    def _enter(self, state: str, s: Situation) -> None:
        self.state, self._scan = state, 0
        self._reset_progress(s)

    # -- diverting targets
    def _set_crossing(self, c: Crossing, s: Situation) -> None:
        odo = s.beliefs.odometry
        self._crossing = c
        self._crossing_world = (odo.to_world(c.left_at), odo.to_world(c.right_at))
        self._crossing_since = s.time
        self._side = None
        self._reset_progress(s)

    def _clear_crossing(self, s: Situation, ending: str) -> None:
        if self._crossing_world is not None:
            self.tried.append((*self._crossing_world, ending))
        self._crossing = self._crossing_world = None
        self._side = None
        self._reset_progress(s)

    def _diverting_line(self, s: Situation) -> tuple[Point, Point] | None:
        """The diverting line, egocentric: its landmarks where the map puts them now (a virtual
        end where it was set, carried by odometry)."""
        if self._crossing is None:
            return None
        c, odo = self._crossing, s.beliefs.odometry
        assert self._crossing_world is not None  # set with the crossing
        ends = []
        for key, world in zip((c.left, c.right), self._crossing_world):
            p = s.landmarks.get(key)
            ends.append((p.x, p.y) if p is not None else odo.to_local(world))
        return ends[0], ends[1]

    def _crossed(self, line: tuple[Point, Point]) -> bool:
        """Has the robot (the origin) passed from one side of the line to the other, between its ends?"""
        (ax, ay), (bx, by) = line
        side = (bx - ax) * (0.0 - ay) - (by - ay) * (0.0 - ax)
        L2 = (bx - ax) ** 2 + (by - ay) ** 2
        t = ((0.0 - ax) * (bx - ax) + (0.0 - ay) * (by - ay)) / L2 if L2 > 0 else -1.0
        crossed = self._side is not None and side * self._side < 0 and 0.0 <= t <= 1.0
        if side != 0.0:
            self._side = side
        return crossed

    # -- blocked
    @property
    def window_s(self) -> float:
        """The blocked window, s."""
        return self.progress.window_s

    @property
    def stall_s(self) -> float:
        """The stall window, s."""
        return self.progress.stall_s

    def _reset_progress(self, s: Situation) -> None:
        self.progress.reset(s.time)

    def _turn(self, s: Situation, events: list[tuple[str, str]], why: str, away: Point | None = None) -> None:
        """Start a random turn (:meth:`_start_turn`) with the progress windows restarted."""
        self._start_turn(s.beliefs.odometry, events, why, away)
        self._reset_progress(s)

    def _blocked(self, s: Situation, line: tuple[Point, Point] | None) -> str | None:
        """Why the robot is blocked on its way to the current target (``line``: the diverting line,
        if one is held), or None: the Pilot reports a long obstacle ahead it cannot easily avoid
        (the thesis' blocked situation), no progress within the blocked window, too many bumps
        within it, a diverting target held too long, or a stall (not in the learning paper's
        task, whose trials end at its own blocked situations)."""
        p = self.params
        aim = s.aim if line is None else midpoint(*line)
        if aim is None:  # the learning paper's task: "blocked by the landmarks or by the wall", known target or not
            return self._stuck(s) if p.blocked_ends else None
        self.progress.came_closer(s, aim)
        held = self._stuck(s)
        if held is not None and s.beliefs.pilot_blocked is not None:
            return held  # (the Pilot's report first, then the windows, then the bumps)
        if self._crossing is not None and s.time - self._crossing_since > self.timeout_s:
            return "the diverting target was not crossed in time"
        if p.blocked_no_progress and self.progress.window_over(s):
            return "no progress toward the target"
        if held is None and p.stall_rule and not p.blocked_ends:
            return self.progress.stalled(s, aim)
        return held

    def _stuck(self, s: Situation) -> str | None:
        """Why the robot is held where it is, whatever its target: the Pilot reports a long
        obstacle ahead it cannot easily avoid, or it hit something ``blocked_bumps`` times within
        the blocked window."""
        if s.beliefs.pilot_blocked is not None:
            return f"the Pilot reports {s.beliefs.pilot_blocked} ahead, which it cannot easily avoid"
        if self.progress.caught():
            return f"{len(self.progress.bumps)} bumps"
        return None
