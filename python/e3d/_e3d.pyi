"""Type stubs of e3d's native module (``e3d._e3d``), re-exported by ``e3d``."""

from os import PathLike
from typing import Any, Callable, Optional, Sequence, Union, final, overload

import numpy as np
import numpy.typing as npt
from typing_extensions import Self, disjoint_base

__version__: str
E3D_VERSION: str

class SceneError(ValueError):
    """A scene or sweep that cannot be used: ``file:line:col: message``, the CLI's text.

    Its parts as attributes, None where the error has none: ``file``,
    ``line`` and ``column`` (1-based), ``field`` (the field at fault, for a
    value the scene cannot hold)."""

    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    field: Optional[str]

class SimulationError(RuntimeError):
    """A command whose simulation failed (a physics blow-up), naming scene and command."""

from e3d._results import (
    BatchOutcome,
    EpisodeRecord,
    Motion,
    Outcome,
    SessionRecord,
)
from e3d._learner import Learner
from e3d._types import (
    CommandsLike,
    PathLike_,
    Progress,
    PythonContextualLearner,
    PythonLearner,
    SceneLike,
    TargetLike,
)

__all__ = [
    "E3D_VERSION",
    "EpisodeWorld",
    "Scene",
    "SceneError",
    "SessionRng",
    "SimulationError",
    "World",
    "_E3dLearner",
    "_Learner",
    "__version__",
    "_run_episodes",
    "_run_sessions",
    "merge_sweeps",
    "run_sweep",
]

@final
class Scene:
    """A parsed and validated scene."""

    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Scene: ...
    @staticmethod
    def builtin(name: str) -> Scene: ...
    @staticmethod
    def resolve(path_or_name: str) -> Scene: ...
    @staticmethod
    def from_text(text: str, file: str = "<string>") -> Scene: ...
    @staticmethod
    def builtins() -> list[str]: ...
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def kind(self) -> str:
        """``"grid"`` or ``"physics"``."""
    @property
    def num_slots(self) -> int: ...
    @property
    def is_continuous(self) -> bool:
        """Whether the slots take values in ``value_ranges`` rather than symbols."""
    @property
    def value_ranges(self) -> list[tuple[float, float]]:
        """Each slot's ``(low, high)`` on a continuous scene; empty otherwise."""
    @property
    def alphabet_sizes(self) -> list[int]: ...
    @property
    def alphabets(self) -> list[str]: ...
    @property
    def num_effects(self) -> int: ...
    @property
    def num_commands(self) -> Optional[int]:
        """``None`` beyond 2**64."""
    @property
    def effect_grid(self) -> tuple[int, int, tuple[float, float], tuple[float, float]]:
        """``(rows, cols, (xmin, ymin), (xmax, ymax))``."""
    @property
    def start_effect(self) -> int: ...
    def reward_table(self) -> npt.NDArray[np.float64]: ...
    def effort(self, commands: Union[str, Sequence[str], npt.ArrayLike]) -> npt.NDArray[np.float64]:
        """Each command's effort (``[N]``): the sum over its slots of the size of the slot's action."""
    @property
    def max_effort(self) -> float: ...
    @property
    def effort_varies(self) -> bool: ...
    def parse(self, commands: Union[str, Sequence[str]]) -> npt.NDArray[np.uint8]:
        """Command strings to a uint8 array ``[N, num_slots]`` of symbol indices."""
    @overload
    def format(self, commands: Sequence[int]) -> str: ...
    @overload
    def format(self, commands: npt.ArrayLike) -> Union[str, list[str]]: ...
    def world(self, prefix_states: Optional[int] = None) -> World:
        """A world that executes this scene's commands; ``execute`` keeps up to
        ``prefix_states`` phase-end states (default 2048; 0: none)."""
    def svg(self, command: Optional[CommandsLike] = None) -> str:
        """The scene as SVG, with a command's path if given (``e3d scene render``)."""
    def _repr_svg_(self) -> str: ...
    def to_ron(self) -> str:
        """RON text that ``Scene.from_text`` reads back as an equal scene."""
    def to_mjcf(self) -> str:
        """The scene as a MuJoCo model (MJCF text), ``e3d scene export --mjcf``."""
    def effect_of(self, values: Sequence[float]) -> int:
        """The effect of the effect's feature values (2 per point, 1 per joint or angle)."""
    def render(
        self, command: Optional[CommandsLike] = None, scale: float = 1.0
    ) -> npt.NDArray[np.uint8]:
        """The SVG rasterised: uint8 ``(H, W, 3)``, without text."""
    def geometry(self) -> dict[str, Any]:
        """Bodies, shapes, joints, walls, the effect grid and the reward cells as data."""
    def to_dict(self) -> dict[str, Any]:
        """The scene's fields (the RON text's structure) as Python data."""
    @staticmethod
    def from_dict(data: dict[str, Any]) -> Scene:
        """A scene from ``to_dict``'s form; ``SceneError`` names the path at fault."""
    def with_(self, overrides: dict[str, Any]) -> Scene:
        """A copy with ``{path: value}`` overrides (``"bodies.puck.linear_damping"``)."""

@final
class World:
    """Executes a scene's commands; keeps every outcome (no command simulated twice)."""

    @property
    def scene(self) -> Scene: ...
    @property
    def memo_len(self) -> int: ...
    @property
    def prefix_states(self) -> int: ...
    def execute(self, command: CommandsLike, seed: int = 0) -> Outcome:
        """One command; under noise its draws are ``run_key(seed, 0, 0)``'s."""
    def execute_batch(
        self,
        commands: CommandsLike,
        progress: Optional[Progress] = None,
        seed: int = 0,
    ) -> BatchOutcome:
        """The commands' outcomes; under noise row ``i`` draws from
        ``run_key(seed, 0, i)`` (``e3d scene exec --seed SEED``)."""
    def reevaluate(
        self, commands: CommandsLike, repeat: int = 20, seed: int = 0
    ) -> dict[str, Any]:
        """Each command run ``repeat`` times under the scene's noise: ``effect``
        (modal), ``share`` (of the runs ending there), ``runs``."""
    def reproducibility(
        self, learner: _Learner, repeat: int = 20, commands: int = 64, seed: int = 0
    ) -> Optional[float]:
        """The share of ``commands`` commands drawn from ``learner``'s policy whose
        effect holds in at least 90% of ``repeat`` noisy runs."""
    def trace(self, command: CommandsLike) -> Motion: ...

@disjoint_base
class _Learner:
    """The native base of ``e3d.Learner``: a built-in learner's state, made,
    stepped by ``propose`` / ``learn``, saved and loaded bit for bit."""

    def __new__(
        cls,
        scene: Union[SceneLike, bytes],
        learner: str = "e3d",
        alpha: float = 0.3,
        beta: float = 1.0,
        lambda_: float = 0.03,
        eta: float = 0.01,
        epsilon: float = 0.1,
        target: Optional[TargetLike] = None,
        k: int = 2,
        sigma: float = 0.1,
        rarity: float = 0.5,
        goal_progress: float = 0.0,
    ) -> Self: ...
    @staticmethod
    def contextual(
        scene: SceneLike,
        learner: str = "e3d",
        commands: Optional[int] = None,
        closed_loop: bool = False,
        observe: Optional[str] = None,
        gamma: float = 0.9,
        alpha: float = 0.3,
        beta: float = 1.0,
        lambda_: float = 0.03,
        eta: float = 0.01,
        epsilon: float = 0.1,
        target: Optional[TargetLike] = None,
        targets: Optional[Sequence[Optional[TargetLike]]] = None,
    ) -> Learner:
        """One learner per context, closed-loop E3D or Q-learning, for ``run_episodes``."""
    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @overload
    def propose(self, rng: SessionRng, /) -> npt.NDArray[Any]: ...
    @overload
    def propose(self, context: int, rng: SessionRng, /) -> npt.NDArray[Any]: ...
    @overload
    def learn(self, command: npt.ArrayLike, outcome: Outcome, /) -> None: ...
    @overload
    def learn(
        self, command: npt.ArrayLike, effect: int, reward: float, /, *,
        point: Optional[tuple[float, float]] = None,
    ) -> None: ...
    @overload
    def learn(
        self, context: int, command: npt.ArrayLike, effect: int, reward: float,
        next: Optional[int] = None, /,
    ) -> None: ...
    def to_bytes(self) -> bytes: ...
    def _tables(self) -> list[tuple[str, list[int], npt.NDArray[np.float64], bool]]: ...
    def _set_table(self, name: str, values: npt.NDArray[np.float64]) -> None: ...

class _E3dLearner(_Learner):
    """The native base of ``e3d.E3dLearner``: a ``Learner`` holding E3D."""

    def __new__(
        cls,
        scene: Union[SceneLike, bytes],
        alpha: float = 0.3,
        beta: float = 1.0,
        lambda_: float = 0.03,
        eta: float = 0.01,
        target: Optional[TargetLike] = None,
    ) -> Self: ...
    @property
    def beta(self) -> float: ...
    def set_q(self, slot: int, q: Sequence[float]) -> None: ...
    def set_policy(self, slot: int, probs: Sequence[float]) -> None: ...
    def _set_effect_model(self, effect_model: Sequence[float]) -> None: ...

@final
class SessionRng:
    """The session's generator, valid during ``propose(rng)`` only (used
    after it, it raises ``RuntimeError``); ``SessionRng(seed)``: one of
    one's own, seeded as ``run_session(seed=seed)`` seeds its own."""

    def __new__(cls, seed: int) -> SessionRng: ...

    def random(self) -> float: ...
    def integers(self, n: int) -> int: ...
    def choice(self, weights: Sequence[float]) -> int: ...
    def __reduce__(self) -> tuple[Any, tuple[int], tuple[str, bool]]:
        """Pickling: the generator's state (a copy draws what it draws next)."""
    def __setstate__(self, state: tuple[str, bool]) -> None: ...

def _run_sessions(
    scene: SceneLike, learner: Any, trials: int, seeds: Sequence[int], one: bool,
    use_reward: bool, params: dict[str, float], outcomes: Optional[str],
    table_cache: Optional[PathLike_], progress: Optional[Progress], target: Optional[TargetLike],
    on_trials: Any, every: int,
) -> list[SessionRecord]: ...

def _run_episodes(
    scene: SceneLike, episodes: int, commands: Optional[int], seeds: Sequence[int], one: bool,
    learner: Any, closed_loop: bool, observe: Optional[str], use_reward: bool, gamma: float,
    params: dict[str, float], target: Optional[TargetLike],
    targets: Optional[Sequence[Optional[TargetLike]]],
) -> list[EpisodeRecord]: ...

@final
class EpisodeWorld:
    """One episode at a time, command by command (what ``run_episodes`` runs)."""

    def __new__(
        cls,
        scene: SceneLike,
        commands: Optional[int] = None,
        observe: Optional[str] = None,
        use_reward: bool = True,
        closed_loop: bool = False,
    ) -> EpisodeWorld: ...
    @property
    def commands(self) -> int: ...
    @property
    def use_reward(self) -> bool: ...
    @property
    def observe(self) -> str: ...
    @property
    def num_contexts(self) -> int: ...
    @property
    def num_starts(self) -> int: ...
    @property
    def start(self) -> int: ...
    @property
    def scene(self) -> Scene: ...
    def reset(
        self, seed: Optional[int] = None, start: Optional[int] = None,
        rng: Optional[SessionRng] = None,
    ) -> int: ...
    def step(self, command: CommandsLike) -> tuple[int, Outcome, bool]: ...
    def __reduce__(self) -> tuple[Any, tuple[Scene, int, str, bool], str]: ...
    def __setstate__(self, state: str) -> None: ...

def run_sweep(
    sweep: Union[str, PathLike[str]],
    threads: Optional[int] = None,
    table_cache: Optional[PathLike_] = None,
    out: Optional[PathLike_] = None,
    resume: bool = False,
    progress: Optional[Progress] = None,
    shard: Optional[tuple[int, int]] = None,
) -> tuple[str, list[str]]: ...
def merge_sweeps(dirs: Sequence[PathLike_], out: PathLike_) -> tuple[str, list[str]]: ...
