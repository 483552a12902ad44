"""Reacher: bring the tip of a two-link arm onto a target (dm_control's `reacher`).

    env = gym.make('dm_control/reacher-easy-v0')        # a target 5 cm in radius
    env = gym.make('dm_control/reacher-hard-v0')        # 1.5 cm

Observations: `position` (both joints' angles), `to_target` (the x and y from the finger to
the target), `velocity` (both joints'). Reward: 1 while the finger's centre is within the
sum of the two radii (the target's and the finger's 1 cm) of the target's, else 0. Random
joint angles and target; 1,000 steps of 20 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import entities.suite
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from tasks.rewards import Tolerance, squared_norms
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
BIG_TARGET, SMALL_TARGET = 0.05, 0.015  # the easy and hard tasks' target radii (m)


class Reacher(SuiteTask):
    """Reach the target with the arm's finger (module docstring)."""

    def __init__(
        self, target_size: float = BIG_TARGET, control_timestep: float | None = None
    ) -> None:
        """Build the scene with a target `target_size` m in radius. Raises
        composer.TaskError for a size that is not a positive number, or a control
        timestep that is not a multiple of 20 ms."""
        if isinstance(target_size, bool) or not (
            isinstance(target_size, (int, float)) and target_size > 0
        ):
            raise composer.TaskError(
                f"target_size must be a positive number of metres, got {target_size!r}"
            )
        self.reacher = entities.suite.Reacher()
        self._arena = SuiteArena(floor_size=(0.3, 0.3, 10.0), floor_name="ground")
        self._arena.add_light(name="light", pos=[0, 0, 1])
        self._arena.attach(self.reacher)
        self._target_size = float(target_size)
        self.render_camera = f"{self.reacher.name}/fixed"
        self.use_control_timestep(control_timestep, default=None)
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {
                "position": BoundField("qpos", joints),
                "to_target": observation.BatchGeneric(self._finger_to_target),
                "velocity": BoundField("qvel", joints),
            }
        )

    def _finger_to_target(self, physics: composer.BatchPhysics) -> np.ndarray:
        """x and y from the finger's centre to the target's, (n, 2)."""
        target = physics.bind(self.reacher.target).xpos[:, :2]
        return target - physics.bind(self.reacher.finger).xpos[:, :2]

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Fix the reward's shape: 1 within the target's radius (the task's, as each
        episode sets it) plus the finger's (as compiled)."""
        radii = self._target_size + float(physics.bind(self.reacher.finger).size[0])
        self._reached = Tolerance(bounds=(0.0, radii))

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Size the target, then dm_control's draws: the joints (`randomizers`), then the
        target's angle U(0, 2 pi) and distance U(0.05, 0.2) from the centre."""
        target = physics.bind(self.reacher.target)
        target.size[0] = self._target_size
        randomizers.randomize_limited_and_rotational_joints(physics, random_state)
        angle = random_state.uniform(0, 2 * np.pi)
        radius = random_state.uniform(0.05, 0.20)
        target.pos[:2] = radius * np.sin(angle), radius * np.cos(angle)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """1 where the finger reached the target, else 0; shape (n,)."""
        return self._reached(np.sqrt(squared_norms(self._finger_to_target(physics))))


for _name, _size, _description, _tags in (
    ("easy", BIG_TARGET, "Reach a 5 cm target with a two-link arm", ("benchmarking", "easy")),
    ("hard", SMALL_TARGET, "Reach a 1.5 cm target with a two-link arm", ("benchmarking",)),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry(
            "reacher", _name, Reacher, {"target_size": _size}, TIME_LIMIT, _description, _tags
        )
    )
