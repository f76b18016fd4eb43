"""Type stubs of e3d's native module (``e3d._e3d``), re-exported by ``e3d``."""

from os import PathLike
from typing import Any, Optional, Protocol, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
E3D_VERSION: str

class SceneError(ValueError):
    """A scene or sweep that cannot be used: ``file:line:col: message``, the CLI's text."""

class SimulationError(RuntimeError):
    """A command whose simulation failed (a physics blow-up), naming scene and command."""

CommandsLike = Union[str, Sequence[str], npt.ArrayLike]

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
    def parse(self, commands: Union[str, Sequence[str]]) -> npt.NDArray[np.uint8]:
        """Command strings to a uint8 array ``[N, num_slots]`` of symbol indices."""
    @overload
    def format(self, commands: Sequence[int]) -> str: ...
    @overload
    def format(self, commands: npt.ArrayLike) -> Union[str, list[str]]: ...
    def world(self) -> World: ...

class Outcome:
    @property
    def effect(self) -> int: ...
    @property
    def reward(self) -> float: ...
    @property
    def x(self) -> float: ...
    @property
    def y(self) -> float: ...

class BatchOutcome:
    @property
    def effect(self) -> npt.NDArray[np.int64]: ...
    @property
    def reward(self) -> npt.NDArray[np.float64]: ...
    @property
    def x(self) -> npt.NDArray[np.float64]: ...
    @property
    def y(self) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...

class World:
    """Executes a scene's commands; keeps every outcome (no command simulated twice)."""

    @property
    def scene(self) -> Scene: ...
    @property
    def memo_len(self) -> int: ...
    def execute(self, command: CommandsLike) -> Outcome: ...
    def execute_batch(self, commands: CommandsLike) -> BatchOutcome: ...

class SessionRng:
    """The session's generator, valid during ``propose(rng)`` only."""

    def random(self) -> float: ...
    def integers(self, n: int) -> int: ...
    def choice(self, weights: Sequence[float]) -> int: ...

class PythonLearner(Protocol):
    def propose(self, rng: SessionRng) -> Union[str, npt.ArrayLike]: ...
    def learn(self, command: npt.NDArray[np.uint8], effect: int, reward: float) -> Any: ...

class SessionRecord:
    @property
    def scene(self) -> str: ...
    @property
    def learner(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def trials(self) -> int: ...
    @property
    def commands(self) -> npt.NDArray[np.uint8]: ...
    @property
    def effects(self) -> npt.NDArray[np.int64]: ...
    @property
    def rewards(self) -> npt.NDArray[np.float64]: ...
    @property
    def metrics(self) -> dict[str, Any]:
        """normalized_entropy, normalized_entropy_last_1000, kl_to_target,
        distinct_effects, cumulative_reward, first_reward_trial (None if no
        reward), trials."""
    @property
    def execution(self) -> str: ...

def run_session(
    scene: Union[Scene, str, PathLike[str]],
    learner: Union[str, PythonLearner, None] = None,
    trials: int = 5000,
    seed: int = 0,
    use_reward: bool = True,
    alpha: float = 0.3,
    beta: float = 1.0,
    lambda_: float = 0.03,
    eta: float = 0.01,
    epsilon: float = 0.1,
    outcomes: Optional[str] = None,
    table_cache: Union[str, PathLike[str], None] = None,
) -> SessionRecord: ...
def run_sweep(
    sweep: Union[str, PathLike[str]],
    threads: Optional[int] = None,
    table_cache: Union[str, PathLike[str], None] = None,
) -> dict[str, Union[npt.NDArray[Any], list[str]]]: ...
