"""The visual memory: where the robot believes the things it has seen are, as fuzzy positions.

Notes, section 1 (thesis node 37): the memory keeps landmarks and obstacles relative to the robot;
odometry moves them, with an imprecision that grows with the distance travelled and more with
turning; seeing an object again reduces its imprecision; an object whose imprecision passes a
threshold is removed. The bumpers add obstacles, and the mission adds what the robot is told at
the start (the target), which is kept however imprecise it becomes.

Representation (our choice; the thesis' operators are not available): each remembered point is
a fuzzy *position*: a crisp egocentric centre (its core) and nested discs around it, radius
``r0`` for the 0 % cut (the support) and ``r1`` for the core, the cuts between linear in alpha.
Discs make every update cheap and conservative:

- **moving** by the odometry's ``(ds, dtheta)``: the centre moves exactly as measured; the
  support grows by what the odometry's error can have shifted it since it was last seen: its
  calibration error (systematic: the centre's sensitivities to it add up along the path) and its
  per-tick random error (adding up like a random walk), each at its bound, plus a floor per metre
  driven (:class:`Spot`, :meth:`VisualMemory.move`), so the true position never leaves the support;
- **seeing** again: the fuzzy intersection (minimum) of memory and observation, enclosed in the
  smallest disc (the true point lies in both, so in their intersection): sharper, still honest;
- **reading** it as the papers do: a fuzzy distance and a fuzzy heading whose 70 % cut widths
  give ``I(l)`` (:func:`navcli.fuzzy.landmark_imprecision`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..fuzzy import ALPHAS, CUT, FuzzyAngle, FuzzyPoint
from ..params import ROBOT, VISION, VisionParams
from . import bumps, line_pieces
from .line_pieces import END_TIE
from .camera import Detection, Sighting

Disc = tuple[float, float, float]  # x, y, radius
STILL = (0.0,) * 10  # a Spot's drift when just seen: jx, jy, kx, ky, vt, vs, run, hx, hy, vh


@dataclass(slots=True)
class Spot:
    """A remembered point: egocentric centre (m), support and core radii (m).

    The support is the radius ``base`` it had when last seen, plus the odometry drift since
    (see :meth:`VisualMemory.move`), kept as sensitivities so that it is tight: ``drift`` is
    ``(jx, jy, kx, ky, vt, vs, run, hx, hy, vh)``: ``J`` and ``K`` are how far the centre would
    shift per unit of the odometry's calibration error in turning and in distance (vectors, m),
    ``vt`` and ``vs`` the summed squares of the per-tick moves (rad*m, m) whose random errors add
    up like a random walk, ``run`` the distance driven, ``H`` and ``vh`` the same as ``J`` and
    ``vt`` for the heading drift per metre driven (m*m, m*m). One tuple, not ten fields (ours, for
    speed: :meth:`VisualMemory.move` updates every spot every tick).
    """

    x: float
    y: float
    base: float  # support radius when last seen
    r1: float  # core radius
    drift: tuple[float, ...] = STILL
    r0: float = 0.0  # the support radius, kept up to date by VisualMemory

    def __post_init__(self) -> None:
        self.r0 = max(self.r0, self.base)

    def radius(self, alpha: float) -> float:
        return self.r0 + alpha * (self.r1 - self.r0)

    def point(self) -> FuzzyPoint:
        """The spot as a value: its centre and the radius of each cut (linear in alpha)."""
        r0, d = self.r0, self.r1 - self.r0
        a0, a1, a2, a3 = ALPHAS
        return FuzzyPoint(self.x, self.y, (r0 + a0 * d, r0 + a1 * d, r0 + a2 * d, r0 + a3 * d))

    def heading(self) -> FuzzyAngle:
        return self.point().heading()

    def contains(self, p: tuple[float, float], alpha: float = 0.0) -> bool:
        return math.hypot(p[0] - self.x, p[1] - self.y) <= self.radius(alpha) + 1e-9


@dataclass(frozen=True)
class Remembered:
    """A remembered object as a value, for the log: per point its egocentric centre (m), the
    radius of its 70 % cut and of its support (m)."""

    key: str
    kind: str
    spots: tuple[tuple[float, float, float, float], ...]  # (x, y, r70, r0)


@dataclass(slots=True)
class Memory:
    """One remembered object: a landmark, an obstacle (one spot, or two for a linear one, the
    walls among them), something the bumpers found, or the target. ``exact`` is, for an
    identified linear obstacle, whether each end (``a``, ``b``) is the obstacle's own end as seen
    (or told), rather than the farthest point of it seen so far: empty for everything else."""

    key: str
    kind: str  # landmark | obstacle | bump | target | wall
    spots: list[Spot]
    radius: float  # physical half-width, m
    prior: bool = False  # told at the start: never forgotten
    seen: float = 0.0  # simulated time of the last sighting
    exact: tuple[bool, ...] = ()
    felt_from: tuple[float, float] | None = None  # a lone bump: the robot's centre when it was felt

    def imprecision(self) -> float:
        """I(l) of the object's worst-known point (section 5.1 of the learning-agent paper)."""
        return max(s.point().imprecision() for s in self.spots)  # I(l) of a spot from its 70 % cut


def _sighting_spot(s: Sighting) -> Spot:
    """The disc around a sighting's polar box, for the support and for the core."""
    h_c, d_c = s.heading.centre, s.distance.centre
    centre = math.cos(h_c), math.sin(h_c)
    cx, cy = d_c * centre[0], d_c * centre[1]
    radii = []
    cos, sin = math.cos, math.sin
    for k in (0, len(ALPHAS) - 1):
        dlo, dhi = s.distance.cuts[k]
        hlo, hhi = s.heading.value.cuts[k]
        rays = ((cos(hlo), sin(hlo)), (cos(hhi), sin(hhi)), centre)
        r = 0.0
        for d in (dlo, dhi):
            for c, sn in rays:
                e = math.hypot(d * c - cx, d * sn - cy)
                if e > r:
                    r = e
        if hhi - hlo > math.pi and dhi + d_c > r:  # a wide fan: its far arc may bulge past the corners
            r = dhi + d_c
        radii.append(r)
    return Spot(cx, cy, radii[0], radii[1])


def _enclose_intersection(a: Disc, b: Disc) -> Disc | None:
    """The smallest disc found that holds the intersection of discs ``a`` and ``b``, or None if
    they do not meet. Either the smaller disc (one inside the other, or a fat lens) or the disc
    on the common chord, whichever holds the whole lens."""
    (ax, ay, ra), (bx, by, rb) = a, b
    d = math.hypot(bx - ax, by - ay)
    if d > ra + rb:
        return None
    small = a if ra <= rb else b
    if d + min(ra, rb) <= max(ra, rb) or d == 0.0:
        return small
    x = (d * d + ra * ra - rb * rb) / (2 * d)  # chord position from a's centre along a -> b
    h2 = ra * ra - x * x
    if h2 <= 0.0:
        return small
    h = math.sqrt(h2)
    ux, uy = (bx - ax) / d, (by - ay) / d
    mx, my = ax + x * ux, ay + x * uy
    tip_a, tip_b = ra - x, x - (d - rb)  # the lens' tips along the line, measured from the chord
    if max(tip_a, tip_b) <= h:
        return (mx, my, h)
    return small


def fuse(m: Spot, o: Spot) -> Spot:
    """Memory and observation of the same point combined: the fuzzy intersection (the true point
    lies in both supports, so in their intersection), enclosed in a disc whose centre becomes
    the crisp estimate; the drift starts again from there (set-membership filtering).

    If the two supports do not meet the memory was wrong (an object moved, a wrong association):
    the observation replaces it."""
    sup = _enclose_intersection((m.x, m.y, m.r0), (o.x, o.y, o.r0))
    if sup is None:
        return Spot(o.x, o.y, o.r0, o.r1)
    x, y, r0 = sup
    return Spot(x, y, r0, min(m.r1, o.r1, r0))


def _nearest(memories: list[Memory], spot: Spot) -> Memory:
    """The memory of ``memories`` whose first spot is nearest ``spot``."""
    return min(memories, key=lambda m: bumps.gap(m.spots[0], spot))


@dataclass
class VisualMemory:
    """The remembered objects, moved by odometry, sharpened by sightings, pruned by imprecision.

    ``odometry_noise`` is the odometry's relative deviation (scenario ``noise.odometry``) and
    ``heading_drift`` its heading drift (rad per metre, ``noise.odometry_drift_deg_per_m``),
    from which :meth:`move` bounds the drift; ``robot_radius`` the robot's body, through which no
    line felt by the bumpers may pass (:meth:`add_bump`)."""

    odometry_noise: float
    params: VisionParams = VISION
    items: dict[str, Memory] = field(default_factory=dict)
    forgotten: list[str] = field(default_factory=list)
    _n: int = 0
    heading_drift: float = 0.0
    robot_radius: float = ROBOT.radius

    def add(
        self, key: str, kind: str, points: list[tuple[float, float]], radius: float, r0: float, prior: bool = False
    ) -> Memory:
        """Put an object the robot was told of at egocentric ``points``, known to within ``r0``."""
        m = Memory(key, kind, [Spot(x, y, r0, 0.0) for x, y in points], radius, prior)
        self.items[key] = m
        return m

    def add_found(self, kind: str, spots: list[Spot], radius: float, time: float = 0.0) -> Memory:
        """Remember a new unidentified object (an obstacle seen, or bumped into) under a fresh key."""
        self._n += 1
        m = Memory(f"{kind}-{self._n}", kind, spots, radius, False, time)
        self.items[m.key] = m
        return m

    def add_bump(self, spot: Spot, radius: float, time: float = 0.0) -> Memory:
        """What the bumpers found (notes, section 2, Pilot: "bump points close to each other or to
        landmarks are merged into a long obstacle between landmarks"), so that a wall the camera
        never saw, found by touch at two places, is known as one long obstacle, which the Pilot
        avoids as such and the Map Manager sees across the region edges it blocks.

        A bumper knows where on the body it was pressed and odometry where the robot was, not what
        it touched; so "one object" is judged from those alone (``vision.bump_lines``, default
        ``one-object``; :meth:`_join` with ``one_object`` off is ``near``):

        1. a bump on a remembered line (a fence, a wall, a line felt before; :func:`.bumps.line_under`)
           confirms it and draws nothing new; the line, one rigid object, is moved across onto the
           contact (:func:`.bumps.onto`), the bump being far sharper than a line seen from afar;
        2. a bump where a lone point is remembered (:func:`_same_point`) is fused with it: one
           point felt twice is no line, and never a second copy;
        3. a bump joins the nearest lone bump within ``bump_merge`` that may be on the same
           object (:func:`.bumps.one_object`): the line between them clears the robot's body where it
           stood at each bump, and the robot stood on one side of that line both times (a bump
           in front and one behind are two objects, with the robot between them);
        4. else a landmark within ``bump_merge`` whose line to the bump clears the body: a line
           from the landmark to it;
        5. else it is remembered as a lone bump, with where the robot stood."""
        if self.params.bump_lines == "near":
            return self._join(spot, radius, time, False)
        line = bumps.line_under(self.items.values(), spot)
        if line is not None:
            bumps.onto(line, spot, self.robot_radius)
            line.seen = time
            return line
        points = [m for m in self.items.values() if bumps.lone(m) and _same_point(m.spots[0], spot)]
        if points:
            m = _nearest(points, spot)
            m.spots[0] = fuse(m.spots[0], spot)
            m.seen = time
            if m.kind == "bump":
                m.felt_from = (0.0, 0.0)
            return m
        return self._join(spot, radius, time, True)

    def _join(self, spot: Spot, radius: float, time: float, one_object: bool) -> Memory:
        """The bump ``spot`` joined into a line with the nearest remembered bump within
        ``bump_merge``, else with the nearest landmark within it, else remembered alone. With
        ``one_object`` (``vision.bump_lines`` ``one-object``) only a bump that may lie on one
        object with it (:func:`.bumps.one_object`) and a landmark joined by a line clear of the
        robot's body, and a lone bump keeps where the robot stood; else (``near``) any within
        ``bump_merge``, whatever lies between them."""
        near, body = self.params.bump_merge, self.robot_radius
        felt = [
            m
            for m in self.items.values()
            if m.kind == "bump"
            and len(m.spots) == 1
            and bumps.gap(m.spots[0], spot) <= near
            and (not one_object or bumps.one_object(m, spot, body))
        ]
        if felt:
            other = _nearest(felt, spot)
            del self.items[other.key]
            return self.add_found("obstacle", [other.spots[0], spot], radius, time)
        marks = [
            m
            for m in self.items.values()
            if m.kind == "landmark"
            and bumps.gap(m.spots[0], spot) <= near
            and (not one_object or bumps.clears((0.0, 0.0), m.spots[0], spot, body))
        ]
        if marks:
            a = _nearest(marks, spot).spots[0]
            return self.add_found("obstacle", [Spot(a.x, a.y, a.r0, a.r1), spot], radius, time)
        m = self.add_found("bump", [spot], radius, time)
        if one_object:
            m.felt_from = (0.0, 0.0)
        return m

    def move(self, ds: float, dtheta: float) -> None:
        """The robot moved ``ds`` ahead along the mid-tick heading and turned ``dtheta`` (odometry).

        Each centre moves as measured. The support then is ``base + drift``, the drift bounding
        what the odometry's errors (scenario ``noise.odometry`` = sigma, each part bounded at
        ``noise_bound`` sigma, as the world draws them) can have displaced the point since it
        was seen: the per-run calibration errors of distance and turn act linearly, through the
        sensitivities K and J; the per-tick errors add up as a random walk (bounded at
        ``walk_bound`` of its standard deviations); plus a floor for the physics' own
        integration error, ``odometry_floor`` per metre driven; and the heading drift's, per metre
        driven, like the turn's (a systematic rate and a random walk, ``heading_drift`` each)."""
        if ds == 0.0 and dtheta == 0.0:
            return
        P = self.params
        sig, hd = self.odometry_noise, self.heading_drift
        # the calibration error is relative to the true motion, the bound to the measured one: a
        # reading (1 - b sigma) short leaves b sigma / (1 - b sigma) of what was measured unmeasured
        cal, walk = P.noise_bound * sig / (1.0 - P.noise_bound * sig), P.walk_bound * sig
        hcal, hwalk = P.noise_bound * hd, P.walk_bound * hd
        floor = P.odometry_floor
        half = dtheta / 2
        ux, uy = math.cos(half), math.sin(half)
        sx, sy = ds * ux, ds * uy  # the move along the mid-tick heading
        c, s = math.cos(dtheta), -math.sin(dtheta)  # rotation by -dtheta
        ads, adt, ds2 = abs(ds), abs(dtheta), ds * ds
        hypot, sqrt = math.hypot, math.sqrt
        for m in self.items.values():
            for p in m.spots:
                x, y = p.x, p.y
                jx, jy, kx, ky, vt, vs, run, hx, hy, vh = p.drift
                D = hypot(x, y)
                # a turn error swings the point about the robot: d(position)/d(turn) = perp(p)
                jx, jy = jx - dtheta * y, jy + dtheta * x
                if hd:  # and so does a heading drift, per metre driven (skipped without one: a hot loop)
                    hx, hy = hx - ads * y, hy + ads * x
                kx, ky = kx - sx, ky - sy  # a distance error shifts it along the motion
                x, y = x - sx, y - sy
                p.x, p.y = c * x - s * y, s * x + c * y
                jx, jy = c * jx - s * jy, s * jx + c * jy
                kx, ky = c * kx - s * ky, s * kx + c * ky
                vt += (adt * D) ** 2
                vs += ds2
                run += ads
                r0 = p.base + cal * (hypot(jx, jy) + hypot(kx, ky)) + walk * (sqrt(vt) + sqrt(vs)) + floor * run
                if hd:
                    hx, hy = c * hx - s * hy, s * hx + c * hy
                    vh += (ads * D) ** 2
                    r0 += hcal * hypot(hx, hy)
                    r0 += hwalk * sqrt(vh)
                p.drift = (jx, jy, kx, ky, vt, vs, run, hx, hy, vh)
                p.r0 = r0
            f = m.felt_from
            if f is not None:  # where the robot stood moves as the points do, crisp
                x, y = f[0] - sx, f[1] - sy
                m.felt_from = (c * x - s * y, s * x + c * y)

    def shove(self, slip: float) -> None:
        """Sliding along something may have moved the robot ``slip`` metres sideways, which the
        wheels do not measure: widen everything by that much."""
        for m in self.items.values():
            for p in m.spots:
                p.base += slip
                p.r0 += slip

    def snapshot(self) -> tuple[Remembered, ...]:
        """What is remembered now, as values that outlive the next tick."""
        return tuple(
            Remembered(m.key, m.kind, tuple((s.x, s.y, s.radius(CUT), s.r0) for s in m.spots))
            for m in self.items.values()
        )

    def forget(self) -> list[str]:
        """Drop what has become too imprecise (not what the robot was told); return the keys:
        A landmark, a point or the target goes when its I(l) passes ``forget_above`` (the thesis'
        rule for landmarks); a linear obstacle when both its ends have (ours: the end nearest a
        robot driving along a fence blurs first, and forgetting the fence with it lost a 7 m river
        every ten seconds). ``forget_line_by_one_end`` 1 forgets it by one end."""
        lim = self.params.forget_above
        whole = not self.params.forget_line_by_one_end
        gone = [
            k
            for k, m in self.items.items()
            if not m.prior
            and (
                min(s.point().imprecision() for s in m.spots) > lim
                if whole and len(m.spots) == 2
                else m.imprecision() > lim
            )
        ]
        for k in gone:
            del self.items[k]
        self.forgotten += gone
        return gone

    def observe(self, detections: list[Detection], time: float) -> None:
        """Fold one image's detections in: identified objects by id (a linear one end by end,
        :meth:`_observe_line`), plain obstacles by overlap."""
        for det in detections:
            spots = [_sighting_spot(s) for s in det.points]
            if det.ends:
                self._observe_line(det.key, det.kind, spots, det.ends, det.radius, time)
            elif det.key:
                m = self.items.get(det.key)
                if m is None:
                    self.items[det.key] = Memory(det.key, det.kind, spots, det.radius, det.kind == "target", time)
                    if det.kind == "landmark":
                        self._drop_points_at(spots[0])
                else:
                    m.spots = [fuse(a, b) for a, b in zip(m.spots, spots)]
                    m.seen = time
            else:
                self._observe_obstacle(spots, det.radius, time, det.kind)

    def _drop_points_at(self, s: Spot) -> None:
        """A landmark newly identified at ``s``: the plain point obstacles that may be it
        (:func:`_same_point`) were that landmark seen by the obstacle routine, which does not
        identify landmarks (:mod:`.routines`); they are dropped."""
        for k in [
            k
            for k, m in self.items.items()
            if m.kind in ("obstacle", "bump") and len(m.spots) == 1 and _same_point(m.spots[0], s)
        ]:
            del self.items[k]

    def _observe_line(
        self, key: str, kind: str, spots: list[Spot], ends: tuple[bool, ...], radius: float, time: float
    ) -> None:
        """Fold a sighting of the identified linear obstacle ``key`` in, end by end, like landmarks.

        ``spots`` are the extremities seen toward its ends ``a`` and ``b`` (one spot: one sample,
        for both); ``ends`` whether each is that end itself. For each end: a sighting of the end
        itself is fused with a remembered sighting of it (the fuzzy intersection, as a landmark's),
        or replaces a remembered point that was only where a view cut the obstacle; a cut point
        is no measurement of the end (the obstacle goes on past it), so it never moves a
        remembered end, and of two cut points the one farther out along the obstacle is kept
        (both are honest points of it; the farther is the better bound of its extent). So the
        remembered line is the stretch between two honest points of the obstacle, never a join
        of pieces, and no more certain than its ends. Points and bumps that lie on a new line are
        dropped: they were it.

        With ``vision.fence_rigid`` (off by default: in the trap rooms it cost reached runs and
        contacts) the obstacle is one rigid thing: where a sighting sharper than the memory
        corrects one end and leaves the other as remembered, the other end moves with it
        (:func:`.bumps.carried`), so the line keeps its length and direction instead of tilting
        toward where odometry had carried the uncorrected end."""
        if len(spots) == 1:
            spots = [spots[0], _copy(spots[0])]  # two spots: each end is moved on its own
        m = self.items.get(key)
        if m is None:
            self._drop_points_on(spots)
            self.items[key] = Memory(key, kind, spots, radius, False, time, ends)
            return
        a, b = m.spots if len(m.spots) == 2 else (m.spots[0], _copy(m.spots[0]))
        ea, eb = m.exact if len(m.exact) == 2 else (False, False)
        ux, uy = a.x - b.x, a.y - b.y  # the direction of the obstacle, from end b toward end a
        if math.hypot(ux, uy) < 1e-9:
            ux, uy = spots[0].x - spots[1].x, spots[0].y - spots[1].y
        ends_now = [_end(a, ea, spots[0], ends[0], ux, uy, b), _end(b, eb, spots[1], ends[1], -ux, -uy, a)]
        if self.params.fence_rigid:  # an end seen sharper than known corrects it; the other comes along
            fixed = (ea and ends[0] and _corrects(a, spots[0]), eb and ends[1] and _corrects(b, spots[1]))
            if fixed[0] and not (eb and ends[1]) and ends_now[1] is b:
                ends_now[1] = bumps.carried(b, ends_now[0].x - a.x, ends_now[0].y - a.y)
            elif fixed[1] and not (ea and ends[0]) and ends_now[0] is a:
                ends_now[0] = bumps.carried(a, ends_now[1].x - b.x, ends_now[1].y - b.y)
        if ends_now[0] is ends_now[1]:
            ends_now[1] = _copy(ends_now[1])
        m.spots = ends_now
        m.exact = (ea or ends[0], eb or ends[1])
        m.seen, m.radius = time, radius

    def _observe_obstacle(self, spots: list[Spot], radius: float, time: float, kind: str = "obstacle") -> None:
        """Associate a plain obstacle's (or a wall's) sighting with what is remembered, or remember it.

        A point sighting is fused with the nearest remembered point that may be the same thing
        (:func:`_same_point`); a new point is remembered under a fresh key. A stretch of a linear obstacle
        (``vision.line_objects`` 0: the camera does not identify it) is joined with the pieces
        remembered of it by geometry (:mod:`.line_pieces`)."""
        if line_pieces.join(self, spots, radius, time, kind):
            return
        if len(spots) == 1:
            s = spots[0]
            points = [
                m
                for m in self.items.values()
                if m.kind in ("obstacle", "bump") and len(m.spots) == 1 and _same_point(m.spots[0], s)
            ]
            if points:
                m = min(points, key=lambda m: math.hypot(m.spots[0].x - s.x, m.spots[0].y - s.y))
                m.spots[0] = fuse(m.spots[0], s)
                m.kind, m.radius, m.seen = "obstacle", radius, time
                return
        else:  # a new linear obstacle swallows the points and bumps that lie on it
            self._drop_points_on(spots)
        self.add_found(kind, spots, radius, time)

    def _drop_points_on(self, ends: list[Spot]) -> None:
        """The points and bumps that lie on a new linear obstacle between ``ends`` were it: dropped."""
        for k in [
            k
            for k, m in self.items.items()
            if m.kind in ("obstacle", "bump") and len(m.spots) == 1 and line_pieces.near_line(m.spots[0], ends, 0.0)
        ]:  # on it, between its ends
            del self.items[k]


def _copy(s: Spot) -> Spot:
    """A spot of its own at the same place (:meth:`VisualMemory.move` moves every spot it holds
    once: one spot held twice would be moved twice)."""
    return Spot(s.x, s.y, s.base, s.r1, s.drift, s.r0)


def _corrects(mem: Spot, obs: Spot) -> bool:
    """Does the sighting ``obs`` of a remembered end ``mem`` tell where it is: sharper than the
    memory, and within it (supports that do not meet are a wrong memory, replaced, no correction
    of the rest of the obstacle; a blurred sighting moves the fused centre by its own noise)?"""
    return obs.r0 < mem.r0 and math.hypot(obs.x - mem.x, obs.y - mem.y) <= mem.r0 + obs.r0


def _end(mem: Spot, mem_exact: bool, obs: Spot, obs_exact: bool, ux: float, uy: float, origin: Spot) -> Spot:
    """One end of an identified linear obstacle after a sighting (see
    :meth:`VisualMemory._observe_line`): ``mem`` remembered, ``obs`` seen, each flagged as the
    end itself or not; ``(ux, uy)`` the outward direction of this end, from ``origin`` (the
    other end)."""
    if obs_exact:
        return fuse(mem, obs) if mem_exact else obs
    if mem_exact:
        return mem
    tm = (mem.x - origin.x) * ux + (mem.y - origin.y) * uy
    to = (obs.x - origin.x) * ux + (obs.y - origin.y) * uy
    if abs(tm - to) <= END_TIE * math.hypot(ux, uy):
        return obs if obs.r0 < mem.r0 else mem  # as far out: the sharper
    return obs if to > tm else mem


def _same_point(a: Spot, b: Spot) -> bool:
    """May the unidentified points ``a`` and ``b`` be one thing: each centre inside the other's
    support? (Not merely overlapping supports: a point blurred by metres met every sighting near
    it, and the fusion of two things, each honest, can hold neither: an obstacle's remembered point
    lay outside its support in 9 of 24 paper-8x8 runs.)"""
    return math.hypot(a.x - b.x, a.y - b.y) <= min(a.r0, b.r0)
