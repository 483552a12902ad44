"""stable-baselines3 on a VectorEnvironment: all envs stepped by MuJoCo's batch.

    from stable_baselines3 import PPO
    from composer.sb3 import VecEnvAdapter, make_vec_env
    venv = make_vec_env('tasks.locomotion:AntRun', n_envs=64, flatten_observations=True)
    model = PPO('MlpPolicy', venv).learn(1_000_000)    # VecMonitor(venv) for episode stats

`VecEnvAdapter` returns what SB3 expects (`terminal_observation`, `TimeLimit.truncated`) and
raises TaskError for a VectorEnvironment not made with `autoreset_mode=SAME_STEP`. This module
imports stable-baselines3 (`pip install -e '.[train]'`); only it and `composer train` do.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.vec_env import VecEnv

from composer import errors
from composer.task import Task
from composer.vector import VectorEnvironment, make_vector_environment


class VecEnvAdapter(VecEnv):
    """A stable-baselines3 VecEnv over a SAME_STEP VectorEnvironment.

    Serves a `composer.VectorEnvironment` made with `autoreset_mode=SAME_STEP`
    (stable-baselines3's own convention) as a `stable_baselines3.common.vec_env.VecEnv`:
    `step` returns (obs, rewards, dones, infos) with `infos[i]['terminal_observation']` and
    `'TimeLimit.truncated'` as SB3 expects, and the step's info entries (discount,
    physics_error, the task's) per environment. Seeds set with `seed()` apply at the next
    `reset()`. `render()` tiles every environment's frame.
    """

    def __init__(self, env: VectorEnvironment) -> None:
        """Serve `env`; raises TaskError unless its autoreset mode is SAME_STEP."""
        if env.autoreset_mode is not AutoresetMode.SAME_STEP:
            raise errors.TaskError(
                "VecEnvAdapter needs a VectorEnvironment made with "
                f"autoreset_mode=AutoresetMode.SAME_STEP, got {env.autoreset_mode}"
            )
        self.env = env
        self._actions: np.ndarray | None = None
        super().__init__(env.num_envs, env.single_observation_space, env.single_action_space)

    def reset(self) -> Any:
        """Reset every environment (with the seeds of `seed()`, once); the observations."""
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        observations, _ = self.env.reset(seed=seeds)
        self._reset_seeds()
        self._reset_options()
        return observations

    def step_async(self, actions: np.ndarray) -> None:
        """Remember the actions for `step_wait`."""
        self._actions = np.asarray(actions)

    def step_wait(self) -> tuple[Any, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        """Step every environment: (observations, rewards, dones, infos), with ended
        environments reset and their last observation in info['terminal_observation']."""
        observations, rewards, terminated, truncated, info = self.env.step(self._actions)
        dones = terminated | truncated
        infos = _per_env(info, self.num_envs)
        if dones.any():
            final_obs, final_infos = info["final_obs"], _per_env(info["final_info"], self.num_envs)
            for done in np.flatnonzero(dones):
                infos[done].update(final_infos[done])
                infos[done]["terminal_observation"] = final_obs[done]
        for i in range(self.num_envs):
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
        return observations, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        """Close the vector environment."""
        self.env.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        """Attribute `attr_name` of each environment (its composer.Environment)."""
        return [getattr(self.env.environments[i], attr_name) for i in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        """Set attribute `attr_name` of each environment."""
        for i in self._get_indices(indices):
            setattr(self.env.environments[i], attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any
    ) -> list[Any]:
        """Call method `method_name` of each environment (not step or reset: those belong
        to the batch)."""
        return [
            getattr(self.env.environments[i], method_name)(*method_args, **method_kwargs)
            for i in self._get_indices(indices)
        ]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        """False: the environments are not gymnasium-wrapped."""
        return [False for _ in self._get_indices(indices)]

    def get_images(self) -> Sequence[np.ndarray | None]:
        """A frame of each environment (None each without an 'rgb_array' render mode), as
        stable-baselines3's `VecEnv.render` tiles them."""
        frames = self.env.render()
        return list(frames) if frames is not None else [None] * self.num_envs


def _per_env(info: dict[str, Any], n: int) -> list[dict[str, Any]]:
    """Gymnasium's vector info (arrays with '_key' masks) as one dict per environment."""
    out: list[dict[str, Any]] = [{} for _ in range(n)]
    for key, value in info.items():
        if key.startswith("_") or key in ("final_obs", "final_info"):
            continue
        mask = info[f"_{key}"]
        for i in np.flatnonzero(mask):
            out[i][key] = _per_env(value, n)[i] if isinstance(value, dict) else value[i]
    return out


def make_vec_env(
    task: str | Callable[..., Task],
    n_envs: int,
    *,
    time_limit: float | None = None,
    flatten_observations: bool = True,
    **task_kwargs: Any,
) -> VecEnvAdapter:
    """A VecEnvAdapter over `make_vector_environment`'s VectorEnvironment of `task`
    (an import path or a callable) in SAME_STEP mode; raises what it raises."""
    vector = make_vector_environment(
        n_envs,
        task,
        time_limit=time_limit,
        flatten_observations=flatten_observations,
        autoreset_mode=AutoresetMode.SAME_STEP,
        **task_kwargs,
    )
    return VecEnvAdapter(vector)
