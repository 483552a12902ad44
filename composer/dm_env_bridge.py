"""dm_env bridge (the `[dm]` extra): composer environments served to dm_env code.

    dm = composer.dm_env_bridge.DmEnvAdapter(env, seed=0)  # a dm_env.Environment
    timestep = dm.reset()                                  # FIRST: reward, discount None
    while not timestep.last():
        timestep = dm.step(policy(timestep.observation))  # MID ... LAST

`DmEnvAdapter` states its TimeSteps and discounts; a task's own dm_env `action_spec` works
unchanged, and `space_from_spec`/`spec_from_space` convert specs (`composer.dm_env_specs`).
Without dm_env importing this raises ImportError saying how to install it.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np

from composer.dm_env_specs import action_space_from_spec, space_from_spec, spec_from_space
from composer.task import Task

try:
    import dm_env
except ImportError as e:  # the [dm] extra is optional
    raise ImportError(
        "composer.dm_env_bridge needs the dm-env package: pip install -e '.[dm]' from a "
        "checkout (or: pip install dm-env)"
    ) from e

__all__ = ["DmEnvAdapter", "action_space_from_spec", "space_from_spec", "spec_from_space"]


class DmEnvAdapter(dm_env.Environment):
    """A Gymnasium environment (a `composer.Environment`, or any with Box, Discrete, Dict or
    Tuple spaces) as a `dm_env.Environment`.

    `reset()` returns a FIRST TimeStep; `step(action)` a MID one,
    or LAST when the episode ends; `step` after LAST (or before any reset) starts a new episode
    and ignores the action, as dm_env asks. Observations are those of the environment (a dict
    of arrays, or one array when flattened) with specs from its spaces, named by key. Rewards
    are float64 scalars. The discount is the task's `get_discount` (`info['discount']`), except:
    - a terminated step (Gymnasium's `terminated`, from `should_terminate_episode`) has discount
      0.0, dm_env's termination, unless the task defines `get_discount` (or
      `get_discount_batch`) itself: then its value, as dm_control reports it (its tasks say 0.0
      for a failure and 1.0 for an end that should bootstrap);
    - a truncated step (time limit) keeps the task's discount, dm_env's truncation;
    - a step MuJoCo diverged on ends the episode with discount 0.0, as dm_control ends it.
    A task's `get_reward_spec()` / `get_discount_spec()`, when defined and not None, are the
    reward and discount specs (dm_control's hooks); otherwise dm_env's defaults.
    """

    def __init__(self, env: gymnasium.Env[Any, Any], seed: int | None = None) -> None:
        """Serve `env`; its first reset uses `seed` (None: unseeded). Raises TaskError for
        spaces without a dm_env spec."""
        self._env = env
        self._seed = seed
        self._needs_reset = True
        self._task: Task | None = getattr(env.unwrapped, "task", None)
        task = self._task
        if task is not None and _declares(task, "action_spec"):
            self._action_spec = task.action_spec(env.unwrapped.physics)  # type: ignore[attr-defined]
        else:
            self._action_spec = spec_from_space(env.action_space, "action")
        self._observation_spec = spec_from_space(env.observation_space, "observation")
        self._reward_spec = _task_spec(task, "get_reward_spec") or super().reward_spec()
        self._discount_spec = _task_spec(task, "get_discount_spec") or super().discount_spec()
        self._discount_of_termination = task is not None and (
            _declares(task, "get_discount") or _declares(task, "get_discount_batch")
        )

    @property
    def environment(self) -> gymnasium.Env[Any, Any]:
        """The Gymnasium environment served."""
        return self._env

    @property
    def physics(self) -> Any:
        """The environment's `mjcf.Physics` (dm_control code reads `env.physics`)."""
        return self._env.unwrapped.physics  # type: ignore[attr-defined]

    @property
    def task(self) -> Task | None:
        """The composer task, or None for another kind of environment."""
        return self._task

    def reset(self) -> dm_env.TimeStep:
        """Start an episode: a FIRST TimeStep."""
        observation, _ = self._env.reset(seed=self._seed)
        self._seed = None  # later episodes continue the seeded random state
        self._needs_reset = False
        return dm_env.restart(self._observation(observation))

    def step(self, action: Any) -> dm_env.TimeStep:
        """Advance one control step with `action`, or start an episode (FIRST, the action
        ignored) before the first reset and after a LAST step."""
        if self._needs_reset:
            return self.reset()
        observation, reward, terminated, truncated, info = self._env.step(action)
        observation = self._observation(observation)
        reward = np.float64(reward)
        discount = np.float64(info.get("discount", 1.0))
        if "physics_error" in info:
            self._needs_reset = True
            return dm_env.TimeStep(dm_env.StepType.LAST, reward, np.float64(0.0), observation)
        if terminated:
            self._needs_reset = True
            if not self._discount_of_termination:
                return dm_env.termination(reward, observation)
            return dm_env.TimeStep(dm_env.StepType.LAST, reward, discount, observation)
        if truncated:
            self._needs_reset = True
            return dm_env.truncation(reward, observation, discount)
        return dm_env.transition(reward, observation, discount)

    def action_spec(self) -> Any:
        """The task's own `action_spec`, else the spec of the action space."""
        return self._action_spec

    def observation_spec(self) -> Any:
        """The spec of the observation space: a dict of specs named by key (or one)."""
        return self._observation_spec

    def reward_spec(self) -> Any:
        """The task's `get_reward_spec()`, else dm_env's float64 scalar."""
        return self._reward_spec

    def discount_spec(self) -> Any:
        """The task's `get_discount_spec()`, else dm_env's float64 scalar in [0, 1]."""
        return self._discount_spec

    def close(self) -> None:
        """Close the Gymnasium environment."""
        self._env.close()

    def _observation(self, observation: Any) -> Any:
        """`observation` in the spec's structure and dtypes."""
        return _cast(observation, self._observation_spec)


def _cast(value: Any, spec: Any) -> Any:
    if isinstance(spec, dict):
        return {key: _cast(value[key], item) for key, item in spec.items()}
    if isinstance(spec, tuple):
        return tuple(_cast(part, item) for part, item in zip(value, spec, strict=True))
    return np.asarray(value, dtype=spec.dtype)


def _declares(task: Task, name: str) -> bool:
    """Whether `task`'s class defines `name` itself, rather than composer's Task."""
    found = getattr(type(task), name, None)
    return found is not None and found is not getattr(Task, name, None)


def _task_spec(task: Task | None, name: str) -> Any:
    method = getattr(task, name, None)
    return method() if method is not None else None
