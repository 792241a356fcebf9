"""What a plugin gets wrong, told to its author (in the spirit of Gymnasium's ``env_checker``).

Every lookup takes a quick look at the class (:func:`~.contract.contract_problems`: its kind, its
``Params``, its ``Info``); :func:`check` exercises it: made with navcli's defaults, fed a handful of
situations (open floor, an obstacle ahead, a wall across, inside a prohibited area, the target
behind, a bump), its output checked against navcli's contract and its ``/pilot`` messages against
their schema, fed the same situations again by a second instance (the same output: no hidden
randomness), and run for a short mission with each perception, every message of its log checked
against the log's schemas (:mod:`navcli.analysis.schemas`). ``navcli plugins check KIND NAME``
prints the result.

The checker runs missions, so it sits above the runner and the configuration, with the commands:
the package :mod:`navcli.plugins` (the registry, which the configuration imports) does not import
it; ``from navcli.plugins.checker import check``.
prints the result.
"""

from __future__ import annotations

import math
from typing import Any

from ..log.format import encode, pilot_message, plugin_pilot_message
from .contract import contract_problems
from .registry import BLAME, Component, Kind, NavcliError, PluginError, locate

CHECK_SCENARIO = "open-arena"
"""The bundled room the checker's missions run in (an empty room: any pilot should cross it)."""
CHECK_SECONDS = 20.0
"""Simulated seconds of each of the checker's missions."""


def _situations() -> list[tuple[str, Any, Any]]:
    """(what, beliefs, the Navigation system's request) the checker feeds a pilot, egocentric."""
    from ..beliefs import Beliefs, Bump, KnownObstacle
    from ..bidding import Move
    from ..geometry import Pose

    odo = Pose(1.0, 1.0, 0.0)
    ahead = Move(0.0, 0.3)
    fence = KnownObstacle("o1", (1.0, 1.5), (1.0, -1.5), 0.025)
    return [
        ("open floor", Beliefs(0.0, odo, (3.0, 0.0), None, ()), ahead),
        (
            "an obstacle ahead",
            Beliefs(0.1, odo, (3.0, 0.0), None, (KnownObstacle("o0", (0.8, 0.0), (0.8, 0.0), 0.15),)),
            ahead,
        ),
        ("a fence across", Beliefs(0.2, odo, (3.0, 0.2), None, (fence,)), Move(0.07, 0.3)),
        (
            "a wall across",
            Beliefs(0.3, odo, (3.0, 0.0), None, (KnownObstacle("wall-n", (0.6, 3.0), (0.6, -3.0), 0.0, True),)),
            ahead,
        ),
        (
            "inside a prohibited area",
            Beliefs(0.4, odo, (3.0, 0.0), None, (KnownObstacle("o2", (0.35, 0.1), (0.35, 0.1), 0.1),)),
            ahead,
        ),
        ("the target behind", Beliefs(0.5, odo, (-2.0, 0.5), None, (fence,)), Move(math.pi - 0.2, 0.3)),
        ("no target", Beliefs(0.6, odo, None, None, (fence,)), None),
        (
            "a bump",
            Beliefs(
                0.7, odo, (3.0, 0.0), None, (fence,), bumps=(Bump(0.65, "obstacle 1", (2.0, 1.0), 0.0),), touching=True
            ),
            ahead,
        ),
    ]


def _pilot_problems(c: Component) -> list[str]:
    import msgspec
    import numpy as np

    from ..bidding import SYSTEMS, Move
    from ..params import PILOT, ROBOT
    from .boundary import Overran, make_pilot

    P = c.params_class
    own = P() if P is not None else None
    outputs: list[list[Any]] = [[], []]
    problems: list[str] = []
    message = plugin_pilot_message(c)
    for run in (0, 1):
        try:  # as a run makes it: its calls guarded and what they return checked (navcli.plugins.boundary)
            pilot = make_pilot(c, ROBOT.decision_limit_s, PILOT, ROBOT, own_params=own, rng=np.random.default_rng(0))
        except PluginError as e:
            return [
                f"cannot be made as navcli makes it, cls(PilotParams(), RobotParams(), own_params=..., rng=...): {e}"
            ]
        for what, beliefs, request in _situations():
            try:
                out = pilot.decide(beliefs, request)
                winner = next((b for b in out.bids if b.resource == "motion"), None)
                v, w = pilot.execute(winner)
            except Exception as e:  # said once, by the first instance
                if run == 0:
                    said = _said(e) if isinstance(e, PluginError) else f"raised {type(e).__name__}: {e}"
                    problems.append(f"{what}: {said}")
                if isinstance(e, Overran):  # every situation would take as long
                    return problems
                continue
            outputs[run].append((out.bids, out.info, v, w))
            if run:
                continue
            for b in out.bids:
                if b.bidder != SYSTEMS[0]:
                    problems.append(f"{what}: a bid under the name {b.bidder!r}, not the Pilot's {SYSTEMS[0]!r}")
                if b.resource == "motion" and b.value > PILOT.bid_cap + 1e-12:
                    problems.append(f"{what}: a motion bid of {b.value:g}, above the Pilot's cap {PILOT.bid_cap:g}")
                if isinstance(b.action, Move) and abs(b.action.speed) > ROBOT.max_speed + 1e-9:
                    problems.append(f"{what}: a move at {b.action.speed:g} m/s, faster than robot.max_speed")
            if not (math.isfinite(v) and math.isfinite(w)):
                problems.append(f"{what}: the wheel command ({v}, {w}) is not finite")
            try:
                msgspec.json.decode(encode(pilot_message(out.info, v, math.degrees(w))), type=message)
            except (msgspec.ValidationError, TypeError) as e:
                problems.append(f"{what}: its /pilot message breaks the schema its Info declares: {e}")
    if not problems and outputs[0] != outputs[1]:
        problems.append(
            "two instances fed the same situations decided differently: draw random numbers from "
            "self.rng (the run's generator), never from a global one"
        )
    return problems


def _policy_problems(c: Component) -> list[str]:
    import numpy as np

    from ..fuzzy import FuzzyPoint
    from ..navigation.situation import AgentSetup, Situation
    from ..params import ROBOT, Params
    from .boundary import Overran, make_agents

    P = c.params_class
    own = P() if P is not None else None
    params = Params() if own is None else Params().with_plugin(c.group, own)
    setup = AgentSetup(params, own, math.radians(100.0), "target", np.random.default_rng(0))
    try:  # as a run makes it: its calls guarded and what they return checked (navcli.plugins.boundary)
        (agent,) = make_agents((c,), setup, ROBOT.decision_limit_s)
    except PluginError as e:
        return [f"cannot be made as navcli makes it, cls(AgentSetup(...)): {_said(e)}"]
    problems = []
    for what, beliefs, _ in _situations():
        target = FuzzyPoint(beliefs.target[0], beliefs.target[1], (0.3, 0.2, 0.1, 0.0)) if beliefs.target else None
        s = Situation(beliefs, target, None, "memory" if target else "none", 0.05 if target else 1.0)
        try:
            agent.bid(s)
        except PluginError as e:
            problems.append(f"{what}: {_said(e)}")
            if isinstance(e, Overran):  # every situation would take as long
                return problems
        except Exception as e:
            problems.append(f"{what}: bid() raised {type(e).__name__}: {e}")
    return problems


def _said(e: Exception) -> str:
    """A plugin's fault without the advice to run the checker, which is running."""
    return str(e).partition(f". {BLAME}")[0]


def _mission_problems(c: Component) -> list[str]:
    """A short mission in :data:`CHECK_SCENARIO` with each perception, logged, and every JSON
    message of its log checked against the schema its log holds for it (what a viewer and
    ``navcli report`` rely on)."""
    import tempfile
    from pathlib import Path

    from ..analysis.schemas import log_problems
    from ..config import RunSpec
    from ..experiments.reproduce import SCENARIOS
    from ..runner import run_mission
    from ..scenario import load_scenario

    sc = load_scenario(SCENARIOS / f"{CHECK_SCENARIO}.yaml")
    problems: list[str] = []
    for perception in ("oracle", "vision"):
        what = f"a {CHECK_SECONDS:g} s mission in {CHECK_SCENARIO} ({perception})"
        spec = RunSpec.build(
            sc,
            perception=perception,
            time_limit=CHECK_SECONDS,
            pilot=c.asked if c.kind == "pilot" else None,
            navigation=c.asked if c.kind == "policy" else None,
        )
        with tempfile.TemporaryDirectory(prefix="navcli-check-") as folder:
            log = Path(folder) / "check.mcap"
            try:
                run_mission(spec, out=log)
            except NavcliError as e:
                problems.append(f"{what}: {e}")
                continue
            count, broken = log_problems(log)
        if broken:
            problems.append(
                f"{what}: {len(broken)} breaks of the log's schemas in its {count} messages, the first: {broken[0]}"
            )
    return problems


def check(kind: Kind, name: str) -> list[str]:
    """Everything the plugin ``name`` of ``kind`` gets wrong against navcli's contract (see the
    module docstring); empty when it passes. Raises :class:`~navcli.plugins.UnknownPlugin` for a
    name that is not found."""

    try:
        c = locate(kind, name)
    except PluginError as e:
        return [str(e)]
    if c.builtin:
        return []
    problems = contract_problems(c)
    if problems:
        return problems
    problems = _pilot_problems(c) if kind == "pilot" else _policy_problems(c)
    return problems or _mission_problems(c)
