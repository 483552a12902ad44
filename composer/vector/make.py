"""make_vector_environment: Gymnasium's `vector_entry_point` for every registered task.

    vec = gym.make_vec('composer/Reach-v0', num_envs=64,
                       vectorization_mode='vector_entry_point')      # a VectorEnvironment
    vec = make_vector_environment(64, 'tasks.reach:Reach', time_limit=2.0, randomize=False)
    vec = gym.make_vec('composer/Reach-v0', num_envs=16, vectorization_mode='vector_entry_point',
                       pixels=True, width=64, height=64)             # a PixelVectorEnvironment

Keywords are those of `composer.registration.make_environment` (time limit, flattening,
render mode, size and camera, `pixels`, `frame_stack` and `proprioception`; the rest go to
the task), plus Gymnasium's `max_episode_steps` and the VectorEnvironment's
`autoreset_mode` and `nthread`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gymnasium.vector import AutoresetMode

from composer.pixels import DEFAULT_SIZE, CameraError, check_camera, check_positive
from composer.registration import ENVIRONMENT_OPTIONS, RENDER_SIZE, RegistrationError, task_factory
from composer.task import Task
from composer.vector.environment import VectorEnvironment
from composer.vector.pixels import PixelVectorEnvironment

# The keywords of a vector environment beside those of `registration.make_environment`.
_VECTOR_OPTIONS = ("max_episode_steps", "autoreset_mode", "nthread")


def make_vector_environment(
    num_envs: int,
    task: str | Callable[..., Task],
    *,
    time_limit: float | None = None,
    flatten_observations: bool = False,
    action_repeat: int = 1,
    render_mode: str | None = None,
    width: int | None = None,
    height: int | None = None,
    camera_id: int | None = None,
    camera_name: str | None = None,
    pixels: bool = False,
    frame_stack: int = 1,
    proprioception: bool = False,
    max_episode_steps: int | None = None,
    autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    nthread: int | None = None,
    **task_kwargs: Any,
) -> VectorEnvironment:
    """A VectorEnvironment of num_envs `task(**task_kwargs)`s, a PixelVectorEnvironment
    with `pixels`; `task` is an import path ('module:TaskClass') or a callable; the other
    keywords are `make_environment`'s and VectorEnvironment's. Raises RegistrationError as
    `make_environment` does (a keyword the task does not accept, both camera keywords, a
    camera the scene does not have), and what VectorEnvironment raises."""
    if camera_id is not None and camera_name is not None:
        raise RegistrationError(
            f"give camera_id or camera_name, not both (got {camera_id!r} and {camera_name!r})"
        )
    if not pixels and (frame_stack != 1 or proprioception):
        raise RegistrationError(
            "frame_stack and proprioception shape pixel observations; give pixels=True with them"
        )
    for label, value in (("width", width), ("height", height)):
        if value is not None:
            check_positive(label, value)
    camera = camera_name if camera_name is not None else camera_id
    factory = task_factory(task, task_kwargs, (*ENVIRONMENT_OPTIONS, *_VECTOR_OPTIONS))
    options: dict[str, Any] = dict(
        time_limit=time_limit, flatten_observations=flatten_observations,
        action_repeat=action_repeat, max_episode_steps=max_episode_steps,
        autoreset_mode=autoreset_mode,
        render_mode=render_mode, nthread=nthread, render_camera=camera,
        render_height=RENDER_SIZE[0] if height is None else height,
        render_width=RENDER_SIZE[1] if width is None else width,
    )  # fmt: skip
    if pixels:
        try:
            return PixelVectorEnvironment(
                factory, num_envs, height=DEFAULT_SIZE if height is None else height,
                width=DEFAULT_SIZE if width is None else width, camera=camera,
                frame_stack=frame_stack, proprioception=proprioception, **options,
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
