"""Reach: move a planar two-link arm's fingertip to a random target.

    env = gym.make('composer/Reach-v0', flatten_observations=True)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(action)
    info['is_success']                           # fingertip within 2 cm of the target

10 observations, 2 actions in [-1, 1] (`Reach` lists them); a zero action holds the arm
still. Episodes last `time_limit` (3 s: 75 steps of 0.04 s) and never terminate; success
is judged at every step.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import mjcf
from arenas import Floor
from composer import BatchPhysics, observation
from entities import PlanarArm
from entities.features import clip
from tasks.unit_action import UnitActionTask


class Reach(UnitActionTask):
    """Bring the fingertip to a target drawn uniformly in the arm's reachable disc.

    Observations (10 numbers): `arm/joint_angles` (cos, sin of both joints; 4),
    `arm/joint_velocities` (2), `target_position` (x, y; 2) and `to_target` (target minus
    fingertip, x, y; 2), the last two in units of the arm's reach R (0.24 m), so that the
    centimetres that matter are not lost in small inputs. Action: two joint-angle changes
    in [-1, 1], scaled by `max_joint_step` (0.2 rad) and added to the current angles as the
    joint servos' targets, so a zero action holds the arm still.

    Reward per step, in [0, 1]: with d the fingertip-target distance (m) and R the
    arm's reach, `0.5 * (1 - d / (2 R)) + 0.5 * exp(-(d / success_distance)^2)
    - control_cost * mean(action^2)`: the first term pulls from anywhere, the second
    rewards precision within a few centimetres. `info['is_success']` is `d < success_distance`.
    """

    action_size = 2  # joint-angle changes

    def __init__(
        self,
        control_timestep: float = 0.04,
        physics_timestep: float = 0.005,
        randomize: bool = True,
        success_distance: float = 0.02,
        control_cost: float = 0.0,
        max_joint_step: float = 0.2,
        link_lengths: Sequence[float] = (0.12, 0.12),
        floor_size: Sequence[float] = (1.0, 1.0),
    ) -> None:
        """Build the scene. `randomize` draws the target and the initial joint angles
        each episode; without it the target is fixed at (0.1, 0.1) and the arm starts
        straight along x. Raises composer.TaskError for timesteps that do not divide."""
        self.arena = Floor(name="floor", size=floor_size, elevation=-60.0)
        self.arm = PlanarArm(
            link_lengths=link_lengths, actuator="position", kp=1.0, damping=0.05, gear=0.2
        )
        self.arena.attach(self.arm)
        self.servos = self.arm.actuators
        root = self.arena.mjcf_model
        root.statistic.center = [0, 0, 0]
        root.statistic.extent = 0.5
        target = root.worldbody.add("body", name="target", mocap=True, pos=[0.1, 0.1, 0.02])
        target.add("geom", name="target", type="sphere", size=[0.015], contype=0,
                   conaffinity=0, rgba=[0.9, 0.2, 0.2, 0.8])  # fmt: skip
        self.target = target
        for name in ("joint_angles", "joint_velocities"):
            self.arm.observables[name].enabled = True
        self.randomize = randomize
        self.success_distance = float(success_distance)
        self.control_cost = float(control_cost)
        self.max_joint_step = float(max_joint_step)
        # The environments of the last before_step_batch and their actions (control cost).
        self._last_actions = _NO_ACTIONS
        reach = np.array(self.arm.reach)  # a 0-d array: see _HALF below
        self.observe({
            "target_position": observation.BatchGeneric(
                lambda physics: clip(
                    physics.bind(target).mocap_pos[:, :2] / reach, _MINUS_ONE, _ONE
                ),
                bounds=(-1, 1),
            ),
            "to_target": observation.BatchGeneric(
                lambda physics: clip(self._to_target(physics) / reach, _MINUS_TWO, _TWO),
                bounds=(-2, 2),
            ),
        })  # fmt: skip
        self.set_timesteps(control_timestep, physics_timestep)

    def before_step_batch(self, physics: BatchPhysics, actions: np.ndarray) -> None:
        """Servo targets: the current joint angles plus `max_joint_step * actions`, rows
        (n, 2); the actions are kept for the control cost."""
        joints = physics.bind(self.arm.joints)
        physics.bind(self.servos).ctrl = joints.qpos + self.max_joint_step * actions
        self._last_actions = (physics.ids, actions)

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Resolve the target, joints and servos once."""
        self._goal = physics.bind(self.target)
        self._joints = physics.bind(self.arm.joints)
        self._servos = physics.bind(self.servos)

    def _to_target(self, physics: BatchPhysics) -> np.ndarray:
        """Target minus fingertip in the plane (m), (n, 2)."""
        tip = physics.bind(self.arm.fingertip).xpos
        return physics.bind(self.target).mocap_pos[:, :2] - tip[:, :2]

    def distances(self, physics: BatchPhysics) -> np.ndarray:
        """The fingertip-target distance in the plane (m) of each environment, (n,)."""
        to_target = self._to_target(physics)
        return np.hypot(to_target[:, 0], to_target[:, 1])

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """With `randomize`: joint angles uniform (shoulder over a full turn, elbow within
        its limits' middle half), target uniform over the disc of radius 0.9 R (by area),
        at least 0.05 m from the base. The servos hold the initial angles."""
        self._last_actions = _NO_ACTIONS
        if self.randomize:
            self._joints.qpos = [
                random_state.uniform(-np.pi, np.pi),
                random_state.uniform(-1.4, 1.4),
            ]
        self._servos.ctrl = self._joints.qpos
        if not self.randomize:
            return
        reach = self.arm.reach * 0.9
        radius = np.sqrt(random_state.uniform((0.05 / reach) ** 2, 1.0)) * reach
        angle = random_state.uniform(-np.pi, np.pi)
        self._goal.mocap_pos[:2] = radius * np.cos(angle), radius * np.sin(angle)

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The reward of each environment, shape (n,) (see the class docstring); the
        control cost takes each one's actions from the last `before_step_batch`."""
        distance = self.distances(physics)
        ratio = distance / self.success_distance
        pull = _HALF * (_ONE - distance / (2.0 * self.arm.reach))
        reward = pull + _HALF * np.exp(np.negative(ratio * ratio))
        if self.control_cost:
            stepped, actions = self._last_actions
            mine = actions[np.searchsorted(stepped, physics.ids)]
            reward = reward - self.control_cost * np.mean(np.square(mine), axis=1)
        return reward

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        """'is_success': the fingertip within `success_distance` of the target, (n,) bool."""
        return {"is_success": self.distances(physics) < self.success_distance}


# Numbers of the per-step formulas as 0-d arrays: numpy's arithmetic on small arrays takes
# a third less time with these than with Python numbers, to the same result.
_HALF, _ONE, _TWO, _MINUS_ONE, _MINUS_TWO = (np.array(v) for v in (0.5, 1.0, 2.0, -1.0, -2.0))

# Before any step of an episode: environment 0 (a single environment) acted with zeros.
_NO_ACTIONS = (np.zeros(1, dtype=np.intp), np.zeros((1, 2)))
