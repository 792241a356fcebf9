"""The scenario format as a JSON Schema (for editors: the YAML language server), built from the
same ranges the loader checks."""

from __future__ import annotations

import dataclasses
from typing import Any

from ..params import CLUSTERS, NAVIGATION, PERCEPTIONS, PILOT_NAMES
from .model import MAX_ID, MAX_ITEMS, NAME_RE, PILOT_BLOCK, RANGES
from .yaml_reader import MAX_SCALAR



# --- The format as a JSON Schema (for editors: the YAML language server) ---------------------
def _param_schema(f: dataclasses.Field) -> dict[str, Any]:
    """A parameter's JSON Schema from its declared range (:func:`navcli.params._p`)."""
    m = f.metadata
    if m.get("choices"):
        return {"enum": list(m["choices"]), "default": f.default}
    d: dict[str, Any] = {"type": "integer" if isinstance(f.default, int) else "number", "default": f.default}
    if m.get("above") is not None:
        d["exclusiveMinimum"] = m["above"]
    elif m.get("at_least") is not None:
        d["minimum"] = m["at_least"]
    if m.get("at_most") is not None:
        d["maximum"] = m["at_most"]
    if m.get("below") is not None:
        d["exclusiveMaximum"] = m["below"]
    return d



def json_schema() -> dict[str, Any]:
    """The scenario format as a JSON Schema (draft-07), built from the same ranges the loader
    checks. It catches what a schema can (fields, types, ranges, names); where things are
    (inside the arena, clear of obstacles, a reachable target) only the loader checks."""

    def num(key: str, description: str) -> dict:
        r = RANGES[key]
        d: dict[str, Any] = {"type": "number", "description": description, "maximum": r.hi}
        d["exclusiveMinimum" if r.lo_open else "minimum"] = r.lo
        return d

    def obj(props: dict, required: tuple[str, ...] = (), description: str = "") -> dict:
        d = {"type": "object", "properties": props, "additionalProperties": False, "required": list(required)}
        return d | ({"description": description} if description else {})

    point = {"type": "array", "description": "[x, y] in metres, inside the arena", "minItems": 2, "maxItems": 2,
             "items": num("point", "metres")}
    ident = {"type": ["string", "integer"], "description": "a landmark id", "minLength": 1, "maxLength": MAX_ID}
    target = obj({"at": point, "landmark": ident,
                  "line": {"type": "array", "minItems": 2, "maxItems": 2, "items": point,
                           "description": "a diverting target: the line to cross"},
                  "tolerance": num("target.tolerance", "metres: how close to a point target counts as reached")},
                 description="exactly one of at, landmark, line")
    target["oneOf"] = [{"required": [k]} for k in ("at", "landmark", "line")]
    return {
        "$schema": "http://json-schema.org/draft-07/schema#",
        "$id": "https://navcli/scenario-v1.schema.json",
        "title": "navcli scenario, version 1",
        "description": "Metres, seconds, degrees in keys ending _deg. Write exponents with a point and a sign "
                       "(1.0e-3): YAML 1.1 reads 1e-3 as text.",
        **obj({
            "version": {"const": 1},
            "name": {"type": "string", "pattern": f"^{NAME_RE.pattern}$", "not": {"pattern": "\n"},  # no trailing newline
                     "description": "names the log folder"},
            "description": {"type": "string", "maxLength": MAX_SCALAR},
            "arena": obj({"width": num("arena.width", "metres"), "height": num("arena.height", "metres")},
                         ("width", "height")),
            "robot": obj({"start": point, "heading_deg": num("robot.heading_deg", "degrees, counter-clockwise from +x"),
                          "radius": num("robot.radius", "metres"), "max_speed": num("robot.max_speed", "m/s")},
                         ("start",)),
            "target": target,
            "obstacles": {"type": "array", "maxItems": MAX_ITEMS, "items": {"oneOf": [
                obj({"circle": obj({"center": point, "radius": num("circle.radius", "metres")},
                                   ("center", "radius"))}, ("circle",)),
                obj({"segment": obj({"from": point, "to": point,
                                     "thickness": num("segment.thickness", "metres")}, ("from", "to"))},
                    ("segment",))]}},
            "landmarks": {"type": "array", "maxItems": MAX_ITEMS, "items": obj(
                {"id": ident, "at": point, "radius": num("landmark.radius", "metres")}, ("id", "at"))},
            "mission": obj({"pilot": {"enum": list(PILOT_NAMES)}, "perception": {"enum": list(PERCEPTIONS)},
                            "time_limit": num("mission.time_limit", "simulated seconds"),
                            "seed": {"type": "integer", "minimum": 0, "maximum": 2 ** 64 - 1}}),
            "noise": obj({"odometry": num("noise.odometry", "relative standard deviation"),
                          "odometry_drift_deg_per_m": num("noise.odometry_drift_deg_per_m",
                                                          "degrees of heading drift per metre driven, standard deviation"),
                          "vision_heading_deg": num("noise.vision_heading_deg", "degrees, standard deviation"),
                          "vision_distance": num("noise.vision_distance", "relative standard deviation")}),
            "camera": obj({k: num(f"camera.{k}", u) for k, u in (
                ("fov_deg", "degrees"), ("range", "metres"), ("pan_limit_deg", "degrees either side of ahead"),
                ("pan_speed_deg", "degrees per second"), ("look_time", "seconds of processing per look"))}),
            "pilot": obj({k: num(f"pilot.{k}", what) for k, what in PILOT_BLOCK.items()}),
            "navigation": obj({"cluster": {"enum": list(CLUSTERS), "description": "the thesis' GA-tuned bidding "
                                           "parameters: C1 (default, targets reachable directly) or C2 (behind obstacles)"}}
                              | {f.name: _param_schema(f) for f in dataclasses.fields(NAVIGATION)
                                 if not isinstance(f.default, tuple)}),
        }, ("version", "name", "arena", "robot", "target")),
    }
