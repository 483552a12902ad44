"""Walker: stand, walk or run with a planar biped (dm_control's `walker`).

    env = gym.make('dm_control/walker-walk-v0')

Observations: `orientations` (each body's x-x and x-z orientation entries, the cos and sin
of its pitch), `height` (the torso's), `velocity` (every joint's). Reward in [0, 1]:
standing, `(3 * standing + upright) / 4`; to walk (1 m/s) or run (8 m/s), times
`(5 * moving + 1) / 6`, moving being 1 at that forward speed or faster. Joint angles start
within their limits; 1,000 steps of 25 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from composer.utils.rewards import Tolerance
from entities.suite import Walker
from entities.suite.walker import FLOOR_FRICTION
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask

TIME_LIMIT = 25.0
CONTROL_TIMESTEP = 0.025
_STAND_HEIGHT = 1.2
_WALK_SPEED = 1.0
_RUN_SPEED = 8.0
_XX_XZ = np.array([0, 2])  # each body's xmat entries observed


class PlanarWalker(SuiteTask):
    """Stand, walk or run (module docstring)."""

    def __init__(self, move_speed: float = 0.0, control_timestep: float | None = None) -> None:
        """Build the scene: a walker rewarded for moving forward at `move_speed` m/s or
        faster (0: for standing). Raises composer.TaskError for a negative speed or a
        control timestep that is not a multiple of 2.5 ms."""
        if not move_speed >= 0:
            raise composer.TaskError(f"move_speed must be a number >= 0, got {move_speed!r}")
        self.walker = Walker()
        self._arena = SuiteArena(
            floor_size=(250, 0.8, 0.2), floor_pos=(248, 0, 0),
            floor_attributes={"friction": list(FLOOR_FRICTION)},
        )  # fmt: skip
        self._arena.attach(self.walker)
        self._move_speed = float(move_speed)
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        self._standing = Tolerance(bounds=(_STAND_HEIGHT, float("inf")), margin=_STAND_HEIGHT / 2)
        self._moving = None
        if self._move_speed > 0:
            self._moving = Tolerance(
                bounds=(self._move_speed, float("inf")), margin=self._move_speed / 2,
                value_at_margin=0.5, sigmoid="linear",
            )  # fmt: skip
        self.set_observables(
            {
                "orientations": observation.BatchGeneric(self._orientations),
                "height": observation.BatchGeneric(self._height),
                "velocity": observation.BatchGeneric(lambda physics: physics.field("qvel")),
            }
        )

    def _orientations(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The x-x and x-z orientation entries of each body: (n, 2 * bodies)."""
        xmat = physics.bind(self.walker.bodies).xmat  # (n, bodies, 9)
        return xmat.take(_XX_XZ, axis=2).reshape(len(xmat), -1)

    def _height(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The torso's height: (n,)."""
        return physics.bind(self.walker.torso).xpos[:, 2]

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: every limited joint within its range (`randomizers`)."""
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        torso = physics.bind(self.walker.torso)
        standing = self._standing(torso.xpos[:, 2])
        upright = (1 + torso.xmat[:, 8]) / 2
        stand_reward = (3 * standing + upright) / 4
        if self._moving is None:
            return stand_reward
        speed = physics.bind(self.walker.speed_sensor).sensordata[:, 0]
        return stand_reward * (5 * self._moving(speed) + 1) / 6


for _name, _speed, _description in (
    ("stand", 0.0, "Stand up and balance a planar biped"),
    ("walk", _WALK_SPEED, "Walk forward at 1 m/s or faster with a planar biped"),
    ("run", _RUN_SPEED, "Run forward at 8 m/s or faster with a planar biped"),
):
    registry.add(
        registry.SuiteEntry(
            "walker", _name, PlanarWalker, {"move_speed": _speed}, TIME_LIMIT, _description,
            ("benchmarking",),
        )
    )  # fmt: skip
