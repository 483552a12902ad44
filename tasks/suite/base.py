"""SuiteTask: what every Control Suite task here shares with dm_control's `suite.base.Task`.

    class Balance(SuiteTask):
        def __init__(self, control_timestep=None):
            self._arena = SuiteArena(...)
            self.cartpole = Cartpole()
            self._arena.attach(self.cartpole)
            self.use_control_timestep(control_timestep, default=None)  # one physics step

What a suite task promises, as dm_control's does: the action is every actuator's control in
model order (written as given, within the action space: float64, the actuators' control
ranges, as dm_control's `action_spec` and Shimmy's Box); observations are the task's own,
under dm_control's keys, in dm_control's order (also when flattened:
`keep_observation_order`); an episode is truncated at the domain's time limit with discount
1 and never terminates unless the task says so (`get_termination`, dm_control's hook:
None, or the discount the episode ends with); `reset(seed=s)` draws the initial state from
`numpy.random.RandomState(s)`, as dm_control's task made with `random=s` does (and Shimmy's
`dm_control/...` environments), with the same draws in the same order.
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
