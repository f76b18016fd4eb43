"""The arguments of ``run_session``, ``run_sessions``, ``run_episodes`` and
``run_sweep``, checked once for their type, each named by the user's own
keyword; the ranges of the hyper-parameters are the library's to check
(``e3d::Params::validate``), the rest the native module's."""

import math
import os
import operator
from typing import Any, Iterable, Optional

import numpy as np

MAX_SESSIONS = 100_000
"""The most sessions one call runs: the cap of ``e3d run --sessions``."""


def integer(name: str, value: Any, low: Optional[int] = 0, high: int = 2**64 - 1) -> int:
    """An int or numpy integer in ``[low, high]`` (``low`` None: any):
    ``TypeError`` for anything else (a float, a str, a bool, an array),
    ``ValueError`` naming ``name`` out of range."""
    if isinstance(value, (bool, float, np.bool_)) or getattr(value, "ndim", 0) != 0 \
            or not hasattr(value, "__index__"):
        raise TypeError(f"{name}: expected an integer, found {type(value).__name__}")
    v = operator.index(value)
    if low is not None and not low <= v <= high:
        top = "2^64 - 1" if high == 2**64 - 1 else high
        raise ValueError(f"{name} = {value}: expected an integer from {low} to {top}")
    return v


def number(name: str, value: Any) -> float:
    """A number as a float; an int too large for one is an infinity of its
    sign (which the range check then refuses by name), not Python's bare
    ``OverflowError``; anything else is a ``TypeError`` naming ``name``."""
    t = type(value)
    if not (hasattr(t, "__float__") or hasattr(t, "__index__")) or isinstance(value, (str, bytes)):
        raise TypeError(f"{name}: expected a number, found {t.__name__}")
    try:
        return float(value)
    except OverflowError:
        return -math.inf if value < 0 else math.inf


def seeds(value: Any) -> Optional[list[int]]:
    """None, or an iterable of at most ``MAX_SESSIONS`` seeds (``seeds[i]`` named)."""
    if value is None:
        return None
    try:
        items: Iterable[Any] = iter(value)
    except TypeError:
        raise TypeError(f"seeds: expected a sequence of integers, found {type(value).__name__}") from None
    out = []
    for i, s in enumerate(items):
        if i == MAX_SESSIONS:
            raise ValueError(f"seeds: expected at most {MAX_SESSIONS} seeds (the cap of `e3d run --sessions`)")
        out.append(integer(f"seeds[{i}]", s))
    return out


def optional(name: str, value: Any, low: int) -> Optional[int]:
    """None, or an integer from ``low``."""
    return None if value is None else integer(name, value, low)


def hyper(alpha: Any, beta: Any, lambda_: Any, eta: Any, epsilon: Any, k: Any = 2,
          sigma: Any = 0.1, rarity: Any = 0.5, goal_progress: Any = 0.0) -> dict[str, float]:
    """The hyper-parameters by the library's names (``e3d::Params``), each a
    number (``k`` an integer from 1); the native module has the library
    check their ranges."""
    return {"alpha": number("alpha", alpha), "beta": number("beta", beta),
            "lambda": number("lambda_", lambda_), "eta": number("eta", eta),
            "epsilon": number("epsilon", epsilon), "k": float(integer("k", k, 1)),
            "sigma": number("sigma", sigma), "rarity": number("rarity", rarity),
            "goal_progress": number("goal_progress", goal_progress)}


def cache_folder(path: Any) -> Any:
    """``table_cache``: refused when it exists and is not a folder (the
    outcomes would be computed and not kept, silently)."""
    if path is not None and os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"table_cache = {os.fspath(path)}: exists and is not a folder; expected "
                         "the folder of the outcome cache (created if missing)")
    return path
