"""dm_env specs and Gymnasium spaces, each as the other (the `[dm]` extra).

    from composer import dm_env_specs
    box = dm_env_specs.space_from_spec(specs.BoundedArray((2,), float, -1, 1))
    spec = dm_env_specs.spec_from_space(env.observation_space)
    action_space = dm_env_specs.action_space_from_spec(task.action_spec(physics))
    spec = dm_env_specs.actuator_spec(low, high, names)   # Task.action_spec's default

`composer.Task.action_space` and `composer.dm_env_bridge` convert here. Importing this module
imports dm_env; without it, an ImportError says how to install it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from gymnasium import spaces

from composer import errors

try:
    from dm_env import specs
except ImportError as e:  # the [dm] extra is optional
    raise ImportError(
        "composer's dm_env support needs the dm-env package: pip install -e '.[dm]' from a "
        "checkout (or: pip install dm-env)"
    ) from e


def space_from_spec(spec: Any) -> spaces.Space[Any]:
    """The Gymnasium space of a dm_env spec: `DiscreteArray` -> Discrete, `BoundedArray`
    -> Box of its bounds, `Array` -> Box unbounded (integers: their dtype's range, bools:
    0..1), a dict (or list or tuple) of specs -> Dict (Tuple). Raises TaskError for
    anything else (e.g. a `StringArray`)."""
    if isinstance(spec, specs.DiscreteArray):
        return spaces.Discrete(int(spec.num_values))
    if isinstance(spec, specs.BoundedArray):
        return _box(spec.shape, spec.dtype, spec.minimum, spec.maximum)
    if isinstance(spec, specs.StringArray):
        raise errors.TaskError(f"no Gymnasium space for the string spec {spec!r}")
    if isinstance(spec, specs.Array):
        dtype = np.dtype(spec.dtype)
        if dtype == np.bool_:
            return _box(spec.shape, dtype, False, True)
        if np.issubdtype(dtype, np.integer):
            limits = np.iinfo(dtype)
            return _box(spec.shape, dtype, limits.min, limits.max)
        return _box(spec.shape, dtype, -np.inf, np.inf)
    if isinstance(spec, Mapping):
        return spaces.Dict({key: space_from_spec(value) for key, value in spec.items()})
    if isinstance(spec, list | tuple):
        return spaces.Tuple([space_from_spec(value) for value in spec])
    raise errors.TaskError(f"no Gymnasium space for {spec!r}: expected a dm_env spec")


def action_space_from_spec(spec: Any) -> spaces.Box:
    """The Box of a task's `action_spec` (one `Array` or `BoundedArray` of numbers, as
    actions are one array here): the spec's shape, dtype and bounds, unbounded for an
    `Array`; the environment clips actions to it. Raises TaskError for any other spec."""
    if isinstance(spec, specs.Array) and not isinstance(
        spec, specs.DiscreteArray | specs.StringArray
    ):
        space = space_from_spec(spec)
        if isinstance(space, spaces.Box) and np.issubdtype(space.dtype, np.number):
            return space
    raise errors.TaskError(
        f"action_spec must return one dm_env.specs.Array or BoundedArray of numbers, got {spec!r}"
    )


def actuator_spec(low: np.ndarray, high: np.ndarray, names: list[str]) -> Any:
    """dm_control's action spec of a model's actuators (`composer.Task.action_spec`): a
    float64 `BoundedArray` of shape (nu,) from `low` to `high`, (nu,) each, named by the
    actuators' `names` joined by tabs."""
    return specs.BoundedArray(
        shape=low.shape, dtype=np.float64, minimum=low, maximum=high, name="\t".join(names)
    )


def spec_from_space(space: spaces.Space[Any], name: str | None = None) -> Any:
    """The dm_env spec of a Gymnasium space: a Box with a finite bound -> `BoundedArray`,
    without -> `Array`; Discrete -> `DiscreteArray` (`BoundedArray` when it does not start
    at 0); Dict -> dict of specs named by key; Tuple -> tuple. Raises TaskError for other
    spaces."""
    if isinstance(space, spaces.Box):
        if np.isfinite(space.low).any() or np.isfinite(space.high).any():
            return specs.BoundedArray(space.shape, space.dtype, space.low, space.high, name=name)
        return specs.Array(space.shape, space.dtype, name=name)
    if isinstance(space, spaces.Discrete):
        start, count = int(space.start), int(space.n)
        if start == 0:
            return specs.DiscreteArray(count, dtype=space.dtype, name=name)
        return specs.BoundedArray((), space.dtype, start, start + count - 1, name=name)
    if isinstance(space, spaces.Dict):
        return {key: spec_from_space(value, key) for key, value in space.spaces.items()}
    if isinstance(space, spaces.Tuple):
        return tuple(spec_from_space(value, name) for value in space.spaces)
    raise errors.TaskError(f"no dm_env spec for the Gymnasium space {space}")


def _box(shape: Any, dtype: Any, low: Any, high: Any) -> spaces.Box:
    dtype = np.dtype(dtype)
    shape = tuple(int(n) for n in shape)
    bounds = [np.array(np.broadcast_to(np.asarray(b, dtype=dtype), shape)) for b in (low, high)]
    return spaces.Box(bounds[0], bounds[1], shape, dtype)
