"""composer tasks as RLlib environments, on one machine or a Ray cluster (docs/ray.md).

    env = composer.rllib.register_env("tasks:composer/CartpoleSwingup-v0")
    config = (PPOConfig().environment(env, env_config={"time_limit": 5.0})
              .env_runners(num_env_runners=2, num_envs_per_env_runner=8,
                           gym_env_vectorize_mode="vector_entry_point"))   # one batch of 8

Promises (`EnvCreator` states each): every env runner builds the task from its import path
(every machine needs this package); vectorized, one VectorEnvironment on the runner's CPUs;
no two environments of a run share a seed. Without Ray importing this raises ImportError.
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium
from gymnasium.vector import VectorWrapper

from composer import registration
from composer.environment import Environment
from composer.vector import VectorEnvironment, make_vector_environment

try:
    import ray
    from ray.tune.registry import register_env as _ray_register_env
except ImportError as e:
    missing = e.name or "ray"
    raise ImportError(
        f"composer.rllib needs Ray's RLlib ({missing} is missing): pip install -e '.[ray]'"
    ) from e

# Keywords only the batch takes; a single environment drops them.
_VECTOR_ONLY = ("nthread",)

__all__ = ["DistinctSeeds", "EnvCreator", "register_env"]


def register_env(env_id: str) -> str:
    """Register the composer task behind Gymnasium id `env_id` (e.g.
    'composer/Reach-v0', or 'tasks:composer/Reach-v0' to import `tasks` first) as an RLlib
    environment of the same id, and return that id. Raises RegistrationError when the
    module cannot be imported or no composer task is registered under the id."""
    module, _, name = env_id.rpartition(":")
    if module:
        try:
            importlib.import_module(module)
        except ImportError as e:
            raise registration.RegistrationError(
                f"register_env({env_id!r}): cannot import {module!r}: {e}"
            ) from e
    info = registration.registered().get(name)
    if info is None:
        known = ", ".join(sorted(registration.registered())) or "none (import `tasks` first?)"
        raise registration.RegistrationError(
            f"register_env({env_id!r}): no composer task is registered as {name!r}; "
            f"registered: {known}"
        )
    _ray_register_env(name, EnvCreator(info.task, dict(info.default_kwargs)))
    return name


@dataclasses.dataclass(frozen=True)
class EnvCreator:
    """RLlib's env creator for one composer task (picklable: the task is an import path).
    Called with RLlib's env config: with a 'num_envs' entry (RLlib's vector entry point)
    it makes a VectorEnvironment, without one a single Environment. RLlib ships the
    registration to every process of the cluster; each env runner imports the task from
    its import path, so every machine needs this package installed.

    What an env runner gets:
    - `num_envs_per_env_runner` > 1 with `gym_env_vectorize_mode="vector_entry_point"`: one
      `composer.VectorEnvironment` of that many environments, stepped by MuJoCo's batch on as
      many threads as Ray gave the runner CPUs (`num_cpus_per_env_runner`, default 1), its
      per-step task code batched where the task declares it (`composer.vector`). Any other
      mode: RLlib's own vector of single `composer.Environment`s (correct, but a Python loop).
    - Observations flattened into one vector (RLlib's default models take a vector); set
      `env_config={"flatten_observations": False}` for the dict.
    - `env_config` keys are the task's keywords and the environment's (`time_limit`,
      `flatten_observations`, `render_mode`, and `nthread` for the batch), over the defaults
      the task was registered with; a key neither accepts raises `RegistrationError` in the
      env runner, which RLlib reports when it builds the algorithm.
    - Seeds: RLlib resets env runner w with `seed + w`; environment i of a runner's M gets
      seed `(seed + w) * M + i`, so no two environments of a run start from the same seed.
    """

    task: str
    defaults: dict[str, Any]

    def __call__(self, env_config: Mapping[str, Any]) -> Environment | gymnasium.vector.VectorEnv:
        """The environment(s) of `env_config` (see the class docstring)."""
        config = {"flatten_observations": True, **self.defaults, **env_config}
        num_envs = config.pop("num_envs", None)
        if num_envs is None:
            single = {k: v for k, v in config.items() if k not in _VECTOR_ONLY}
            return registration.make_environment(self.task, **single)
        config.setdefault("nthread", _assigned_cpus())
        vector = make_vector_environment(int(num_envs), self.task, **config)
        return DistinctSeeds(vector)


class DistinctSeeds(VectorWrapper):
    """A VectorEnvironment whose `reset(seed=s)` seeds environment i with s * num_envs + i
    (see `EnvCreator`); a list of seeds or None passes through."""

    env: VectorEnvironment

    def reset(
        self,
        *,
        seed: int | Sequence[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[Any, dict[str, Any]]:
        """Reset as VectorEnvironment.reset, with an int seed spread over the runner."""
        if isinstance(seed, int):
            seed = [seed * self.num_envs + i for i in range(self.num_envs)]
        return self.env.reset(seed=seed, options=options)


def _assigned_cpus() -> int | None:
    """The CPUs Ray assigned to this actor (at least 1), or None outside a Ray worker."""
    if not ray.is_initialized():
        return None
    context = ray.get_runtime_context()
    if context.get_actor_id() is None:  # the driver, or a task
        return None
    return max(1, int(context.get_assigned_resources().get("CPU", 1)))
