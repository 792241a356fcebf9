"""The scenes of the log: what Foxglove's 3D panel draws (the arena, the robot, the Pilot's forces
and grown obstacles, the visual memory, the Map Manager's map), built as SDK messages from the
run's values. Colours and heights are our design; lengths are metres, angles radians.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from foxglove.messages import (
    ArrowPrimitive,
    Color,
    CubePrimitive,
    CylinderPrimitive,
    LinePrimitive,
    LinePrimitiveLineType,
    Point3,
    Pose as FxPose,
    Quaternion,
    SceneEntity,
    TextPrimitive,
    Timestamp,
    Vector3,
)

from ..params import SCENE_REFRESH

if TYPE_CHECKING:
    from ..geometry import Pose
    from ..navigation.map_manager import MapSnapshot
    from ..scenario import Scenario
    from ..vision.visual_memory import Remembered

ARROW_MIN = 2.0  # force units: weaker forces are not drawn (2 cm at 100 units per metre)
HEIGHT = 0.5  # m: drawn height of walls, obstacles and landmarks
_GREY, _RED, _BLUE, _GREEN = (
    Color(r=0.55, g=0.55, b=0.6, a=1.0),
    Color(r=0.85, g=0.3, b=0.25, a=1.0),
    Color(r=0.2, g=0.45, b=0.9, a=1.0),
    Color(r=0.2, g=0.75, b=0.3, a=0.6),
)
ROBOT, _ARROW = Color(r=0.95, g=0.75, b=0.1, a=0.8), Color(r=0.9, g=0.2, b=0.8, a=1.0)
_GROWN = Color(r=0.95, g=0.5, b=0.1, a=0.25)
FOV = Color(r=0.3, g=0.8, b=0.95, a=0.8)
_MEMORY_RGB = {
    "landmark": (0.2, 0.45, 0.9),
    "obstacle": (0.85, 0.3, 0.25),
    "bump": (1.0, 0.1, 0.1),
    "target": (0.2, 0.75, 0.3),
}
# a belief's disc faint (a viewer outlines it), so that the wide ones of a long run, overlapping, leave the truth,
# the robot and its path legible; its support's ring fainter still
_MEMORY = {k: (Color(r=r, g=g, b=b, a=0.15), Color(r=r, g=g, b=b, a=0.3)) for k, (r, g, b) in _MEMORY_RGB.items()}
_RING = [
    (math.cos(2 * math.pi * k / 16), math.sin(2 * math.pi * k / 16)) for k in range(16)
]  # a support ring's vertices
NO_TURN = Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)  # the yaw of 0, built once: most primitives are not turned
_ARROW_BASE = Vector3(x=0.0, y=0.0, z=0.35)  # m: where the force arrows start, in base_link
CAMERA_AT = Vector3(x=0.0, y=0.0, z=0.4)  # m: the camera frame's origin in base_link (its field of view's height)


def stamp(ns: int) -> Timestamp:
    return Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)


def yaw(theta: float) -> Quaternion:
    return Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2))


def place(x: float, y: float, theta: float = 0.0, z: float = 0.0) -> FxPose:
    return FxPose(position=Vector3(x=x, y=y, z=z), orientation=yaw(theta) if theta else NO_TURN)


def cylinder(x: float, y: float, radius: float, bottom: float, height: float, color: Color) -> CylinderPrimitive:
    """An upright cylinder (or flat disc) of ``radius`` standing on ``z = bottom`` at (x, y)."""
    d = 2 * radius
    return CylinderPrimitive(
        pose=place(x, y, z=bottom + height / 2),
        size=Vector3(x=d, y=d, z=height),
        bottom_scale=1.0,
        top_scale=1.0,
        color=color,
    )


def force_arrows(arrows: list[tuple[str, float, float]], ns: int) -> SceneEntity:
    """Egocentric force vectors as arrows in ``base_link`` (length scaled: 100 force units = 1 m)."""
    prims = []
    for _name, fx, fy in arrows:
        mag = math.hypot(fx, fy)
        if mag < ARROW_MIN:
            continue
        L = min(mag / 100.0, 1.5)
        prims.append(
            ArrowPrimitive(
                pose=FxPose(position=_ARROW_BASE, orientation=yaw(math.atan2(fy, fx))),
                shaft_length=max(L - 0.08, 0.01),
                shaft_diameter=0.025,
                head_length=0.08,
                head_diameter=0.07,
                color=_ARROW,
            )
        )
    return SceneEntity(timestamp=stamp(ns), frame_id="base_link", id="forces", frame_locked=True, arrows=prims)


def fan(fov: float, rng: float) -> list[Point3]:
    """The camera's field of view (``fov`` rad wide, ``rng`` m deep) in its frame: a closed fan."""
    pts = [Point3(x=0.0, y=0.0, z=0.0)]
    for k in range(9):
        a = -fov / 2 + fov * k / 8
        pts.append(Point3(x=rng * math.cos(a), y=rng * math.sin(a), z=0.0))
    pts.append(Point3(x=0.0, y=0.0, z=0.0))
    return pts


_MAP = Color(r=0.55, g=0.3, b=0.85, a=0.9)
_MAP_CUT = Color(r=0.55, g=0.3, b=0.85, a=0.25)  # a mapped landmark's 70 % cut: faint, as the memory's
_MAP_FAINT = Color(r=0.55, g=0.3, b=0.85, a=0.35)
_BLOCKED = Color(r=0.9, g=0.2, b=0.7, a=0.9)  # pink: apart from the true obstacles (red) in a plot
_DIVERTING = Color(r=0.1, g=0.8, b=0.3, a=1.0)
_DIVERTING_ENDED = Color(r=0.1, g=0.55, b=0.25, a=0.8)  # a diverting line the Rescuer is done with


_MAP_Z = 0.06  # m: the map's height, above the memory's discs


def _at_map(xy) -> Point3:
    return Point3(x=xy[0], y=xy[1], z=_MAP_Z)


def map_entities(m: MapSnapshot, diverting, ns: int) -> list[SceneEntity]:
    """The Map Manager's map in ``base_link`` (``/map/scene``, shown by default): each mapped
    landmark with the disc of its 70 % cut and its name, blocked edges in pink, the diverting
    line in green and those ended, named. Its regions and beta-units are a layer of their own
    (:func:`region_entities`). Not frame-locked: drawn every few seconds, a viewer keeps it where
    the robot was when it was drawn."""
    ts = stamp(ns)
    z = _MAP_Z
    P = _at_map
    marks = {k: (p.x, p.y) for k, p in m.landmarks.items()}
    cyl = [cylinder(p.x, p.y, max(p.radius(0.7), 0.05), z - 0.01, 0.02, _MAP_CUT) for p in m.landmarks.values()]
    texts = [
        TextPrimitive(
            pose=place(p.x, p.y, z=0.7), billboard=True, font_size=12.0, scale_invariant=True, color=_MAP, text=f"{k}'"
        )
        for k, p in m.landmarks.items()
    ]
    lines = []
    at = marks | m.vertices  # a blocked edge may end at an obstacle's point or a virtual landmark
    for u, v in m.blocked:
        if u in at and v in at:
            lines.append(
                LinePrimitive(
                    type=LinePrimitiveLineType.LineStrip, thickness=0.04, color=_BLOCKED, points=[P(at[u]), P(at[v])]
                )
            )
    for pa, pb, ending in m.tried:  # the diverting lines ended, thin, named by how they ended
        lines.append(
            LinePrimitive(
                type=LinePrimitiveLineType.LineStrip, thickness=0.02, color=_DIVERTING_ENDED, points=[P(pa), P(pb)]
            )
        )
        mid = ((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2)
        texts.append(
            TextPrimitive(
                pose=place(*mid, z=0.5),
                billboard=True,
                font_size=11.0,
                scale_invariant=True,
                color=_DIVERTING_ENDED,
                text=ending,
            )
        )
    if diverting is not None:
        lines.append(
            LinePrimitive(
                type=LinePrimitiveLineType.LineStrip,
                thickness=0.06,
                color=_DIVERTING,
                points=[P(diverting[0]), P(diverting[1])],
            )
        )
    return [
        SceneEntity(
            timestamp=ts, frame_id="base_link", id="map", frame_locked=False, cylinders=cyl, texts=texts, lines=lines
        )
    ]


def region_entities(m: MapSnapshot, ns: int) -> list[SceneEntity]:
    """The map's regions (``/map/regions``, a layer a user switches on): each triangle of
    landmarks, faint, and each beta-unit as lines from the encoded landmark to its three basis
    landmarks; drawn with :func:`map_entities`, in ``base_link``, not frame-locked."""
    P = _at_map
    marks = {k: (p.x, p.y) for k, p in m.landmarks.items()}
    lines = [
        LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=0.01, color=_MAP_FAINT, points=[P(v) for v in tri])
        for tri in m.regions
    ]
    for a, b, c, d in m.units:
        if d in marks and all(k in marks for k in (a, b, c)):
            lines.append(
                LinePrimitive(
                    type=LinePrimitiveLineType.LineList,
                    thickness=0.008,
                    color=_MAP_FAINT,
                    points=[P(marks[d]), P(marks[a]), P(marks[d]), P(marks[b]), P(marks[d]), P(marks[c])],
                )
            )
    return [SceneEntity(timestamp=stamp(ns), frame_id="base_link", id="regions", frame_locked=False, lines=lines)]


def memory_entities(memory: tuple[Remembered, ...], ns: int) -> list[SceneEntity]:
    """The visual memory in ``base_link`` (``/memory/scene``, shown by default): per remembered
    point a disc the size of its 70 % cut (the belief), beside the truth of ``/world/scene``; the
    supports, often 1-2 m wide, are a layer of their own (:func:`support_entities`). Not
    frame-locked: drawn every few seconds, a viewer keeps it where the robot was when it was drawn
    (frame-locked, it would drift along with the robot until the next drawing)."""
    ents = []
    ts = stamp(ns)
    for m in memory:
        cyl, lines = [], []
        color, _ = _MEMORY.get(m.kind, _MEMORY["obstacle"])
        for x, y, r70, _r0 in m.spots:
            cyl.append(cylinder(x, y, max(r70, 0.03), 0.015, 0.03, color))
        if len(m.spots) == 2:
            (ax, ay, *_), (bx, by, *_) = m.spots
            lines.append(
                LinePrimitive(
                    type=LinePrimitiveLineType.LineStrip,
                    thickness=0.03,
                    color=color,
                    points=[Point3(x=ax, y=ay, z=0.04), Point3(x=bx, y=by, z=0.04)],
                )
            )
        ents.append(
            SceneEntity(
                timestamp=ts, frame_id="base_link", id=f"memory-{m.key}", frame_locked=False, cylinders=cyl, lines=lines
            )
        )
    return ents


def support_entities(memory: tuple[Remembered, ...], ns: int) -> list[SceneEntity]:
    """The supports of the visual memory (``/memory/supports``, a layer a user switches on): per
    remembered point a faint thin ring of its support's radius, in an entity of the same id as
    its disc in ``/memory/scene`` (``memory-KEY``, its rings in the order of the discs)."""
    ts = stamp(ns)
    return [
        SceneEntity(
            timestamp=ts,
            frame_id="base_link",
            id=f"memory-{m.key}",
            frame_locked=False,
            lines=[
                LinePrimitive(
                    type=LinePrimitiveLineType.LineLoop,
                    thickness=0.01,
                    color=_MEMORY.get(m.kind, _MEMORY["obstacle"])[1],
                    points=[Point3(x=x + r0 * c, y=y + r0 * s, z=0.01) for c, s in _RING],
                )
                for x, y, _r70, r0 in m.spots
            ],
        )
        for m in memory
    ]


PATH_STEP = 0.1
"""m: the drawn path keeps a pose when the robot has moved this far from the last one kept (and
the last pose always): 10 points a metre, a few kilobytes for a room's mission, whatever its time."""
_PATH = Color(r=0.05, g=0.05, b=0.05, a=1.0)
PATH_PIXELS = 4.0  # the path's width on screen, whatever the zoom: wider than the 1-pixel outlines a viewer draws


PATH_EVERY_NS = 10 * round(SCENE_REFRESH * 1e9)
"""The path is drawn again when it has a new point, else at least this often (for a live viewer
that joins while the robot stands still): drawn every second whatever it held, the path of a long
run was the largest drawing of its log (3.6 kB a simulated second in trap-box)."""


def path_entity(points: list[tuple[float, float]], ns: int) -> SceneEntity:
    """The path driven so far (``/robot/path``, in ``world``), whole in every message, so a viewer
    that seeks finds all of it in the latest."""
    return SceneEntity(
        timestamp=stamp(ns),
        frame_id="world",
        id="path",
        lines=[
            LinePrimitive(
                type=LinePrimitiveLineType.LineStrip,
                thickness=PATH_PIXELS,
                scale_invariant=True,
                color=_PATH,
                points=[Point3(x=x, y=y, z=0.005) for x, y in points],
            )
        ],
    )


class PathDrawing:
    """The path for ``/robot/path``: told of every true position (:meth:`moved`), it keeps one
    :data:`PATH_STEP` from the last kept; :meth:`due` gives the drawing (to the last position) when
    a point was kept since the last, or :data:`PATH_EVERY_NS` has passed, else None."""

    def __init__(self, x: float, y: float):
        self.points = [(x, y)]
        self.last = (x, y)
        self._drawn = (0, -PATH_EVERY_NS)  # the points kept when it was last drawn, and when

    def moved(self, x: float, y: float) -> None:
        self.last = (x, y)
        kx, ky = self.points[-1]
        if (x - kx) ** 2 + (y - ky) ** 2 >= PATH_STEP * PATH_STEP:
            self.points.append((x, y))

    def due(self, ns: int) -> SceneEntity | None:
        kept, at = self._drawn
        if len(self.points) == kept and ns - at < PATH_EVERY_NS:
            return None
        self._drawn = (len(self.points), ns)
        return path_entity(self.points if self.last == self.points[-1] else self.points + [self.last], ns)


def grown(obstacles, pose: Pose, R: float, ns: int) -> SceneEntity:
    """The pilot's prohibited areas (section 3.1): known obstacles grown by R_min from their
    surface, drawn flat in ``world`` where the robot perceives them (egocentric positions placed
    with the true pose)."""
    cyl, cubes = [], []
    for o in obstacles:
        g = o.radius + R
        a = pose.to_world(o.a)
        cyl.append(cylinder(*a, g, 0.0, 0.01, _GROWN))
        if o.a != o.b:
            b = pose.to_world(o.b)
            cyl.append(cylinder(*b, g, 0.0, 0.01, _GROWN))
            cubes.append(
                CubePrimitive(
                    pose=place((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, math.atan2(b[1] - a[1], b[0] - a[0]), z=0.005),
                    size=Vector3(x=math.dist(a, b), y=2 * g, z=0.01),
                    color=_GROWN,
                )
            )
    return SceneEntity(timestamp=stamp(ns), frame_id="world", id="grown-obstacles", cylinders=cyl, cubes=cubes)


def arena_shapes(sc: Scenario) -> list[tuple[str, dict[str, list]]]:
    """The arena's entities (id, primitives), built once per run and stamped at each refresh."""
    W, H, t = sc.arena.width, sc.arena.height, 0.1
    walls = [
        CubePrimitive(pose=place(x, y, z=HEIGHT / 2), size=Vector3(x=sx, y=sy, z=HEIGHT), color=_GREY)
        for x, y, sx, sy in (
            (W / 2, -t / 2, W + 2 * t, t),
            (W / 2, H + t / 2, W + 2 * t, t),
            (-t / 2, H / 2, t, H),
            (W + t / 2, H / 2, t, H),
        )
    ]
    ents: list[tuple[str, dict[str, list]]] = [("walls", {"cubes": walls})]
    for o in sc.objects:
        if o.kind == "circle":
            ents.append((f"obstacle-{o.key[1:]}", {"cylinders": [cylinder(*o.a, o.radius, 0.0, HEIGHT, _RED)]}))
        elif o.kind == "segment":
            (ax, ay), (bx, by) = o.a, o.b
            ents.append(
                (
                    f"obstacle-{o.key[1:]}",
                    {
                        "cubes": [
                            CubePrimitive(
                                pose=place((ax + bx) / 2, (ay + by) / 2, math.atan2(by - ay, bx - ax), z=HEIGHT / 2),
                                size=Vector3(x=math.hypot(bx - ax, by - ay), y=2 * o.radius, z=HEIGHT),
                                color=_RED,
                            )
                        ]
                    },
                )
            )
        elif o.kind == "landmark":
            ents.append(
                (
                    f"landmark-{o.key}",
                    {
                        "cylinders": [cylinder(*o.a, o.radius, 0.0, HEIGHT, _BLUE)],
                        "texts": [
                            TextPrimitive(
                                pose=place(*o.a, z=HEIGHT + 0.15),
                                billboard=True,
                                font_size=14.0,
                                scale_invariant=True,
                                color=_BLUE,
                                text=o.key,
                            )
                        ],
                    },
                )
            )
    tg = sc.target
    target: dict[str, list]
    if tg.line is not None:
        (ax, ay), (bx, by) = tg.line
        target = {
            "lines": [
                LinePrimitive(
                    type=LinePrimitiveLineType.LineStrip,
                    thickness=0.05,
                    color=_GREEN,
                    points=[Point3(x=ax, y=ay, z=0.01), Point3(x=bx, y=by, z=0.01)],
                )
            ]
        }
    else:
        r = tg.tolerance
        target = {"cylinders": [cylinder(*tg.point, r, 0.0, 0.02, _GREEN)]}
    ents.append(("target", target))
    return ents
