"""Sweeps given as Python dicts: written out as the text of a sweep file.

The dict has the fields of a sweep file (docs/sweeps.md), with Python
values: ``{"scenes": ["two_rooms"], "learners": ["e3d", "uniform"],
"params": {"beta": {"scale": "Log", "from": 1, "to": 1000, "steps": 7}},
"sessions": 10, "trials": 5000, "seed": 2020}``. The library parses the
text and checks it, so a mistake is reported as in a file, with its line
and column in the text that ``sweep_text`` returns.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any, Mapping

# fields whose strings are RON identifiers (enum variants), not strings
_IDENTIFIER_LISTS = ("learners", "metrics")
_CUMULATIVE = re.compile(r"^cumulative_reward(?:_at_(\d+)|\((\d+)\))$")


def _number(v: Any, where: str) -> str:
    if isinstance(v, bool):
        raise TypeError(f"{where}: expected a number, found a bool")
    if isinstance(v, int):
        return str(v)
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
    if isinstance(k, str) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", k):
        return k
    raise ValueError(f"{where}: expected a field name such as trials or beta, found the key {k!r}")


def _identifier(v: Any, where: str) -> str:
    if isinstance(v, str):
        m = _CUMULATIVE.match(v)
        if m is not None:
            # the results.csv column name is accepted for the metric
            return f"cumulative_reward({m.group(1) or m.group(2)})"
        if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", v):
            return v
    raise ValueError(f"{where}: expected a name such as e3d or normalized_entropy, found {v!r}")


def _values(v: Any, where: str) -> str:
    """A parameter's values: a number, a list of numbers or a range."""
    if isinstance(v, Mapping):
        fields = []
        for k, x in v.items():
            if k == "scale":
                fields.append(f"scale: {_identifier(x, where + '.scale')}")
            elif k == "steps":
                fields.append(f"steps: {int(x)}")
            else:
                fields.append(f"{_key(k, where)}: {_number(x, where + '.' + str(k))}")
        return "(" + ", ".join(fields) + ")"
    if isinstance(v, (list, tuple)) or hasattr(v, "tolist"):
        items = v.tolist() if hasattr(v, "tolist") else v
        if not isinstance(items, list):
            return _number(items, where)
        return "[" + ", ".join(_number(x, where) for x in items) + "]"
    return _number(v, where)


def _list(v: Any, item: Any, where: str) -> str:
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        v = [v]
    return "[" + ", ".join(item(x, where) for x in v) + "]"


def _bool(v: Any, where: str) -> str:
    if hasattr(v, "item"):
        v = v.item()
    if not isinstance(v, bool):
        raise TypeError(f"{where}: expected True or False, found {v!r}")
    return "true" if v else "false"


def sweep_text(sweep: Mapping[str, Any]) -> str:
    """The text of a sweep file (RON) holding the sweep ``sweep`` (a dict
    with the fields of a sweep file, docs/sweeps.md).

    Strings of ``learners`` and ``metrics`` are names (``"e3d"``,
    ``"normalized_entropy"``, ``"cumulative_reward(1000)"`` or the column
    name ``"cumulative_reward_at_1000"``); a parameter is a number, a list
    of numbers or a range ``{"scale": "Log", "from": 1, "to": 1000,
    "steps": 7}``; a single value where a list is expected is taken as a
    list of one. Unknown fields are passed on, for the library to refuse
    with its message.
    """
    if not isinstance(sweep, Mapping):
        raise TypeError(f"expected a dict of a sweep's fields, found {type(sweep).__name__}")
    fields = []
    for key, v in sweep.items():
        k = _key(key, "sweep")
        if k in ("name", "description"):
            text = _string(v, k)
        elif k == "scenes":
            text = _list(v, _string, k)
        elif k in _IDENTIFIER_LISTS:
            text = _list(v, _identifier, k)
        elif k == "use_reward":
            text = _list(v, _bool, k)
        elif k == "params":
            if not isinstance(v, Mapping):
                raise TypeError(f"params: expected a dict of parameters, found {v!r}")
            text = "(" + ", ".join(f"{_key(p, 'params')}: {_values(x, 'params.' + str(p))}" for p, x in v.items()) + ")"
        elif k in ("sessions", "trials", "seed"):
            if isinstance(v, bool) or int(v) != v:
                raise TypeError(f"{k}: expected an integer, found {v!r}")
            text = str(int(v))
        else:
            text = _string(v, k) if isinstance(v, str) else repr(v)
        fields.append(f"    {k}: {text},")
    return "Sweep(\n" + "\n".join(fields) + "\n)\n"
