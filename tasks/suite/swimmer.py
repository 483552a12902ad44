"""Swimmer: swim a planar chain of links to a target (dm_control's `swimmer`).

    env = gym.make('dm_control/swimmer-swimmer6-v0')
    env = gym.make('dm_control/swimmer-swimmer15-v0')

Observations: `joints` (each link's angle on the previous one), `to_target` (from the nose,
in the head's frame), `body_velocities` (each body's, in its own frame). Reward in [0, 1]:
1 with the nose within the target's 0.1 m radius, falling off with a long tail (0.1 at
0.5 m beyond). Random heading, link angles and target; 1,000 steps of 30 ms (details in
docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from composer.utils.rewards import Tolerance
from entities.suite import Swimmer
from tasks.rewards import squared_norms
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 30.0
CONTROL_TIMESTEP = 0.03
_CLOSE_TARGET_PROBABILITY = 0.2
_CLOSE_BOX, _FAR_BOX = 0.3, 2.0
# Each link's velocimeter and gyro give (vx, vy, vz, wx, wy, wz): the planar ones.
_PLANAR_VELOCITIES = np.array([0, 1, 5])


class SwimToTarget(SuiteTask):
    """Swim to the target (module docstring)."""

    def __init__(self, n_links: int = 6, control_timestep: float | None = None) -> None:
        """Build the scene: a swimmer of `n_links` links. Raises composer.EntityError for
        fewer than 3 links, composer.TaskError for a control timestep that is not a
        multiple of 2 ms."""
        self.swimmer = Swimmer(n_links=n_links)
        self._arena = SuiteArena(floor_name="ground", floor_size=(2, 2, 0.1))
        self._arena.attach(self.swimmer)
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        self._near_target: Tolerance | None = None
        # The planar columns of every link's six readings, in order.
        links = len(self.swimmer.velocity_sensors) // 2
        planar_velocities = (6 * np.arange(links)[:, None] + _PLANAR_VELOCITIES).ravel()
        self.set_observables(
            {
                "joints": BoundField("qpos", self.swimmer.joints),
                "to_target": observation.BatchGeneric(self._nose_to_target),
                # Each link's planar velocities, (n, 3 * links).
                "body_velocities": BoundField(
                    "sensordata", self.swimmer.velocity_sensors, index=planar_velocities
                ),
            }
        )

    def _nose_to_target(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The vector from the nose to the target, x and y in the head's frame: (n, 2)."""
        positions = physics.bind([self.swimmer.nose, self.swimmer.target]).xpos  # (n, 2, 3)
        head_frame = physics.bind(self.swimmer.head).xmat.reshape(-1, 3, 3)
        to_target = positions[:, 1] - positions[:, 0]
        return np.matmul(to_target[:, None, :], head_frame)[:, 0, :2]

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """The reward's reach: the target's radius, as compiled (a model constant: read
        once, not every step)."""
        radius = float(physics.bind(self.swimmer.target).size[0])
        self._near_target = Tolerance(bounds=(0.0, radius), margin=5 * radius, sigmoid="long_tail")

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: the heading and link angles (`randomizers`), whether the
        target is close (`rand() < 0.2`), then its x and y in one draw; its light follows
        it."""
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)
        close = random_state.rand() < _CLOSE_TARGET_PROBABILITY
        box = _CLOSE_BOX if close else _FAR_BOX
        x, y = random_state.uniform(-box, box, size=2)
        for element in (self.swimmer.target, self.swimmer.target_light):
            bound = physics.bind(element)
            bound.pos = [x, y, bound.pos[2]]

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        assert self._near_target is not None, "after_compile runs before any step"
        return self._near_target(np.sqrt(squared_norms(self._nose_to_target(physics))))


for _links in (6, 15):
    registry.add(
        registry.SuiteEntry(
            "swimmer", f"swimmer{_links}", SwimToTarget, {"n_links": _links}, TIME_LIMIT,
            f"Swim a chain of {_links} links to a target", ("benchmarking",),
        )
    )  # fmt: skip
