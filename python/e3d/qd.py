"""Quality-diversity with pyribs: any e3d scene as a scoring function for
pyribs' ask/tell loop, the ``GridArchive`` over the scene's effect grid,
pyribs' MAP-Elites on a scene, and the QD-score and coverage of an e3d
session's commands, computed as pyribs computes them::

    import e3d, ribs
    from e3d import qd
    scoring = qd.Scoring("arm7", quality="effort")   # commands in; objective, measures out
    archive = qd.grid_archive(scoring)                 # pyribs' GridArchive, one cell per effect
    emitter = ribs.emitters.GaussianEmitter(archive, sigma=0.45, x0=[1.0] * 7,
                                            bounds=scoring.bounds, batch_size=50)
    scheduler = ribs.schedulers.Scheduler(archive, [emitter])
    for _ in range(20):
        solutions = scheduler.ask()
        scheduler.tell(*scoring(solutions))           # one World.execute_batch call
    archive.stats.qd_score, archive.stats.coverage

    rec = e3d.run_session("arm7", "e3d", trials=1000)
    elites = scoring.elites(rec.commands, rec.effects)  # e3d's session as an archive
    scoring.qd_score(elites), scoring.coverage(elites)  # the same numbers pyribs would give

Needs pyribs (``pip install ribs``, or ``pip install e3d[qd]``); importing
this module without it raises an ``ImportError`` that says so. ``Scoring``
documents the encoding of commands, the qualities, the descriptors and the
QD-score (with ``quality="effort"``, e3d's own ``qd_score``);
docs/quality-diversity.md compares E3D, goal babbling, uniform sampling,
e3d's and pyribs' MAP-Elites on arm7 and three_rooms.
"""

import math
from typing import Any, Optional, Union

import numpy as np

try:
    from ribs.archives import GridArchive  # type: ignore[import-not-found, unused-ignore]
    from ribs.emitters import GaussianEmitter  # type: ignore[import-not-found, unused-ignore]
    from ribs.schedulers import Scheduler  # type: ignore[import-not-found, unused-ignore]
except ImportError:  # the message is what python/tests/test_qd.py checks
    raise ImportError("e3d.qd needs pyribs: pip install ribs (or pip install 'e3d[qd]')")

from ._args import integer, number
from ._qd import DESCRIPTORS, QUALITIES, Array, Scoring
from ._types import SceneLike


def grid_archive(scoring: Union[Scoring, SceneLike], quality: Any = "reward",
                 **kwargs: Any) -> GridArchive:
    """pyribs' ``GridArchive`` matching the scene's effect grid: one cell
    per effect (``dims = (cols, rows)``, ``ranges`` the grid's x and y
    extent), ``solution_dim`` the scene's slots and ``qd_score_offset`` the
    scoring's ``offset``, so that its ``stats.qd_score`` and
    ``stats.coverage`` are ``scoring.qd_score`` and ``scoring.coverage``
    of the same elites. ``scoring``: a ``Scoring``, or a scene (then
    ``Scoring(scene, quality)``'s). ``kwargs`` go to ``GridArchive``
    (``seed``, ...)."""
    if not isinstance(scoring, Scoring):
        scoring = Scoring(scoring, quality)
    kwargs.setdefault("qd_score_offset", scoring.offset)
    return GridArchive(solution_dim=scoring.solution_dim, dims=list(scoring.dims),
                       ranges=list(scoring.ranges), **kwargs)


def elites_of(archive: GridArchive, scoring: Scoring) -> Array:
    """A pyribs archive's elites in ``Scoring.elites``' form: per e3d
    effect the elite's objective, NaN where the cell is empty."""
    data = archive.data(["index", "objective"])
    out = np.full(scoring.num_cells, np.nan)
    out[scoring.effect_of(data["index"])] = data["objective"]
    return out


def map_elites(scene: SceneLike, trials: int, seed: int = 0, quality: Any = "reward",
               sigma: float = 0.15, batch_size: int = 50, scoring: Optional[Scoring] = None,
               ) -> GridArchive:
    """pyribs' MAP-Elites on a scene for ``trials`` rollouts: a
    ``GridArchive`` (``grid_archive``), one ``GaussianEmitter`` and a
    ``Scheduler``; the first batch is ``batch_size`` solutions drawn
    uniformly in the scoring's ``bounds``, each later one mutates elites
    chosen uniformly from the archive by a Gaussian of standard deviation
    ``sigma`` times each slot's width (the width of its bounds: its
    alphabet's size, or its range), clipped to the bounds. ``trials`` must
    be a multiple of ``batch_size``. The same ``seed`` gives the same
    archive. ``scoring``: one to reuse (its world keeps the outcomes
    already simulated); else ``Scoring(scene, quality)``. Returns the
    archive."""
    trials = integer("trials", trials, 1)
    batch_size = integer("batch_size", batch_size, 1)
    sigma = number("sigma", sigma)
    if not (sigma > 0 and math.isfinite(sigma)):
        raise ValueError(f"sigma = {sigma}: expected a positive number")
    if trials % batch_size:
        raise ValueError(f"trials = {trials}: expected a multiple of batch_size = {batch_size}")
    s = Scoring(scene, quality) if scoring is None else scoring
    rng = np.random.default_rng(integer("seed", seed))
    lo, hi = np.array(s.bounds).T
    archive = grid_archive(s, seed=int(rng.integers(2**32)))
    emitter = GaussianEmitter(archive, sigma=sigma * (hi - lo), bounds=s.bounds,
                              initial_solutions=rng.uniform(lo, hi, size=(batch_size, len(lo))),
                              batch_size=batch_size, seed=int(rng.integers(2**32)))
    scheduler = Scheduler(archive, [emitter])
    for _ in range(trials // batch_size):
        scheduler.tell(*s(scheduler.ask()))
    return archive


__all__ = ["DESCRIPTORS", "QUALITIES", "Scoring", "elites_of", "grid_archive", "map_elites"]
