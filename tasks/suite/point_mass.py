"""Point mass: push a ball in a plane onto a target (dm_control's `point_mass`).

    env = gym.make('dm_control/point_mass-easy-v0')
    env = gym.make('dm_control/point_mass-hard-v0')     # each motor pushes a random way

Observations: `position` and `velocity` (the ball's x and y, and their rates). Reward in
[0, 1]: `near_target * small_control`, 1 within the target's 1.5 cm radius (gaussian, 0.1
one radius beyond), times (4 + c) / 5, c the mean of 1 - u^2 over both controls. Episodes
start anywhere in the joints' range; 1,000 steps of 20 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import entities.suite
import mjcf
from arenas.suite import SuiteArena
from tasks.rewards import Tolerance, row_means, squared_norms
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
_MOST_PARALLEL = 0.9  # |cos| of the angle between the hard task's two directions


# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_FOUR, _FIVE = np.array(4.0), np.array(5.0)


class PointMass(SuiteTask):
    """Push the point mass onto the target (module docstring)."""

    def __init__(
        self, randomize_gains: bool = False, control_timestep: float | None = None
    ) -> None:
        """Build the scene; with `randomize_gains` each motor pushes along a random
        direction drawn each episode. Raises composer.TaskError for a control timestep
        that is not a multiple of 20 ms."""
        self.point_mass = entities.suite.PointMass()
        self._arena = SuiteArena(floor_size=(0.3, 0.3, 0.1), floor_name="ground")
        self._arena.add_light(name="light", pos=[0, 0, 1])
        self._arena.attach(self.point_mass)
        self._randomize_gains = bool(randomize_gains)
        self.render_camera = f"{self.point_mass.name}/fixed"
        self.use_control_timestep(control_timestep, default=None)
        self._small_control = Tolerance(margin=1.0, value_at_margin=0.0, sigmoid="quadratic")
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {"position": BoundField("qpos", joints), "velocity": BoundField("qvel", joints)}
        )

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Fix the reward's shape to the target's radius as compiled (1.5 cm), and find
        the tendons' coefficients in MjModel `wrap_prm`."""
        radius = float(physics.bind(self.point_mass.target).size[0])
        self._near_target = Tolerance(bounds=(0.0, radius), margin=radius)
        first = physics.bind(self.point_mass.tendons).adr  # each tendon's first wrap
        self._coefficients = first[:, None] + np.arange(2)  # (tendons, joints)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: the joints (`randomizers`), then in the hard task the first
        tendon's direction, normalised `randn(2)`, and the second's, drawn again while
        within |cos| 0.9 of the first."""
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)
        if not self._randomize_gains:
            return
        first = random_state.randn(2)
        first /= np.linalg.norm(first)
        while True:
            second = random_state.randn(2)
            second /= np.linalg.norm(second)
            if abs(np.dot(first, second)) <= _MOST_PARALLEL:
                break
        physics.model.wrap_prm[self._coefficients] = (first, second)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        to_target = (
            physics.bind(self.point_mass.target).xpos - physics.bind(self.point_mass.mass).xpos
        )
        near_target = self._near_target(np.sqrt(squared_norms(to_target)))
        small_control = (row_means(self._small_control(physics.field("ctrl"))) + _FOUR) / _FIVE
        return near_target * small_control


for _name, _randomize, _description, _tags in (
    ("easy", False, "Push a point mass in a plane onto a target", ("benchmarking", "easy")),
    ("hard", True, "Push a point mass onto a target, each motor pushing a random way", ()),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry(
            "point_mass", _name, PointMass, {"randomize_gains": _randomize}, TIME_LIMIT,
            _description, _tags,
        )
    )  # fmt: skip
