"""Scenes as Python data, the parts in Python: ``json_lines`` writes a
scene's dict as JSON, one value a line with the path each line holds, for
``Scene.from_dict`` (the library parses and checks it; an error's line
names the path), and ``with_`` sets overrides by path.

The dict form is the scene's serde form: a struct is a dict of its
fields, an enum variant with data a dict of one key, the variant's name
(``{"Physics": {...}}``, ``{"Ball": {"radius": 0.1}}``), a variant
without data its name (``"Dynamic"``), a tuple a list."""

import json
import math
from typing import Any

from ._e3d import Scene, SceneError

MAX_DEPTH = 100
"""The deepest nesting of dicts and lists a scene's data may have (a
scene's is under 15; a value that holds itself would recurse for ever)."""


def _error(message: str, file: str, path: str) -> SceneError:
    e = SceneError(message)
    e.file, e.field = file, path
    return e


def _leaf(path: str, v: Any) -> str:
    """A scalar as JSON (numpy scalars through ``int()`` / ``float()``)."""
    if v is None or isinstance(v, (bool, str)):
        return json.dumps(v)
    if isinstance(v, int):
        if -2**63 <= v < 2**64:
            return str(v)
        raise _error(f"<dict>: {path}: {v} is out of range for any field", "<dict>", path)
    if isinstance(v, float) or hasattr(v, "__float__"):
        if hasattr(v, "__index__") and -2**63 <= int(v) < 2**63:
            return str(int(v))
        x = float(v)
        if not math.isfinite(x):
            shown = "NaN" if x != x else str(x)
            raise _error(f"<dict>: {path}: {shown} is not a finite number", "<dict>", path)
        return repr(x)
    raise TypeError(f"{path}: expected a dict, list, str, number, bool or None, "
                    f"found {type(v).__name__}")


def json_lines(data: Any, at: str = "") -> tuple[str, list[str]]:
    """``data`` as JSON text, one value a line, and the path each line holds
    (``world.Physics.bodies[2].mass``), starting at ``at``."""
    lines: list[str] = []
    paths: list[str] = []

    def value(path: str, head: str, v: Any, tail: str, depth: int) -> None:
        if depth > MAX_DEPTH:
            at = path or "<scene>"
            raise _error(f"<dict>: {at}: nested more than {MAX_DEPTH} levels deep "
                         "(a dict or list that holds itself?)", "<dict>", path)
        if isinstance(v, dict):
            lines.append(head + "{")
            paths.append(path)
            for i, (k, x) in enumerate(v.items()):
                if not isinstance(k, str):
                    raise TypeError(f"{path or '<scene>'}: keys must be strings, found {k!r}")
                sub = f"{path}.{k}" if path else k
                value(sub, json.dumps(k) + ": ", x, "," if i + 1 < len(v) else "", depth + 1)
            lines.append("}" + tail)
        elif isinstance(v, (list, tuple)):
            lines.append(head + "[")
            paths.append(path)
            for i, x in enumerate(v):
                value(f"{path}[{i}]", "", x, "," if i + 1 < len(v) else "", depth + 1)
            lines.append("]" + tail)
        else:
            lines.append(head + _leaf(path, v) + tail)
        paths.append(path)

    value(at, "", data, "", 1)
    return "\n".join(lines) + "\n", paths


def _world_point(body: dict[str, Any], q: Any) -> tuple[float, float]:
    """A point of ``body`` (in its own frame) in world coordinates (the
    library's ``to_world_point``)."""
    (x, y), a = body["position"], body["angle"]
    s, c = math.sin(a), math.cos(a)
    return (x + c * q[0] - s * q[1], y + s * q[0] + c * q[1])


def _body_geometry(b: dict[str, Any]) -> dict[str, Any]:
    """A body's name, kind, pose, shape, radius and outline (world coordinates)."""
    (shape, f), = b["shape"].items()
    if shape == "Ball":
        points = [tuple(b["position"])]
    elif shape == "Cuboid":
        x, y = f["width"] / 2.0, f["height"] / 2.0
        points = [_world_point(b, q) for q in ((-x, -y), (x, -y), (x, y), (-x, y), (-x, -y))]
    else:
        points = [_world_point(b, q) for q in (f["points"] if shape == "Polyline" else (f["a"], f["b"]))]
    return {"name": b["name"], "kind": b["kind"].lower(), "position": tuple(b["position"]),
            "angle": b["angle"], "shape": shape.lower(), "radius": f.get("radius", 0.0),
            "points": points}


def geometry(scene: Scene) -> dict[str, Any]:
    """``Scene.geometry``: what the scene's picture draws, as plain data."""
    rows, cols, lo, hi = scene.effect_grid
    d: dict[str, Any] = {
        "effect_grid": {"rows": rows, "cols": cols, "min": lo, "max": hi},
        "reward_cells": [divmod(e, cols) for e, r in enumerate(scene.reward_table()) if r != 0.0]}
    world = scene.to_dict()["world"]
    if "Grid" in world:
        g = world["Grid"]
        d.update(kind="grid", start=tuple(g["start"]),
                 walls=[(tuple(a), tuple(b)) for a, b in g["walls"]])
        return d
    p = world["Physics"]
    bodies = {b["name"]: b for b in p["bodies"]}
    d["kind"] = "physics"
    d["bodies"] = [_body_geometry(b) for b in p["bodies"]]
    d["joints"] = [{"name": j["name"], "parent": j["parent"], "child": j["child"],
                    "position": _world_point(bodies[j["child"]], j["child_anchor"])}
                   for j in p["joints"]]
    # an effect of features (cart_pole's joints) tracks no point
    tracked = p["effect"].get("body")
    d["tracked_point"] = _world_point(bodies[tracked], p["effect"]["point"]) if tracked else None
    d["tracked_body"] = tracked
    return d
