"""A Stable-Baselines3 ``VecEnv`` over e3d's batched execution.

``E3dSB3VecEnv(scene, num_envs)`` steps ``num_envs`` copies of the
one-command episode of ``e3d.gym.E3dEnv`` with one
``World.execute_batch`` call, as ``E3dVectorEnv`` does, and speaks SB3's
``VecEnv`` protocol: ``reset() -> obs``, ``step(actions) -> (obs,
rewards, dones, infos)`` with every copy done at every step and reset in
the same call (the returned observations are the start effect; each
info's ``terminal_observation`` is the command's terminal effect, as
SB3's own ``DummyVecEnv`` gives it), ``infos[i]["x"]``, ``["y"]``.

``discrete=True`` flattens the ``MultiDiscrete`` command into one
``Discrete(num_commands)`` action, for the algorithms that take only a
``Discrete`` one (DQN): action ``i`` is the command of index ``i`` in the
library's order (``CommandSpace::index_of``: slot 0 most significant, as
``numpy.unravel_index`` over the alphabet sizes), and ``commands(actions)``
gives the commands of such actions.

    from stable_baselines3 import DQN
    model = DQN("MlpPolicy", E3dSB3VecEnv("two_rooms", 4, discrete=True), learning_starts=64)
    model.learn(1_000)

    from stable_baselines3 import PPO
    from e3d.sb3 import E3dSB3VecEnv
    model = PPO("MlpPolicy", E3dSB3VecEnv("two_rooms", 16), n_steps=64, batch_size=256)
    model.learn(10_000)

Importing this module imports stable_baselines3 (and so torch) when it
is installed; without it, the class stands on a minimal base of the same
methods (what the tests without SB3 step).
"""

import abc
from typing import Any, Optional, Sequence, Union

import numpy as np

class _StandIn:
    """Without SB3: the part of its ``VecEnv`` the adapter uses (its
    attributes, and ``step`` as ``step_async`` then ``step_wait``)."""

    def __init__(self, num_envs: int, observation_space: Any, action_space: Any):
        self.num_envs = num_envs
        self.observation_space = observation_space
        self.action_space = action_space

    def step(self, actions: np.ndarray) -> Any:
        self.step_async(actions)  # type: ignore[attr-defined]
        return self.step_wait()  # type: ignore[attr-defined]


_Base: Any
try:
    from stable_baselines3.common.vec_env import VecEnv as _Base  # type: ignore[import-not-found, no-redef, unused-ignore]
except ImportError:
    _Base = _StandIn

from ._e3d import Scene
from ._args import integer
from .gym import E3dVectorEnv, _flag


class E3dSB3VecEnv(_Base, metaclass=abc.ABCMeta):  # type: ignore[misc, unused-ignore]
    """``num_envs`` one-command episodes stepped together (see the module)."""

    #: the most commands ``discrete=True`` flattens (one output of DQN's
    #: network per command)
    MAX_DISCRETE = 1 << 20

    def __init__(self, scene: Union[Scene, str], num_envs: int, use_reward: bool = True, discrete: bool = False):
        discrete = _flag(discrete, "discrete")
        self.venv = E3dVectorEnv(scene, num_envs, use_reward=use_reward)
        action_space = self.venv.single_action_space
        self.discrete = discrete
        self._sizes: tuple[int, ...] = ()
        if discrete:
            scene = self.venv.scene
            n = scene.num_commands
            if scene.is_continuous or n is None or n > self.MAX_DISCRETE:
                raise ValueError(
                    f"discrete=True: scene `{scene.name}` has "
                    + ("continuous commands" if scene.is_continuous else f"{n} commands")
                    + f"; expected symbols, at most {self.MAX_DISCRETE} commands"
                )
            from gymnasium import spaces

            self._sizes = tuple(scene.alphabet_sizes)
            action_space = spaces.Discrete(n)
        super().__init__(self.venv.num_envs, self.venv.single_observation_space, action_space)
        self._actions: Optional[np.ndarray] = None

    def commands(self, actions: np.ndarray) -> np.ndarray:
        """The commands (symbol indices, ``(n, num_slots)``) of flattened
        ``discrete=True`` actions (command indices); other actions as given."""
        a = np.asarray(actions)
        if not self.discrete:
            return a
        flat = a.reshape(-1)
        n = int(np.prod(self._sizes))
        if flat.dtype.kind not in "iu" or (flat < 0).any() or (flat >= n).any():
            raise ValueError(f"actions: expected command indices from 0 to {n - 1}, found {flat.tolist()}")
        return np.stack(np.unravel_index(flat.astype(np.int64), self._sizes), axis=1)

    def reset(self) -> np.ndarray:
        seeds = getattr(self, "_seeds", [None])
        seed = seeds[0] if seeds else None
        obs, _ = self.venv.reset(seed=seed)
        if hasattr(self, "_reset_seeds"):
            self._reset_seeds()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        a = np.asarray(actions)
        if self.discrete and a.reshape(-1).size != self.num_envs:
            raise ValueError(
                f"actions: expected one command index per environment ({self.num_envs}), "
                f"found shape {list(a.shape)}"
            )
        self._actions = self.commands(a)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        assert self._actions is not None, "step_async first"
        obs, rewards, terminated, _, infos = self.venv.step(self._actions)
        final = infos["final_obs"]
        x, y = infos["final_info"]["x"], infos["final_info"]["y"]
        out = [
            {"terminal_observation": final[i], "TimeLimit.truncated": False, "x": float(x[i]), "y": float(y[i])}
            for i in range(self.num_envs)
        ]
        return obs, rewards.astype(np.float32), terminated.copy(), out

    def close(self) -> None:
        pass

    def _indices(self, indices: Union[None, int, Sequence[int]]) -> list[int]:
        """The copies ``indices`` names (``None``: all; an integer or a
        sequence of integers, numpy's too, each from 0 to ``num_envs - 1``,
        else ``TypeError``/``ValueError`` naming ``indices``)."""
        if indices is None:
            return list(range(self.num_envs))
        if isinstance(indices, (str, bytes)) or not hasattr(indices, "__iter__"):
            items = [indices]
        else:
            items = list(indices)
        out = [integer("indices", i, None) for i in items]
        for i in out:
            if not 0 <= i < self.num_envs:
                raise ValueError(f"indices: {i} is no copy's index: expected integers from 0 to {self.num_envs - 1}")
        return out

    def get_attr(self, attr_name: str, indices: Union[None, int, Sequence[int]] = None) -> list[Any]:
        return [getattr(self.venv.env, attr_name) for _ in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Union[None, int, Sequence[int]] = None) -> None:
        # the copies share one environment: set once
        setattr(self.venv.env, attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Union[None, int, Sequence[int]] = None, **method_kwargs: Any
    ) -> list[Any]:
        return [getattr(self.venv.env, method_name)(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Union[None, int, Sequence[int]] = None) -> list[bool]:
        return [False for _ in self._indices(indices)]
