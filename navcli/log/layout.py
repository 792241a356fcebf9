"""The Foxglove layout that comes with navcli (``navcli layout``).

Built once with the SDK's layout builder (:mod:`foxglove.layouts`): a 3D panel in the 2D top-down
view on frame ``world`` with the scene topics (:data:`SHOWN` on; the :data:`LAYERS` listed, off), a
Plot of the bids per resource, a Plot of the pilot's forces and turn, the events Log and the raw
summary. Two forms are written:

- ``sdk``: the SDK's own JSON (``Layout.to_json``), for Foxglove's notebook widget and tools that
  read that schema;
- ``app`` (default): the layout file format that Foxglove's *Import from file…* reads (the format
  the app exports: ``configById`` and a tree of splits), which Lichtblick and Foxglove Studio 1.x
  import too. It is converted from the same SDK objects (the SDK has no such export).
  Each panel carries its title under both apps' keys (``foxglovePanelTitle``,
  ``lichtblickPanelTitle``), and the 3D panel preloads the transforms, which Lichtblick otherwise
  recommends in an alert and without which, after a seek, it draws the beliefs (frame
  ``base_link``) displaced from the truth.
"""

from __future__ import annotations

import json
from typing import Any

from .format import (
    BIDS_TOPIC,
    CAMERA_SCENE_TOPIC,
    EVENTS_TOPIC,
    MAP_REGIONS_TOPIC,
    MAP_SCENE_TOPIC,
    MEMORY_SCENE_TOPIC,
    MEMORY_SUPPORTS_TOPIC,
    PILOT_TOPIC,
    ROBOT_BODY_TOPIC,
    ROBOT_PATH_TOPIC,
    ROBOT_SCENE_TOPIC,
    SUMMARY_TOPIC,
    WORLD_SCENE_TOPIC,
)

SHOWN = (WORLD_SCENE_TOPIC, ROBOT_PATH_TOPIC, ROBOT_BODY_TOPIC, CAMERA_SCENE_TOPIC, MEMORY_SCENE_TOPIC, MAP_SCENE_TOPIC)
"""The default view, legible at any time of a long run: the truth (the arena), the robot, its path and
its beliefs (the memory's and the map's 70 % cuts)."""
LAYERS = (MEMORY_SUPPORTS_TOPIC, MAP_REGIONS_TOPIC, ROBOT_SCENE_TOPIC)
"""Listed in the 3D panel, off until a user switches them on: the memory's supports, the map's
regions and beta-units, the pilot's forces and grown obstacles. Drawn filled or wide, after a few
minutes they cover the whole room."""
SCENE_TOPICS = SHOWN + LAYERS
BID_PATHS = tuple(f"{BIDS_TOPIC}.{r}.{s}" for r in ("motion", "camera") for s in ("pilot", "navigation"))
FORCE_PATHS = tuple(f"{PILOT_TOPIC}.{f}" for f in ("net.x", "net.y", "repulsive.x", "target.x", "turn_deg"))
_APP_PANEL = {"ThreeDee": "3D", "Log": "RosOut"}  # SDK panel type -> the app's


def build(arena: tuple[float, float] = (8.0, 8.0)):
    """The layout as :mod:`foxglove.layouts` objects; ``arena`` (m) centres the top-down view."""
    import foxglove.layouts as fl

    w, h = arena
    three_d = fl.ThreeDeePanel(
        title="Arena (2D top-down, frame world)",
        config=fl.ThreeDeeConfig(
            follow_tf="world",
            follow_mode="follow-none",
            camera_state=fl.ThreeDeeCameraState(
                perspective=False,
                distance=1.5 * max(w, h),
                phi=0.0,
                theta_offset=0.0,
                target_offset=(w / 2, h / 2, 0.0),
            ),
            topics={t: {"visible": t in SHOWN} for t in SCENE_TOPICS},  # type: ignore[misc]  # the SDK takes the JSON form
        ),
    )

    def plot(title: str, paths: tuple[str, ...]):
        return fl.PlotPanel(
            title=title,
            config=fl.PlotConfig(
                paths=[fl.PlotSeries(value=p, enabled=True, timestamp_method="receiveTime") for p in paths],
                show_legend=True,
                legend_display="floating",
                is_synced=True,
                x_axis_val="timestamp",
            ),
        )

    return fl.Layout(
        content=fl.SplitContainer(
            direction="row",
            items=[
                fl.SplitItem(proportion=1.2, content=three_d),
                fl.SplitItem(
                    proportion=1.0,
                    content=fl.SplitContainer(
                        direction="column",
                        items=[
                            fl.SplitItem(content=plot("Bids per resource", BID_PATHS)),
                            fl.SplitItem(content=plot("Pilot forces (force units) and turn (deg)", FORCE_PATHS)),
                            fl.SplitItem(
                                content=fl.SplitContainer(
                                    direction="row",
                                    items=[
                                        fl.SplitItem(
                                            content=fl.LogPanel(
                                                title="Events",
                                                config=fl.LogConfig(topic_to_render=EVENTS_TOPIC, min_log_level=1),
                                            )
                                        ),
                                        fl.SplitItem(
                                            content=fl.RawMessagesPanel(
                                                title="Summary",
                                                config=fl.RawMessagesConfig(topic_path=SUMMARY_TOPIC, expansion="all"),
                                            )
                                        ),
                                    ],
                                )
                            ),
                        ],
                    ),
                ),
            ],
        )
    )


def sdk_json(arena: tuple[float, float] = (8.0, 8.0)) -> dict[str, Any]:
    return json.loads(build(arena).to_json())


def app_json(arena: tuple[float, float] = (8.0, 8.0)) -> dict[str, Any]:
    """The same layout in the app's import format: each panel's config under ``<Type>!<id>`` in
    ``configById``, and the split tree as nested binary splits with percentages."""
    config_by_id: dict[str, Any] = {}

    def node(n: dict) -> Any:
        if n["type"] == "panel":
            kind = _APP_PANEL.get(n["panelType"], n["panelType"])
            key = f"{kind}!{len(config_by_id) + 1}"
            config = n.get("config", {})
            if kind == "3D":  # seeking: the transforms preloaded, so beliefs in base_link are drawn where they were;
                # no frame names over the robot (world, base_link and camera written across it), no line from the
                # world's origin to the robot
                config = config | {
                    "scene": config.get("scene", {})
                    | {"transforms": {"enablePreloading": True, "showLabel": False, "lineWidth": 0}}
                }
            # Foxglove reads foxglovePanelTitle, Lichtblick lichtblickPanelTitle: both, so each shows the title
            titles = {"foxglovePanelTitle": n["title"], "lichtblickPanelTitle": n["title"]} if n.get("title") else {}
            config_by_id[key] = config | titles
            return key
        items = n["items"]
        first, rest = items[0], items[1:]
        if not rest:
            return node(first["content"])
        total = sum(i["proportion"] for i in items)
        head = node(first["content"])
        second = (
            node({"type": "split", "direction": n["direction"], "items": rest})
            if len(rest) > 1
            else node(rest[0]["content"])
        )
        return {
            "direction": n["direction"],
            "first": head,
            "second": second,
            "splitPercentage": round(100 * first["proportion"] / total, 1),
        }

    tree = node(sdk_json(arena)["content"])
    return {
        "configById": config_by_id,
        "globalVariables": {},
        "userNodes": {},
        "playbackConfig": {"speed": 1},
        "layout": tree,
    }
