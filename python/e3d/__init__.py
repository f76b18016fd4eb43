"""e3d: a 2D physics sandbox (Rapier) for learning compositional motor
commands by End-Effect Exploration Drive (E3D, after E. Daucé 2020).

The Rust library does all the work; this package hands numpy arrays in and
out::

    import numpy as np, e3d
    scene = e3d.Scene.builtin("puck_rooms")        # or e3d.Scene.load("scenes/puck_rooms.ron")
    world = scene.world()
    out = world.execute_batch(scene.parse(["EESSEES", "SEEEEES"]))
    out.effect, out.reward, out.x, out.y           # numpy arrays, one entry per command
    rec = e3d.run_session(scene, learner="e3d", trials=5000, seed=0)
    rec.effects, rec.metrics["normalized_entropy"]
    recs = e3d.run_sessions(scene, learner="e3d", trials=5000, seeds=range(10))
    recs.effects                                   # int64[10, 5000], one row a session
    cols = e3d.run_sweep({"scenes": ["two_rooms"], "learners": ["e3d", "uniform"],
                          "sessions": 10, "trials": 5000})   # dict of columns: pandas.DataFrame(cols)

``e3d.gym`` holds a Gymnasium environment (it imports gymnasium; this
module does not). See docs/python.md in the repository.
"""

import os
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _e3d
from ._e3d import (
    E3D_VERSION,
    EpisodeWorld,
    Scene,
    SceneError,
    SessionRng,
    SimulationError,
    World,
    __version__,
)
from ._args import cache_folder, optional, shard_arg
from ._crosscheck import crosscheck
from ._learner import E3dLearner, Learner
from ._results import (BatchOutcome, EpisodeRecord, Motion, Outcome, SessionBatch,
                       SessionRecord)
from ._run import run_episodes, run_session, run_sessions
from ._sweep import columns, sweep_text
from ._types import PythonContextualLearner, PythonLearner


def run_sweep(
    sweep: Union[str, "os.PathLike[str]", Mapping[str, Any]],
    threads: Optional[int] = None,
    table_cache: Union[str, "os.PathLike[str]", None] = None,
    out: Union[str, "os.PathLike[str]", None] = None,
    resume: bool = False,
    progress: Optional[Callable[[int, int], object]] = None,
    shard: Union[tuple[int, int], str, None] = None,
) -> "dict[str, Union[np.ndarray, list[str]]]":
    """Runs every session of a sweep, in parallel, and returns its
    ``results.csv`` as a dict of columns (``pandas.DataFrame(cols)`` and
    ``polars.DataFrame(cols)`` take it as it is), in the file's order:
    ``scene``, ``learner``, ``failure`` (lists of str), ``use_reward`` (bool
    array), ``session`` (int64), ``seed`` (uint64), the parameters and the
    metrics (float64, NaN where the CSV cell is empty). The values of
    ``e3d sweep FILE --out DIR`` (docs/analysis.md names the columns).

    ``sweep``: a sweep file's path (scene paths relative to its folder), the
    text of one, or a dict of its fields (see ``sweep_text``; scene paths
    relative to the current folder). ``threads``: default every core (the
    results do not depend on it). ``table_cache``: the CLI's
    ``--table-cache``. ``out``: a folder that receives exactly what
    ``e3d sweep --out DIR`` writes, the same bytes; ``resume=True``
    completes the sweep it holds (``--resume``). ``progress``: called as
    ``progress(trials_done, trials_of_all_sessions)`` at most ten times a
    second and once at the end. Ctrl-C raises ``KeyboardInterrupt`` once
    the sessions running have finished.

    ``shard=(k, n)`` (or ``"k/n"``; needs ``out``): runs only part ``k``
    of ``n`` of the sessions (``e3d sweep --shard k/n``), into ``out``,
    and returns that part's columns; ``merge_sweeps`` joins the folders of
    all ``n`` parts into the files of a one-process run, byte for byte.
    """
    if isinstance(sweep, Mapping):
        sweep = sweep_text(sweep)
    part = shard_arg(shard)
    if part is not None and out is None:
        raise ValueError("shard: a shard is written into a folder: give out= (then merge_sweeps "
                         "joins the shards' folders)")
    return columns(*_e3d.run_sweep(sweep, optional("threads", threads, 1),
                                   cache_folder(table_cache), out, resume, progress, part))


def merge_sweeps(
    dirs: "Sequence[Union[str, os.PathLike[str]]]",
    out: Union[str, "os.PathLike[str]"],
) -> "dict[str, Union[np.ndarray, list[str]]]":
    """Joins the output folders of every shard of one sweep
    (``run_sweep(..., out=DIR_k, shard=(k, n))`` for k = 1..n, or
    ``e3d sweep --shard k/n``) into ``out``, which then holds the files of a
    one-process run byte for byte (``e3d merge DIR... --out OUT``), and
    returns its ``results.csv`` as ``run_sweep`` does. Every shard must be
    given once and be complete; ``out`` must not exist or be empty
    (``ValueError`` naming what is wrong otherwise)."""
    if isinstance(dirs, (str, bytes, os.PathLike)):
        raise TypeError("dirs: expected a sequence of the shards' folders, found one path")
    return columns(*_e3d.merge_sweeps([os.fspath(d) for d in dirs], out))


__all__ = [
    "E3D_VERSION",
    "BatchOutcome",
    "E3dLearner",
    "EpisodeRecord",
    "EpisodeWorld",
    "Learner",
    "Motion",
    "Outcome",
    "PythonContextualLearner",
    "PythonLearner",
    "Scene",
    "SceneError",
    "SessionBatch",
    "SessionRecord",
    "SessionRng",
    "SimulationError",
    "World",
    "__version__",
    "crosscheck",
    "run_episodes",
    "run_session",
    "run_sessions",
    "merge_sweeps",
    "run_sweep",
    "sweep_text",
]
