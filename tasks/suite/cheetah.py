"""Cheetah: run forward as fast as a planar half cheetah can (dm_control's `cheetah`).

    env = gym.make('dm_control/cheetah-run-v0')

Observations: `position` (every joint's but the horizontal root slide's: translation
invariant), `velocity` (every joint's). Reward in [0, 1]: the torso subtree's forward
speed, linearly from 0 at rest to 1 at 10 m/s and above. An episode starts from joint
angles drawn within their limits, settled by 200 physics steps (the clock reset to 0);
1,000 steps of 10 ms.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from composer.utils.rewards import Tolerance
from entities.suite import Cheetah
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 10.0
_RUN_SPEED = 10.0
_SETTLING_STEPS = 200


class Run(SuiteTask):
    """Run forward (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not a
        multiple of 10 ms."""
        self.cheetah = Cheetah()
        self._arena = SuiteArena(
            floor_name="ground", floor_size=(100, 0.8, 0.5), floor_pos=(98, 0, 0)
        )
        self._arena.attach(self.cheetah)
        self.use_control_timestep(control_timestep, default=None)
        self._speed = Tolerance(
            bounds=(_RUN_SPEED, float("inf")), margin=_RUN_SPEED, value_at_margin=0,
            sigmoid="linear",
        )  # fmt: skip
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {
                "position": BoundField("qpos", joints[1:]),  # but the root's x slide's
                "velocity": BoundField("qvel", joints),
            }
        )

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: every limited joint uniformly within its range (one draw of
        them all, in model order); then 200 physics steps to settle, and time 0."""
        limited = physics.model.jnt_limited == 1
        lower, upper = physics.model.jnt_range[limited].T
        # Every joint has one coordinate, so joints index qpos.
        physics.data.qpos[limited] = random_state.uniform(lower, upper)
        physics.step(nstep=_SETTLING_STEPS)
        physics.data.time = 0.0

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        return self._speed(physics.bind(self.cheetah.speed_sensor).sensordata[:, 0])


registry.add(
    registry.SuiteEntry(
        "cheetah", "run", Run, {}, TIME_LIMIT, "Run forward with a planar half cheetah",
        ("benchmarking",),
    )
)  # fmt: skip
