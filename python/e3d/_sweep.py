"""Sweeps given as Python dicts: written out as the text of a sweep file.

The dict has the fields of a sweep file (docs/sweeps.md), with Python
values: ``{"scenes": ["two_rooms"], "learners": ["e3d", "uniform"],
"params": {"beta": {"scale": "Log", "from": 1, "to": 1000, "steps": 7}},
"sessions": 10, "trials": 5000, "seed": 2020}``. Each value is written in
the RON form its field takes (``True`` as ``true``, a learner, a metric,
``observe`` or a range's ``scale`` as a bare name, ...). The library
parses the text and checks it, so a mistake is reported as in a file, with
its line and column in the text that ``sweep_text`` returns.
"""

from __future__ import annotations

import math
import operator
import os
import re
from typing import Any, Callable, Mapping

import numpy as np

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# a metric's column name (results.csv) and its name in a sweep file
_CUMULATIVE = re.compile(r"^cumulative_reward(?:_at_(\d+)|\((\d+)\))$")
_PER_CONTEXT = re.compile(
    r"^(normalized_entropy_context|cumulative_reward_context|first_reward_trial_context)(?:_(\d+)|\((\d+)\))$"
)
# ``observe`` as the rest of the package spells it (run_episodes,
# EpisodeWorld), and the sweep file's variants
_OBSERVE = {"start": "StartContext", "state": "State", "blind": "Blind"}
# the fields a sweep file may leave out (``None`` leaves them out: their
# default), the fixed parameters (integers and numbers, not grid axes)
_DEFAULTED = ("name", "description", "use_reward", "params", "axes", "seed", "metrics",
              "commands", "observe", "closed_loop", "gamma")
_INTEGERS = ("sessions", "trials", "seed", "commands")


def _scalar(v: Any) -> Any:
    """A numpy scalar (or 0-d array) as the Python value it holds."""
    if hasattr(v, "dtype") and getattr(v, "shape", None) == () and hasattr(v, "item"):
        return v.item()
    return v


def _is_bool(v: Any) -> bool:
    return isinstance(v, bool) or type(v).__name__ in ("bool_", "bool") and hasattr(v, "dtype")


def _integer(v: Any, where: str) -> str:
    """An integer (a Python or numpy int, not a bool), as
    ``e3d.gym``'s and ``run_session``'s checks take one; its range is the
    library's to check (its message names the field)."""
    if not _is_bool(v) and not isinstance(v, (float, str, bytes)) and hasattr(v, "__index__"):
        return str(operator.index(v))
    raise TypeError(f"{where}: expected an integer, found {type(v).__name__} {v!r}")


def _number(v: Any, where: str) -> str:
    v = _scalar(v)
    if _is_bool(v):
        raise TypeError(f"{where}: expected a number, found a bool")
    if isinstance(v, int):
        return str(v)
    if isinstance(v, (str, bytes)):
        raise TypeError(f"{where}: expected a number, found {v!r}")
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise TypeError(f"{where}: expected a number, found {v!r}") from None
    if not math.isfinite(f):
        raise ValueError(f"{where}: expected a finite number, found {f}")
    return repr(f)


def _string(v: Any, where: str) -> str:
    if isinstance(v, os.PathLike):
        v = os.fspath(v)
    if not isinstance(v, str):
        hint = (
            " (a sweep names its scenes: write this one with its to_ron() to a .ron file and give the path)"
            if hasattr(v, "to_ron") else ""
        )
        raise TypeError(
            f"{where}: expected a string (a scene's name or path: str or os.PathLike), "
            f"found {type(v).__name__} {v!r}{hint}"
        )
    # every character RON would read otherwise is escaped: the backslash,
    # the quote and every control character (a line feed, ESC, ...)
    escaped = "".join(
        "\\\\" if c == "\\"
        else '\\"' if c == '"'
        else f"\\u{{{ord(c):04x}}}" if ord(c) < 0x20 or 0x7F <= ord(c) < 0xA0
        else c
        for c in v
    )
    return f'"{escaped}"'


def _key(k: Any, where: str) -> str:
    """A dict key written as a RON field name: an identifier, or refused
    (a key such as ``"trials: 5, seed"`` would otherwise write fields of
    its own into the text)."""
    if isinstance(k, str) and _NAME.fullmatch(k):
        return k
    raise ValueError(f"{where}: expected a field name such as trials or beta, found the key {k!r}")


def _name(v: Any, where: str, example: str, aliases: Mapping[str, str] = {}) -> str:
    """A bare RON identifier (an enum's variant): written as it is, for the
    library to check against the variants (its message lists them); text
    that is no identifier is refused here, as it would write more than a
    name into the text."""
    if isinstance(v, str):
        name: str = aliases.get(v, v)
        if _NAME.fullmatch(name):
            return name
    raise ValueError(f"{where}: expected a name such as {example}, found {v!r}")


def _learner(v: Any, where: str) -> str:
    return _name(v, where, "e3d or uniform")


def _metric(v: Any, where: str) -> str:
    if isinstance(v, str):
        m = _CUMULATIVE.match(v)
        if m is not None:
            # the results.csv column name is accepted for the metric
            return f"cumulative_reward({m.group(1) or m.group(2)})"
        m = _PER_CONTEXT.match(v)
        if m is not None:
            return f"{m.group(1)}({m.group(2) or m.group(3)})"
    return _name(v, where, "normalized_entropy or cumulative_reward(1000)")


def _observe(v: Any, where: str) -> str:
    return _name(v, where, '"state" or State (StartContext, State, Blind)', _OBSERVE)


def _bool(v: Any, where: str) -> str:
    v = _scalar(v)
    if not isinstance(v, bool):
        raise TypeError(f"{where}: expected True or False, found {type(v).__name__} {v!r}")
    return "true" if v else "false"


def _values(v: Any, where: str) -> str:
    """A parameter's values: a number, a list of numbers or a range."""
    if isinstance(v, Mapping):
        fields = []
        for k, x in v.items():
            name = _key(k, where)
            if name == "scale":
                fields.append(f"scale: {_name(x, where + '.scale', 'Log or Linear')}")
            elif name == "steps":
                fields.append(f"steps: {_integer(x, where + '.steps')}")
            else:
                fields.append(f"{name}: {_number(x, where + '.' + name)}")
        return "(" + ", ".join(fields) + ")"
    if hasattr(v, "tolist"):
        v = v.tolist()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_number(x, where) for x in v) + "]"
    return _number(v, where)


def _params(v: Any, where: str) -> str:
    if not isinstance(v, Mapping):
        raise TypeError(f"{where}: expected a dict of parameters, found {type(v).__name__} {v!r}")
    fields = []
    for p, x in v.items():
        name = _key(p, where)
        at = f"{where}.{name}"
        if x is None:
            continue  # the default
        if name == "k":
            text = _integer(x, at)
        elif name in ("sigma", "rarity", "goal_progress", "initial"):
            text = _number(x, at)
        else:
            text = _values(x, at)
        fields.append(f"{name}: {text}")
    return "(" + ", ".join(fields) + ")"


def _axes(v: Any, where: str) -> str:
    """The scene axes: a dict of scene field paths to their values."""
    if not isinstance(v, Mapping):
        raise TypeError(f"{where}: expected a dict of scene field paths to values, "
                        f"such as {{'joints.j1.damping': [0.1, 1.0]}}, found {type(v).__name__} {v!r}")
    items = (f"{_string(p, where)}: {_values(x, f'{where}[{p!r}]')}" for p, x in v.items())
    return "{" + ", ".join(items) + "}"


def _list(v: Any, item: Callable[[Any, str], str], where: str) -> str:
    if hasattr(v, "tolist"):
        v = v.tolist()
    if isinstance(v, Mapping):
        raise TypeError(f"{where}: expected a list, found a dict {v!r}")
    if isinstance(v, (str, bytes, os.PathLike)) or not hasattr(v, "__iter__"):
        v = [v]
    return "[" + ", ".join(item(x, where) for x in v) + "]"


def _ron(v: Any, where: str) -> str:
    """Any value in its RON form (for a field the library does not know, so
    that its message is about the field and not the value)."""
    v = _scalar(v)
    if v is None:
        return "None"
    if isinstance(v, bool):
        return _bool(v, where)
    if isinstance(v, (str, os.PathLike)):
        return _string(v, where)
    if isinstance(v, (int, float)):
        return _number(v, where)
    if isinstance(v, Mapping):
        return "(" + ", ".join(f"{_key(k, where)}: {_ron(x, where)}" for k, x in v.items()) + ")"
    if hasattr(v, "tolist"):
        v = v.tolist()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_ron(x, where) for x in v) + "]"
    raise TypeError(f"{where}: expected a number, a string, a bool, a list or a dict, found {type(v).__name__}")


_FIELDS: dict[str, Callable[[Any, str], str]] = {
    "name": _string,
    "description": _string,
    "scenes": lambda v, k: _list(v, _string, k),
    "learners": lambda v, k: _list(v, _learner, k),
    "use_reward": lambda v, k: _list(v, _bool, k),
    "params": _params,
    "axes": _axes,
    "sessions": _integer,
    "trials": _integer,
    "seed": _integer,
    "metrics": lambda v, k: _list(v, _metric, k),
    "commands": _integer,
    "observe": _observe,
    "closed_loop": _bool,
    "gamma": _number,
}


def sweep_text(sweep: Mapping[str, Any]) -> str:
    """The text of a sweep file (RON) holding the sweep ``sweep`` (a dict
    with the fields of a sweep file, docs/sweeps.md).

    Each value is written in its field's RON form: ``scenes``, ``name``,
    ``description`` strings (or paths); ``learners`` and ``metrics`` names
    (``"e3d"``, ``"normalized_entropy"``, ``"cumulative_reward(1000)"`` or
    the column name ``"cumulative_reward_at_1000"``); ``use_reward`` and
    ``closed_loop`` bools (Python's or numpy's); ``sessions``, ``trials``,
    ``seed``, ``commands`` integers (not bools or floats); ``gamma`` a
    number; ``observe`` the file's ``StartContext``, ``State``, ``Blind``
    or, as ``run_episodes`` spells them, ``"start"``, ``"state"``,
    ``"blind"``. A parameter is a number, a list of numbers or a range
    ``{"scale": "Log", "from": 1, "to": 1000, "steps": 7}`` (``k`` an
    integer; ``sigma``, ``rarity``, ``goal_progress``, ``initial`` a number);
    ``axes`` a dict of scene field paths (``Scene.with_``'s) to such values; a single
    value where a list is expected is taken as a list of one; ``None`` (a
    field or a parameter) is its default. A value of the wrong type
    raises ``TypeError`` naming its field; a name the library does not
    know (``observe: "Nope"``) is written as it is and refused by the
    library with the names it knows, as in a file. Unknown fields are
    passed on, for the library to refuse with its message.
    """
    if not isinstance(sweep, Mapping):
        raise TypeError(f"expected a dict of a sweep's fields, found {type(sweep).__name__}")
    fields = []
    for key, v in sweep.items():
        k = _key(key, "sweep")
        if v is None and k in _DEFAULTED:
            continue
        text = _FIELDS.get(k, _ron)(v, k)
        fields.append(f"    {k}: {text},")
    return "Sweep(\n" + "\n".join(fields) + "\n)\n"


def _cell(parse: Callable[[str], Any], s: str, missing: Any) -> Any:
    try:
        return parse(s)
    except ValueError:
        return missing


def columns(header: str, rows: list[str]) -> dict[str, Any]:
    """``results.csv``'s header and rows as the dict of columns ``run_sweep``
    returns: ``scene``, ``learner`` and ``failure`` lists of str,
    ``use_reward`` bool, ``session`` int64 (-1 if empty), ``seed`` uint64,
    the others float64 (NaN where the cell is empty)."""
    cells = [r.split(",") for r in rows]
    out: dict[str, Any] = {}
    for j, name in enumerate(header.split(",")):
        col = [c[j] if j < len(c) else "" for c in cells]
        if name in ("scene", "learner", "failure"):
            out[name] = col
        elif name == "use_reward":
            out[name] = np.array([s == "true" for s in col], dtype=bool)
        elif name in ("session", "seed"):
            missing = -1 if name == "session" else 0
            out[name] = np.array([_cell(int, s, missing) for s in col],
                                 dtype=np.int64 if name == "session" else np.uint64)
        else:
            out[name] = np.array([_cell(float, s, np.nan) for s in col], dtype=np.float64)
    return out
