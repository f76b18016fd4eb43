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
          sigma: Any = 0.1, rarity: Any = 0.5, goal_progress: Any = 0.0,
          initial: Any = 1.0) -> dict[str, float]:
    """The hyper-parameters by the library's names (``e3d::Params``), each a
    number (``k`` an integer from 1); the native module has the library
    check their ranges."""
    return {"alpha": number("alpha", alpha), "beta": number("beta", beta),
            "lambda": number("lambda_", lambda_), "eta": number("eta", eta),
            "epsilon": number("epsilon", epsilon), "k": float(integer("k", k, 1)),
            "sigma": number("sigma", sigma), "rarity": number("rarity", rarity),
            "goal_progress": number("goal_progress", goal_progress),
            "initial": number("initial", initial)}


def cache_folder(path: Any) -> Any:
    """``table_cache``: refused when it exists and is not a folder (the
    outcomes would be computed and not kept, silently)."""
    if path is not None and os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"table_cache = {os.fspath(path)}: exists and is not a folder; expected "
                         "the folder of the outcome cache (created if missing)")
    return path


def target_weights(scene: Any, target: Any) -> list[float]:
    """``target`` (not None): an array of one weight per effect, or a dict
    ``{effect: weight}`` / ``{(row, col): weight}`` whose cells not named
    weigh 0, as the weights the library then checks."""
    n = scene.num_effects
    if not isinstance(target, dict):
        try:
            a = np.asarray(target, "float64")
        except Exception as err:
            raise ValueError(f"target: expected None, {n} weights (one per effect) or a dict "
                             f"{{effect: weight}}: {type(err).__qualname__}: {err}") from None
        if a.ndim != 1:
            raise ValueError(f"target: expected a 1-D array of {n} weights (one per effect), "
                             f"found shape {a.shape!r}")
        return a.tolist()  # type: ignore[no-any-return]
    rows, cols = scene.effect_grid[:2]
    weights, named = [0.0] * n, [None] * n
    for k, v in target.items():
        e = _cell(k, rows, cols, n)
        if e is None:
            raise ValueError(f"target: key {k!r} is not an effect: expected an int in [0, {n}) "
                             f"or a (row, col) cell of the {rows}x{cols} grid")
        if named[e] is not None:
            raise ValueError(f"target: keys {named[e]!r} and {k!r} are the same effect {e}: "
                             "give each effect once")
        named[e] = k
        try:
            weights[e] = number("target", v)
        except TypeError:
            raise ValueError(f"target[{k!r}]: expected a number") from None
    return weights


def _cell(k: Any, rows: int, cols: int, n: int) -> Optional[int]:
    """The effect a target's key names: an int below ``n`` or a ``(row,
    col)`` tuple in the grid; None for anything else (a bool included)."""
    try:
        if isinstance(k, tuple) and len(k) == 2:
            r, c = operator.index(k[0]), operator.index(k[1])
            return r * cols + c if 0 <= r < rows and 0 <= c < cols else None
        e = operator.index(k)
        return e if not isinstance(k, (bool, np.bool_)) and 0 <= e < n else None
    except TypeError:
        return None


def _check_shape(a: Any, ndim: int, slots: int, what: str) -> None:
    """Refuses an array that is not ``ndim`` dimensions of rows of ``slots``
    values (with ``ndim == 2``, at least one row)."""
    shape = list(a.shape)
    if ndim == 2 and a.size == 0:
        raise ValueError(f"commands: an empty batch (shape {shape}); expected at least one "
                         f"command, {what}")
    if a.ndim != ndim:
        raise ValueError(f"expected {what}, found an array of {a.ndim} dimension(s), shape {shape}")
    if shape[-1] != slots:
        raise ValueError(f"expected {what}, found shape {shape}: the scene's commands have "
                         f"{slots} slots")


def symbols(sizes: list[int], alphabets: list[str], obj: Any, ndim: int) -> Any:
    """Commands of symbol indices from an integer array (anything
    ``numpy.asarray`` takes) of shape ``[slots]`` (``ndim`` 1) or ``[N,
    slots]`` (``ndim`` 2), each row checked against the slots' alphabet
    ``sizes``: a C-contiguous uint8 array ``[N, slots]``."""
    try:
        a = np.asarray(obj)
    except Exception as err:
        raise ValueError("expected commands as an integer array, a command string or a list of "
                         f"them: {type(err).__qualname__}: {err}") from None
    slots = len(sizes)
    what = (f"one command, an array of shape [{slots}]" if ndim == 1
            else f"an array of shape [N, {slots}] (one command per row)")
    _check_shape(a, ndim, slots, what)
    if a.dtype.kind not in "ui":
        raise ValueError("expected an integer array of symbol indices (dtype uint8, as "
                         f"Scene.parse returns), found dtype {a.dtype}")
    rows = a.reshape(-1, slots)
    bad = (rows < 0) | (rows >= np.array(sizes))
    if bad.any():
        r, s = (int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"row {r}: symbol {int(rows[r, s])} at slot {s} is out of range: slot "
                         f"{s} has {sizes[s]} symbols ({alphabets[s]}), indices 0 to {sizes[s] - 1}")
    return np.ascontiguousarray(rows, dtype=np.uint8)


def values(slots: int, obj: Any, ndim: int) -> Any:
    """Continuous commands from a float array (anything ``numpy.asarray``
    takes) of shape ``[slots]`` (``ndim`` 1) or ``[N, slots]`` (``ndim``
    2): a C-contiguous float64 array ``[N, slots]``, its ranges for the
    library to check."""
    try:
        a = np.asarray(obj, "float64")
    except Exception as err:
        raise ValueError("expected continuous commands as a float array, a string of values or a "
                         f"list of them: {type(err).__qualname__}: {err}") from None
    what = (f"one command, an array of shape [{slots}] (one value per slot)" if ndim == 1
            else f"an array of shape [N, {slots}] (one command of values per row)")
    _check_shape(a, ndim, slots, what)
    return np.ascontiguousarray(a.reshape(-1, slots))


def learn_takes_point(learner: Any) -> bool:
    """Whether a Python learner's ``learn`` takes the terminal point: a
    parameter named ``point``, or ``**kwargs``. Such a learner is called
    ``learn(command, effect, reward, point=(x, y))``, any other as before,
    ``learn(command, effect, reward)``. A ``learn`` without a signature
    (a builtin) is called without it."""
    import inspect
    try:
        params = inspect.signature(learner.learn).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == "point" or p.kind is inspect.Parameter.VAR_KEYWORD for p in params)


def shard_arg(shard: Any) -> Optional[tuple[int, int]]:
    """``run_sweep``'s ``shard``: None, ``(k, n)`` or ``"k/n"`` with
    ``1 <= k <= n`` (the CLI's ``--shard k/n``)."""
    if shard is None:
        return None
    if isinstance(shard, str):
        parts = shard.split("/")
        if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
            raise ValueError(f"shard = {shard!r}: expected K/N with 1 <= K <= N, for example 2/8")
        k, n = int(parts[0]), int(parts[1])
    elif isinstance(shard, (tuple, list)) and len(shard) == 2:
        k, n = integer("shard[0]", shard[0], None), integer("shard[1]", shard[1], None)
    else:
        raise TypeError(f"shard: expected None, (k, n) or 'k/n', found {type(shard).__name__}")
    if not 1 <= k <= n:
        raise ValueError(f"shard = ({k}, {n}): expected K/N with 1 <= K <= N, for example 2/8")
    if n > 2**64 - 1:
        raise ValueError(f"shard = ({k}, {n}): too many parts")
    return k, n
