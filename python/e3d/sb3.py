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
from .gym import E3dEnv, E3dVectorEnv, _flag


class E3dSB3VecEnv(_Base, metaclass=abc.ABCMeta):  # type: ignore[misc, unused-ignore]
    """``num_envs`` one-command episodes stepped together (see the module)."""

    #: the most commands ``discrete=True`` flattens (one output of DQN's
    #: network per command)
    MAX_DISCRETE = 1 << 20

    def __init__(self, scene: Union[Scene, str], num_envs: int, use_reward: bool = True, discrete: bool = False,
                 render_mode: Optional[str] = None, commands: Optional[int] = 1):
        discrete = _flag(discrete, "discrete")
        integer("num_envs", num_envs, 1, E3dVectorEnv.MAX_NUM_ENVS)
        one = E3dEnv(scene, use_reward=use_reward, render_mode=render_mode, commands=commands)
        #: the copies, each an ``E3dEnv`` stepped in turn, when episodes are
        #: several commands or start apart (``commands=K``, start
        #: contexts); else None and ``venv`` steps them in one batch
        self.envs: Optional[list[E3dEnv]] = None
        if one.episodes is None:
            self.venv = E3dVectorEnv(one.scene, num_envs, use_reward=use_reward, render_mode=render_mode)
        else:
            self.envs = [one] + [E3dEnv(one.scene, use_reward=use_reward, render_mode=render_mode,
                                        commands=commands) for _ in range(int(num_envs) - 1)]
            self.venv = None  # type: ignore[assignment]
        self.scene = one.scene
        self.render_mode = render_mode
        action_space = one.action_space
        self.discrete = discrete
        self._sizes: tuple[int, ...] = ()
        if discrete:
            scene = one.scene
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
        super().__init__(int(num_envs), one.observation_space, action_space)
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
        if self.envs is None:
            obs, _ = self.venv.reset(seed=seed)
        else:
            # copy i seeded seed + i (SB3's VecEnv.seed(seed) convention)
            obs = np.array([env.reset(seed=None if seed is None else seed + i)[0]
                            for i, env in enumerate(self.envs)], dtype=np.int64)
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
        if self.envs is not None:
            return self._step_each(self._actions)
        obs, rewards, terminated, _, infos = self.venv.step(self._actions)
        final = infos["final_obs"]
        x, y = infos["final_info"]["x"], infos["final_info"]["y"]
        out = [
            {"terminal_observation": final[i], "TimeLimit.truncated": False, "x": float(x[i]), "y": float(y[i])}
            for i in range(self.num_envs)
        ]
        return obs, rewards.astype(np.float32), terminated.copy(), out

    def _step_each(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        """Steps each copy by its action, resetting (SB3's auto-reset) those
        whose episode ended: their observation is the next episode's first
        context, the last one's in ``terminal_observation``."""
        assert self.envs is not None
        if len(actions) != self.num_envs:
            raise ValueError(f"actions: expected one action per environment ({self.num_envs}), "
                             f"found {len(actions)}")
        obs = np.zeros(self.num_envs, dtype=np.int64)
        rewards = np.zeros(self.num_envs, dtype=np.float32)
        dones = np.zeros(self.num_envs, dtype=np.bool_)
        infos: list[dict[str, Any]] = []
        for i, (env, a) in enumerate(zip(self.envs, actions)):
            o, r, done, _, info = env.step(a)
            info = {"x": float(info["x"]), "y": float(info["y"]), "start": info.get("start")}
            if done:
                info["terminal_observation"] = o
                info["TimeLimit.truncated"] = False
                o, _ = env.reset()
            obs[i], rewards[i], dones[i] = o, r, done
            infos.append(info)
        return obs, rewards, dones, infos

    def render(self, mode: Optional[str] = None) -> Optional[np.ndarray]:
        """With ``render_mode="rgb_array"``: the copies' pictures (each with
        the path of its last command) tiled in a grid, as SB3's ``VecEnv``
        tiles them; else ``None``."""
        if self.render_mode != "rgb_array":
            return None
        images = [im for im in self.get_images() if im is not None]
        n = len(images)
        cols = int(np.ceil(np.sqrt(n)))
        rows = int(np.ceil(n / cols))
        h, w, c = images[0].shape
        out = np.zeros((rows * h, cols * w, c), dtype=np.uint8)
        for i, im in enumerate(images):
            r, q = divmod(i, cols)
            out[r * h:(r + 1) * h, q * w:(q + 1) * w] = im
        return out

    def get_images(self) -> Sequence[Optional[np.ndarray]]:
        """One picture per copy (``render_mode="rgb_array"``), else Nones."""
        if self.render_mode != "rgb_array":
            return [None] * self.num_envs
        if self.envs is not None:
            return [env.render() for env in self.envs]
        return list(self.venv.render() or ())

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

    def _env(self, i: int) -> Any:
        """The ``E3dEnv`` of copy ``i`` (one shared by all when batched)."""
        return self.venv.env if self.envs is None else self.envs[i]

    def get_attr(self, attr_name: str, indices: Union[None, int, Sequence[int]] = None) -> list[Any]:
        return [getattr(self._env(i), attr_name) for i in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Union[None, int, Sequence[int]] = None) -> None:
        if self.envs is None:
            # the copies share one environment: set once
            setattr(self.venv.env, attr_name, value)
        else:
            for i in self._indices(indices):
                setattr(self.envs[i], attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Union[None, int, Sequence[int]] = None, **method_kwargs: Any
    ) -> list[Any]:
        return [getattr(self._env(i), method_name)(*method_args, **method_kwargs) for i in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Union[None, int, Sequence[int]] = None) -> list[bool]:
        return [False for _ in self._indices(indices)]
