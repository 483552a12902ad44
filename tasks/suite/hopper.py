"""Hopper: stand up, or hop forward, on one planar leg (dm_control's `hopper`).

    env = gym.make('dm_control/hopper-hop-v0')

Observations: `position` (every joint's but the horizontal root slide's), `velocity`,
`touch` (log(1 + force) at the toe and the heel). Reward in [0, 1]: standing, 1 while the
torso's centre of mass is 0.6 to 2 m above the foot's, else 0; times, to stand,
`(4 + small_control) / 5`, to hop, the forward speed's term (1 at 2 m/s and above). Joint
angles start within their limits; 1,000 steps of 20 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from entities.suite import Hopper
from tasks.rewards import Tolerance, row_means
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
CONTROL_TIMESTEP = 0.02
_STAND_HEIGHT = 0.6
_HOP_SPEED = 2.0


# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_FOUR, _FIVE = np.array(4.0), np.array(5.0)


class PlanarHopper(SuiteTask):
    """Stand, or hop forward (module docstring)."""

    def __init__(self, hopping: bool = False, control_timestep: float | None = None) -> None:
        """Build the scene: a hopper rewarded for hopping forward with `hopping`, for
        standing still otherwise. Raises composer.TaskError for a control timestep that is
        not a multiple of 5 ms."""
        self.hopper = Hopper()
        self._arena = SuiteArena(floor_size=(50, 1, 0.2), floor_pos=(48, 0, 0))
        self._arena.attach(self.hopper)
        self._hopping = bool(hopping)
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        self._standing = Tolerance(bounds=(_STAND_HEIGHT, 2.0))
        self._hop = Tolerance(
            bounds=(_HOP_SPEED, float("inf")), margin=_HOP_SPEED / 2, value_at_margin=0.5,
            sigmoid="linear",
        )  # fmt: skip
        self._small_control = Tolerance(margin=1, value_at_margin=0, sigmoid="quadratic")
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {
                "position": BoundField("qpos", joints[1:]),  # but the root's x slide's
                "velocity": BoundField("qvel", joints),
                "touch": BoundField("sensordata", self.hopper.touch_sensors, function=np.log1p),
            }
        )

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: every limited joint within its range (`randomizers`)."""
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        heights = physics.bind([self.hopper.torso, self.hopper.foot]).xipos[:, :, 2]
        standing = self._standing(heights[:, 0] - heights[:, 1])
        if self._hopping:
            speed = physics.bind(self.hopper.speed_sensor).sensordata[:, 0]
            return standing * self._hop(speed)
        small_control = row_means(self._small_control(physics.field("ctrl")))
        return standing * ((small_control + _FOUR) / _FIVE)


for _name, _hopping, _description in (
    ("stand", False, "Stand upright on one planar leg"),
    ("hop", True, "Hop forward on one planar leg"),
):
    registry.add(
        registry.SuiteEntry(
            "hopper", _name, PlanarHopper, {"hopping": _hopping}, TIME_LIMIT, _description,
            ("benchmarking",),
        )
    )  # fmt: skip
