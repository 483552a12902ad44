"""Pendulum: swing a pendulum up and hold it upright (dm_control's `pendulum`).

    env = gym.make('dm_control/pendulum-swingup-v0')

Observations: `orientation` (the pole's cos and sin of its angle from upright, as the z-z
and x-z entries of its orientation), `velocity` (the hinge's). Reward: 1 while the pole is
within 8 degrees of upright, else 0. The motor is too weak to lift the pole straight up:
the pendulum must swing. Each episode starts at an angle uniform in [-pi, pi); 1,000
steps of 20 ms.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from entities.suite import Pendulum
from tasks.rewards import Tolerance
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
_ANGLE_BOUND = 8  # degrees
_COSINE_BOUND = np.cos(np.deg2rad(_ANGLE_BOUND))
_ZZ_XZ = [8, 2]  # the pole's xmat entries observed: its cos and sin


class SwingUp(SuiteTask):
    """Swing up and balance a pendulum (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not a
        multiple of 20 ms."""
        self.pendulum = Pendulum()
        self._arena = SuiteArena(floor_size=(2.0, 2.0, 0.2))
        self._arena.add_light(name="light", pos=[0, 0, 2])
        self._arena.attach(self.pendulum)
        self.render_camera = f"{self.pendulum.name}/fixed"
        self.use_control_timestep(control_timestep, default=None)
        self._upright = Tolerance(bounds=(_COSINE_BOUND, 1.0))
        self.set_observables(
            {
                "orientation": BoundField("xmat", self.pendulum.pole, index=_ZZ_XZ),
                "velocity": BoundField("qvel", self.pendulum.hinge),
            }
        )

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draw: the hinge at U(-pi, pi)."""
        physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-np.pi, np.pi)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """1 where the pole is within 8 degrees of upright, else 0; shape (n,)."""
        return self._upright(physics.bind(self.pendulum.pole).xmat[:, 8])


registry.add(
    registry.SuiteEntry(
        "pendulum", "swingup", SwingUp, {}, TIME_LIMIT,
        "Swing up and balance a pendulum; reward 1 while within 8 degrees of upright",
        ("benchmarking",),
    )
)  # fmt: skip
