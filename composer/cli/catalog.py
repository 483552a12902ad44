"""The tasks the command line knows: every id registered through `composer.registration`.

    infos = catalog.tasks()                  # {'Reach': TaskInfo(...), ...}, after `import tasks`
    info = catalog.find('reach')             # by name, any case, or by id 'composer/Reach-v0'
    env = catalog.make(info, render_mode='rgb_array')   # observations flattened by default
    info = catalog.with_pixels(info)         # `--pixels`: observed through its camera
    catalog.import_modules(['mypkg.tasks'])  # a user's own, from the current folder first

`find` raises UnknownTaskError with a did-you-mean and the known names.
"""

from __future__ import annotations

import dataclasses
import difflib
import importlib
import os
import sys
from collections.abc import Iterable
from typing import Any

from composer import registration
from composer.cli.errors import CliError, UnknownTaskError
from composer.environment import Environment
from composer.pixels import PixelEnvironment

SHIPPED = "tasks"
# Shadow map size for CLI frames: MuJoCo's default 4096 costs about 5x per frame on software
# OpenGL (Mesa llvmpipe, the usual headless EGL) and looks the same at 320x240.
SHADOW_SIZE = 1024
# `--pixels`: 64x64 frames of the task's camera (small enough for a CNN on a CPU), the latest
# three stacked so a policy sees motion.
# `--pixels` (of `train`, `run` and `eval`): the task observed through its camera as its
# pixel recipes were measured, as `gym.make(id, **PIXELS)` makes it (`composer.pixels`).
PIXELS = {"pixels": True, "width": 64, "height": 64, "frame_stack": 3}
PIXELS_SUFFIX = "-pixels"


def import_modules(modules: Iterable[str]) -> None:
    """Import each module (registering the tasks it defines), looking in the current folder
    first as `python -m` does (the `composer` script alone would not: Python puts the
    script's folder on the path, not the current one); raises CliError for a module that
    does not exist."""
    modules = list(modules)
    here = os.getcwd()
    if modules and here not in sys.path:
        sys.path.insert(0, here)
    for module in modules:
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as e:
            raise CliError(
                f"cannot import {module!r} (given with --import) from {here} or the "
                f"installed packages: {e}"
            ) from e


def tasks() -> dict[str, registration.TaskInfo]:
    """Every registered task by name (the shipped `tasks` package imported first), sorted;
    of several versions of a name, the newest."""
    try:
        importlib.import_module(SHIPPED)
    except ModuleNotFoundError as e:
        if e.name != SHIPPED:
            raise
    found: dict[str, registration.TaskInfo] = {}
    for info in registration.registered().values():
        known = found.get(info.name)
        if known is None or _version(info.env_id) > _version(known.env_id):
            found[info.name] = info
    return dict(sorted(found.items()))


def find(name: str) -> registration.TaskInfo:
    """The task called `name` (any case) or registered as the id `name`; raises
    UnknownTaskError listing the known tasks, with the closest names first."""
    known = tasks()
    for info in known.values():
        env_id = info.env_id.lower()
        if name.lower() in (info.name.lower(), env_id, env_id.partition("/")[2]):
            return info
    if not known:
        raise UnknownTaskError(
            f"unknown task {name!r}: no tasks are registered (is the 'tasks' package installed?)"
        )
    lowered = {n.lower(): n for n in known}
    close = [lowered[n] for n in difflib.get_close_matches(name.lower(), lowered, n=3, cutoff=0.5)]
    hint = f"; did you mean {' or '.join(repr(n) for n in close)}?" if close else "."
    raise UnknownTaskError(f"unknown task {name!r}{hint} Known tasks: {', '.join(known)}")


def with_pixels(info: registration.TaskInfo) -> registration.TaskInfo:
    """`info`'s task observed through its camera as `--pixels` says (PIXELS over its
    defaults), named NAME-pixels (its runs' default folder: runs/NAME-pixels-ALGO)."""
    if observes_pixels(info):
        return info
    return dataclasses.replace(
        info, name=info.name + PIXELS_SUFFIX, default_kwargs={**info.default_kwargs, **PIXELS}
    )


def command_line(info: registration.TaskInfo) -> str:
    """How a command names `info`'s task: 'CartpoleSwingup', or 'CartpoleSwingup --pixels'
    for `with_pixels`' variant."""
    base = info.name.removesuffix(PIXELS_SUFFIX)
    if base != info.name and observes_pixels(info):
        return f"{base} --pixels"
    return info.name


def observes_pixels(info: registration.TaskInfo) -> bool:
    """Whether `info`'s environment is observed through a camera (`pixels=True`)."""
    return bool(info.default_kwargs.get("pixels"))


def make(
    info: registration.TaskInfo, *, flatten: bool = True, render_mode: str | None = None
) -> Environment | PixelEnvironment:
    """Build `info`'s environment with its registered defaults, observations flattened into
    one vector unless `flatten` is False (what stable-baselines3's MlpPolicy takes); a
    PixelEnvironment when `observes_pixels(info)`. With a render mode, its shadow map is at
    most SHADOW_SIZE pixels."""
    env = registration.make_environment(info.task, **environment_kwargs(info, flatten, render_mode))
    if render_mode is not None:
        quality = env.physics.model.vis.quality
        quality.shadowsize = min(int(quality.shadowsize), SHADOW_SIZE)
    return env


def environment_kwargs(
    info: registration.TaskInfo, flatten: bool = True, render_mode: str | None = None
) -> dict[str, Any]:
    """The keywords `make` passes to `registration.make_environment` (after the task)."""
    return {**info.default_kwargs, "flatten_observations": flatten, "render_mode": render_mode}


def _version(env_id: str) -> int:
    return int(env_id.rpartition("-v")[2] or 0)
