"""The JSON messages of a tick as plain values (the fields of :mod:`navcli.log.format`'s
structs): what the recorder encodes into the log, and what :mod:`navcli.log.frames` keeps in
memory for a run's DataFrames. Every tick; plain dicts, built inline (docs/design.md, "Writing the
log")."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ..bidding import RESOURCES, SYSTEMS

if TYPE_CHECKING:
    from ..mission import Tick


_NO_BIDS = dict.fromkeys(SYSTEMS, 0.0)


def bids_record(t: Tick) -> dict[str, Any]:
    """The ``/bids`` message (a :class:`~navcli.messages.Bids` as plain values): fixed keys per
    resource so every value is plottable in Foxglove."""
    msg: dict[str, Any] = {r: {**_NO_BIDS, "actions": {}} for r in RESOURCES}
    for b in t.bids:
        per = msg[b.resource]
        per[b.bidder] = b.value
        per["actions"][b.bidder] = b.action.as_json()
    for r in RESOURCES:
        win = t.winners[r]
        if win is not None:
            msg[r]["winner"] = win.bidder
    agents: dict[str, dict[str, float]] = {}
    for b in t.agent_bids:
        per = agents.get(b.bidder)
        if per is None:
            per = agents[b.bidder] = {}
        per[b.resource] = b.value
    msg["agents"] = agents
    return msg


def navigation_record(t: Tick) -> dict[str, Any]:
    """The ``/navigation`` message (a :class:`~navcli.messages.Navigation` as plain values): every
    agent's bids, what was forwarded, and why."""
    nav = t.navigation
    assert nav is not None  # called for ticks with a Navigation system's output only
    agents: dict[str, dict[str, float]] = {}
    for b in nav.agent_bids:
        a = agents.get(b.bidder)
        if a is None:
            a = agents[b.bidder] = {"motion": 0.0, "camera": 0.0}
        if b.value > a[b.resource]:  # max(), as a test: no call
            a[b.resource] = b.value
    fwd: dict[str, Any] = {"motion": 0.0, "camera": 0.0}
    for b in nav.bids:
        fwd[b.resource] = b.value
        fwd[f"{b.resource}_agent"] = nav.forwarded_by[b.resource]
    msg = {"agents": agents, "forwarded": fwd, **nav.info, "diverting": nav.diverting}  # info: the scalar fields
    if nav.target is not None:
        msg["target"] = {"x": nav.target[0], "y": nav.target[1]}
    if nav.target_line is not None:
        (ax, ay), (bx, by) = nav.target_line
        msg["line_a"], msg["line_b"] = {"x": ax, "y": ay}, {"x": bx, "y": by}
    return msg


def vision_record(t: Tick) -> dict[str, Any]:
    """The ``/vision`` message (a :class:`~navcli.log.format.Vision` as plain values): the pan, the
    camera's state, the detections of an image taken this tick, and the purpose of the look being
    carried out (none while idle)."""
    pan, state, purpose = t.camera
    dets = t.detections
    vision = {
        "pan_deg": math.degrees(pan),
        "state": state,
        "image": dets is not None,
        "detections": {d.key or f"obstacle{i}": d.as_json() for i, d in enumerate(dets)} if dets else {},
    }
    if purpose is not None:
        vision["purpose"] = purpose
    return vision
