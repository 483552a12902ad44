"""SuiteTask: what every Control Suite task here shares with dm_control's `suite.base.Task`.

    class Balance(SuiteTask):      # builds self._arena, a SuiteArena with the robot attached
        def __init__(self, control_timestep=None):
            self.use_control_timestep(control_timestep, default=None)  # one physics step

As dm_control's (in full: docs/suite.md): the action is each actuator's control in model
order (float64, in the control ranges); observations use dm_control's keys and order
(flattened too); episodes are truncated at the time limit with discount 1 (sooner only by
`get_termination`); `reset(seed=s)` draws from `RandomState(s)` as `random=s` does.
"""

from __future__ import annotations

import mujoco
import numpy as np
from gymnasium import spaces

import composer
import mjcf
from composer import observation


class SuiteTask(composer.Task):
    """A Control Suite task (see the module docstring)."""

    keep_observation_order = True
    #: The camera `render()` and `pixels=True` use: the model's first, as DrQ-v2 and CURL
    #: observe the suite (dm_control's `physics.render()` default).
    render_camera: int | str = 0

    #: The domain's world, which the robot is attached to (the task's root entity).
    _arena: composer.Arena
    _observables: dict[str, observation.Observable]

    @property
    def root_entity(self) -> composer.Entity:
        """The domain's world with its robot attached."""
        return self._arena

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        """The task's observations, dm_control's keys in its order."""
        return self._observables

    def set_observables(self, observables: dict[str, observation.Observable]) -> None:
        """Observe `observables` (dm_control's keys in its order), each enabled; a task that
        adds some later calls this again with the whole dict."""
        for item in observables.values():
            item.enabled = True
        self._observables = observables

    def random_state_for_seed(self, seed: int) -> np.random.RandomState:
        """dm_control's `random=seed`: `numpy.random.RandomState(seed)`."""
        return np.random.RandomState(seed)

    def action_space(self, physics: mjcf.Physics) -> spaces.Box:
        """dm_control's action spec as a Box, as Shimmy serves it: float64, each actuator's
        ctrlrange, +-mjMAXVAL (1e10) where an actuator is not control-limited."""
        model = physics.model
        limited = model.actuator_ctrllimited.astype(bool)
        low = np.where(limited, model.actuator_ctrlrange[:, 0], -mujoco.mjMAXVAL)
        high = np.where(limited, model.actuator_ctrlrange[:, 1], mujoco.mjMAXVAL)
        return spaces.Box(low, high, dtype=np.float64)

    def use_control_timestep(self, control_timestep: float | None, default: float | None) -> None:
        """Set the control timestep: `control_timestep`, else the domain's `default`, else
        one physics step (dm_control's environments step once without either). Raises
        composer.TaskError when it is not a multiple of the model's physics timestep."""
        physics_timestep = self.physics_timestep
        chosen = control_timestep if control_timestep is not None else default
        self.set_timesteps(physics_timestep if chosen is None else chosen, physics_timestep)

    def get_termination(self, physics: mjcf.Physics) -> float | None:
        """dm_control's hook: None while the episode goes on, else the discount it ends
        with. None here: suite episodes end at their time limit."""
        return None
