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
from composer.utils.rewards import Tolerance
from entities.suite import Walker
from entities.suite.walker import FLOOR_FRICTION
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 25.0
CONTROL_TIMESTEP = 0.025
_STAND_HEIGHT = 1.2
_WALK_SPEED = 1.0
_RUN_SPEED = 8.0
_XX_XZ = [0, 2]  # each body's xmat entries observed
# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_ONE, _TWO, _THREE, _FOUR, _FIVE, _SIX = (np.array(v) for v in (1.0, 2.0, 3.0, 4.0, 5.0, 6.0))


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
                # The x-x and x-z orientation entries of each body: (n, 2 * bodies).
                "orientations": BoundField(
                    "xmat", self.walker.bodies, index=(slice(None), _XX_XZ), flat=True
                ),
                "height": BoundField("xpos", self.walker.torso, index=2),  # the torso's
                "velocity": BoundField("qvel", self._arena.mjcf_model.find_all("joint")),
            }
        )

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: every limited joint within its range (`randomizers`)."""
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        torso = physics.bind(self.walker.torso)
        standing = self._standing(torso.xpos[:, 2])
        upright = (_ONE + torso.xmat[:, 8]) / _TWO
        stand_reward = (_THREE * standing + upright) / _FOUR
        if self._moving is None:
            return stand_reward
        speed = physics.bind(self.walker.speed_sensor).sensordata[:, 0]
        return stand_reward * (_FIVE * self._moving(speed) + _ONE) / _SIX


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
