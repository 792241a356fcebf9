"""The physical world: the only module that imports pymunk.

A static arena (four walls, circle and segment obstacles, landmarks as cylinders) and the robot,
a dynamic disc driven like a differential-drive base: each control tick it is commanded a forward
speed ``v`` (m/s) and a turn rate ``omega`` (rad/s), limited in speed, acceleration and turn rate.
The wheels are modelled as a velocity servo inside pymunk's step (``velocity_func``), so contacts
are solved *after* the command is applied and the robot cannot push into or tunnel through a
wall. Bumper contacts come out as :class:`Bump` events; the robot's own belief of where it is
comes from :class:`Odometry`, which sees the true motion through the scenario's noise.

The wheels do not execute the command exactly (:class:`Slip`): as in Webots, the simulator of
the papers' group ("noise to the robot movement and sensing", learning paper, section 6), every
physics step each wheel's speed is multiplied by a factor of its own drawn uniformly from
``[1 - s, 1 + s]``, with ``s`` the parameter ``robot.slip_noise`` (scenario ``noise.slip``). The
Webots Reference Manual's DifferentialWheels node declares this field, ``slipNoise``, with the
default 0.1: "a noise component of +/- 10 percent is added to the command for each simulation
step ... different for each wheel ... a uniform distribution". The wheels of a differential
drive sit on an axle as long as the robot's diameter. In Webots' kinematic model the wheel turns
by the noisy amount and its encoder counts that turn (the encoder's own error, ``encoderNoise``,
comes on top), so :class:`Odometry` measures the motion the robot executed, and its own errors
(``noise.odometry``) play the encoder's part: the slip moves the robot and the dead reckoning
follows it, independently of the dead reckoning's own error.

Cost (our design): a control tick is PHYSICS_SUBSTEPS pymunk steps, and pymunk's own work is a
small part of it (Chipmunk's solver is under 1 % of a mission's time); what costs is Python called
per step. So no Python runs inside Chipmunk's step where the build has the servo in C
(``navcli/servo.c``, built with the compiled modules: :func:`c_servo`), and only the servo (one
callback, :meth:`World._drive`, the reference the C servo repeats call for call) where it has not.
Contacts are followed by a collision handler (``begin``/``separate``), which runs Python only when
a contact starts or ends, instead of polling the robot's arbiters every step (the robot often
slides along a wall for seconds). The step, the servo and the position read call Chipmunk's
functions through pymunk's cffi library (``pymunk._chipmunk.lib``) on the space's and the body's
handles: the very calls pymunk's ``Space.step`` and ``Body`` properties make, without their Python
around them (the lock for objects added in callbacks, which this world never does; argument
checks; a ``Vec2d`` per read), which cost a third of a tick's physics. The same numbers come out:
:func:`check_handles` says at the start that the handles are there, and the golden runs would show
any difference.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
import pymunk
from pymunk._chipmunk import ffi
from pymunk._chipmunk import lib as chipmunk

from .beliefs import Bump
from .geometry import Pose, motion_between, wrap_angle
from .noise import bounded_normals
from .params import COLLISION_SLOP, NOISE_BOUND, PHYSICS_DT, PHYSICS_DT_NS, PHYSICS_SUBSTEPS, RobotParams
from .scenario import Scenario

WALL_THICKNESS = 0.10  # m; walls sit outside the arena, their inner face on the border
BUMP_REARM = 1.0  # s without touching a thing before touching it again counts as a new bump
ROBOT_MASS = 20.0  # kg
ROBOT = 1  # the robot shape's pymunk collision type: its contacts, with anything, go to the bumper


def check_handles(space: pymunk.Space, body: pymunk.Body) -> tuple[object, object]:
    """The Chipmunk handles of ``space`` and ``body`` that :meth:`World.step` steps and reads
    directly, checked to be what pymunk's own methods use (a pymunk release that renames them fails
    here, at the start of a run, with its version)."""
    cp_space, cp_body = getattr(space, "_space", None), getattr(body, "_body", None)
    if cp_space is None or cp_body is None or chipmunk.cpBodyGetSpace(cp_body) != cp_space:
        raise RuntimeError(f"pymunk {pymunk.version} keeps its Chipmunk handles elsewhere than navcli.world expects")
    return cp_space, cp_body


ServoStep = Callable[[int, int, float, float, float], None]
"""The C servo's step: ``(space, body, v, w, dt)``, the cpSpace's and the cpBody's addresses."""


def c_servo() -> tuple[int, ServoStep] | None:
    """The wheels' servo in C (``navcli/servo.c``): the address of its velocity function, bound to
    the Chipmunk functions of pymunk's library that the Python servo calls, and the step that runs
    it; None where this build has none (pure Python) or this pymunk's Chipmunk types are not the
    ones the C code declares (then the Python servo runs: the same numbers, slower)."""
    try:
        from . import servo
    except ImportError:
        return None
    if (
        ffi.typeof("cpBodyVelocityFunc").cname != "void(*)(struct cpBody *, struct cpVect, double, double)"
        or ffi.sizeof("cpVect") != 16
        or ffi.offsetof("cpVect", "y") != 8
    ):
        return None
    calls = ("cpBodyGetAngle", "cpBodySetVelocity", "cpBodySetAngularVelocity", "cpSpaceStep")
    velocity = servo.bind(*(address(ffi.addressof(chipmunk, name)) for name in calls))
    return velocity, servo.step


def address(handle: object) -> int:
    """The address a cffi pointer holds."""
    return int(ffi.cast("uintptr_t", handle))


C_SERVO = c_servo()
"""The C servo that :class:`World` drives its robot with, where there is one (see :func:`c_servo`);
None: the Python servo (:meth:`World._drive`), the reference."""


class Odometry:
    """Dead reckoning from the wheels: the pose the robot believes it has.

    Each tick the true forward distance and turned angle are measured with a relative error made
    of a per-run calibration error (drawn once: the systematic drift of real odometry) and a
    per-tick random error, both with standard deviation ``noise`` (scenario ``noise.odometry``),
    clipped at ``NOISE_BOUND`` deviations. With ``heading_drift`` (rad per metre, scenario
    ``noise.odometry_drift_deg_per_m``) the measured heading also drifts as the robot drives, by
    a per-run rate and a per-tick random part of that standard deviation per metre: the drift of
    a differential drive whose wheels differ a little in diameter (UMBmark's E_d), which no
    measured turn shows. Zero noise gives exact dead reckoning.
    """

    def __init__(self, start: Pose, noise: float, rng: np.random.Generator, heading_drift: float = 0.0):
        self.pose = start
        self.noise = noise
        self.rng = rng
        self.heading_drift = heading_drift
        self.scale_d, self.scale_a = (1.0, 1.0)
        self.drift_rate = 0.0  # rad per metre: the per-run heading drift
        if noise > 0:
            ed, ea = bounded_normals(self.rng, NOISE_BOUND)
            self.scale_d, self.scale_a = 1.0 + noise * ed, 1.0 + noise * ea
        if heading_drift > 0:
            self.drift_rate = heading_drift * bounded_normals(self.rng, NOISE_BOUND)[0]

    def update(self, ds: float, dtheta: float) -> Pose:
        """Integrate one tick of true motion (ds along the heading, m; dtheta, rad)."""
        if self.heading_drift > 0 and ds != 0.0:  # drawn first: the turn's scale applies to the turn alone
            drift = abs(ds) * (self.drift_rate + self.heading_drift * bounded_normals(self.rng, NOISE_BOUND)[0])
        else:
            drift = 0.0
        if self.noise > 0 and (ds != 0.0 or dtheta != 0.0):
            ed, ea = bounded_normals(self.rng, NOISE_BOUND)
            ds *= self.scale_d + self.noise * ed
            dtheta *= self.scale_a + self.noise * ea
        dtheta += drift
        p = self.pose
        mid = p.theta + dtheta / 2
        self.pose = Pose(p.x + ds * math.cos(mid), p.y + ds * math.sin(mid), wrap_angle(p.theta + dtheta))
        return self.pose


class Slip:
    """The wheels' execution noise of a differential drive (see the module docstring).

    A command (``v`` m/s, ``omega`` rad/s) is the wheels' speeds ``v -/+ omega * axle / 2``; each
    is multiplied by ``1 + u``, ``u`` uniform in ``[-noise, noise]`` and drawn per wheel and per
    physics step, and the speeds executed are turned back into (v, omega). The draws of a control
    tick are made at once (one call of the generator a tick, not one a physics step: the world
    runs on the hot path), and no draw is made with ``noise`` 0, which executes the command as given.
    """

    def __init__(self, noise: float, axle: float, rng: np.random.Generator | None):
        self.noise = noise
        self.axle = axle
        self.rng = rng
        if noise > 0 and rng is None:
            raise ValueError("wheel slip needs a generator of its own")

    def factors(self) -> list[float]:
        """The tick's factors, left and right wheel of each physics step in turn (2 x PHYSICS_SUBSTEPS)."""
        rng = self.rng
        assert rng is not None
        n = self.noise
        factors: list[float] = rng.uniform(1.0 - n, 1.0 + n, 2 * PHYSICS_SUBSTEPS).tolist()
        return factors

    def executed(self, v: float, omega: float, left: float, right: float) -> tuple[float, float]:
        """The (v, omega) the wheels execute for the command (v, omega) with their factors ``left``
        and ``right``."""
        half = omega * self.axle / 2
        vl, vr = (v - half) * left, (v + half) * right
        return (vl + vr) / 2, (vr - vl) / self.axle


class World:
    """The pymunk arena of one scenario, stepped one control tick at a time."""

    def __init__(
        self,
        scenario: Scenario,
        rng: np.random.Generator,
        robot: RobotParams | None = None,
        motion_rng: np.random.Generator | None = None,
    ):
        """``rng`` draws the odometry's errors, ``motion_rng`` the wheels' slip (needed unless the
        robot's ``slip_noise`` is 0); ``robot``: the body and drive limits, by default the
        scenario's (``scenario.params.robot``)."""
        self.scenario = scenario
        self.robot = robot = robot or scenario.params.robot
        self.slip = Slip(robot.slip_noise, 2 * robot.radius, motion_rng)
        self.max_speed = robot.max_speed
        self._substeps = 0
        self._pose: tuple[int, Pose] | None = None
        self.bumps = 0
        self._v = 0.0  # the drive's current (commanded, rate-limited) speed, m/s
        self._w = 0.0  # and turn rate, rad/s
        self._ve = 0.0  # the speed the wheels execute this physics step (the drive's, slip added), m/s
        self._we = 0.0  # and turn rate, rad/s
        self._last_touch: dict[pymunk.Shape, float] = {}  # when each thing was last touched, s
        self._contacts: set[pymunk.Shape] = set()  # what the robot touches now
        self._bumps: list[Bump] = []  # the bumps of the tick being stepped
        self.touching = False  # the bumper was pressed during the last tick

        space = pymunk.Space()
        space.collision_slop = COLLISION_SLOP
        self.space = space
        self._names: dict[pymunk.Shape, str] = {}
        self._add_walls()
        # obstacles first, then landmarks: the order pymunk meets them in
        for o in sorted(
            (o for o in scenario.objects if o.kind in ("circle", "segment", "landmark")),
            key=lambda o: o.kind == "landmark",
        ):
            shape: pymunk.Shape = (
                pymunk.Segment(space.static_body, o.a, o.b, o.radius)
                if o.kind == "segment"
                else pymunk.Circle(space.static_body, o.radius, o.a)
            )
            self._add_static(shape, o.label)

        r = robot.radius
        body = pymunk.Body(ROBOT_MASS, pymunk.moment_for_circle(ROBOT_MASS, 0, r))
        body.position = scenario.robot.start
        body.angle = scenario.robot.heading
        robot_shape = pymunk.Circle(body, r)
        robot_shape.friction = 0.3
        robot_shape.collision_type = ROBOT
        space.add(body, robot_shape)
        space.on_collision(ROBOT, None, begin=self._begin, separate=self._separate)
        self.body = body
        self._cp_space, self._cp_body = check_handles(space, body)
        self._servo = self._choose_servo(C_SERVO)
        self._trail = (0.0, body.position.x, body.position.y)  # metres travelled, and where that was summed to
        self.odometry = Odometry(self.pose, scenario.noise.odometry, rng, scenario.noise.heading_drift)

    def _add_walls(self) -> None:
        W, H = self.scenario.arena.width, self.scenario.arena.height
        h = WALL_THICKNESS / 2
        corners = [(-h, -h), (W + h, -h), (W + h, H + h), (-h, H + h)]
        for a, b in zip(corners, corners[1:] + corners[:1]):
            self._add_static(pymunk.Segment(self.space.static_body, a, b, h), "wall")

    def _add_static(self, shape: pymunk.Shape, name: str) -> None:
        shape.friction = 0.3
        self.space.add(shape)
        self._names[shape] = name

    def _choose_servo(self, servo: tuple[int, ServoStep] | None) -> tuple[int, int, ServoStep] | None:
        """Hand the body's velocity function to Chipmunk: the C servo's, if given (then return the
        space's and the body's addresses and its step), or else :meth:`_drive`."""
        if servo is None:
            self.body.velocity_func = self._drive
            return None
        velocity, step = servo
        chipmunk.cpBodySetVelocityUpdateFunc(self._cp_body, ffi.cast("cpBodyVelocityFunc", velocity))
        return address(self._cp_space), address(self._cp_body), step

    def _drive(self, body: pymunk.Body, gravity: pymunk.Vec2d, damping: float, dt: float) -> None:
        """The wheels' velocity servo, called by pymunk before it solves the contacts (the C servo,
        ``navcli/servo.c``, makes the same calls)."""
        cp = self._cp_body
        a = chipmunk.cpBodyGetAngle(cp)  # body.angle, .velocity, .angular_velocity without pymunk's wrappers
        chipmunk.cpBodySetVelocity(cp, (self._ve * math.cos(a), self._ve * math.sin(a)))
        chipmunk.cpBodySetAngularVelocity(cp, self._we)

    @property
    def time(self) -> float:
        """Simulated seconds since the start (a whole number of physics steps)."""
        return self.time_ns / 1e9

    @property
    def time_ns(self) -> int:
        """Simulated time in integer nanoseconds (the log's clock: exact, no float drift)."""
        return self._substeps * PHYSICS_DT_NS

    @property
    def pose(self) -> Pose:
        """Ground-truth pose of the robot (read from pymunk once per physics step)."""
        cached = self._pose
        if cached is not None and cached[0] == self._substeps:
            return cached[1]
        p = chipmunk.cpBodyGetPosition(self._cp_body)
        pose = Pose(p.x, p.y, wrap_angle(chipmunk.cpBodyGetAngle(self._cp_body)))
        self._pose = (self._substeps, pose)
        return pose

    @property
    def path_length(self) -> float:
        """Metres travelled, summed control tick by control tick: the path through the poses the
        log holds, a pose a tick (the wheels' slip, drawn per physics step, jitters the robot by
        fractions of a millimetre within a tick, most of all while it turns on the spot; summed step
        by step, that jitter would count as travel). A tick stopped between two steps (Ctrl-C,
        SIGTERM) has its steps counted as the straight line to where the robot is, so the path
        length always agrees with the pose a run ends at."""
        path, x, y = self._trail
        p = self.body.position
        return path + math.hypot(p.x - x, p.y - y)

    @property
    def speed(self) -> tuple[float, float]:
        """The drive's current (v, omega)."""
        return self._v, self._w

    def step(self, v: float, omega: float) -> list[Bump]:
        """Advance one control tick (CONTROL_DT) with the command (v m/s, omega rad/s); return new bumps.

        The command is clipped to the robot's limits and reached at bounded acceleration.
        """
        lim = self.robot
        v = min(max(v, -self.max_speed), self.max_speed)
        omega = min(max(omega, -lim.max_turn_rate), lim.max_turn_rate)
        dt = PHYSICS_DT
        dv, dw = lim.max_accel * dt, lim.max_turn_accel * dt
        start = self.pose
        cp_space, cp_body, contacts = self._cp_space, self._cp_body, self._contacts
        bumps: list[Bump] = []
        self._bumps = bumps
        touching = False
        slip, servo = self.slip, self._servo
        factors = slip.factors() if slip.noise > 0 else None
        for i in range(PHYSICS_SUBSTEPS):
            self._v += min(max(v - self._v, -dv), dv)
            self._w += min(max(omega - self._w, -dw), dw)
            if factors is None:
                self._ve, self._we = self._v, self._w
            else:
                self._ve, self._we = slip.executed(self._v, self._w, factors[2 * i], factors[2 * i + 1])
            # Space.step's call: runs the servo, and _begin/_separate when a contact starts or ends
            if servo is None:
                chipmunk.cpSpaceStep(cp_space, dt)
            else:
                servo[2](servo[0], servo[1], self._ve, self._we, dt)
            self._substeps += 1
            if contacts:
                touching = True
        self.touching = touching
        path, x, y = self._trail
        p = chipmunk.cpBodyGetPosition(cp_body)
        self._trail = (path + math.hypot(p.x - x, p.y - y), p.x, p.y)  # one assignment: never half made
        self.odometry.update(*motion_between(start, self.pose))
        return bumps

    def _other(self, arbiter: pymunk.Arbiter) -> tuple[pymunk.Shape, int]:
        """The shape the robot touches, and the index of the robot's own in ``arbiter.shapes``."""
        a, b = arbiter.shapes
        return (b, 0) if a.body is self.body else (a, 1)

    def _begin(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        """A contact starts (inside the step, after pymunk moved the body): a bump, unless the same
        thing was let go of less than BUMP_REARM ago."""
        other, mine = self._other(arbiter)
        self._contacts.add(other)
        now = (self._substeps + 1) * PHYSICS_DT_NS / 1e9  # the time at the end of this step
        last = self._last_touch.get(other)
        if last is not None and now - last < BUMP_REARM:
            return
        pts = arbiter.contact_point_set.points
        if not pts:
            return
        q = pts[0].point_a if mine == 0 else pts[0].point_b
        p = self.body.position
        bearing = wrap_angle(math.atan2(q.y - p.y, q.x - p.x) - wrap_angle(self.body.angle))
        self.bumps += 1
        self._bumps.append(Bump(now, self._names[other], (q.x, q.y), bearing))

    def _separate(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        """A contact ended during this step: the thing was last touched at the end of the step before."""
        other, _ = self._other(arbiter)
        self._contacts.discard(other)
        self._last_touch[other] = self.time

    def stop(self) -> None:
        """Halt the drive at once (at the end of a mission)."""
        self._v = self._w = self._ve = self._we = 0.0
