"""Type aliases and protocols of e3d's API, for annotations (the stubs of
``e3d._e3d`` use them; ``e3d`` re-exports ``PythonLearner``)."""

import os
from typing import TYPE_CHECKING, Any, Callable, Optional, Protocol, Sequence, Union

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from e3d._e3d import Scene

SceneLike = Union["Scene", str, "os.PathLike[str]"]
"""A scene: a ``Scene``, a path to a RON file or a built-in scene's name."""

PathLike_ = Union[str, "os.PathLike[str]"]
"""A path: a string or an ``os.PathLike``."""

CommandsLike = Union[str, Sequence[str], npt.ArrayLike]
"""Commands: a string of symbols, a list of them, or an integer array of symbol indices; on a
continuous scene a string of values (``"1.8, -1.2, ..."``), a list of them, or a float array."""

TargetLike = Union[npt.ArrayLike, "dict[Any, float]"]
"""The target ``p*``: one weight per effect, or ``{effect or (row, col): weight}``."""

Progress = Callable[[int, int], object]
"""``progress(done, total)``: called at most ten times a second and once at the end."""


class PythonLearner(Protocol):
    """A learner written in Python, for ``run_session`` and ``run_sessions``."""

    def propose(self, rng: Any) -> Union[str, npt.ArrayLike]:
        """The next command (symbol indices, or a string), drawn from ``rng`` (a ``SessionRng``)."""
        ...

    def learn(self, command: "npt.NDArray[np.uint8]", effect: int, reward: float) -> Any:
        """Learns from the command's outcome; a ``learn`` that also takes
        ``point`` (or ``**kwargs``) gets ``point=(x, y)``, the terminal point."""
        ...


class PythonContextualLearner(Protocol):
    """A contextual learner written in Python, for ``run_episodes``."""

    def propose(self, context: int, rng: Any) -> Union[str, npt.ArrayLike]:
        """The next command in ``context`` (symbol indices, or a string), drawn from ``rng``."""
        ...

    def learn(self, context: int, command: "npt.NDArray[np.uint8]", effect: int, reward: float,
              next: Optional[int]) -> Any:
        """Learns from the command's outcome; ``next`` is the context it led to (None at the
        episode's end)."""
        ...
