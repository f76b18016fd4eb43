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


def json_lines(data: Any) -> tuple[str, list[str]]:
    """``data`` as JSON text, one value a line, and the path each line holds
    (``world.Physics.bodies[2].mass``)."""
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

    value("", "", data, "", 1)
    return "\n".join(lines) + "\n", paths


def _through_variants(at: Any, key: str) -> Any:
    """``at`` stepped through the one-key dicts of enum variants (such as
    ``{"Physics": {...}}``) down to the first dict that holds ``key``, or
    that is not a variant's."""
    while isinstance(at, dict) and key not in at and len(at) == 1:
        (variant, inner), = at.items()
        if not (isinstance(variant, str) and variant[:1].isascii() and variant[:1].isupper()):
            break
        at = inner
    return at


#: the fields of a scene (docs/scenes.md), those it may leave out included
_SCENE_FIELDS = ("name", "description", "world", "slots", "command", "reward")


def _set_path(data: dict[str, Any], path: str, value: Any) -> None:
    """``value`` at ``path`` in a scene's dict: dot-separated keys; a list's
    element by index or by its ``name``; a one-key dict (an enum variant)
    may be stepped through without naming it; and a path whose first key
    is not a field of the scene starts in the world (``bodies.puck.mass``)."""
    def bad(msg: str) -> SceneError:
        return _error(f"with_: {path}: {msg}", "<with_>", path)

    keys = path.split(".")
    if any(not k for k in keys):
        raise bad("expected dot-separated names, e.g. bodies.puck.linear_damping")
    at: Any = data
    if keys[0] in _SCENE_FIELDS and keys[0] not in data:
        # an optional field the scene leaves out (`slots`, the check of
        # the number of slots): set, then checked with the scene
        if len(keys) > 1:
            raise bad(f"the scene has no `{keys[0]}` to step into: set `{keys[0]}` whole")
        data[keys[0]] = value
        return
    if keys[0] not in data:
        if "world" not in data:
            raise bad("the scene has no world")
        at = data["world"]
    for i, key in enumerate(keys):
        at = _through_variants(at, key)
        if isinstance(at, dict):
            if key not in at:
                raise bad(f"no field `{key}` here; its fields: {', '.join(at)}")
            if i + 1 == len(keys):
                at[key] = value
                return
            at = at[key]
        elif isinstance(at, list):
            if key.isascii() and key.isdigit():
                idx = int(key)
                if idx >= len(at):
                    raise bad(f"index {idx}: the list has {len(at)} items")
            else:
                names = [x["name"] for x in at if isinstance(x, dict) and isinstance(x.get("name"), str)]
                if key not in names:
                    raise bad(f"no item named `{key}`; the names: {', '.join(names)}")
                idx = names.index(key)
            if i + 1 == len(keys):
                at[idx] = value
                return
            at = at[idx]
        else:
            raise bad(f"`{key}`: {at!r} has no fields")


def with_(scene: Scene, overrides: dict[Any, Any]) -> Scene:
    """``Scene.with_``: a copy of ``scene`` with ``{path: value}`` overrides."""
    d = scene.to_dict()
    for k, v in overrides.items():
        if not isinstance(k, str):
            raise TypeError("with_: keys must be paths (str)")
        _set_path(d, k, v)
    return Scene.from_dict(d)


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
