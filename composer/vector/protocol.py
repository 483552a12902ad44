"""The batch protocol: optional `*_batch` twins of a Task's per-step methods.

    class Swing(composer.Task):
        def get_reward(self, physics):                   # one environment, a float
            return -abs(physics.bind(self.hinge).qpos[0])

        def get_reward_batch(self, physics):             # every stepped environment at once
            return -np.abs(physics.bind(self.hinge).qpos[:, 0])      # shape (n,)

A `VectorEnvironment` calls a twin on the first environment's task with a `BatchPhysics`
over the n environments of the call (`physics.ids`); it returns one row per environment.
Elements are bound once, on the first environment's compiled model (all environments share
its layout). Per-episode state a task keeps on `self` (a target drawn in
`initialize_episode`) is per environment: read it from `physics.tasks`, or better, keep
it in the simulation (a mocap body, a site).

A twin is used when it is defined on the same class as its per-environment method or on a
subclass of it (a subclass that overrides only `get_reward` does not inherit a stale
`get_reward_batch`). Without a twin, a method the task left as `Task` defines it runs
batched by default (`before_step` writes the actions to `ctrl`, no termination, discount
1, no info entries); any other runs once per environment on that environment's own
`mjcf.Physics`, its MjData materialized from the batch first (correct, but slower: the
batch then keeps one MjData per simulation, and each call copies it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from composer import errors
from composer.task import Task

if TYPE_CHECKING:
    from composer.vector.physics import BatchPhysics

# Per-step task methods that may have a batched twin, named `<method>_batch`.
BATCHABLE = (
    "before_step",
    "after_step",
    "get_reward",
    "should_terminate_episode",
    "get_discount",
    "get_info",
)
# Those whose Task version has a batched equivalent the vector environment runs itself.
_DEFAULTS = frozenset(BATCHABLE) - {"get_reward"}


class BatchError(errors.Error):
    """A batched method or observable returned values of the wrong shape, or asked the
    batch for something it cannot give (a field MuJoCo's batch does not bind)."""


class BatchedTask(Protocol):
    """The optional methods by which a Task computes per-step quantities for many
    environments at once. Each gets a `BatchPhysics` over the environments of the call."""

    def before_step_batch(self, physics: BatchPhysics, actions: np.ndarray) -> None:
        """Apply `actions`, (n, action size) float64, already clipped to the action space."""

    def after_step_batch(self, physics: BatchPhysics) -> None:
        """After the physics steps of a control step, before observations are read."""

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The rewards of the control step that just ended, shape (n,)."""

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        """Whether each episode ended in a terminal state, shape (n,) bool."""

    def get_discount_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The discount of each step, shape (n,)."""

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        """Extra info entries, each an array of shape (n, ...)."""


def _owner(cls: type, name: str) -> type | None:
    """The class of `cls`'s MRO that defines attribute `name`, or None."""
    for klass in cls.__mro__:
        if name in vars(klass):
            return klass
    return None


def batched(task: Task, name: str) -> Any:
    """How a VectorEnvironment runs `task`'s per-step method `name`: its bound `*_batch`
    twin, the string 'default' when the task keeps `Task`'s own method (which has a
    batched equivalent), or None for a per-environment loop (see the module docstring)."""
    cls = type(task)
    single = _owner(cls, name)
    twin = _owner(cls, f"{name}_batch")
    if twin is not None and (single is None or issubclass(twin, single)):
        return getattr(task, f"{name}_batch")
    if (single is None or single in Task.__mro__) and name in _DEFAULTS:
        return "default"
    return None


def check_rows(name: str, values: Any, n: int, dtype: type) -> np.ndarray:
    """`values` as an (n,) array of `dtype`; raises BatchError naming method `name`."""
    array = np.asarray(values, dtype=dtype)
    if array.shape != (n,):
        raise BatchError(
            f"{name} returned shape {array.shape} for {n} environments; expected ({n},)"
        )
    return array
