"""make_vector_environment: Gymnasium's `vector_entry_point` for every registered task.

    vec = gym.make_vec('composer/Reach-v0', num_envs=64,
                       vectorization_mode='vector_entry_point')      # a VectorEnvironment
    vec = make_vector_environment(64, 'tasks.reach:Reach', time_limit=2.0, randomize=False)
    vec = gym.make_vec('composer/Reach-v0', num_envs=16, vectorization_mode='vector_entry_point',
                       pixels=True, width=64, height=64)             # a PixelVectorEnvironment

Keywords are `make_environment`'s (the `EnvironmentOptions`, the rest the task's) plus
`max_episode_steps`, `autoreset_mode` and `nthread`; a bad one raises RegistrationError.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gymnasium.vector import AutoresetMode

from composer.pixels import CameraError, check_camera
from composer.registration import (
    ENVIRONMENT_OPTIONS,
    EnvironmentOptions,
    RegistrationError,
    task_factory,
)
from composer.task import Task
from composer.vector.environment import VectorEnvironment
from composer.vector.pixels import PixelVectorEnvironment

# The keywords of a vector environment beside the `EnvironmentOptions`.
_VECTOR_OPTIONS = ("max_episode_steps", "autoreset_mode", "nthread")


def make_vector_environment(
    num_envs: int,
    task: str | Callable[..., Task],
    *,
    max_episode_steps: int | None = None,
    autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    nthread: int | None = None,
    **keywords: Any,
) -> VectorEnvironment:
    """A VectorEnvironment of num_envs `task(**task_kwargs)`s, a PixelVectorEnvironment
    with `pixels`; `task` is an import path ('module:TaskClass') or a callable; `keywords`
    are the `EnvironmentOptions` of `make_environment` and the task's. Raises
    RegistrationError as `make_environment` does (a keyword the task does not accept, both
    camera keywords, a camera the scene does not have), and what VectorEnvironment raises."""
    environment, task_kwargs = EnvironmentOptions.split(keywords)
    environment.check()
    camera = (
        environment.camera_name if environment.camera_name is not None else environment.camera_id
    )
    factory = task_factory(task, task_kwargs, (*ENVIRONMENT_OPTIONS, *_VECTOR_OPTIONS))
    render_height, render_width = environment.render_size
    options: dict[str, Any] = dict(
        time_limit=environment.time_limit, flatten_observations=environment.flatten_observations,
        action_repeat=environment.action_repeat, max_episode_steps=max_episode_steps,
        autoreset_mode=autoreset_mode,
        render_mode=environment.render_mode, nthread=nthread, render_camera=camera,
        render_height=render_height, render_width=render_width,
    )  # fmt: skip
    if environment.pixels:
        height, width = environment.pixel_size
        try:
            return PixelVectorEnvironment(
                factory, num_envs, height=height, width=width, camera=camera,
                frame_stack=environment.frame_stack,
                proprioception=environment.proprioception, **options,
            )  # fmt: skip
        except CameraError as e:
            raise RegistrationError(str(e)) from e
    vector = VectorEnvironment(factory, num_envs, **options)
    if camera is not None:
        try:
            check_camera(vector.environments[0].physics.model, camera)
        except CameraError as e:
            vector.close()
            raise RegistrationError(str(e)) from e
    return vector
