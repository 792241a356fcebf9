"""The Navigation system: each agent against hand-worked bids, the Communicator, the Rescuer's
states, and whole missions that need a diverting target."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np
import pytest

from navcli.analysis import read_log
from conftest import SCENARIOS
from navcli.beliefs import Beliefs, Bump
from navcli.bidding import Bid, Look, Move
from navcli.config import RunSpec
from navcli.fuzzy import ALPHAS, CUT, FuzzyPoint
from navcli.geometry import Pose, wrap_angle
from navcli.navigation import Communicator, DistanceEstimator, NavigationSystem, RiskManager, Situation, TargetTracker
from navcli.navigation.regions import Crossing
from navcli.navigation.rescuer import Rescuer
from navcli.params import CLUSTERS, NAVIGATION, PILOT, ROBOT
from navcli.runner import run_mission
from navcli.scenario import load_scenario

P = NAVIGATION  # the parameters the agents use by default; the agent tests also run with cluster C2's
CRISP = (0.0, 0.0, 0.0, 0.0)
CLUSTER = pytest.mark.parametrize("P", list(CLUSTERS.values()), ids=list(CLUSTERS))


def situation(  # noqa: PLR0913 (each field of a test's Situation a keyword with its default)
    target=(3.0, 4.0),
    I_a=0.0,
    line=None,
    landmarks=None,
    ahead=(),
    q_ahead=0.0,
    q_around=0.0,
    radii=CRISP,
    time=0.0,
    odometry=Pose(0.0, 0.0, 0.0),
    looked=None,
    bumps=(),
):
    b = Beliefs(time, odometry, target, line, (), 0.0, looked, tuple(bumps))
    t = None if target is None else FuzzyPoint(*target, radii)
    return Situation(b, t, line, "memory", I_a, landmarks or {}, ahead, q_ahead, q_around)


def bids_of(agent, s):
    return {b.resource: b for b in agent.bid(s)}


# -- Target Tracker -----------------------------------------------------------------------------
# The expected bids are worked out here from the formulas of TargetTracker's docstring (thesis eq. 6
# and the notes' bids), with the parameters read from the params object handed to the agent.
@CLUSTER
def test_a_precisely_known_target_gets_kappa1_to_move_toward_it_and_no_look(P):
    b = bids_of(TargetTracker(P, 0.3), situation())
    assert b["motion"].value == pytest.approx(P.kappa1 * (1 - 0.0) ** P.alpha)  # I_a = 0: kappa1
    assert b["motion"].action.heading == pytest.approx(math.atan2(4.0, 3.0)) and b["motion"].action.speed == 0.3
    assert "camera" not in b  # the look bid kappa2 * 0 / I_a_bar is 0: not offered


@CLUSTER
def test_the_target_trackers_imprecision_and_bids(P):
    tt = TargetTracker(P, 0.3)
    i_a = (math.pi / (2 * math.pi)) ** P.beta  # eq. 6, I_a = (eps / 2 pi) ** beta, for a half-turn cut
    assert tt.imprecision(math.pi) == pytest.approx(i_a)
    assert tt.imprecision(4 * math.pi) == 1.0  # a cut wider than a turn: lost (eps / 2 pi capped at 1)
    assert 0.0 < i_a <= P.I_a_bar  # the look bid's rising branch (both clusters)
    b = bids_of(tt, situation(I_a=i_a))
    assert b["motion"].value == pytest.approx(P.kappa1 * (1 - i_a) ** P.alpha)
    assert b["camera"].value == pytest.approx(P.kappa2 * i_a / P.I_a_bar)
    assert b["camera"].action.pan == pytest.approx(math.atan2(4.0, 3.0))
    # a cut whose I_a lies halfway between I_a_bar and 1, by eq. 6 inverted: the falling branch
    i_a = (1 + P.I_a_bar) / 2
    eps = 2 * math.pi * i_a ** (1 / P.beta)
    assert tt.imprecision(eps) == pytest.approx(i_a)
    b = bids_of(tt, situation(I_a=i_a))
    assert b["camera"].value == pytest.approx(P.kappa2 * (1 - i_a) / (1 - P.I_a_bar))
    assert b["motion"].value == pytest.approx(P.kappa1 * (1 - i_a) ** P.alpha)


def test_a_lost_target_gets_no_motion_bid_at_all():
    assert bids_of(TargetTracker(P, 0.3), situation(I_a=1.0)) == {}  # heading unknown: no bid of 0
    assert TargetTracker().bid(situation(target=None)) == []


def test_a_line_target_is_headed_for_through_the_pilots_corridor():
    m = PILOT.corridor_margin
    tt = TargetTracker(P, 0.3, m)
    # the line x = 2 runs from two margins below the robot to 5 m above it: the robot is inside its
    # corridor and heads straight across (heading 0), not for the line's middle (the target point)
    line = ((2.0, -2 * m), (2.0, 5.0))
    b = bids_of(tt, situation(target=(2.0, (5.0 - 2 * m) / 2), line=line))
    assert b["motion"].action.heading == pytest.approx(0.0)
    # beside the line's end (it starts m / 2 from the robot's side, within the margin): for its middle
    lo, hi = m / 2, 4.0
    b = bids_of(tt, situation(target=(9.0, 9.0), line=((2.0, lo), (2.0, hi))))
    assert b["motion"].action.heading == pytest.approx(math.atan2((lo + hi) / 2, 2.0))


# -- Risk Manager -------------------------------------------------------------------------------
def risk_eq9(P, q_ahead, n_ahead, q_around, n_around):
    """Thesis eq. 9 as RiskManager's docstring gives it ("+" read in for the elided operator)."""
    return 1 - min(1.0, q_ahead * (n_ahead / 6) ** P.gamma_A + q_around * (n_around / 6) ** P.gamma_B)


@CLUSTER
def test_risk_from_the_landmarks_ahead_and_around(P):
    rm = RiskManager(P)
    lm = {k: FuzzyPoint(x, y, CRISP) for k, (x, y) in {"a": (2, 1), "b": (2, -1), "c": (3, 0), "d": (-2, 0)}.items()}
    s = situation(landmarks=lm, ahead=("a", "b", "c"), q_ahead=0.5, q_around=0.8)
    want = risk_eq9(P, 0.5, 3, 0.8, 4)
    assert rm.risk(s) == pytest.approx(want)
    assert want <= P.R_bar and rm.bid(s) == []  # at or below R_bar: no bid
    # one landmark ahead, poorly spread: a risk above R_bar, bid R ** gamma_R
    few = situation(landmarks={"a": lm["a"]}, ahead=("a",), q_ahead=0.3, q_around=0.3)
    r = risk_eq9(P, 0.3, 1, 0.3, 1)
    assert rm.risk(few) == pytest.approx(r) and P.R_bar < r < 1.0
    (b,) = rm.bid(few)
    assert b.value == pytest.approx(r**P.gamma_R) and b.resource == "camera"
    lonely = situation(landmarks={"a": lm["a"]}, ahead=("a",))  # qualities 0 (one landmark): R = 1
    (b,) = rm.bid(lonely)
    assert rm.risk(lonely) == 1.0 and b.value == pytest.approx(1.0**P.gamma_R) and b.resource == "camera"
    # the least-known reachable sector: "a" is ahead-left (in the 0-degree sector); the empty +-60 ones
    # tie, the camera goes to +60 (listed first)
    assert b.action.pan == pytest.approx(math.radians(60))


# -- Distance Estimator -------------------------------------------------------------------------
@CLUSTER
def test_distance_estimator_bids_to_move_across_the_target_when_its_distance_is_imprecise(P):
    de = DistanceEstimator(P, 0.3)
    assert de.bid(situation()) == []  # the distance is known exactly: tanh(0) = 0
    radii, d = (1.0, 0.7, 0.3, 0.0), 4.0
    s = situation(target=(d, 0.0), radii=radii)
    r = radii[ALPHAS.index(CUT)]  # the 70 % cut's radius: the distance's cut is (d - r, d + r)
    b = bids_of(de, s)
    assert b["motion"].value == pytest.approx(P.kappa * math.tanh(2 * r / d))  # I_d = 2 r
    assert b["camera"].value == b["motion"].value
    assert abs(b["motion"].action.heading) == pytest.approx(math.pi / 2)  # at right angles to the target
    assert b["camera"].action.pan == pytest.approx(0.0)  # and looking at it
    assert de.bid(situation(target=(2.0, 0.0), line=((2.0, -1.0), (2.0, 1.0)), radii=radii)) == []


# -- Communicator -------------------------------------------------------------------------------
def test_the_communicators_ties_go_to_this_ticks_first_bidder_even_after_its_bids_expired():
    """The Rescuer is heard first and wins ties, also when it bids again after its earlier bids
    expired and another agent's tied bid has been held all along."""
    c = Communicator(window=0.2)
    c.forward([Bid("rescuer", "camera", Look(0.5, "scan"), 1.0)], 0.0)
    for t in (0.1, 0.2, 0.3, 0.4):  # the rescuer falls silent; the risk manager keeps bidding 1.0
        c.forward([Bid("risk-manager", "camera", Look(0.0, "search"), 1.0)], t)
    out = c.forward(
        [Bid("rescuer", "camera", Look(0.7, "scan"), 1.0), Bid("risk-manager", "camera", Look(0.0, "search"), 1.0)], 0.5
    )
    assert [b.action for b in out] == [Look(0.7, "scan")]


def test_the_communicator_keeps_each_agents_latest_bid_within_its_window():
    c = Communicator(window=0.25)
    go, stop = Move(0.0, 0.3), Move(0.0, 0.0)
    out = c.forward([Bid("tracker", "motion", go, 0.3), Bid("rescuer", "motion", stop, 0.5)], 0.0)
    assert [(b.resource, b.value, b.action) for b in out] == [("motion", 0.5, stop)]
    out = c.forward([Bid("rescuer", "motion", stop, 0.1)], 0.1)  # a later bid replaces the rescuer's 0.5
    assert [(b.value, b.action) for b in out] == [(0.3, go)]  # the tracker's, still within the window
    out = c.forward([Bid("risk", "camera", Look(1.0, "search"), 0.2)], 0.3)  # 0.3 s on: the first bids have expired
    assert {b.resource: b.value for b in out} == {"motion": 0.1, "camera": 0.2}
    assert {b.bidder for b in out} == {"navigation"}


# -- Rescuer ------------------------------------------------------------------------------------
def _sweep(r: Rescuer):
    """Carry out the initial sweep: the camera reports each look the Rescuer asks for."""
    looked, t = None, 0.0
    for _ in range(20):
        out = r.decide(situation(time=t, looked=looked), lambda failed: None)
        if r.state != "sweep":
            return t
        look = next(b for b in out.bids if b.resource == "camera")
        assert next(b for b in out.bids if b.resource == "motion").action == Move(0.0, 0.0)  # stopped
        looked, t = look.action, t + 0.1
    raise AssertionError("the sweep never ended")


def test_rescuer_sweeps_then_blocked_diverts_crosses_and_restores_the_original_target():
    p = replace(NAVIGATION, stall_rule=False)  # the long window alone (the stall rule: its own tests)
    r = Rescuer(p, np.random.default_rng(0))
    t = _sweep(r)
    assert r.state == "normal"
    asked = []
    crossing = Crossing("L", "R", (1.0, 1.0), (1.0, -1.0), 3.0)

    def ask(failed):
        asked.append(failed)
        return crossing

    # no progress toward the target (3, 4) for the whole window: blocked, a diverting target is set
    out = None
    swept = t
    while not asked:
        t += 0.1
        out = r.decide(situation(time=t), ask)
    # progress is measured from the first tick after the sweep; blocked at the first tick past the window
    assert swept + r.window_s < t <= swept + 0.1 + r.window_s + 0.1 + 1e-9 and asked == [None]
    assert out.diverting == ((1.0, 1.0), (1.0, -1.0)) and r.diverting_targets == 1
    assert any("diverting target set" in m for _, m in out.events)
    # the robot drives across the line (the landmarks come nearer and pass behind)
    marks = {}
    for x in (1.0, 0.5, 0.1, -0.1):
        t += 0.1
        marks = {"L": FuzzyPoint(x, 1.0, CRISP), "R": FuzzyPoint(x, -1.0, CRISP)}
        out = r.decide(situation(time=t, landmarks=marks), ask)
    assert out.diverting is None and any("crossed" in m for _, m in out.events)
    assert r.failures == 0


def _bumped_until_given_up(r: Rescuer, t: float, answers, limit: float = 1000.0):
    """Bump the robot into something every second, never crossing, until the Rescuer gives up
    (or ``limit``); the map answers with ``answers`` in turn. Returns the time, the reason, the
    events and the edges the map was told had failed."""
    answers, failed_edges = iter(answers), []

    def ask(failed):
        failed_edges.append(failed)
        return next(answers)

    bumps_at, looked = 0.0, None
    events, give_up = [], None
    while give_up is None and t < limit:
        t += 0.1
        bumps = ()
        if t - bumps_at > 1.0:  # the robot keeps hitting something, never crossing
            bumps, bumps_at = (Bump(t, "obstacle 0", (0.0, 0.0), 0.0),), t
        # the camera reports each look asked for, and a turn asked for is made at once
        out = r.decide(situation(time=t, bumps=bumps, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), ask)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        events += [m for _, m in out.events]
        give_up = out.give_up
    return t, give_up, events, failed_edges


CROSSINGS = (
    Crossing("A", "B", (2.0, 1.0), (2.0, -1.0), 2.0),
    Crossing("C", "D", (0.0, 3.0), (1.0, 3.0), 2.0),
    Crossing("E", "F", (-1.0, 2.0), (-2.0, 1.0), 2.0),
)


def test_rescuer_abandons_a_diverting_target_that_cannot_be_reached_and_asks_again_until_no_way_is_left():
    """The Rescuer's rule: failures end no mission by their count. Each diverting target not crossed
    is abandoned, the map told of its edge, and another asked for; the mission ends blocked only
    when the map shows no way out, and again after a look around (with ``gives_up``: by default
    it never ends the mission)."""
    from navcli.navigation.regions import NoCrossing

    r = Rescuer(replace(NAVIGATION, gives_up=True), np.random.default_rng(0))
    none_left = NoCrossing("every edge out is blocked", trapped=True)
    t, give_up, events, failed = _bumped_until_given_up(r, _sweep(r), [*CROSSINGS, none_left, none_left])
    assert give_up == "no way out: every edge out is blocked"
    assert failed == [None, frozenset("AB"), frozenset("CD"), frozenset("EF"), None]  # each failure told once
    assert sum("abandoned" in m for m in events) == r.failures == len(CROSSINGS)
    # it drove out after each failure by bumps, and looked around once between the two answers
    assert sum("caught by bumps" in m for m in events) == len(CROSSINGS)
    assert sum("exploring" in m for m in events) == len(CROSSINGS) + 1


def test_a_rescuer_that_never_gives_up_goes_on_asking_the_map():
    """``gives_up`` off (the default): neither the map's "no way out", twice, nor a count of
    failures ends the mission; where it would give up, the Rescuer turns by a random angle and
    asks the map again at once (the thesis), and explores when the answer is still none."""
    from navcli.navigation.regions import NoCrossing

    none_left = NoCrossing("every edge out is blocked", trapped=True)
    for extra in ({}, {"max_diverting_failures": 2}):
        r = Rescuer(replace(NAVIGATION, **extra), np.random.default_rng(0))
        answers = itertools.chain(CROSSINGS, itertools.repeat(none_left))
        t, give_up, events, failed = _bumped_until_given_up(r, _sweep(r), answers, limit=2000.0)
        assert give_up is None and len(failed) > len(CROSSINGS) + 3, extra  # asked again and again
        turns = [i for i, m in enumerate(events) if "not giving up: turning by" in m]
        assert len(turns) >= 2, extra
        # each such turn is followed by a request at once (answered "no way out": going on)
        assert all("still no diverting target: going on" in events[i + 1] for i in turns), extra


def test_not_giving_up_turns_by_a_random_angle_from_the_runs_generator():
    """The turn that replaces giving up is drawn uniformly within ``random_turn_deg`` from the
    Rescuer's generator: two generators of one seed turn alike, of two seeds differently."""
    from navcli.navigation.regions import NoCrossing

    def first_turn(seed):
        r = Rescuer(NAVIGATION, np.random.default_rng(seed))
        t = _sweep(r)
        r._trapped = True  # the map said "no way out" once already
        t, out, _ = _blocked_until_asked(r, t, NoCrossing("every edge out is blocked", trapped=True))
        assert out.give_up is None and r.state == "turn" and r._ask_after_turn
        return r._turn_to

    a, b, c = first_turn(1), first_turn(1), first_turn(2)
    assert a == b and a != c and all(abs(x) <= math.radians(NAVIGATION.random_turn_deg) for x in (a, c))


def test_a_target_found_again_starts_the_next_loss_with_fresh_scans():
    """Found during the turn after a scan, the target's next loss takes LOST_SCANS scans again
    before the map is asked (a count left from the last loss asked it after one)."""
    from navcli.navigation.rescuer import LOST_SCANS

    r = Rescuer(NAVIGATION, np.random.default_rng(0))
    t, looked, asked = _sweep(r), None, []

    def step(I_a):
        nonlocal t, looked
        t += 0.1
        out = r.decide(
            situation(time=t, I_a=I_a, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)),
            lambda f: asked.append(f) or CROSSINGS[0],
        )
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        return out

    scans = 0
    while scans < 1:  # lost: one scan, then the turn
        scans += sum("still lost after a scan" in m for _, m in step(0.9).events)
    for _ in range(5):
        step(0.0)  # found again
    scans = 0
    while not asked and t < 200.0:
        scans += sum("still lost after a scan" in m for _, m in step(0.9).events)
    assert asked == [None] and scans == LOST_SCANS - 1


def test_bumped_out_of_a_diverting_target_the_robot_drives_out_before_the_map_is_asked_again():
    """Three bumps on a diverting target's way: the Rescuer abandons it and explores (turns away
    and drives) instead of asking the map for the next way from where it is caught; the map hears
    of the failure with the next request, when the robot is blocked again."""
    r = Rescuer(NAVIGATION, np.random.default_rng(0))
    t, failed = _sweep(r), []

    def ask(f):
        failed.append(f)
        return CROSSINGS[len(failed) - 1]

    out = r.decide(situation(time=t + 60.0), ask)  # no progress for a window: blocked, a diverting target
    assert out.diverting is not None and failed == [None]
    t += 60.0
    for _ in range(NAVIGATION.blocked_bumps):
        t += 1.0
        out = r.decide(situation(time=t, bumps=(Bump(t, "landmark A", (0.3, 0.0), 0.0),)), ask)
    assert failed == [None] and r.failures == 1  # the map is not asked from where the robot is caught
    assert out.diverting is None and r.state == "turn" and r.diverting_targets == 1
    assert any("caught by" in m and "exploring" in m for _, m in out.events)
    looked = None
    while len(failed) < 2 and t < 400.0:  # it drives out, looks around, and is blocked again
        t += 0.1
        out = r.decide(situation(time=t, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), ask)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
    assert failed == [None, frozenset("AB")] and out.diverting is not None  # told with the next request


def test_the_count_of_failures_may_still_end_a_mission():
    """``max_diverting_failures`` > 0 (3: a switch for the rule of ending after three): that many abandoned
    diverting targets end the mission, each taking ``blocked_bumps`` bumps, not the time limit."""
    p = replace(NAVIGATION, max_diverting_failures=2, gives_up=True)
    r = Rescuer(p, np.random.default_rng(0))
    t, give_up, events, failed = _bumped_until_given_up(r, _sweep(r), CROSSINGS)
    assert give_up == "2 diverting targets failed"
    assert failed == [None, frozenset("AB")]  # the second failure ends it before the map is asked again
    assert sum("abandoned" in m for m in events) == 2
    assert t < 3 * r.window_s


def test_rescuer_stops_and_scans_when_the_target_is_lost_then_turns():
    r = Rescuer(NAVIGATION, np.random.default_rng(0))
    t = _sweep(r)
    out = r.decide(situation(time=t + 0.1, I_a=0.9), lambda f: None)
    assert r.state == "lost" and any("target lost" in m for _, m in out.events)
    pans = []
    looked = None
    for k in range(30):
        out = r.decide(situation(time=t + 0.2 + k / 10, I_a=0.9, looked=looked), lambda f: None)
        if r.state != "lost":
            break
        look = next(b for b in out.bids if b.resource == "camera")
        pans.append(round(math.degrees(look.action.pan)))
        looked = look.action
    assert sorted(set(pans)) == sorted(NAVIGATION.scan_pans_deg) and r.state == "turn"
    out = r.decide(situation(time=10.0, I_a=0.9), lambda f: None)
    (turn,) = out.bids
    assert turn.action.speed == 0.0 and turn.value == NAVIGATION.rescuer_bid  # turning in place


# -- whole missions -----------------------------------------------------------------------------
def test_blocked_wall_is_passed_round_a_fence_end_and_every_diverting_target_is_logged(tmp_path):
    """A fence across the room between start and target. With ground truth (the oracle, so this
    is the map's and the Rescuer's behaviour, not vision's), the potential-field pilot is held in
    front of the fence until the Rescuer sets a diverting target: the map knows the fence, so
    the target lies round one of its ends (its line does not cross the fence), and the robot
    reaches the target well before the time limit. Every diverting target is the Rescuer's,
    logged as it is set and counted in the summary."""
    from navcli.navigation.regions import CROSS_MARGIN, crossing_along

    sc = load_scenario(SCENARIOS / "blocked-wall.yaml")
    spec = RunSpec.build(sc, pilot="potential-field", perception="oracle")
    (fence,) = sc.obstacles
    crossings = []
    res = run_mission(
        spec,
        out=tmp_path / "bw.mcap",
        on_tick=lambda m, t: crossings.extend(
            m.navigation.rescuer._crossing_world for e in t.events if e.message.startswith("diverting target set")
        ),
    )
    s = res.summary
    assert s["outcome"] == "reached" and s["time_s"] < spec.time_limit / 4, s
    assert crossings and not any(crossing_along(a, b, fence.start, fence.end, CROSS_MARGIN) for a, b in crossings)
    events = read_log(res.log, topics=["/events"])["/events"]
    set_ = events[events["message"].str.startswith("diverting target set")]
    assert len(set_) == s["diverting_targets"] == len(crossings) and set(set_["name"]) <= {"rescuer"}
    # the log's last map names every diverting line the Rescuer ended, by how it ended
    from navcli.analysis.mapplot import last_map

    _, entities = last_map(res.log)
    labels = [t.text for e in entities for t in e.texts]
    crossed = events["message"].str.contains("diverting target crossed").sum()
    assert crossed >= 1 and labels.count("crossed") + labels.count("crossed, led nowhere") == crossed


def test_a_trap_with_no_way_out_ends_blocked_well_before_its_time_limit():
    from navcli.mission import Mission

    sc = load_scenario(SCENARIOS / "trap-box.yaml")
    m = Mission(RunSpec.build(sc, pilot="geometric", overrides={"navigation.gives_up": True}))
    while m.outcome is None:
        m.step()
    assert m.outcome == "blocked" and m.reason.split(": ")[1] == "no way out", m.reason
    assert m.time < sc.mission.time_limit / 2


def test_the_navigation_system_lists_its_agents_and_forwards_their_bids():
    nav = NavigationSystem()
    assert [a.name for a in nav.agents] == ["target-tracker", "risk-manager", "distance-estimator"]
    b = Beliefs(0.0, Pose(0, 0, 0), (3.0, 4.0), None, (), 0.0, target_at=FuzzyPoint(3.0, 4.0, CRISP))
    out = nav.bid(b)  # the first tick: the Rescuer's initial sweep (stop, look) wins both resources
    assert {x.bidder for x in out.bids} == {"navigation"}
    assert {(x.resource, x.value) for x in out.bids} == {("motion", P.rescuer_bid), ("camera", P.rescuer_bid)}
    assert {x.bidder for x in out.agent_bids} >= {"rescuer", "target-tracker"}
    assert out.target == pytest.approx((3.0, 4.0)) and out.info["rescuer"] == "sweep"


# -- the Rescuer explores before it gives up ---------------------------------------------------------
def _blocked_until_asked(r, t, answer, limit=200.0):
    """Tick a Rescuer that makes no progress until it asks the map; return the time and events."""
    asked, events = [], []

    def ask(failed):
        asked.append(failed)
        return answer

    while not asked and t < limit:
        t += 0.1
        out = r.decide(situation(time=t), ask)
        events += [m for _, m in out.events]
    return t, out, events


def test_with_the_target_in_the_robots_region_the_rescuer_only_turns_by_a_random_angle():
    """The map's way is straight (the target in the robot's own region): the Rescuer turns by a
    random angle within random_turn_deg and goes back to normal, no drive away, no failure; with
    ``turn_when_here`` off it explores (the turn is followed by a drive out)."""
    from navcli.navigation.regions import NoCrossing

    here = NoCrossing("the target is in the robot's region", here=True)
    for turn, after in ((True, "normal"), (False, "drive")):
        r = Rescuer(replace(NAVIGATION, turn_when_here=turn), np.random.default_rng(0))
        t, out, events = _blocked_until_asked(r, _sweep(r), here)
        assert r.state == "turn" and r.failures == 0 and out.give_up is None
        lim = math.radians(NAVIGATION.random_turn_deg)
        away = math.atan2(4.0, 3.0) + math.pi  # exploring: within half of it of the way away from (3, 4)
        if turn:
            assert abs(r._turn_to) <= lim and not any("exploring" in m for m in events)
        else:
            assert abs(wrap_angle(r._turn_to - away)) <= lim / 2 and any("exploring" in m for m in events)
        r.decide(situation(time=t + 0.1, odometry=Pose(0.0, 0.0, r._turn_to)), lambda f: here)
        assert r.state == after, turn


def test_a_lost_target_in_the_robots_region_is_explored_for_not_turned_for():
    """After LOST_SCANS scans the map is asked for a way toward the lost target; its answer that
    the target is in the robot's region sends the robot exploring (what hides a target is most
    often a long obstacle), not only turning."""
    from navcli.navigation.regions import NoCrossing

    r = Rescuer(NAVIGATION, np.random.default_rng(0))
    t, looked, asked, events = _sweep(r), None, [], []
    here = NoCrossing("the target is in the robot's region", here=True)
    while not asked and t < 200.0:
        t += 0.1
        s = situation(time=t, I_a=0.9, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0))
        out = r.decide(s, lambda f: asked.append(f) or here)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        events += [m for _, m in out.events]
    assert asked == [None] and any("target not found" in m for m in events)
    assert "exploring" in events[-1] and r.state == "turn" and r._scan_after_turn


def test_a_request_the_map_cannot_answer_leads_to_exploring_not_to_a_failure():
    from navcli.navigation.regions import NoCrossing

    p = NAVIGATION
    r = Rescuer(p, np.random.default_rng(0))
    t = _sweep(r)
    t, out, events = _blocked_until_asked(r, t, NoCrossing("2 landmark(s) mapped, too few for regions"))
    assert r.failures == 0 and r.state == "turn" and any("exploring" in m for m in events)
    looked = None  # the turn, then a scan for landmarks
    for _ in range(400):
        t += 0.1
        out = r.decide(situation(time=t, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), lambda f: None)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        if r.state == "normal":
            break
    assert r.state == "normal" and r.failures == 0 and any("looked around" in m for _, m in out.events)


def _explore_until_driving(seed: int, target=(3.0, 4.0)):
    """A Rescuer blocked with a map that cannot answer, turned (odometry follows the turn)
    until it drives; returns it, the time and the first drive tick's bids."""
    from navcli.navigation.regions import NoCrossing

    r = Rescuer(NAVIGATION, np.random.default_rng(seed))
    t = _sweep(r)
    t, out, _ = _blocked_until_asked(r, t, NoCrossing("too few landmarks"))
    turned_to = r._turn_to
    while r.state == "turn":
        t += 0.1
        out = r.decide(situation(target=target, time=t, odometry=Pose(0.0, 0.0, turned_to)), lambda f: None)
    return r, t, turned_to, out


def test_exploring_turns_away_from_the_target_and_drives_looking_around():
    """No diverting target: the robot turns to a heading within half of random_turn_deg of the
    one away from the target (bearing atan2(4, 3) = 53.1 deg, away -126.9 deg), then drives
    straight on at full speed, looking around, for up to explore_m (odometry), then scans."""
    P = NAVIGATION
    away = math.atan2(4.0, 3.0) + math.pi
    for seed in range(8):
        r, t, turned_to, out = _explore_until_driving(seed)
        assert abs(math.remainder(turned_to - away, 2 * math.pi)) <= math.radians(P.random_turn_deg) / 2 + 1e-9
        assert r.state == "drive" and r.failures == 0
        bids = {b.resource: b.action for b in out.bids}
        assert bids["motion"] == Move(0.0, ROBOT.max_speed) and "camera" in bids
    # driven explore_m along the turned heading, it stops to scan
    step = ROBOT.max_speed * 0.1
    for k in range(1, 200):
        d = min(k * step, P.explore_m)
        t += 0.1
        r.decide(
            situation(time=t, odometry=Pose(d * math.cos(turned_to), d * math.sin(turned_to), turned_to)),
            lambda f: None,
        )
        if r.state != "drive":
            break
    assert r.state == "explore" and d == pytest.approx(P.explore_m)


def test_an_exploring_drive_ends_when_a_new_landmark_is_seen():
    r, t, turned_to, out = _explore_until_driving(0)
    assert r.state == "drive"
    seen = {"A": FuzzyPoint(2.0, 0.0, CRISP)}  # one more landmark known than when the drive began
    r.decide(situation(time=t + 0.1, odometry=Pose(0.0, 0.0, turned_to), landmarks=seen), lambda f: None)
    assert r.state == "explore"


def test_explore_m_0_looks_around_in_place_as_before():
    from dataclasses import replace as dc_replace

    from navcli.navigation.regions import NoCrossing

    r = Rescuer(dc_replace(NAVIGATION, explore_m=0.0), np.random.default_rng(0))
    t = _sweep(r)
    t, out, _ = _blocked_until_asked(r, t, NoCrossing("too few landmarks"))
    while r.state == "turn":
        t += 0.1
        r.decide(situation(time=t, odometry=Pose(0.0, 0.0, r._turn_to)), lambda f: None)
    assert r.state == "explore"


def test_after_a_diverting_target_is_crossed_a_target_in_sight_is_headed_for_directly():
    """Crossed, the Rescuer asks the map for the next step only while a known long obstacle
    lies across the straight way to the target; in sight, it goes back to the original target."""
    from navcli.beliefs import KnownObstacle
    from navcli.navigation.regions import Crossing

    def crossed_with(obstacles, params=NAVIGATION):
        r = Rescuer(params, np.random.default_rng(0))
        t = _sweep(r)
        nxt = Crossing("C", "D", (5.0, 1.0), (5.0, -1.0), 2.0)
        r._set_crossing(Crossing("A", "B", (1.0, 1.0), (1.0, -1.0), 1.0), situation(time=t))
        asked = []

        def ask(failed):
            asked.append(failed)
            return nxt

        for x in (1.0, -0.5):  # the line A-B ahead, then behind: the robot has passed it
            t += 0.1
            marks = {"A": FuzzyPoint(x, 1.0, CRISP), "B": FuzzyPoint(x, -1.0, CRISP)}
            b = Beliefs(t, Pose(0, 0, 0), (3.0, 4.0), None, tuple(obstacles), 0.0)
            r.decide(Situation(b, FuzzyPoint(3.0, 4.0, CRISP), None, "memory", 0.0, marks), ask)
        return r, asked

    r, asked = crossed_with([])
    assert r._crossing is None and asked == []  # in sight: back to the original target
    fence_across = KnownObstacle("fence", (-1.0, 2.0), (4.0, 2.0), 0.025)
    r, asked = crossed_with([fence_across])
    assert asked == [None] and r._crossing is not None and r._crossing.left == "C"  # the way goes on
    from dataclasses import replace as dc_replace

    r, asked = crossed_with([], dc_replace(NAVIGATION, sight_ends_way=0))  # off: the way goes on
    assert asked == [None] and r._crossing.left == "C"


def test_the_rescuer_gives_up_only_when_the_map_still_shows_no_way_out_after_exploring():
    from navcli.navigation.regions import NoCrossing

    r = Rescuer(replace(NAVIGATION, gives_up=True), np.random.default_rng(0))
    t = _sweep(r)
    trapped = NoCrossing("every edge out is blocked", trapped=True)
    t, out, _ = _blocked_until_asked(r, t, trapped)
    assert out.give_up is None and r.state == "turn"  # the first time: look around first
    looked = None
    for _ in range(400):  # the turn and the scan
        if r.state == "normal":
            break
        t += 0.1
        out = r.decide(situation(time=t, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), lambda f: None)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
    assert r.state == "normal"
    t, out, _ = _blocked_until_asked(r, t, trapped, limit=t + 200.0)
    assert out.give_up == "no way out: every edge out is blocked" and r.failures == 0


def test_looking_around_is_bounded_by_the_count_of_failures_when_there_is_one():
    """A map that never gives a diverting target (too few landmarks, say): with
    ``max_diverting_failures`` set, the mission ends after that many looks around; without (the
    default), the robot goes on looking, since the map may yet learn a way."""
    from navcli.navigation.regions import NoCrossing

    r = Rescuer(replace(NAVIGATION, max_diverting_failures=3, gives_up=True), np.random.default_rng(0))
    t = _sweep(r)
    looked, give_up, asked = None, None, 0

    def ask(failed):
        nonlocal asked
        asked += 1
        return NoCrossing("too few landmarks")

    while give_up is None and t < 2000.0:
        t += 0.1
        out = r.decide(situation(time=t, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), ask)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        give_up = out.give_up
    assert asked == 3 + 1 and r.failures == 0
    assert give_up.startswith("the map gives no diverting target after 3 looks around")
    r, t, asked = Rescuer(NAVIGATION, np.random.default_rng(0)), 0.0, 0
    while t < 2000.0:
        t += 0.1
        out = r.decide(situation(time=t, looked=looked, odometry=Pose(0.0, 0.0, r._turn_to or 0.0)), ask)
        looked = next((b.action for b in out.bids if b.resource == "camera"), None)
        assert out.give_up is None
    assert asked > 3 * 3  # far more looks around than the count would allow


def test_a_target_no_scan_finds_sends_the_robot_the_maps_way_and_counts_no_failure():
    """Lost for good: after LOST_SCANS scans without the target (each followed by a random turn),
    the Rescuer asks the map for a way toward where the target is believed to be and sets it as a
    diverting target; nothing is counted as failed, and the mission goes on. With no way, it
    explores: it turns away from the target and drives."""
    from navcli.navigation.regions import NoCrossing
    from navcli.navigation.rescuer import LOST_SCANS

    for answer in (CROSSINGS[0], NoCrossing("too few landmarks")):
        r = Rescuer(NAVIGATION, np.random.default_rng(0))
        t, looked, asked, scans, out = _sweep(r), None, [], 0, None
        while not asked and t < 500.0:
            t += 0.1
            theta = r._turn_to or 0.0  # the robot has made the last turn asked for
            out = r.decide(
                situation(time=t, I_a=0.9, looked=looked, odometry=Pose(0.0, 0.0, theta)),
                lambda f, asked=asked, answer=answer: asked.append(f) or answer,
            )
            scans += sum("still lost after a scan" in m for _, m in out.events)
            looked = next((b.action for b in out.bids if b.resource == "camera"), None)
            assert out.give_up is None
        assert asked == [None] and scans == LOST_SCANS - 1 and r.failures == 0
        if isinstance(answer, Crossing):
            assert out.diverting is not None and r.diverting_targets == 1 and r.state == "normal"
        else:
            assert r.state == "turn" and out.diverting is None
            turn = math.degrees(r._turn_to - theta)  # the target is at (3, 4), egocentric: away is 233 deg
            assert (
                abs((turn - (math.degrees(math.atan2(4.0, 3.0)) + 180.0) + 180.0) % 360.0 - 180.0)
                <= NAVIGATION.random_turn_deg / 2 + 1e-9
            )
