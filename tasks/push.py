"""ArmPushBox: a UR5e with a Robotiq 2F-85 pushes a box into a target disc on a table.

    env = gym.make('composer/ArmPushBox-v0', flatten_observations=True)
    env = gym.make('composer/ArmPushBox-v0', menagerie_root='~/mujoco_menagerie')

The robots are MuJoCo Menagerie's, shipped with the package (`entities.menagerie`), so the
task needs no download; `menagerie_root` names a Menagerie folder to take them from first
(searched as `entities.robots.from_menagerie` says). 24 observations, 7 actions in [-1, 1]
(`ArmPushBox` lists them).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

import mjcf
from arenas import Table
from composer import BatchPhysics, observation
from entities import Box, features, robots
from entities.features import clip
from tasks.rewards import squared_norms
from tasks.unit_action import UnitActionTask

HOME = (np.pi, -1.9, 2.0, -1.67, -np.pi / 2, 0.0)
TARGET_WINDOW = 0.3  # rad: how far an arm joint's target may lead its angle
REGION = ((0.05, 0.25), (-0.2, 0.2))  # x and y ranges on the table for box and target


class ArmPushBox(UnitActionTask):
    """Push a box into the target disc with a real arm and gripper.

    Action (7 numbers in [-1, 1]): six changes of the arm's joint targets, each scaled by
    `max_joint_step` rad (targets stay within `TARGET_WINDOW` rad of the joint angles, so
    they cannot wind up; a zero action holds them), and the gripper command (-1 open, 1
    closed). Observations: `arm_joint_positions` (6), `arm_joint_velocities` (6),
    `gripper_opening` (1), `tcp_position` (3), `box_position` (3), `tcp_to_box` (3),
    `box_to_target` (2): 24 numbers.

    Reward per step, in [0, 1]: with d_reach the tool-centre-point-to-box distance and
    d_push the box-to-target distance in the table plane (m),
    `0.3 * (1 - tanh(5 d_reach)) + 0.7 * (1 - tanh(5 d_push))`.
    `info['is_success']` is `d_push < target_radius`. Terminates when the box falls off
    the table.
    """

    action_size = 7  # six joint-target changes, then the gripper command

    def __init__(
        self,
        control_timestep: float = 0.04,
        physics_timestep: float = 0.004,
        randomize: bool = True,
        menagerie_root: str | os.PathLike[str] | None = None,
        target_radius: float = 0.05,
        box_half_size: float = 0.025,
        max_joint_step: float = 0.05,
        table_height: float = 0.4,
    ) -> None:
        """Build the scene. `randomize` draws the box and target positions each episode
        (else box at (0.1, -0.1), target at (0.2, 0.1)). Raises composer.TaskError for
        timesteps that do not divide."""
        self.robot = robots.ur5e_with_2f85(menagerie_root)
        self.arena = Table(height=table_height)
        self.arena.attach(self.robot, attach_site=self.arena.mount)
        self.box = Box(half_sizes=[box_half_size] * 3, mass=0.1)
        self.arena.attach(self.box)
        root = self.arena.mjcf_model
        root.statistic.center = [-0.1, 0, table_height + 0.15]
        root.statistic.extent = 1.4
        self.target = root.worldbody.add(
            "geom", name="target", type="cylinder", size=[target_radius, 0.001],
            pos=[0.2, 0.1, table_height + 0.001], contype=0, conaffinity=0,
            rgba=[0.2, 0.8, 0.3, 0.6],
        )  # fmt: skip
        self.arm_joints = self.robot.arm.mjcf_model.find_all("joint", exclude_attachments=True)
        self.arm_actuators = self.robot.arm.mjcf_model.find_all(
            "actuator", exclude_attachments=True
        )
        self.gripper_actuators = self.robot.gripper.actuators
        gripper_joint = self.robot.gripper.mjcf_model.find("joint", "right_driver_joint")
        assert gripper_joint is not None, "the 2F-85's driver joint"
        self.gripper_joint = gripper_joint
        for entity in self.robot.iter_entities():
            entity.observables.disable_all()
        self.randomize = randomize
        self.target_radius = float(target_radius)
        self.max_joint_step = float(max_joint_step)
        self.table_height = float(table_height)
        self._box_height = table_height + box_half_size
        box, tcp, target = self.box.body, self.robot.tcp, self.target
        self.observe({
            "arm_joint_positions": features.angles(self.arm_joints),
            "arm_joint_velocities": features.velocities(self.arm_joints),
            "gripper_opening": features.angles([self.gripper_joint]),
            "tcp_position": features.positions(self.robot.tcp),
            "box_position": features.positions(self.box.body),
            "tcp_to_box": observation.BatchGeneric(
                lambda physics: clip(
                    _tcp_to_box(physics.bind(box), physics.bind(tcp)), _MINUS_TEN, _TEN
                ),
                bounds=(-10, 10),
            ),
            "box_to_target": observation.BatchGeneric(
                lambda physics: clip(
                    _box_to_target(physics.bind(box), physics.bind(target)), _MINUS_TEN, _TEN
                ),
                bounds=(-10, 10),
            ),
        })  # fmt: skip
        self.set_timesteps(control_timestep, physics_timestep)

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Resolve joints, actuators, sites and bodies once."""
        self._arm = physics.bind(self.arm_joints)
        self._arm_ctrl = physics.bind(self.arm_actuators)
        self._gripper_ctrl = physics.bind(self.gripper_actuators)
        self._ctrl_low, self._ctrl_high = self._arm_ctrl.ctrlrange.T.copy()
        low, high = self._gripper_ctrl.ctrlrange[0]
        self._gripper_low, self._gripper_span = np.array(low), np.array(high - low)
        self._target = physics.bind(self.target)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Arm at its home pose (tool pointing down above the table), gripper open, box and
        target placed (drawn at least 0.12 m apart with `randomize`); the arm's targets
        (its actuators' controls) at the home pose."""
        self._arm.qpos = HOME
        self._arm_ctrl.ctrl = HOME
        box, target = np.array([0.1, -0.1]), np.array([0.2, 0.1])
        if self.randomize:
            (x_low, x_high), (y_low, y_high) = REGION
            while True:
                box, target = random_state.uniform([x_low, y_low], [x_high, y_high], (2, 2))
                if np.linalg.norm(box - target) >= 0.12:
                    break
        self.box.set_pose(physics, [*box, self._box_height], [1, 0, 0, 0])
        physics.model.geom_pos[self._target.ids, :2] = target

    def before_step_batch(self, physics: BatchPhysics, actions: np.ndarray) -> None:
        """Arm targets: the last ones (the arm actuators' controls) plus `max_joint_step *
        actions[:, :6]`, within `TARGET_WINDOW` of the angles and the actuators' ranges;
        gripper: `actions[:, 6]` mapped from [-1, 1] to its control range. Actions (n, 7);
        each environment's last targets are its controls, so no state is kept outside the
        simulations; the control ranges are the first environment's (all share them)."""
        arm_ctrl = physics.bind(self.arm_actuators)
        angles = physics.bind(self.arm_joints).qpos
        targets = arm_ctrl.ctrl + self.max_joint_step * actions[:, :6]
        targets = clip(targets, angles - _WINDOW, angles + _WINDOW)
        arm_ctrl.ctrl = clip(targets, self._ctrl_low, self._ctrl_high)
        gripper = self._gripper_low + (actions[:, 6:] + _ONE) / _TWO * self._gripper_span
        physics.bind(self.gripper_actuators).ctrl = gripper

    def _distances(self, physics: BatchPhysics) -> tuple[np.ndarray, np.ndarray]:
        """Tool-to-box and box-to-target distances (m) of each environment, (n,) each."""
        box = physics.bind(self.box.body)
        reach = np.sqrt(squared_norms(_tcp_to_box(box, physics.bind(self.robot.tcp))))
        return reach, self._push_distances(physics)

    def _push_distances(self, physics: BatchPhysics) -> np.ndarray:
        """Box-to-target distances (m) of each environment, (n,)."""
        box = physics.bind(self.box.body)
        return np.sqrt(squared_norms(_box_to_target(box, physics.bind(self.target))))

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The reward of each environment, (n,): see the class docstring."""
        reach, push = self._distances(physics)
        one, five = _ONE, _FIVE
        return _REACH_SHARE * (one - np.tanh(five * reach)) + _PUSH_SHARE * (
            one - np.tanh(five * push)
        )

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The box fell off the table: (n,) bool."""
        return physics.bind(self.box.body).xpos[:, 2] < self.table_height - 0.1

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        """'is_success': the box's centre within `target_radius` of the target's, (n,)."""
        return {"is_success": self._push_distances(physics) < self.target_radius}


def _tcp_to_box(box: Any, tcp: Any) -> np.ndarray:
    """The box's centre minus the tool centre point (m), (n, 3), from batch bindings."""
    return box.xpos - tcp.xpos


def _box_to_target(box: Any, target: Any) -> np.ndarray:
    """The target's centre minus the box's in the table plane (m), (n, 2)."""
    return target.xpos[:, :2] - box.xpos[:, :2]


# Numbers of the per-step formulas as 0-d arrays: numpy's arithmetic on small arrays takes
# a third less time with these than with Python numbers, to the same result.
_ONE, _TWO, _FIVE, _TEN, _MINUS_TEN = (np.array(value) for value in (1.0, 2.0, 5.0, 10.0, -10.0))
_REACH_SHARE, _PUSH_SHARE = np.array(0.3), np.array(0.7)
_WINDOW = np.array(TARGET_WINDOW)
