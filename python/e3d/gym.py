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

**Episodes of several commands.** On a scene with start contexts (a grid's
``contexts``, e.g. ``four_rooms``, ``scenes/two_rooms_contexts.ron``), or
with ``commands=K > 1`` or ``observe`` given, the environment is a true
multi-step one (an ``EpisodeWorld``, what ``run_episodes`` runs): ``reset()``
draws the episode's start context and start state, the observation is the
context (``observe="state"``: the current cell, ``Discrete(num_effects)``,
the default with ``K > 1``; ``"start"``: the start context's index,
``Discrete(number of start contexts)``, the default with ``K = 1``;
``"blind"``: 0), and each ``step`` executes one command from where the
last one ended; the episode terminates after ``K`` commands, with the
scene's reward after the last one (0 after the others).
``reset(seed=s)`` seeds the draws of the start contexts (the library's
``SessionRng``; a ``reset()`` without seed continues them), and
``reset(options={"start": i})`` picks start context ``i``. ``info`` holds
``start`` too.

Else the world is deterministic: the same action always gives the same effect
and reward, whatever the seed; ``reset(seed=...)`` seeds ``self.np_random``
as Gymnasium asks, for agents that sample from it. Outcomes are kept (each
command is simulated once per environment).

Importing this module imports gymnasium (``import e3d`` does not) and
registers the environment as ``"e3d/E3d-v0"``:
``gymnasium.make("e3d/E3d-v0", scene="two_rooms")``.
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from . import EpisodeWorld, Scene
from ._args import integer, optional


def _flag(v: Any, name: str) -> bool:
    """``v`` if it is a bool (Python's or numpy's), else a ``TypeError``
    naming ``name`` (a string such as ``"no"`` would be taken as True)."""
    if not isinstance(v, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, found {type(v).__name__}")
    return bool(v)


__all__ = ["E3dEnv", "E3dVectorEnv", "ENV_ID"]

ENV_ID = "e3d/E3d-v0"
"""The id under which ``gymnasium.make`` finds ``E3dEnv``."""


class E3dEnv(gym.Env):
    """One command per episode on an e3d scene, or episodes of ``commands``
    commands on a scene with start contexts (see the module's text).

    Parameters
    ----------
    scene:
        A ``Scene``, or a scene file's path or a built-in scene's name.
    use_reward:
        ``False`` gives reward 0 always (the paper's task 1); a bool
        (Python's or numpy's), else ``TypeError``.
    render_mode:
        ``None``, or ``"rgb_array"``: ``render()`` returns the scene's
        picture (``Scene.render``, uint8 ``(H, W, 3)``) with the path of
        the last step's command (the bare scene before any step).
    commands:
        The commands of an episode, ``K`` (1 to 64; ``None``: 1; a
        continuous scene takes 1 only): an integer (not a bool), else
        ``TypeError``.
    observe:
        ``None``, ``"start"``, ``"state"`` or ``"blind"``: what the
        observation is on episodes (see the module's text).

    ``info`` holds ``x``, ``y`` (the terminal point, metres) and ``command``
    (the command as its symbols) after ``step``.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 1}

    def __init__(
        self,
        scene: Union[Scene, str],
        use_reward: bool = True,
        render_mode: Optional[str] = None,
        commands: Optional[int] = 1,
        observe: Optional[str] = None,
    ):
        super().__init__()
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode = {render_mode!r}: expected None or 'rgb_array'")
        self.render_mode = render_mode
        self._last: Any = None
        if isinstance(scene, os.PathLike):
            scene = os.fspath(scene)
        if not isinstance(scene, (Scene, str)):
            raise TypeError(
                f"scene: expected a Scene, or a scene file's path or a built-in scene's name, "
                f"found {type(scene).__name__}"
            )
        self.scene = scene if isinstance(scene, Scene) else Scene.resolve(scene)
        self.world = self.scene.world()
        self.use_reward = _flag(use_reward, "use_reward")
        k = 1 if commands is None else integer("commands", commands, None)
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
        self.episodes: Optional[EpisodeWorld] = None
        if not self.scene.is_continuous:
            ep = EpisodeWorld(self.scene, k, observe, self.use_reward)
            if ep.commands > 1 or observe is not None or ep.num_starts > 1:
                self.episodes = ep
                self.observation_space = spaces.Discrete(ep.num_contexts)
        elif k != 1 or observe is not None:
            raise ValueError(
                f"scene `{self.scene.name}` takes continuous values: its episodes are one command"
            )
        self._seeded = False

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.int64, dict[str, Any]]:
        seed = optional("seed", seed, 0)
        if options is not None and not isinstance(options, Mapping):
            raise TypeError(f"options: expected None or a dict such as {{'start': 0}}, found {type(options).__name__}")
        start = (options or {}).get("start")
        if start is not None:
            start = integer("start", start, None)
        super().reset(seed=seed)
        self._last = None
        if self.episodes is None:
            return self._start, {}
        if seed is None and not self._seeded:
            seed = int(self.np_random.integers(2**63))
        self._seeded = True
        context = self.episodes.reset(seed, start)
        return np.int64(context), {"start": self.episodes.start}

    def values_of(self, action: Any, rows: bool = False) -> np.ndarray:
        """A continuous scene's values for an action in ``[-1, 1]`` per slot
        (clamped): ``low + (u + 1) / 2 * (high - low)``, ``high`` at 1; one
        action ``[slots]``, or with ``rows`` one per row ``[n, slots]``. An
        action of another shape, or not finite, raises ``ValueError``, and
        so does a scene of symbols (its actions are symbol indices)."""
        if not self.scene.is_continuous:
            raise ValueError(
                f"values_of: scene `{self.scene.name}` takes symbols, not continuous values: "
                "its actions are symbol indices, one per slot"
            )
        rows = _flag(rows, "rows")
        u = np.asarray(action, dtype=np.float64)
        n = self.scene.num_slots
        if u.ndim != 1 + rows or u.shape[-1] != n:
            raise ValueError(
                f"action: expected {n} values in [-1, 1] (one per slot), found shape {list(u.shape)}"
            )
        if not np.isfinite(u).all():
            raise ValueError(f"action: expected finite values in [-1, 1], found {u[~np.isfinite(u)][0]}")
        u = np.clip(u, -1.0, 1.0)
        v = self._low + (u + 1.0) * 0.5 * (self._high - self._low)
        return np.where(u == 1.0, self._high, v)

    def step(self, action: Any) -> tuple[np.int64, float, bool, bool, dict[str, Any]]:
        info: dict[str, Any]
        if self.episodes is not None:
            symbols = np.asarray(action)
            context, out, done = self.episodes.step(symbols)
            self._last = symbols
            info = {
                "x": out.x,
                "y": out.y,
                "command": self.scene.format(symbols),
                "start": self.episodes.start,
            }
            return np.int64(context), float(out.reward), done, False, info
        if self.scene.is_continuous:
            values = self.values_of(action)
            out = self.world.execute(values)
            self._last = values
            info = {"x": out.x, "y": out.y, "values": values}
        else:
            symbols = np.asarray(action)
            out = self.world.execute(symbols)
            self._last = symbols
            info = {"x": out.x, "y": out.y, "command": self.scene.format(symbols)}
        reward = float(out.reward) if self.use_reward else 0.0
        return np.int64(out.effect), reward, True, False, info

    def render(self) -> Optional[np.ndarray]:
        """With ``render_mode="rgb_array"``: the scene's picture with the
        path of the last step's command, uint8 ``(H, W, 3)``; else ``None``."""
        if self.render_mode != "rgb_array":
            return None
        return self.scene.render(self._last)


class E3dVectorEnv(VectorEnv):
    """``num_envs`` copies of ``E3dEnv`` stepped together by one
    ``World.execute_batch`` call (the commands run in parallel, without
    the GIL, 32 at once per Rapier world where that is exact; one outcome
    memo for all copies).

    Autoreset is ``SAME_STEP`` (``metadata["autoreset_mode"]``): every
    episode is one command, so every ``step`` terminates every copy and
    resets it within the same call. The observations returned are
    therefore the reset ones (the start effect); the terminal effects are
    in ``infos["final_obs"]`` (int64 ``[num_envs]``, with the mask
    ``infos["_final_obs"]``), and ``infos["final_info"]`` holds ``x`` and
    ``y``, as ``SyncVectorEnv(..., autoreset_mode=SAME_STEP)`` gives them.
    Rewards are those of the commands of this very step: repeating a
    rewarded command is rewarded every step (gymnasium's default
    ``NEXT_STEP`` mode would spend every other step on the reset, rewards
    1, 0, 1, 0).

    ``render_mode="rgb_array"``: ``render()`` returns a tuple of
    ``num_envs`` pictures (``Scene.render``), each with the path of its
    copy's last command (the bare scene before any step and after
    ``reset()``, as ``E3dEnv``).
    """

    metadata: dict[str, Any] = {
        "render_modes": ["rgb_array"],
        "render_fps": 1,
        "autoreset_mode": AutoresetMode.SAME_STEP,
    }

    #: the most copies (each step's arrays hold one row per copy)
    MAX_NUM_ENVS = 1 << 20

    def __init__(
        self,
        scene: Union[Scene, str],
        num_envs: int,
        use_reward: bool = True,
        render_mode: Optional[str] = None,
    ):
        super().__init__()
        integer("num_envs", num_envs, 1, self.MAX_NUM_ENVS)
        self.env = E3dEnv(scene, use_reward=use_reward, render_mode=render_mode)
        if self.env.episodes is not None:
            raise ValueError(
                f"E3dVectorEnv: scene `{self.env.scene.name}` has start contexts; its episodes "
                "start apart: use gymnasium.vector.SyncVectorEnv over E3dEnv"
            )
        self.render_mode = render_mode
        self._last: Optional[np.ndarray] = None
        self.scene, self.world = self.env.scene, self.env.world
        self.num_envs = int(num_envs)
        self.single_action_space = self.env.action_space
        self.single_observation_space = self.env.observation_space
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._start = np.full(self.num_envs, self.scene.start_effect, dtype=np.int64)

    def reset(
        self, *, seed: Optional[Union[int, list[Optional[int]]]] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        if isinstance(seed, (list, tuple)):
            # gymnasium's form: one seed per copy; the copies share one
            # world, whose start is the same whatever the seed: the first
            # seeds the spaces
            if len(seed) != self.num_envs:
                raise ValueError(
                    f"seed: expected None, an integer or a list of num_envs = {self.num_envs} seeds, "
                    f"found a list of {len(seed)}"
                )
            for one in seed:
                optional("seed", one, 0)
            seed = seed[0]
        seed = optional("seed", seed, 0)
        if options is not None and not isinstance(options, Mapping):
            raise TypeError(f"options: expected None or a dict, found {type(options).__name__}")
        super().reset(seed=seed)
        if seed is not None:
            self.action_space.seed(seed)
        self._last = None
        return self._start.copy(), {}

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        a = np.asarray(actions)
        if a.ndim != 2 or a.shape[0] != self.num_envs:
            raise ValueError(
                f"actions: expected one action per environment, an array of shape "
                f"[{self.num_envs}, {self.scene.num_slots}], found shape {list(a.shape)}"
            )
        if self.scene.is_continuous:
            a = self.env.values_of(a, rows=True)
        out = self.world.execute_batch(a)
        self._last = a
        reward = out.reward if self.env.use_reward else np.zeros(self.num_envs)
        done = np.ones(self.num_envs, dtype=np.bool_)
        infos = {
            "final_obs": out.effect,
            "_final_obs": done,
            "final_info": {"x": out.x, "_x": done, "y": out.y, "_y": done},
            "_final_info": done,
        }
        return self._start.copy(), np.asarray(reward, dtype=np.float64), done, ~done, infos

    def render(self) -> Optional[tuple[np.ndarray, ...]]:
        """With ``render_mode="rgb_array"``: one picture per copy, with the
        path of its last command; else ``None``."""
        if self.render_mode != "rgb_array":
            return None
        if self._last is None:
            return tuple(self.scene.render() for _ in range(self.num_envs))
        return tuple(self.scene.render(c) for c in self._last)


if ENV_ID not in gym.registry:
    gym.register(id=ENV_ID, entry_point="e3d.gym:E3dEnv")
