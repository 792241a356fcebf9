"""Where a plugin's code meets navcli's: every call into it is guarded, and what it returns is
checked before navcli takes it.

A plugin pilot is run as a subclass of its own class made here (:func:`pilot_class`) that
overrides each method navcli calls on it and the plugin implements (``avoid``, and ``decide`` or
``execute`` where the plugin replaces navcli's), a plugin policy's agent in an :class:`Agent`
wrapper. Each such call:

- raises whatever the plugin's code raised, or the call itself (a method with the wrong
  signature), as the plugin's :class:`~.registry.PluginError`, naming the file and line in the
  plugin where it happened;
- has its result checked, field by field, the ``info`` by msgspec against the log's ``/pilot``
  schema (a control tick's hot path: the guard and the checks together take some 8 % of the
  instructions of a tick whose ``info`` is as large as the potential-field pilot's, most of them
  in the ``info``'s check, which grows with it; ``benchmarks/plugin_boundary.py --instructions``): an ``avoid`` returning something else than an
  :class:`~navcli.pilot.Avoidance`, a :class:`~navcli.bidding.Move` or a bid that is not a finite
  number in its range (``Move._make((nan, nan))`` skips the constructor's own check), a bid under
  another bidder's name, are the plugin's faults too;
- is given at most ``robot.decision_limit_s`` seconds of wall-clock time (:class:`Deadline`):
  one that takes longer ends the run as ``error``, its log closed. In the main thread a timer
  (``signal.setitimer``, ``SIGALRM``) interrupts the call where it is (a ``time.sleep``, a loop);
  elsewhere (a thread of one's own, a Dask worker's thread), where no signal can be delivered, a
  call that returns late is caught when it returns, and one that never returns is not caught.
  The clock decides only whether a run errs: it never enters the log or a normal run's course.
"""

from __future__ import annotations

import math
import signal
import types
import threading
import time
from typing import Any, Callable

import msgspec

from ..bidding import PURPOSES, RESOURCES, SYSTEMS, Bid, Look, Move
from ..log.format import plugin_pilot_message
from ..pilot import Avoidance, Pilot, PilotOutput
from .names import NAME_RE, NAME_RULE
from .registry import BLAME, Component, PluginError, failed


class TooSlow(BaseException):
    """Raised in a plugin's frame when its decision's time is up. A ``BaseException``, so that the
    plugin's own ``except Exception`` does not swallow it; :meth:`Deadline.call` turns it into the
    plugin's :class:`~.registry.PluginError`."""


class Overran(PluginError):
    """A plugin's call took more than ``robot.decision_limit_s`` of wall-clock time."""


class Deadline:
    """The wall-clock limit of one plugin's calls (see the module docstring): ``call(fn, *args)``
    runs ``fn`` under it. ``limit_s`` is ``robot.decision_limit_s``."""

    def __init__(self, c: Component, limit_s: float) -> None:
        self.c = c
        self.limit_s = limit_s
        _install()

    def call(self, fn: Callable[..., Any], *args: Any) -> Any:
        """``fn(*args)``, raising what it raises as the plugin's (``fn``: the plugin's function, named
        for a fault with no line of the plugin's in its traceback, a call its signature refused)."""
        alarm = _arm(self.limit_s)
        t0 = time.monotonic()
        try:
            try:
                out = fn(*args)
            finally:  # inside the handlers below: an alarm that comes as the call returns is still caught
                if alarm:
                    _disarm()
        except TooSlow:
            raise self.too_slow() from None
        except PluginError:
            raise
        except Exception as e:
            raise failed(self.c, e, at=fn) from e
        if time.monotonic() - t0 > self.limit_s:  # a call the timer could not interrupt (see _arm)
            raise self.too_slow()
        return out

    def make(self, cls: Any, *args: Any, **kw: Any) -> Any:
        """``cls(*args, **kw)``, the plugin's class (or navcli's subclass of it) made, under
        :meth:`call`'s guard."""
        try:
            return self.call(lambda: cls(*args, **kw))
        except Overran:
            raise
        except PluginError as e:
            cause = e.__cause__
            if cause is None:
                raise
            raise failed(self.c, cause, "could not be made", at=self.c.cls) from cause

    def too_slow(self) -> Overran:
        return Overran(
            f"{self.c.label} took more than robot.decision_limit_s = {self.limit_s:g} s of wall-clock time "
            f"for one decision, and was stopped. {BLAME} (a slow plugin may be "
            f"given more: --param robot.decision_limit_s=SECONDS)"
        )


# --- the timer --------------------------------------------------------------------------------
_deadline: list[float] = []  # the monotonic time the call under way must end by (one at most)
_previous: list[Any] = [None]  # the SIGALRM handler ours stands in front of


def _on_alarm(signum: int, frame: Any) -> None:
    """SIGALRM: a plugin's call past its deadline is stopped; any other alarm (the executor's, a
    retried Ctrl-C's) goes to the handler that was there before ours."""
    if _deadline and time.monotonic() >= _deadline[0] - 1e-3:
        _deadline.clear()
        raise TooSlow
    previous = _previous[0]
    if callable(previous):
        previous(signum, frame)


def _install() -> None:
    """Put :func:`_on_alarm` in front of the SIGALRM handler there is, in the main thread (where a
    handler can be set): once for each run's plugins (a worker process's own handler, set when it
    starts, then stands behind it)."""
    if threading.get_ident() != threading.main_thread().ident:
        return
    handler = signal.getsignal(signal.SIGALRM)
    if handler is not _on_alarm:
        _previous[0] = handler
        signal.signal(signal.SIGALRM, _on_alarm)


def _arm(limit_s: float) -> bool:
    """Start the timer of a call that may take ``limit_s``: in the main thread, where :func:`_install`
    put our handler and no other alarm is pending (that alarm is left to come; the call is then
    timed when it returns). True when armed."""
    if threading.get_ident() != threading.main_thread().ident:
        return False
    pending, interval = signal.setitimer(signal.ITIMER_REAL, limit_s)
    if pending:  # someone else's alarm is pending: theirs, not ours
        signal.setitimer(signal.ITIMER_REAL, pending, interval)
        return False
    _deadline[:] = [time.monotonic() + limit_s]
    return True


def _disarm() -> None:
    _deadline.clear()
    signal.setitimer(signal.ITIMER_REAL, 0.0)


# --- what a plugin returns ----------------------------------------------------------------------
def _number(x: object) -> bool:
    """A finite float or int, as the log's encoder writes one (a numpy scalar, a bool, a string are
    not: ``float(x)`` makes one)."""
    return (type(x) is float or type(x) is int) and math.isfinite(x)


def move_problem(m: object, max_speed: float) -> str | None:
    """What is wrong with ``m`` as a :class:`Move` a plugin offers, or None."""
    if not isinstance(m, Move) or len(m) != 2:
        return f"a move that is no navcli.Move: {m!r}"
    if not (_number(m.heading) and _number(m.speed)):
        return f"a move that is not two finite numbers: {m!r} (Move(heading, speed) checks it; Move._make does not)"
    if abs(m.speed) > max_speed + 1e-9:
        return f"a move at {m.speed:g} m/s, faster than robot.max_speed = {max_speed:g}"
    return None


def avoidance_problem(a: object, bid_cap: float, max_speed: float, schemas: Any) -> str | None:
    """What is wrong with ``a`` as what a pilot's ``avoid`` returns, or None."""
    if not isinstance(a, Avoidance):
        return f"returned {_short(a)}, not a navcli.pilot.Avoidance"
    if a.move is not None:
        problem = move_problem(a.move, max_speed)
        if problem is not None:
            return f"returned {problem}"
    if not _number(a.bid):
        return f"returned a bid of {_short(a.bid)}, not a finite number"
    if a.bid > bid_cap + 1e-12:
        return f"returned a motion bid of {a.bid:g}, above the Pilot's cap {bid_cap:g} (pilot.bid_cap)"
    if a.bid < 0.0:
        return f"returned a motion bid of {a.bid:g}, below 0"
    problem = returned_info_problem(a.info, schemas)
    if problem is not None:
        return problem
    if a.arrows and not all(
        isinstance(r, tuple) and len(r) == 3 and type(r[0]) is str and _number(r[1]) and _number(r[2]) for r in a.arrows
    ):
        return f"returned arrows {_short(a.arrows)}, not a list of (name, fx, fy) with finite numbers"
    return None


def info_type(c: Component) -> Any:
    """What a pilot plugin's ``info`` may hold, as a ``msgspec.Struct`` to convert it to: every
    ``/pilot`` field of its log's (its ``Info``'s and navcli's) but the command, each optional,
    an enumerated one as a ``Literal`` of its values (the log's schema holds them as ``enum``).
    msgspec takes what its encoder writes: a numpy scalar is refused here as the log would refuse
    it. Fields that none declares are left to the run (:func:`undeclared` names them)."""
    import typing

    import msgspec

    from ..log.format import ENUM
    from ..pilot import ENUMERATIONS

    def literal(t: Any) -> Any:
        if typing.get_origin(t) is typing.Annotated:
            for meta in typing.get_args(t)[1:]:
                name = (getattr(meta, "extra_json_schema", None) or {}).get(ENUM)
                if name is not None:
                    return typing.Literal[tuple(ENUMERATIONS[name])]
            return t
        if typing.get_origin(t) in (typing.Union, types.UnionType):
            return typing.Union[tuple(literal(a) for a in typing.get_args(t))]
        return t

    hints = typing.get_type_hints(plugin_pilot_message(c), include_extras=True)
    fields = [
        (k, typing.Union[literal(t), msgspec.UnsetType], msgspec.UNSET) for k, t in hints.items() if k != "command"
    ]
    return msgspec.defstruct(f"PilotInfo+{c.group}", fields)


def pilot_fields(c: Component) -> frozenset[str] | None:
    """The fields a plugin pilot's ``/pilot`` message may hold: navcli's and its ``Info``'s (None
    for navcli's own pilots, whose fields the log format declares)."""
    return None if c.builtin else frozenset(plugin_pilot_message(c).__struct_fields__)


def undeclared(c: Component, info: dict[str, Any]) -> PluginError:
    """The fault of a plugin pilot whose ``info`` holds fields that neither navcli's log format nor
    its ``Info`` declares (so cannot go into ``/pilot``)."""
    extra = sorted(set(info) - (pilot_fields(c) or frozenset()))
    return PluginError(
        f"{c.label} wrote {', '.join(extra)} into /pilot, which its Info does not declare: declare every "
        f"field its avoid() returns in its class's Info (a msgspec.Struct); `navcli plugins check pilot "
        f"{c.asked}` shows what else it gets wrong"
    )


def info_problem(info: dict[str, Any], kind: Any) -> str | None:
    """What is wrong with a pilot's ``info`` as ``/pilot`` fields (``kind``: :func:`info_type`), or
    None."""
    for k in info:
        if type(k) is not str:
            return f"an info with the key {k!r}: /pilot's field names are text"
    try:
        msgspec.convert({k: v for k, v in info.items() if v is not None}, kind)  # `is`: a numpy array has no ==
    except msgspec.ValidationError as e:
        return f"an info that breaks the log's /pilot schema: {e}"
    return None


def returned_info_problem(info: object, kind: Any) -> str | None:
    """What is wrong with the ``info`` a pilot's method returned (a dict that :func:`info_problem`
    passes), said as what it returned, or None."""
    if type(info) is not dict:
        return f"returned an info of {_short(info)}, not a dict of /pilot's field names to values"
    problem = info_problem(info, kind)
    return f"returned {problem}" if problem is not None else None


def bid_problem(b: object, bidder: str, max_speed: float) -> str | None:
    """What is wrong with ``b`` as a bid of ``bidder``'s, or None."""
    if not isinstance(b, Bid) or len(b) != 4:
        return f"a bid that is no navcli.Bid: {_short(b)}"
    if b.bidder != bidder:
        return f"a bid under the name {b.bidder!r}, not its own {bidder!r}"
    if b.resource not in RESOURCES or not (_number(b.value) and 0.0 <= b.value <= 1.0):
        return f"a bid for {b.resource!r} of {b.value!r} (a resource of {', '.join(RESOURCES)}, a number in [0, 1])"
    if b.resource == "motion":
        return move_problem(b.action, max_speed)
    if not (isinstance(b.action, Look) and _number(b.action.pan) and b.action.purpose in PURPOSES):
        return f"a camera bid whose action is no navcli.Look with a finite pan and a purpose: {_short(b.action)}"
    return None


def _short(x: object) -> str:
    r = repr(x)
    return r if len(r) <= 120 else r[:117] + "..."


def wrong(c: Component, method: Callable[..., Any], problem: str) -> PluginError:
    """The :class:`~.registry.PluginError` of a plugin whose ``method`` returned what navcli does not
    take (``problem``), at the method's definition."""
    return PluginError(f"{c.label}: its {_where(method)} {problem}. {_blame(c)}")


def _where(method: Callable[..., Any]) -> str:
    from .registry import definition

    name = getattr(method, "__name__", "method")
    at = definition(method)
    return f"{name}() (defined at {at})" if at else f"{name}()"


def _blame(c: Component) -> str:
    return f"{BLAME}: `navcli plugins check {c.kind} {c.asked}` tests it against navcli's contract"


# --- the guarded pilot and agent -------------------------------------------------------------
def pilot_class(c: Component, limit_s: float) -> type:
    """The class navcli runs ``c``'s pilot as: a subclass of it whose ``avoid`` (and ``decide``,
    ``execute``, where the plugin replaces navcli's) are guarded and checked (module docstring).
    Its name and module are the plugin class's."""
    cls = c.cls
    deadline = Deadline(c, limit_s)
    schemas = info_type(c)
    own = {m for m in ("avoid", "decide", "execute") if getattr(cls, m) is not getattr(Pilot, m)}

    def avoid(self: Any, beliefs: Any, obstacles: Any, request: Any) -> Any:
        method = cls.avoid
        a = deadline.call(method, self, beliefs, obstacles, request)
        problem = avoidance_problem(a, self.params.bid_cap, self.max_speed, schemas)
        if problem is not None:
            raise wrong(c, method, problem)
        return a

    def decide(self: Any, beliefs: Any, request: Any = None) -> Any:
        method = cls.decide
        out = deadline.call(method, self, beliefs, request)
        problem = None if isinstance(out, PilotOutput) else f"returned {_short(out)}, not a navcli.pilot.PilotOutput"
        for b in out.bids if problem is None else ():
            problem = bid_problem(b, SYSTEMS[0], self.max_speed)
            if problem is not None:
                break
        if problem is None:
            problem = returned_info_problem(out.info, schemas)
        if problem is not None:
            raise wrong(c, method, problem)
        return out

    def execute(self: Any, winner: Any) -> Any:
        method = cls.execute
        out = deadline.call(method, self, winner)
        if not (isinstance(out, tuple) and len(out) == 2 and _number(out[0]) and _number(out[1])):
            raise wrong(c, method, f"returned {_short(out)}, not a wheel command (v, omega) of finite numbers")
        return out

    methods = {"avoid": avoid, "decide": decide, "execute": execute}
    body: dict[str, Any] = {m: methods[m] for m in own}
    body |= {"__module__": cls.__module__, "__qualname__": cls.__qualname__, "__doc__": cls.__doc__}
    return type(cls.__name__, (cls,), body)


class Agent:
    """A plugin policy's Navigation agent as navcli runs it: its ``bid`` guarded and checked (module
    docstring), its ``name`` the one checked when it was made."""

    def __init__(self, c: Component, agent: Any, name: str, limit_s: float, max_speed: float) -> None:
        self.agent = agent
        self.name = name
        self._c = c
        self._deadline = Deadline(c, limit_s)
        self._max_speed = max_speed

    def bid(self, s: Any) -> list[Bid]:
        method = self.agent.bid
        bids = self._deadline.call(method, s)
        if not isinstance(bids, (list, tuple)):
            raise wrong(self._c, method, f"returned {_short(bids)}, not a list of navcli.Bid")
        for b in bids:
            problem = bid_problem(b, self.name, self._max_speed)
            if problem is not None:
                raise wrong(self._c, method, f"returned {problem}")
        return list(bids)

    def __getattr__(self, name: str) -> Any:  # what else navcli or a test reads of the agent
        if name == "agent":  # not yet set (a copy being made): no agent to ask
            raise AttributeError(name)
        return getattr(self.agent, name)


NAVCLI_AGENTS = ("target-tracker", "risk-manager", "distance-estimator", "rescuer", "learning-agent")
"""The names navcli's own Navigation agents bid under (a plugin's agent must not take one)."""


def agent_name(c: Component, agent: Any, taken: set[str]) -> str:
    """The name ``agent`` (``c``'s, just made) bids under, checked: a name the log can carry
    (:data:`~.names.NAME_RULE`), not one of navcli's agents' and not ``taken``."""

    name = getattr(agent, "name", None)
    if not isinstance(name, str) or not NAME_RE.fullmatch(name):
        problem = f"its agent's name is {_short(name)}, not {NAME_RULE}"
    elif name in NAVCLI_AGENTS or name in taken:
        problem = f"its agent's name {name!r} is taken (by one of navcli's agents or another plugin's)"
    else:
        return name
    raise PluginError(f"{c.label}: {problem}: its bids and the log's /navigation go by it. {_blame(c)}")


def make_pilot(c: Component, limit_s: float, *args: Any, **kw: Any) -> Any:
    """An instance of ``c``'s pilot as navcli runs it (:func:`pilot_class`), made with ``args`` and
    ``kw``."""
    return Deadline(c, limit_s).make(pilot_class(c, limit_s), *args, **kw)


def make_agents(components: tuple[Component, ...], setup: Any, limit_s: float) -> tuple[Agent, ...]:
    """The agents of the plugin policies ``components`` as navcli runs them (:class:`Agent`), each
    made with ``setup`` (an :class:`~navcli.navigation.situation.AgentSetup`) holding its own
    parameters."""
    agents: list[Agent] = []
    for c in components:
        made = Deadline(c, limit_s).make(c.cls, setup._replace(own_params=setup.params.plugin(c.group)))
        name = agent_name(c, made, {a.name for a in agents})
        agents.append(Agent(c, made, name, limit_s, setup.params.robot.max_speed))
    return tuple(agents)
