"""A Gymnasium environment for e3d's open-loop setting.

One episode is one trial: ``reset()`` puts the world at its start state,
``step(action)`` executes a whole command open loop (``action`` holds one
symbol index per slot, ``action_space = MultiDiscrete(alphabet sizes)``) and
returns its effect (``observation_space = Discrete(num_effects)``), its
reward and ``terminated=True``. The observation after ``reset()`` is the
effect of the start state (``Scene.start_effect``).

On a continuous scene (``Scene.is_continuous``) the action is a float32
``Box(-1, 1, (num_slots,))``: each slot's position in its range, -1 its
low end and 1 its high end (the library's ``ValueSpace::from_unit``;
values outside are clamped), and ``info["values"]`` holds the values
executed.

The world is deterministic: the same action always gives the same effect
and reward, whatever the seed; ``reset(seed=...)`` seeds ``self.np_random``
as Gymnasium asks, for agents that sample from it. Outcomes are kept (each
command is simulated once per environment).

Importing this module imports gymnasium (``import e3d`` does not) and
registers the environment as ``"e3d/E3d-v0"``:
``gymnasium.make("e3d/E3d-v0", scene="two_rooms")``.
"""

from __future__ import annotations

from typing import Any, Optional, Union

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from . import Scene

__all__ = ["E3dEnv", "ENV_ID"]

ENV_ID = "e3d/E3d-v0"
"""The id under which ``gymnasium.make`` finds ``E3dEnv``."""


class E3dEnv(gym.Env):
    """One command per episode on an e3d scene.

    Parameters
    ----------
    scene:
        A ``Scene``, or a scene file's path or a built-in scene's name.
    use_reward:
        ``False`` gives reward 0 always (the paper's task 1).
    render_mode:
        ``None``, the only mode (``metadata["render_modes"]`` is empty:
        ``e3d scene render`` draws a command's path as SVG, and
        ``World.trace`` gives its whole motion).

    ``info`` holds ``x``, ``y`` (the terminal point, metres) and ``command``
    (the command as its symbols) after ``step``.
    """

    metadata: dict[str, Any] = {"render_modes": []}

    def __init__(
        self,
        scene: Union[Scene, str],
        use_reward: bool = True,
        render_mode: Optional[str] = None,
    ):
        super().__init__()
        if render_mode is not None:
            raise ValueError(
                f"render_mode = {render_mode!r}: E3dEnv does not render (render_modes is empty); "
                "`e3d scene render --command` draws a command's path, World.trace gives its motion"
            )
        self.render_mode = None
        self.scene = scene if isinstance(scene, Scene) else Scene.resolve(str(scene))
        self.world = self.scene.world()
        self.use_reward = bool(use_reward)
        self.action_space: spaces.Space[Any]
        if self.scene.is_continuous:
            ranges = np.array(self.scene.value_ranges, dtype=np.float64)
            self._low, self._high = ranges[:, 0], ranges[:, 1]
            self.action_space = spaces.Box(-1.0, 1.0, (self.scene.num_slots,), np.float32)
        else:
            self.action_space = spaces.MultiDiscrete(
                np.array(self.scene.alphabet_sizes, dtype=np.int64)
            )
        self.observation_space = spaces.Discrete(self.scene.num_effects)
        self._start = np.int64(self.scene.start_effect)

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict] = None
    ) -> tuple[np.int64, dict[str, Any]]:
        super().reset(seed=seed)
        return self._start, {}

    def values_of(self, action: Any) -> np.ndarray:
        """A continuous scene's values for an action in ``[-1, 1]`` per slot
        (clamped): ``low + (u + 1) / 2 * (high - low)``, ``high`` at 1."""
        u = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        v = self._low + (u + 1.0) * 0.5 * (self._high - self._low)
        return np.where(u == 1.0, self._high, v)

    def step(self, action) -> tuple[np.int64, float, bool, bool, dict[str, Any]]:
        info: dict[str, Any]
        if self.scene.is_continuous:
            values = self.values_of(action)
            out = self.world.execute(values)
            info = {"x": out.x, "y": out.y, "values": values}
        else:
            symbols = np.asarray(action)
            out = self.world.execute(symbols)
            info = {"x": out.x, "y": out.y, "command": self.scene.format(symbols)}
        reward = float(out.reward) if self.use_reward else 0.0
        return np.int64(out.effect), reward, True, False, info

    def render(self) -> None:
        """Nothing to draw (``render_mode`` is ``None``): returns ``None``."""
        return None


if ENV_ID not in gym.registry:
    gym.register(id=ENV_ID, entry_point="e3d.gym:E3dEnv")
