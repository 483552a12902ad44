"""UnitActionTask: what the goal tasks (Reach, ArmPushBox) share: the arena at the root, the
task's own observables, all enabled, and an action in [-1, 1] it maps to its actuators.

    class Reach(UnitActionTask):
        action_size = 2                                  # the action space: Box(-1, 1, (2,))
        def __init__(self):
            self.arena = Floor()                         # ... and the rest of the scene
            self.observe({'to_target': observation.BatchGeneric(...)})
        def before_step_batch(self, physics, actions):   # actions (n, 2), in [-1, 1]
            ...
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

import composer
import mjcf
from composer import observation


class UnitActionTask(composer.Task):
    """A task rooted at `self.arena`, observing what `observe` gave it, acting with
    `action_size` numbers in [-1, 1]."""

    arena: composer.Entity
    action_size: int
    _task_observables: dict[str, observation.Observable]

    def observe(self, observables: dict[str, observation.Observable]) -> None:
        """Make `observables` the task's own observables (by name), enabled."""
        for item in observables.values():
            item.enabled = True
        self._task_observables = observables

    @property
    def root_entity(self) -> composer.Entity:
        """The arena, holding everything else."""
        return self.arena

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        """The observables `observe` gave (see the task's module docstring)."""
        return self._task_observables

    def action_space(self, physics: mjcf.Physics) -> spaces.Box:
        """`action_size` numbers in [-1, 1] (the task's `before_step` scales them)."""
        return spaces.Box(-1.0, 1.0, (self.action_size,), dtype=np.float32)
