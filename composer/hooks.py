"""Episode hooks: their names, their fixed order, and dispatch to overriders only.

    hooks = Hooks(task)                   # after any change of the entity tree
    for hook in hooks.after_substep:      # bound methods; empty if nobody overrides it
        hook(physics, random_state)

Order (`composer.Environment` says when each runs): the task, then each entity of
`task.root_entity.iter_entities()` (the root, then attached ones depth first, in attach
order), then the environment's extra hooks. Only overriders are called, so an unused hook
costs nothing per step; the task's and extra `before_step`/`before_substep` get the action.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    import numpy as np

    import mjcf
    from composer.task import Task

HOOK_NAMES = (
    "initialize_episode_mjcf",
    "after_compile",
    "initialize_episode",
    "before_step",
    "before_substep",
    "after_substep",
    "after_step",
)

F = TypeVar("F", bound=Callable[..., Any])


def noop(function: F) -> F:
    """Mark a base-class hook as a no-op, so that `overriders` skips objects keeping it."""
    function._composer_noop = True  # type: ignore[attr-defined]
    return function


def is_noop(method: Callable[..., Any]) -> bool:
    """Whether `method` is a base-class no-op (marked by `noop`) that nobody overrode."""
    return getattr(method, "_composer_noop", False)


def overriders(objects: Iterable[object], name: str) -> tuple[Callable[..., Any], ...]:
    """The bound `name` methods of `objects` whose class overrides the no-op, in order."""
    found = []
    for obj in objects:
        method = getattr(obj, name)
        if not is_noop(method):
            found.append(method)
    return tuple(found)


class EpisodeHooks:
    """The hooks that tasks and entities share, as no-ops to override. (`before_step`
    and `before_substep` differ: the task's receive the action.)"""

    @noop
    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        """Before compiling, each episode: change the MJCF model (recompiled if changed)."""

    @noop
    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """After each compile: resolve bindings, cache indices."""

    @noop
    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """After the physics is reset, each episode: set the initial state."""

    @noop
    def after_substep(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """After each physics step."""

    @noop
    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """After the physics steps of a control step, before observations are read."""


class Hooks:
    """The hook methods of a task and its entities, resolved once per entity tree."""

    def __init__(
        self, task: Task, extra: Mapping[str, Sequence[Callable[..., Any]]] | None = None
    ) -> None:
        """Collect the overriding hooks of `task` and every entity of its root entity, and
        the `extra` callables by hook name, which run last."""
        extra = extra or {}
        entities = list(task.root_entity.iter_entities())
        everyone = [task, *entities]

        def last(name: str) -> tuple[Callable[..., Any], ...]:
            return tuple(extra.get(name, ()))

        self.initialize_episode_mjcf = overriders(everyone, "initialize_episode_mjcf") + last(
            "initialize_episode_mjcf"
        )
        self.after_compile = overriders(everyone, "after_compile") + last("after_compile")
        self.initialize_episode = overriders(everyone, "initialize_episode") + last(
            "initialize_episode"
        )
        # The task's before_step and after_step have batched forms, which
        # `composer.stepping.TaskStep` runs: these are the entities' (and the extra
        # after_step ones). The task's before_substep and the extra before_step and
        # before_substep ones take the action: kept apart.
        self.before_step = overriders(entities, "before_step")
        self.extra_before_step = last("before_step")
        self.task_before_substep = overriders([task], "before_substep")
        self.before_substep = overriders(entities, "before_substep")
        self.extra_before_substep = last("before_substep")
        self.after_substep = overriders(everyone, "after_substep") + last("after_substep")
        self.after_step = overriders(entities, "after_step") + last("after_step")

    @property
    def has_substep_hooks(self) -> bool:
        """Whether anything runs before or after each physics step."""
        return bool(
            self.task_before_substep or self.before_substep or self.extra_before_substep
            or self.after_substep
        )  # fmt: skip
