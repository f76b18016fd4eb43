"""What worlds and sessions return: ``Outcome``, ``BatchOutcome``,
``Motion``, ``SessionRecord``, ``SessionBatch`` and ``EpisodeRecord``,
plain Python objects over the values the native module fills. Their fields are read-only (arrays included: ``np.array(a)`` is a
writable copy); they pickle field by field (``(cls._from_state,
(fields,))``, each field's type checked when read back), compare equal
field by field (arrays value by value, NaN equal to NaN) and draw
themselves for notebooks (``_repr_svg_``)."""

import dataclasses
import json
import math
from typing import Any, ClassVar, Optional, Union

import numpy as np
import numpy.typing as npt

_ANY: Any = object
_OPT_ARRAY: Any = (np.ndarray, type(None))


def _freeze(v: Any) -> None:
    """Every numpy array in ``v`` (lists, tuples and dicts searched) read-only."""
    if isinstance(v, np.ndarray):
        v.setflags(write=False)
    elif isinstance(v, (list, tuple)):
        for x in v:
            _freeze(x)
    elif isinstance(v, dict):
        for x in v.values():
            _freeze(x)


def _same(a: Any, b: Any) -> bool:
    """Arrays of one dtype, shape and values (NaN equal to NaN), dicts key by
    key, lists and tuples item by item, floats equal or both NaN, else ``==``."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.dtype == b.dtype \
            and bool(np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (a != a and b != b)
    return bool(a == b)


def _grid_svg(grid: dict[str, Any], counts: list[float], unit: str, title: str) -> str:
    """An SVG of the effect grid, each cell shaded by its count over the
    largest (white to dark blue) and labelled with it in ``unit``, the
    rewarded cells outlined in green; row 0 at the bottom, as the scene's
    picture has it."""
    rows, cols, rewarded = grid["rows"], grid["cols"], grid["rewarded"]
    cell = min(max(480.0 / max(cols, rows), 4.0), 60.0)
    w, h = cols * cell + 20.0, rows * cell + 40.0
    top = max(max(counts, default=0.0), 0.0, 1.0)
    total = max(sum(counts), 1.0)
    title = title.replace("&", "&amp;").replace("<", "&lt;")
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0f}" height="{h:.0f}" '
           f'viewBox="0 0 {w:.0f} {h:.0f}" font-family="Helvetica, Arial, sans-serif">'
           f'<rect width="100%" height="100%" fill="#ffffff"/>'
           f'<text x="10" y="20" font-size="14" fill="#222">{title}</text>']
    for e, c in enumerate(counts):
        r, col = divmod(e, cols)
        x, y = 10.0 + col * cell, 30.0 + (rows - 1 - r) * cell
        f = c / top
        # white to (31, 78, 156), each channel rounded half away from zero
        rgb = ",".join(str(math.floor(255 + (lo - 255) * f + 0.5)) for lo in (31, 78, 156))
        stroke = ('stroke="#2e8b57" stroke-width="3"' if e < len(rewarded) and rewarded[e]
                  else 'stroke="#b8c4d6" stroke-width="0.8"')
        n = int(c) if c == int(c) else c
        out.append(f'<rect x="{x:.1f}" y="{y:.1f}" width="{cell:.1f}" height="{cell:.1f}" '
                   f'fill="rgb({rgb})" {stroke}><title>cell ({r}, {col}): {n} {unit} '
                   f'({100.0 * c / total:.1f}%)</title></rect>')
    return "".join(out) + "</svg>"


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class _Result:
    """A result of the fields its subclass declares (a leading ``_``: kept,
    not shown), each of the type of ``_TYPES`` (``object``: any)."""

    _TYPES: ClassVar[tuple[Any, ...]] = ()
    _FROZEN: ClassVar[bool] = True
    __hash__ = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self._FROZEN:
            _freeze(self._state())

    def _state(self) -> tuple[Any, ...]:
        return tuple(getattr(self, f.name) for f in dataclasses.fields(self))

    def __reduce__(self) -> tuple[Any, tuple[tuple[Any, ...]]]:
        return (type(self)._from_state, (self._state(),))

    @classmethod
    def _from_state(cls, state: tuple[Any, ...]) -> Any:
        names = [f.name for f in dataclasses.fields(cls)]
        name, n = cls.__name__, len(names)
        if not isinstance(state, tuple) or len(state) != n:
            raise TypeError(f"{name}._from_state: expected a state of {n} fields (what pickling "
                            f"an {name} gives), found {len(state) if isinstance(state, tuple) else state!r}")
        for i, (v, t) in enumerate(zip(state, cls._TYPES)):
            if not isinstance(v, t) or (t is int and isinstance(v, bool)):
                raise TypeError(f"{name}._from_state: field {i} ({names[i].lstrip('_')}): "
                                f"expected {getattr(t, '__name__', t)}, found {type(v).__name__}")
        return cls(*state)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return _same(self._state(), other._state())


_NUM: Any = (float, int)


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class Outcome(_Result):
    """The outcome of one command: ``effect`` (int), ``reward`` (float) and
    the terminal point ``x``, ``y`` (metres)."""

    _TYPES = (int, _NUM, _NUM, _NUM)
    _FROZEN = False
    effect: int
    reward: float
    x: float
    y: float

    def __repr__(self) -> str:
        return f"Outcome(effect={self.effect}, reward={self.reward!r}, x={self.x!r}, y={self.y!r})"


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class BatchOutcome(_Result):
    """The outcomes of a batch of commands, one entry per row: ``effect``
    (int64), ``reward``, ``x``, ``y`` (float64)."""

    _TYPES = (np.ndarray,) * 4
    _FROZEN = False
    effect: npt.NDArray[np.int64]
    reward: npt.NDArray[np.float64]
    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.effect)

    def __repr__(self) -> str:
        return f"BatchOutcome({len(self)} commands)"


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class Motion(_Result):
    """The whole motion of one command (``World.trace``), one row a frame
    (the start, then every step): ``time`` (float64 ``[F]``, seconds), per
    body (``bodies``, the scene's order, fixed ones included) ``x``, ``y``,
    ``angle``, ``vx``, ``vy``, ``omega`` (float64 ``[F, bodies]``), per
    joint (``joints``) ``joint_angle`` (the child's rotation relative to
    its parent, 0 at the start pose, radians in (-pi, pi]) and
    ``joint_velocity`` (float64 ``[F, joints]``), and the command's
    ``outcome``. ``columns()`` gives the same as a dict of the CSV columns
    of ``e3d scene exec --trace``."""

    _BODY = ("x", "y", "angle", "vx", "vy", "omega")
    _TYPES = (str, list, list, *(np.ndarray,) * 9, Outcome)
    command: str
    bodies: list[str]
    joints: list[str]
    time: npt.NDArray[np.float64]
    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    angle: npt.NDArray[np.float64]
    vx: npt.NDArray[np.float64]
    vy: npt.NDArray[np.float64]
    omega: npt.NDArray[np.float64]
    joint_angle: npt.NDArray[np.float64]
    joint_velocity: npt.NDArray[np.float64]
    outcome: Outcome

    @classmethod
    def _from_state(cls, state: tuple[Any, ...]) -> "Motion":
        m: Motion = super()._from_state(state)
        f, b, j = len(m.time), len(m.bodies), len(m.joints)
        if any(getattr(m, n).shape != (f, b) for n in cls._BODY) or \
                any(a.shape != (f, j) for a in (m.joint_angle, m.joint_velocity)):
            raise ValueError(f"Motion: not a pickled state: arrays of {f} frames x {b} bodies "
                             f"and x {j} joints expected")
        return m

    def __len__(self) -> int:
        """The number of frames (the start and every step)."""
        return len(self.time)

    def still_bodies(self) -> list[str]:
        """The bodies that do not move over the whole motion: all six of
        their columns constant (walls and other fixed bodies, and a free
        body this command never stirs), in the order of ``bodies``."""
        return [name for c, name in enumerate(self.bodies)
                if all((getattr(self, f)[:, c] == getattr(self, f)[0, c]).all() for f in self._BODY)]

    def columns(self, still: bool = True) -> dict[str, npt.NDArray[Any]]:
        """The columns of ``e3d scene exec --trace FILE.csv``, in its order:
        ``step`` (int64), ``time``, then per body ``NAME.x``, ``NAME.y``,
        ``NAME.angle``, ``NAME.vx``, ``NAME.vy``, ``NAME.omega``, then per
        joint ``NAME.angle``, ``NAME.velocity`` (float64 arrays ``[F]``).
        ``still=False`` leaves out the columns of ``still_bodies()`` (on
        puck_rooms: the 6 walls' 36 constant columns, leaving 8)."""
        if not isinstance(still, (bool, np.bool_)):
            raise TypeError(f"still: expected a bool, found {type(still).__name__}")
        skip = set() if still else set(self.still_bodies())
        out: dict[str, npt.NDArray[Any]] = {"step": np.arange(len(self), dtype=np.int64),
                                            "time": self.time.copy()}
        for c, name in enumerate(self.bodies):
            if name in skip:
                continue
            out.update({f"{name}.{f}": getattr(self, f)[:, c].copy() for f in self._BODY})
        for c, name in enumerate(self.joints):
            out[f"{name}.angle"] = self.joint_angle[:, c].copy()
            out[f"{name}.velocity"] = self.joint_velocity[:, c].copy()
        return out

    def __repr__(self) -> str:
        return (f"Motion(command={json.dumps(self.command)}, {len(self)} frames, "
                f"{len(self.bodies)} bodies, {len(self.joints)} joints)")


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class SessionRecord(_Result):
    """What a session recorded: ``commands`` (``[T, slots]``: uint8 symbol
    indices, or float64 values on a continuous scene), ``effects`` (int64
    ``[T]``), ``rewards`` (float64 ``[T]``, 0 when the reward is not used),
    ``metrics`` (a dict, ``summary.json``'s names), ``effect_counts``
    (float64 ``[num_effects]``), ``final_policy`` (per slot the symbols'
    probabilities, or ``[slots, 2]`` (mean, sd) on a continuous scene; None
    for a Python learner), ``policy_effect_distribution`` (the exact effect
    distribution of the final policy where the outcomes come from a table,
    else None), E3D's final ``q`` (per slot) and ``effect_model`` (its
    running effect histogram), from ``run_session(learner="e3d")`` only
    (else None), and how outcomes were obtained (``execution``)."""

    _TYPES = (str, str, int, int, np.ndarray, np.ndarray, np.ndarray, dict, np.ndarray, _ANY,
              _OPT_ARRAY, (list, type(None)), _OPT_ARRAY, str, dict)
    scene: str
    learner: str
    seed: int
    trials: int
    commands: npt.NDArray[Any]
    effects: npt.NDArray[np.int64]
    rewards: npt.NDArray[np.float64]
    _metrics: dict[str, Any]
    effect_counts: npt.NDArray[np.float64]
    final_policy: Union[list[npt.NDArray[np.float64]], npt.NDArray[np.float64], None]
    policy_effect_distribution: Optional[npt.NDArray[np.float64]]
    q: Optional[list[npt.NDArray[np.float64]]]
    effect_model: Optional[npt.NDArray[np.float64]]
    execution: str
    _grid: dict[str, Any]

    @property
    def metrics(self) -> dict[str, Any]:
        """The metrics (a copy: the record keeps its own)."""
        return dict(self._metrics)

    def _repr_svg_(self) -> str:
        """The effect grid, each cell shaded by its share of the trials, the
        rewarded cells outlined (notebooks)."""
        title = f"{self.scene}: {self.learner}, seed {self.seed}, {self.trials} trials"
        return _grid_svg(self._grid, self.effect_counts.tolist(), "trials", title)

    def __repr__(self) -> str:
        return (f"SessionRecord(scene={json.dumps(self.scene)}, learner={json.dumps(self.learner)}, "
                f"seed={self.seed}, trials={self.trials})")


_INTS = ("distinct_effects", "trials", "coverage_cells")
_COLUMNS = ("normalized_entropy", "normalized_entropy_last_1000", "kl_to_target",
            "distinct_effects", "cumulative_reward", "first_reward_trial", "trials",
            "reachable_effects", "normalized_entropy_reachable", "coverage_cells", "coverage",
            "trials_to_50_percent", "trials_to_90_percent", "qd_score")


def _metrics(*values: Any) -> dict[str, Any]:
    """A session's metrics by ``summary.json``'s names, from the native module's values."""
    return dict(zip(_COLUMNS + ("discovery_trials",), values))


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class SessionBatch(_Result):
    """Sessions of one scene run together, in lockstep (``run_sessions``):
    ``seeds`` (uint64 ``[S]``), ``commands`` (``[S, T, slots]``), ``effects``
    (int64 ``[S, T]``), ``rewards`` (float64 ``[S, T]``), ``metrics`` (one
    array ``[S]`` a metric: int64 for ``distinct_effects``, ``trials`` and
    ``coverage_cells``, else float64 with NaN for none, as in ``run_sweep``;
    each session's ``discovery_trials`` is in ``batch[i].metrics``).
    ``batch[i]`` is session ``i``'s ``SessionRecord`` (views of these
    arrays), ``batch[a:b]`` the batch of those sessions."""

    _TYPES = (str, str, np.ndarray, int, _ANY, np.ndarray, np.ndarray, dict, str, dict, list, list,
              list, list)
    scene: str
    learner: str
    seeds: npt.NDArray[np.uint64]
    trials: int
    commands: npt.NDArray[Any]
    effects: npt.NDArray[np.int64]
    rewards: npt.NDArray[np.float64]
    _metrics: dict[str, npt.NDArray[Any]]
    execution: str
    _grid: dict[str, Any]
    _per_session: list[dict[str, Any]]
    _counts: list[npt.NDArray[np.float64]]
    _policies: list[Any]
    #: per session ``(policy_effect_distribution, q, effect_model)``, as
    #: ``run_session`` gives them
    _finals: list[tuple[Any, Any, Any]]

    @classmethod
    def _stack(cls, seeds: list[int], records: list[SessionRecord]) -> "SessionBatch":
        """The batch of sessions ``records`` (of ``seeds``), stacked."""
        r0 = records[0]
        per = [r._metrics for r in records]
        metrics = {k: np.array([np.nan if m[k] is None else m[k] for m in per],
                               dtype=np.int64 if k in _INTS else np.float64) for k in _COLUMNS}
        return cls(r0.scene, r0.learner, np.array(seeds, dtype=np.uint64), r0.trials,
                   np.stack([r.commands for r in records]), np.stack([r.effects for r in records]),
                   np.stack([r.rewards for r in records]), metrics, r0.execution, r0._grid, per,
                   [r.effect_counts for r in records], [r.final_policy for r in records],
                   [(r.policy_effect_distribution, r.q, r.effect_model) for r in records])

    @classmethod
    def _from_state(cls, state: tuple[Any, ...]) -> "SessionBatch":
        b: SessionBatch = super()._from_state(state)
        shape: tuple[int, ...] = getattr(b.commands, "shape", ())
        if not (len(shape) == 3 and shape[0] == len(b._per_session) and shape[1] == b.trials):
            raise ValueError(f"SessionBatch: not a pickled state: commands of {len(b._per_session)} "
                             f"sessions x {b.trials} trials expected")
        return b

    @property
    def metrics(self) -> dict[str, npt.NDArray[Any]]:
        """The metrics (a copy: the batch keeps its own)."""
        return dict(self._metrics)

    def __len__(self) -> int:
        return len(self._per_session)

    def __getitem__(self, i: Any) -> Any:
        """Session ``i``'s record; a slice, the batch of those sessions."""
        if isinstance(i, slice):
            rows = list(range(len(self)))[i]
            return SessionBatch(
                self.scene, self.learner, self.seeds[i], self.trials, self.commands[i],
                self.effects[i], self.rewards[i], {k: v[i] for k, v in self._metrics.items()},
                self.execution, self._grid, [self._per_session[k] for k in rows],
                [self._counts[k] for k in rows], [self._policies[k] for k in rows],
                [self._finals[k] for k in rows])
        if isinstance(i, (bool, float, np.bool_)) or getattr(i, "ndim", 0) != 0 \
                or not hasattr(i, "__index__"):
            raise TypeError(f"session index: expected an integer or a slice, found {type(i).__name__}")
        n = len(self)
        k = int(i) + n if int(i) < 0 else int(i)
        if not 0 <= k < n:
            raise IndexError(f"session {i} out of range: {n} sessions")
        return SessionRecord(
            self.scene, self.learner, int(self.seeds[k]), self.trials, self.commands[k],
            self.effects[k], self.rewards[k], dict(self._per_session[k]), self._counts[k],
            self._policies[k], *self._finals[k], self.execution, self._grid)

    def _repr_svg_(self) -> str:
        """The effect grid shaded by the effect counts of every session together (notebooks)."""
        cells = self._grid["rows"] * self._grid["cols"]
        total = np.sum([np.zeros(cells), *self._counts], axis=0).tolist()
        title = f"{self.scene}: {self.learner}, {len(self)} sessions of {self.trials} trials"
        return _grid_svg(self._grid, total, "trials", title)

    def __repr__(self) -> str:
        return (f"SessionBatch(scene={json.dumps(self.scene)}, learner={json.dumps(self.learner)}, "
                f"{len(self)} sessions, seeds {self.seeds.tolist()}, trials={self.trials})")


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class EpisodeRecord(_Result):
    """A session of episodes (``run_episodes``), one entry per command
    (``commands_per_episode`` per episode) or per episode (``starts``): the
    start context of each episode, the context observed before each command
    (int64), the commands (uint8 ``[N, slots]``), their effects (int64) and
    rewards (float64: the scene's after an episode's last command, 0 after
    the others), the first rewarded episode (1-based, or None), and per
    start context the normalised entropy of the episodes' terminal cells."""

    _TYPES = (int, str, int, int, int, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
              (int, type(None)), float, list, dict, dict)
    seed: int
    learner: str
    commands_per_episode: int
    num_effects: int
    episodes: int
    starts: npt.NDArray[np.int64]
    contexts: npt.NDArray[np.int64]
    commands: npt.NDArray[np.uint8]
    effects: npt.NDArray[np.int64]
    rewards: npt.NDArray[np.float64]
    first_reward_episode: Optional[int]
    cumulative_reward: float
    entropy_per_start: list[float]
    _metrics: dict[str, Any]
    _grid: dict[str, Any]

    @property
    def metrics(self) -> dict[str, Any]:
        """The metrics of ``SessionRecord.metrics`` (the same names and
        computation) over the episodes' terminal effects and rewards: each
        episode counts as one trial (``trials``: the episodes,
        ``first_reward_trial``: the first rewarded episode, ``coverage``:
        the share of the effect grid's cells some episode ended in), the
        target uniform (``kl_to_target``). A copy: the record keeps its own."""
        return dict(self._metrics)

    def _repr_svg_(self) -> str:
        """The effect grid shaded by where the episodes ended (notebooks)."""
        k = max(self.commands_per_episode, 1)
        ends = self.effects[k - 1::k]
        cells = self._grid["rows"] * self._grid["cols"]
        counts = np.bincount(ends, minlength=cells)[:cells]
        title = (f"{self.learner}, seed {self.seed}: {self.episodes} episodes of "
                 f"{self.commands_per_episode} commands, where they ended")
        return _grid_svg(self._grid, counts.astype(np.float64).tolist(), "episodes", title)

    def __repr__(self) -> str:
        return (f"EpisodeRecord(seed={self.seed}, learner={json.dumps(self.learner)}, "
                f"episodes={self.episodes}, commands_per_episode={self.commands_per_episode}, "
                f"cumulative_reward={self.cumulative_reward!r})")
