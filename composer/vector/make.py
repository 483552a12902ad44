"""make_vector_environment: Gymnasium's `vector_entry_point` for every registered task.

    vec = gym.make_vec('composer/Reach-v0', num_envs=64,
                       vectorization_mode='vector_entry_point')      # a VectorEnvironment
    vec = make_vector_environment(64, 'tasks.reach:Reach', time_limit=2.0, randomize=False)

Keywords are those of `composer.registration.make_environment` (time limit, flattening,
render mode; the rest go to the task), plus Gymnasium's `max_episode_steps` and the
VectorEnvironment's `autoreset_mode` and `nthread`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gymnasium.vector import AutoresetMode

from composer.registration import ENVIRONMENT_OPTIONS, task_factory
from composer.task import Task
from composer.vector.environment import VectorEnvironment

# The keywords of a vector environment beside those of `registration.make_environment`.
_VECTOR_OPTIONS = ("max_episode_steps", "autoreset_mode", "nthread")


def make_vector_environment(
    num_envs: int,
    task: str | Callable[..., Task],
    *,
    time_limit: float | None = None,
    flatten_observations: bool = False,
    render_mode: str | None = None,
    max_episode_steps: int | None = None,
    autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    nthread: int | None = None,
    **task_kwargs: Any,
) -> VectorEnvironment:
    """A VectorEnvironment of num_envs `task(**task_kwargs)`s; `task` is an import path
    ('module:TaskClass') or a callable; the other keywords are VectorEnvironment's.
    Raises RegistrationError for a task that cannot be imported or a keyword it does not
    accept, and what VectorEnvironment raises."""
    return VectorEnvironment(
        task_factory(task, task_kwargs, (*ENVIRONMENT_OPTIONS, *_VECTOR_OPTIONS)),
        num_envs,
        time_limit=time_limit,
        flatten_observations=flatten_observations,
        max_episode_steps=max_episode_steps,
        autoreset_mode=autoreset_mode,
        render_mode=render_mode,
        nthread=nthread,
    )
