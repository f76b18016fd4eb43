"""What ``e3d.qd`` needs without pyribs: a scene as a quality-diversity
scoring function (``Scoring``: commands in, quality and descriptor out,
batched through ``World.execute_batch``), the archive of elites of any
list of commands and effects, and its QD-score and coverage.
``e3d.qd`` re-exports all of it and adds what needs pyribs."""

import os
from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt

from ._e3d import Scene, World
from ._results import BatchOutcome
from ._types import SceneLike

Array = npt.NDArray[np.float64]
Quality = Union[str, Callable[[npt.NDArray[Any], BatchOutcome], npt.ArrayLike]]

QUALITIES = ("reward", "effort")
"""The built-in qualities (``Scoring(quality=...)``)."""

DESCRIPTORS = ("cell", "point")
"""The built-in descriptors (``Scoring(descriptor=...)``)."""


class Scoring:
    """A scene as a quality-diversity scoring function: ``scoring(solutions)
    -> (objective, measures)``, what pyribs' ``scheduler.tell`` takes.

    **Solutions** are real arrays ``[N, num_slots]``. On a scene of symbols,
    slot ``k``'s value ``x`` is the symbol ``clip(rint(x), 0, n_k - 1)``
    (the nearest index, numpy's ``rint``: halves to even; ``n_k`` the
    slot's alphabet size), so the box ``bounds`` = ``(-0.5, n_k - 0.5)``
    per slot gives every symbol an interval of width 1; ``solutions(commands)``
    is the inverse (the indices as floats). On a continuous scene the
    values are the command's, clipped to the slot's range (``bounds`` =
    ``Scene.value_ranges``).

    **Quality** (the objective), per command: ``"reward"`` (the scene's
    reward of the outcome), ``"effort"`` (e3d's effort quality ``1 -
    effort / max_effort``, in [0, 1]: ``Scene.effort``, the sum over slots
    of the size of the slot's action, ``|torque|`` in N·m, the norm of an
    impulse in N·s or of a force in N, ``|angle|`` of a set point, the
    length of a grid move, 0 for ``Idle``; on a continuous scene of the
    action of the value), or a callable ``quality(commands, outcome) ->
    array[N]`` (then give ``offset``).

    **Descriptor** (the measures), per command, two numbers (x, y) in the
    effect grid's plane: ``"cell"`` the centre of the command's effect cell
    (so pyribs bins it into the same cell as e3d, never across a border),
    or ``"point"`` the terminal point itself (``Outcome.x``, ``.y``: the
    same cell except for rounding at a cell's border, and clamped to the
    grid by both). The grid is ``Scene.effect_grid``: ``cols`` cells along
    x over ``(xmin, xmax)``, ``rows`` along y over ``(ymin, ymax)``, e3d's
    row 0 at the top; ``dims``, ``ranges``.

    **QD-score** (pyribs' ``archive.stats.qd_score``): the sum over filled
    cells of the elite's quality minus ``offset``; ``offset`` (pyribs'
    ``qd_score_offset``) is the lowest quality a command can have (default:
    the smallest reward of a cell for ``"reward"``, 0 for ``"effort"``), so
    every term is non-negative; with ``"effort"`` it is e3d's own
    ``qd_score`` of the same commands.
    **Coverage**: the share of the grid's ``rows * cols`` cells filled.
    """

    def __init__(self, scene: SceneLike, quality: Quality = "reward", descriptor: str = "cell",
                 world: Optional[World] = None, offset: Optional[float] = None):
        self.scene: Scene = scene if isinstance(scene, Scene) else Scene.resolve(os.fspath(scene))
        #: the world that executes the commands (its memo keeps every outcome)
        self.world: World = self.scene.world() if world is None else world
        if self.world.scene.name != self.scene.name:
            raise ValueError(f"world: a world of {self.world.scene.name!r}, not of the scene "
                             f"{self.scene.name!r}")
        if descriptor not in DESCRIPTORS:
            raise ValueError(f"descriptor = {descriptor!r}: expected one of {DESCRIPTORS}")
        if not callable(quality) and quality not in QUALITIES:
            raise ValueError(f"quality = {quality!r}: expected one of {QUALITIES} or a callable "
                             "quality(commands, outcome) -> array")
        self.quality = quality
        self.descriptor = descriptor
        s = self.scene
        rows, cols, (x0, y0), (x1, y1) = s.effect_grid
        self.rows, self.cols = rows, cols
        #: pyribs' ``GridArchive(dims=..., ranges=...)``: x then y
        self.dims: tuple[int, int] = (cols, rows)
        self.ranges: tuple[tuple[float, float], tuple[float, float]] = ((x0, x1), (y0, y1))
        #: the number of cells of the grid
        self.num_cells: int = rows * cols
        if s.num_effects != self.num_cells:
            raise ValueError(f"{s.name}: {s.num_effects} effects on a grid of {self.num_cells} "
                             "cells: expected one effect per cell")
        self.solution_dim: int = s.num_slots
        if s.is_continuous:
            self.bounds: list[tuple[float, float]] = [(float(a), float(b)) for a, b in s.value_ranges]
        else:
            self.bounds = [(-0.5, n - 0.5) for n in s.alphabet_sizes]
        if offset is not None:
            self.offset = float(offset)
        elif quality == "reward":
            self.offset = float(np.min(s.reward_table()))
        elif quality == "effort":
            self.offset = 0.0
        else:
            raise ValueError("offset: a callable quality needs its offset (the lowest quality "
                             "a command can have, pyribs' qd_score_offset)")

    def commands(self, solutions: npt.ArrayLike) -> npt.NDArray[Any]:
        """The commands of ``solutions`` (``[N, num_slots]``, or one row):
        uint8 symbol indices, or float64 values on a continuous scene."""
        x = np.atleast_2d(np.asarray(solutions, dtype=np.float64))
        if x.ndim != 2 or x.shape[1] != self.solution_dim:
            raise ValueError(f"solutions: expected an array [N, {self.solution_dim}] "
                             f"(one value per slot), found shape {np.shape(solutions)}")
        if not np.isfinite(x).all():
            raise ValueError("solutions: expected finite values, found NaN or infinity")
        lo, hi = np.array(self.bounds).T
        if self.scene.is_continuous:
            return np.clip(x, lo, hi)
        return np.clip(np.rint(x), 0, hi - 0.5).astype(np.uint8)

    def solutions(self, commands: npt.ArrayLike) -> Array:
        """The solutions of ``commands`` (symbol indices or values, ``[N,
        num_slots]``): what ``commands`` maps back to them."""
        c = np.atleast_2d(np.asarray(commands))
        return self.commands(c.astype(np.float64)).astype(np.float64)

    def effort(self, commands: npt.ArrayLike) -> Array:
        """Each command's effort (``[N]``): e3d's ``Scene.effort``."""
        c = np.atleast_2d(np.asarray(commands))
        c = c.astype(np.float64) if self.scene.is_continuous else c.astype(np.uint8)
        return np.asarray(self.scene.effort(c), dtype=np.float64)

    def quality_of(self, commands: npt.NDArray[Any], outcome: BatchOutcome) -> Array:
        """The quality of each command (``[N]``) given its outcome."""
        if self.quality == "reward":
            return np.array(outcome.reward, dtype=np.float64)
        if self.quality == "effort":
            top = self.scene.max_effort
            return 1.0 - self.effort(commands) / top if top > 0 else np.ones(len(commands))
        assert callable(self.quality)
        q = np.asarray(self.quality(commands, outcome), dtype=np.float64)
        if q.shape != (len(commands),):
            raise ValueError(f"quality: expected an array of {len(commands)} numbers, one per "
                             f"command, found shape {q.shape}")
        return q

    def centre(self, effects: npt.ArrayLike) -> Array:
        """The centre ``(x, y)`` of each effect's cell (``[N, 2]``)."""
        row, col = np.divmod(np.asarray(effects, dtype=np.int64), self.cols)
        (x0, x1), (y0, y1) = self.ranges
        w, h = (x1 - x0) / self.cols, (y1 - y0) / self.rows
        return np.stack([x0 + (col + 0.5) * w, y1 - (row + 0.5) * h], axis=-1)

    def index_of(self, effects: npt.ArrayLike) -> npt.NDArray[np.int64]:
        """The pyribs ``GridArchive`` index of each effect's cell:
        ``x_bin * rows + y_bin``, ``x_bin`` e3d's column and ``y_bin`` =
        ``rows - 1 - row`` (pyribs counts y upwards)."""
        row, col = np.divmod(np.asarray(effects, dtype=np.int64), self.cols)
        return np.asarray(col * self.rows + (self.rows - 1 - row), dtype=np.int64)

    def effect_of(self, index: npt.ArrayLike) -> npt.NDArray[np.int64]:
        """The e3d effect of each pyribs ``GridArchive`` index (the inverse of ``index_of``)."""
        col, y = np.divmod(np.asarray(index, dtype=np.int64), self.rows)
        return np.asarray((self.rows - 1 - y) * self.cols + col, dtype=np.int64)

    def evaluate(self, solutions: npt.ArrayLike) -> tuple[Array, Array, BatchOutcome]:
        """``(objective [N], measures [N, 2], outcome)``: the solutions
        executed with one ``World.execute_batch`` call."""
        commands = self.commands(solutions)
        out = self.world.execute_batch(commands)
        measures = (self.centre(out.effect) if self.descriptor == "cell"
                    else np.stack([out.x, out.y], axis=-1))
        return self.quality_of(commands, out), measures, out

    def __call__(self, solutions: npt.ArrayLike) -> tuple[Array, Array]:
        """``(objective, measures)`` of ``solutions`` (see ``evaluate``)."""
        objective, measures, _ = self.evaluate(solutions)
        return objective, measures

    def elites(self, commands: npt.ArrayLike, effects: npt.ArrayLike,
               rewards: Optional[npt.ArrayLike] = None) -> Array:
        """The archive of a list of commands and their effects (a
        session's ``record.commands`` and ``record.effects``): per cell
        (``[num_cells]``, e3d's effect order) the best quality of a command
        that reached it, NaN where none did. ``"reward"`` reads the
        scene's reward of each effect (a session run without reward
        records 0); a callable quality gets ``rewards`` (default: the
        scene's) in the outcome it is handed, and NaN for the point."""
        c = np.atleast_2d(np.asarray(commands))
        e = np.asarray(effects, dtype=np.int64)
        if c.shape != (len(e), self.solution_dim):
            raise ValueError(f"commands: expected [{len(e)}, {self.solution_dim}] (one command "
                             f"per effect), found {c.shape}")
        r = (self.scene.reward_table()[e] if rewards is None
             else np.asarray(rewards, dtype=np.float64))
        nan = np.full(len(e), np.nan)
        q = self.quality_of(c, BatchOutcome(e, r, nan, nan))
        best = np.full(self.num_cells, -np.inf)
        np.maximum.at(best, e, q)
        best[np.isneginf(best)] = np.nan
        return best

    def qd_score(self, elites: npt.ArrayLike) -> float:
        """The QD-score of an archive (``elites``' form): the sum over
        filled cells of quality minus ``offset``."""
        q = np.asarray(elites, dtype=np.float64)
        return float(np.sum(q[~np.isnan(q)] - self.offset))

    def coverage(self, elites: npt.ArrayLike) -> float:
        """The share of the grid's cells an archive (``elites``' form) fills."""
        return float(np.count_nonzero(~np.isnan(np.asarray(elites, dtype=np.float64)))
                     / self.num_cells)
