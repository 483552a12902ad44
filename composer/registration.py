"""Registration: composer tasks as Gymnasium ids.

    registration.register('Reach', 'tasks.reach:Reach', 'planar arm tip to a target',
                          time_limit=2.0)                 # -> 'composer/Reach-v0'
    env = gym.make('tasks:composer/Reach-v0', flatten_observations=True)  # imports `tasks`
    vec = gym.make_vec('composer/Reach-v0', num_envs=8, vectorization_mode='vector_entry_point')

Promises: a spec holds only strings and plain values, so it pickles into `AsyncVectorEnv`
and SB3's `SubprocVecEnv` workers; `gym.make`'s keywords go to the task, except the
`EnvironmentOptions`; one neither accepts raises RegistrationError listing what they accept.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import inspect
import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any, Literal, overload

import gymnasium

from composer import errors
from composer.environment import Environment
from composer.pixels import DEFAULT_SIZE, PixelEnvironment, check_camera, check_positive
from composer.task import Task

NAMESPACE = "composer"
ENTRY_POINT = "composer.registration:make_environment"
VECTOR_ENTRY_POINT = "composer.vector:make_vector_environment"
# The size of render() frames when `width` and `height` are not given (Environment's).
RENDER_SIZE = (240, 320)


class RegistrationError(errors.TaskError):
    """A task could not be registered, found, or built from the keywords given."""


class RegistrationWarning(UserWarning):
    """An id another package had registered now makes a composer task."""


@dataclasses.dataclass(frozen=True)
class TaskInfo:
    """What `register` recorded about one Gymnasium id."""

    name: str
    env_id: str
    task: str
    description: str
    default_kwargs: dict[str, Any]


_REGISTERED: dict[str, TaskInfo] = {}


@dataclasses.dataclass(frozen=True)
class EnvironmentOptions:
    """The keywords of `gym.make` and `gym.make_vec` that go to the environment rather than
    the task (`make_environment`, `composer.vector.make_vector_environment`), with their
    defaults: `time_limit`, `flatten_observations`, `action_repeat` and `render_mode` are
    `composer.Environment`'s.

    Rendering and pixels take Gymnasium's MuJoCo keywords: `gym.make(id, render_mode='rgb_array',
    width=64, height=64)` renders 64x64 frames (default 320x240) through `camera_name` or
    `camera_id` (one of them; default the task's `render_camera`, else the free camera);
    `pixels=True` observes the task through that camera instead (`composer.pixels`: uint8
    (height, width, 3) frames, 84x84 unless `width`/`height` say otherwise), with
    `frame_stack=k` and `proprioception=True` (a Dict of 'pixels' and the flattened state).
    """

    time_limit: float | None = None
    flatten_observations: bool = False
    action_repeat: int = 1
    render_mode: str | None = None
    width: int | None = None
    height: int | None = None
    camera_id: int | None = None
    camera_name: str | None = None
    pixels: bool = False
    frame_stack: int = 1
    proprioception: bool = False

    @classmethod
    def split(cls, keywords: dict[str, Any]) -> tuple[EnvironmentOptions, dict[str, Any]]:
        """(the options among `keywords`, the other keywords: the task's)."""
        options = {k: v for k, v in keywords.items() if k in ENVIRONMENT_OPTIONS}
        rest = {k: v for k, v in keywords.items() if k not in ENVIRONMENT_OPTIONS}
        return cls(**options), rest

    def check(self, where: str = "") -> None:
        """Raise RegistrationError (its message starting with `where`) for both `camera_id`
        and `camera_name`, or `frame_stack` or `proprioception` without `pixels`; and
        composer.TaskError for a size that is not a positive integer."""
        if self.camera_id is not None and self.camera_name is not None:
            raise RegistrationError(
                f"{where}give camera_id or camera_name, not both "
                f"(got {self.camera_id!r} and {self.camera_name!r})"
            )
        if not self.pixels and (self.frame_stack != 1 or self.proprioception):
            raise RegistrationError(
                f"{where}frame_stack and proprioception shape pixel observations; "
                "give pixels=True with them"
            )
        for label, value in (("width", self.width), ("height", self.height)):
            if value is not None:
                check_positive(label, value)

    @property
    def render_size(self) -> tuple[int, int]:
        """(height, width) of render() frames."""
        return (RENDER_SIZE[0] if self.height is None else self.height,
                RENDER_SIZE[1] if self.width is None else self.width)  # fmt: skip

    @property
    def pixel_size(self) -> tuple[int, int]:
        """(height, width) of pixel observations."""
        return (DEFAULT_SIZE if self.height is None else self.height,
                DEFAULT_SIZE if self.width is None else self.width)  # fmt: skip


# Their names, in order.
ENVIRONMENT_OPTIONS = tuple(field.name for field in dataclasses.fields(EnvironmentOptions))


def register(
    name: str,
    task: str,
    description: str,
    *,
    version: int = 0,
    namespace: str = NAMESPACE,
    **default_kwargs: Any,
) -> str:
    """Register `task` (an import path, 'package.module:TaskClass') as the Gymnasium id
    `{namespace}/{name}-v{version}` ('composer/...' by default) and return the id;
    `default_kwargs` are `gym.make`'s defaults (task keywords and `time_limit`,
    `flatten_observations`, `render_mode`). Registering an id of ours again is a no-op; an
    id another package registered (Shimmy's `dm_control/...` ids) is replaced with a
    RegistrationWarning naming it. Raises RegistrationError when `task` is not a
    'module:attribute' string (a string keeps the spec picklable).

    Gymnasium 1.x loads no plugins, so an id exists only once the module registering it was
    imported: `import tasks` first, or use Gymnasium's module prefix `'tasks:composer/X-v0'`,
    which imports `tasks` inside `gym.make`.
    """
    if not isinstance(task, str) or ":" not in task:
        raise RegistrationError(
            f"register({name!r}): task must be an import path 'package.module:TaskClass', "
            f"got {task!r}"
        )
    env_id = f"{namespace}/{name}-v{version}"
    existing = gymnasium.registry.get(env_id)
    if existing is not None and existing.entry_point != ENTRY_POINT:
        warnings.warn(
            f"{env_id} was registered by {existing.entry_point!r} (another package, e.g. "
            f"Shimmy's dm_control environments); it now makes composer's task {task}",
            RegistrationWarning,
            stacklevel=2,
        )
        del gymnasium.registry[env_id]
        existing = None
    if existing is None:
        gymnasium.register(
            id=env_id,
            entry_point=ENTRY_POINT,
            vector_entry_point=VECTOR_ENTRY_POINT,
            kwargs={"task": task, **default_kwargs},
        )
    _REGISTERED.setdefault(env_id, TaskInfo(name, env_id, task, description, dict(default_kwargs)))
    return env_id


def registered() -> dict[str, TaskInfo]:
    """Every id registered through `register` in this process, by id (a copy)."""
    return dict(_REGISTERED)


def resolve_task(task: str | Callable[..., Task]) -> Callable[..., Task]:
    """The task factory `task` names: a callable is returned as is; 'module:attribute'
    (or 'module.attribute') is imported. Raises RegistrationError when the module or
    attribute does not exist or is not callable."""
    if callable(task):
        return task
    if not isinstance(task, str):
        raise RegistrationError(
            f"a task is an import path 'module:TaskClass' or a callable, got {task!r}"
        )
    module_name, _, attribute = task.partition(":") if ":" in task else task.rpartition(".")
    if not module_name or not attribute:
        raise RegistrationError(f"task {task!r} is not an import path 'module:TaskClass'")
    try:
        module = importlib.import_module(module_name)
    except ImportError as e:
        raise RegistrationError(f"task {task!r}: cannot import {module_name!r}: {e}") from e
    found = getattr(module, attribute, None)
    if not callable(found):
        raise RegistrationError(
            f"task {task!r}: module {module_name!r} has no callable {attribute!r}"
        )
    return found


def accepted_keywords(factory: Callable[..., Any]) -> list[str] | None:
    """The keyword arguments `factory` accepts, in order, or None when it takes **kwargs."""
    accepted = []
    for parameter in inspect.signature(factory).parameters.values():
        if parameter.kind is inspect.Parameter.VAR_KEYWORD:
            return None
        if parameter.kind in (parameter.POSITIONAL_OR_KEYWORD, parameter.KEYWORD_ONLY):
            accepted.append(parameter.name)
    return accepted


def task_factory(
    task: str | Callable[..., Task], task_kwargs: dict[str, Any], options: Sequence[str]
) -> Callable[[], Task]:
    """A function of no arguments making `task(**task_kwargs)`, `task` as `resolve_task`
    takes it. Raises RegistrationError for a keyword the task does not accept, naming the
    task and listing what it accepts and the environment's own `options`, and what
    `resolve_task` raises."""
    factory = resolve_task(task)
    accepted = accepted_keywords(factory)
    if accepted is not None:
        unknown = sorted(set(task_kwargs) - set(accepted))
        if unknown:
            raise RegistrationError(
                f"task {_label(task)} got unknown keyword argument(s) {unknown}; it accepts "
                f"{accepted} and the environment options {list(options)}"
            )
    return functools.partial(factory, **task_kwargs)


@overload
def make_environment(
    task: str | Callable[..., Task], *, pixels: Literal[False] = False, **kwargs: Any
) -> Environment: ...


@overload
def make_environment(
    task: str | Callable[..., Task], *, pixels: Literal[True], **kwargs: Any
) -> PixelEnvironment: ...


def make_environment(
    task: str | Callable[..., Task], **keywords: Any
) -> Environment | PixelEnvironment:
    """Build `task(**task_kwargs)` and serve it as a `composer.Environment` (Gymnasium's
    entry point for every registered id); with `pixels`, served through a
    `composer.pixels.PixelEnvironment`. `keywords` are the `EnvironmentOptions` (whose
    docstring says what each does; `time_limit` None means no limit) and the task's.
    Raises RegistrationError for a keyword the task does not accept (listing those it
    does), both `camera_id` and `camera_name`, or a camera the scene does not have, and
    what the task, Environment or PixelEnvironment raise (composer.Error subclasses)."""
    options, task_kwargs = EnvironmentOptions.split(keywords)
    options.check(f"task {_label(task)}: ")
    built = task_factory(task, task_kwargs, ENVIRONMENT_OPTIONS)()
    if not isinstance(built, Task):
        raise RegistrationError(
            f"task {_label(task)} made a {type(built).__name__}, not a composer.Task"
        )
    camera = next(
        (c for c in (options.camera_name, options.camera_id) if c is not None),
        getattr(built, "render_camera", -1),
    )
    render_height, render_width = options.render_size
    env = Environment(
        built,
        time_limit=math.inf if options.time_limit is None else options.time_limit,
        flatten_observations=options.flatten_observations
        or (options.pixels and options.proprioception),
        action_repeat=options.action_repeat,
        render_mode=options.render_mode,
        render_height=render_height,
        render_width=render_width,
        render_camera=camera,
    )
    try:
        check_camera(env.physics.model, camera)
    except errors.TaskError as e:
        env.close()
        raise RegistrationError(f"task {_label(task)}: {e}") from e
    if not options.pixels:
        return env
    height, width = options.pixel_size
    return PixelEnvironment(
        env, height=height, width=width, camera=camera, frame_stack=options.frame_stack,
        proprioception=options.proprioception,
    )  # fmt: skip


def _label(task: str | Callable[..., Any]) -> str:
    return repr(task) if isinstance(task, str) else getattr(task, "__qualname__", repr(task))


# gym.make reads its entry point's render modes to offer 'human' and '*_list' wrappers.
make_environment.metadata = Environment.metadata  # type: ignore[attr-defined]
