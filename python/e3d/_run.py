"""``run_session``, ``run_sessions`` and ``run_episodes``: their keywords,
defaults and documentation; the arguments checked once (``_args``) and
handed to the native module, which runs them."""

from typing import Any, Callable, Optional, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

from . import _e3d
from ._args import MAX_SESSIONS, cache_folder, hyper, integer, number, optional, seeds as seeds_arg
from ._learner import Learner
from ._results import EpisodeRecord, SessionBatch, SessionRecord
from ._types import (PathLike_, Progress, PythonContextualLearner, PythonLearner, SceneLike,
                     TargetLike)

OnTrials = Callable[[int, npt.NDArray[np.uint8], npt.NDArray[np.int64], npt.NDArray[np.float64]],
                    object]


def run_session(
    scene: SceneLike,
    learner: Union[str, PythonLearner, Learner, None] = None,
    trials: int = 5000,
    seed: int = 0,
    use_reward: bool = True,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    outcomes: Optional[str] = None,
    table_cache: Optional[PathLike_] = None,
    progress: Optional[Progress] = None,
    target: Optional[TargetLike] = None,
    on_trials: Optional[OnTrials] = None,
    every: int = 1000,
    k: int = 2,
    sigma: float = 0.1,
    rarity: float = 0.5,
    goal_progress: float = 0.0,
    initial: float = 1.0,
) -> SessionRecord:
    """Runs one session of ``trials`` trials: the learner proposes a command,
    the scene's world executes it, the learner learns from its effect and
    reward. The same numbers as ``e3d run SCENE --trials T --seed S``.

    ``learner``: a built-in learner's name (``"e3d"``, ``"uniform"``,
    ``"egreedy"``, ``"e3d_relax"``, ``"count"``, ``"smm"``,
    ``"goal_babbling"``, ``"archive"``, ``"archive_reached"``, ``"map_elites"``;
    on a continuous scene ``"e3d"``, the Gaussian E3D, ``"uniform"``,
    ``"goal_babbling"``, ``"archive"``, ``"archive_reached"`` or
    ``"map_elites"``), or a
    Python object with ``propose(rng) -> symbols`` and ``learn(command,
    effect, reward)`` (see ``docs/python.md``). ``use_reward=False`` is the
    CLI's ``--no-reward``. ``k``, ``sigma``, ``rarity`` and
    ``goal_progress`` are goal babbling's and the archive's (the CLI's
    ``--k``, ``--sigma``, ``--rarity``, ``--goal-progress``), ``initial``
    per-move Q-learning's (``--initial``; it runs in ``run_episodes``); a
    hyper-parameter given a non-default value that the learner does not
    read is a ``UserWarning``. ``outcomes``: ``None`` (the cheapest of
    table, memo or live, as the CLI chooses) or one of ``"table"``,
    ``"memo"``, ``"live"``; ``table_cache``: a folder to keep outcomes in
    (the CLI's ``--table-cache``). ``progress``: a callable, called as
    ``progress(trials_done, trials)`` at most ten times a second and once
    at the end. Ctrl-C stops the session and raises ``KeyboardInterrupt``.
    ``target``: E3D's ``p*`` (None: uniform; an array of one weight per
    effect, or a dict ``{effect or (row, col): weight}``), also the
    metrics' target.

    ``learner`` may also be an ``e3d.Learner`` (or ``E3dLearner``): the
    session starts from its state (its own hyper-parameters and target; a
    target given here only sets the metrics') and leaves it in the state it
    ends in. ``on_trials``: a callable, called as ``on_trials(first,
    commands, effects, rewards)`` with the arrays of every ``every`` trials
    (the last call may hold fewer), ``first`` the index of their first
    trial; it runs the session on this thread (with the GIL), and an
    exception from it stops the session and is raised.
    """
    if on_trials is not None and not callable(on_trials):
        raise TypeError("on_trials: expected a callable, on_trials(first, commands, effects, "
                        f"rewards), found {type(on_trials).__name__}")
    return _e3d._run_sessions(
        scene, learner, integer("trials", trials, 1), [integer("seed", seed)], True, use_reward,
        hyper(alpha, beta, lambda_, eta, epsilon, k, sigma, rarity, goal_progress, initial),
        outcomes, cache_folder(table_cache), progress, target, on_trials,
        integer("every", every, 1))[0]


def run_sessions(
    scene: SceneLike,
    learner: Union[str, Sequence[PythonLearner], None] = None,
    trials: int = 5000,
    seeds: Optional[Sequence[int]] = None,
    sessions: Optional[int] = None,
    seed: int = 0,
    use_reward: bool = True,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    outcomes: Optional[str] = None,
    table_cache: Optional[PathLike_] = None,
    progress: Optional[Progress] = None,
    target: Optional[TargetLike] = None,
    k: int = 2,
    sigma: float = 0.1,
    rarity: float = 0.5,
    goal_progress: float = 0.0,
    initial: float = 1.0,
) -> SessionBatch:
    """Runs several sessions of one scene together, in lockstep: at every
    trial each session proposes its command, the new commands of all are
    simulated together (several copies of a physics scene stepped at once,
    as ``e3d run --sessions N`` does), then each session learns from its own
    outcome. Each session's numbers are those of ``run_session`` with its
    seed, and of ``e3d run SCENE --sessions N --seed S``.

    ``seeds``: the sessions' seeds; or ``sessions=N`` with ``seed=S`` for the
    CLI's seeds ``S, S+1, ..., S+N-1``. ``learner``: a built-in learner's
    name (the sessions run in parallel groups, without the GIL), or a
    sequence of Python learners, one per seed (they run on this thread,
    with the GIL). The other arguments are ``run_session``'s; ``progress``
    is called as ``progress(trials_done, trials * sessions)``. The first
    session that fails (a simulation that blows up) raises its error.
    """
    trials = integer("trials", trials, 1)
    listed = seeds_arg(seeds)
    n = optional("sessions", sessions, 1)
    seed = integer("seed", seed)
    if n is not None and n > MAX_SESSIONS:
        raise ValueError(f"sessions = {n}: expected at most {MAX_SESSIONS} "
                         "(the cap of `e3d run --sessions`)")
    if listed is not None and n is not None:
        raise ValueError("give either seeds or sessions (with seed), not both")
    if listed is None and n is None:
        raise ValueError("expected seeds=[...] or sessions=N (seeds seed, seed+1, ..., "
                         "as e3d run --sessions N --seed S)")
    if listed is None:
        assert n is not None
        if seed + n - 1 > 2**64 - 1:
            raise ValueError(f"seed = {seed} with sessions = {n}: "
                             "the seeds seed..seed+N-1 pass 2^64 - 1")
        listed = list(range(seed, seed + n))
    if not listed:
        raise ValueError("no session: expected at least one seed")
    return SessionBatch._stack(listed, _e3d._run_sessions(
        scene, learner, trials, listed, False, use_reward,
        hyper(alpha, beta, lambda_, eta, epsilon, k, sigma, rarity, goal_progress, initial),
        outcomes, cache_folder(table_cache), progress, target, None, 1))


@overload
def run_episodes(
    scene: SceneLike,
    episodes: Optional[int] = None,
    commands: Optional[int] = None,
    seed: Optional[int] = None,
    seeds: None = None,
    learner: Union[str, PythonContextualLearner, Learner, None] = None,
    closed_loop: bool = False,
    observe: Optional[str] = None,
    use_reward: bool = True,
    gamma: float = 0.9,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    target: Optional[TargetLike] = None,
    targets: Optional[Sequence[Optional[TargetLike]]] = None,
    initial: float = 1.0,
) -> EpisodeRecord: ...
@overload
def run_episodes(
    scene: SceneLike,
    episodes: Optional[int] = None,
    commands: Optional[int] = None,
    seed: Optional[int] = None,
    *,
    seeds: Sequence[int],
    learner: Union[str, Sequence[PythonContextualLearner], None] = None,
    closed_loop: bool = False,
    observe: Optional[str] = None,
    use_reward: bool = True,
    gamma: float = 0.9,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    target: Optional[TargetLike] = None,
    targets: Optional[Sequence[Optional[TargetLike]]] = None,
    initial: float = 1.0,
) -> list[EpisodeRecord]: ...
def run_episodes(
    scene: SceneLike,
    episodes: Optional[int] = None,
    commands: Optional[int] = None,
    seed: Optional[int] = None,
    seeds: Optional[Sequence[int]] = None,
    learner: Any = None,
    closed_loop: bool = False,
    observe: Optional[str] = None,
    use_reward: bool = True,
    gamma: float = 0.9,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    target: Optional[TargetLike] = None,
    targets: Optional[Sequence[Optional[TargetLike]]] = None,
    initial: float = 1.0,
) -> Union[EpisodeRecord, list[EpisodeRecord]]:
    """Sessions of episodes on a scene with start contexts, or of
    ``commands`` commands per episode (closed loop): ``e3d run SCENE
    --trials EPISODES --commands K [--closed-loop] [--observe ...]``, bit
    for bit.

    ``learner``: a built-in learner's name (None: ``"e3d"``), one per
    observed context; with ``closed_loop=True``, ``"e3d"`` is closed-loop
    E3D (Q_ref, discount ``gamma``) and ``"egreedy"`` epsilon-greedy
    Q-learning. ``"qlearning_moves"`` is per-move Q-learning (``e3d run
    --learner qlearning_moves``): on a scene whose command is ``Repeat``,
    each episode is ``commands`` times the scene's moves, each move a
    command chosen from the cell it starts in, the values starting at
    ``initial`` (1: optimistic), ``epsilon`` and ``gamma`` its own. Or a
    Python learner (with ``seeds``, a sequence of them, one
    per seed) with ``propose(context, rng)`` and ``learn(context, command,
    effect, reward, next)``, run on this thread; its first exception stops
    the run and is raised. ``target``: the target ``p*`` of every context;
    ``targets``: one per context (``p*(e|s)``), in context order.
    ``observe``: what the learner reads before each command, ``"start"``
    (the episode's start context), ``"state"`` (the current cell) or
    ``"blind"``; None: ``"state"`` with ``commands > 1`` or
    ``closed_loop``, else ``"start"``. Returns an ``EpisodeRecord`` for
    ``seed``, or with ``seeds`` a list of them (run in parallel, the same
    whatever the threads).
    """
    episodes = 1000 if episodes is None else integer("episodes", episodes, 1)
    listed = seeds_arg(seeds)
    one = listed is None
    if not one and seed is not None:
        raise ValueError("give either seed or seeds, not both")
    if listed is None:
        listed = [0 if seed is None else integer("seed", seed)]
    elif not listed:
        raise ValueError("no session: expected at least one seed")
    records = _e3d._run_episodes(
        scene, episodes, commands, listed, one, learner, closed_loop, observe, use_reward,
        number("gamma", gamma), hyper(alpha, beta, lambda_, eta, epsilon, initial=initial),
        target, targets)
    return records[0] if one else records
