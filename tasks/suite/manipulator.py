"""Manipulator: a planar arm brings a ball or a peg to a target, or into a cup or a slot
(dm_control's `manipulator`).

    env = gym.make('dm_control/manipulator-bring_ball-v0')
    env = gym.make('dm_control/manipulator-insert_peg-v0', fully_observable=False)

Observations: `arm_pos`, `arm_vel`, `touch`, and fully observable (the default)
`hand_pos`, `object_pos`, `target_pos` and `object_vel`. Reward in [0, 1]: the prop at its
target (or, for the peg, a third as much for grasping it). Episodes start from dm_control's
draws in dm_control's order; 1,000 steps of 10 ms (physics at 1 ms). Details: docs/suite.md.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import composer
import mjcf
from arenas.suite import PlanarArena
from composer import observation
from entities.suite import Manipulator
from entities.suite.manipulator import CONTACT_SOLREF
from tasks.rewards import Tolerance
from tasks.suite import planar, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 10.0
CONTROL_TIMESTEP = 0.01
_CLOSE = 0.01  # metres: a thing this close is where it should be
_P_IN_HAND = 0.1
_P_IN_TARGET = 0.1
_INIT_TYPES = ["in_hand", "in_target", "uniform"]
# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_TWO, _THREE = np.array(2.0), np.array(3.0)


class Bring(SuiteTask):
    """Bring the ball or the peg to the target, or insert it (module docstring)."""

    def __init__(
        self,
        use_peg: bool = False,
        insert: bool = False,
        fully_observable: bool = True,
        control_timestep: float | None = None,
    ) -> None:
        """Build the scene: the peg with `use_peg`, else the ball, and a receptacle with
        `insert`; the props' and target's observations with `fully_observable`. Raises
        composer.TaskError for a control timestep that is not a multiple of 1 ms."""
        self._arena = PlanarArena(contact_solref=CONTACT_SOLREF)
        self.manipulator = Manipulator(use_peg=use_peg, insert=insert)
        self._arena.attach(self.manipulator)
        self._use_peg = bool(use_peg)
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        self._is_close = Tolerance(bounds=(0, _CLOSE), margin=_CLOSE * 2)
        arm, robot = self.manipulator.arm, self.manipulator
        if self._use_peg:  # grasp, pinch, bring and bring_tip's distances (the reward's)
            self._peg_distances = planar.SiteDistances(
                [(robot.peg_grasp, arm.grasp), (robot.peg_pinch, arm.pinch),
                 (robot.object_site, robot.target_site), (robot.target_peg_tip, robot.peg_tip)]
            )  # fmt: skip
        observables: dict[str, observation.Observable] = {
            "arm_pos": observation.BatchGeneric(
                lambda physics: planar.bounded_joint_positions(physics, arm.joints)
            ),
            "arm_vel": BoundField("qvel", arm.joints),
            "touch": BoundField("sensordata", arm.touch_sensors, function=np.log1p),
        }
        if fully_observable:
            observables |= {
                "hand_pos": planar.observed_2d_pose(arm.hand),
                "object_pos": planar.observed_2d_pose(robot.object),
                "object_vel": BoundField("qvel", robot.object_joints),
                "target_pos": planar.observed_2d_pose(robot.target),
            }
        self.set_observables(observables)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws, repeated until no two geoms touch: the arm's pose, the
        target's x in [-0.4, 0.4] and z in [0.1, 0.4], its angle (within +-60 degrees, the
        receptacle's too, when inserting, else any), then where the prop starts (module
        docstring): in the hand at the grasp site, turned with it; in the target; or at x in
        [-0.5, 0.5], z in [0, 0.7], any angle, moving sideways at up to 5 m/s."""
        robot = self.manipulator
        target = physics.bind(robot.target)
        props = physics.bind(robot.object_joints)
        grasp = physics.bind(robot.arm.grasp)
        penetrating = True
        while penetrating:
            planar.randomize_arm(physics, robot.arm, random_state)
            target_x = random_state.uniform(-0.4, 0.4)
            target_z = random_state.uniform(0.1, 0.4)
            if robot.receptacle is not None:
                target_angle = random_state.uniform(-np.pi / 3, np.pi / 3)
                _place(physics.bind(robot.receptacle), target_x, target_z, target_angle)
            else:
                target_angle = random_state.uniform(-np.pi, np.pi)
            _place(target, target_x, target_z, target_angle)
            probabilities = [_P_IN_HAND, _P_IN_TARGET, 1 - _P_IN_HAND - _P_IN_TARGET]
            init_type = random_state.choice(_INIT_TYPES, p=probabilities)
            if init_type == "in_target":
                object_x, object_z, object_angle = target_x, target_z, target_angle
            elif init_type == "in_hand":
                physics.after_reset()
                object_x, object_z = grasp.xpos[0], grasp.xpos[2]
                xx, zx = grasp.xmat[0], grasp.xmat[6]
                object_angle = np.pi - np.arctan2(zx, xx)
            else:
                object_x = random_state.uniform(-0.5, 0.5)
                object_z = random_state.uniform(0, 0.7)
                object_angle = random_state.uniform(0, 2 * np.pi)
                velocities = props.qvel
                velocities[0] = random_state.uniform(-5, 5)
                props.qvel = velocities
            props.qpos = [object_x, object_z, object_angle]
            physics.after_reset()
            penetrating = physics.data.ncon > 0

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        robot, is_close = self.manipulator, self._is_close
        if not self._use_peg:
            return is_close(planar.site_distances(physics, robot.object_site, robot.target_site))
        close = is_close(self._peg_distances(physics))  # (n, 4): grasp, pinch, bring, tip
        grasping = (close[:, 0] + close[:, 1]) / _TWO
        bringing = (close[:, 2] + close[:, 3]) / _TWO
        return np.maximum(bringing, grasping / _THREE)


def _place(body: Any, x: float, z: float, angle: float) -> None:
    """Move a static body (its model pose) to `x`, `z`, turned by `angle` about y: the
    quaternion's w and y set, its x and z kept (zero for these bodies)."""
    position, quaternion = body.pos, body.quat
    position[[0, 2]] = x, z
    quaternion[[0, 2]] = np.cos(angle / 2), np.sin(angle / 2)
    body.pos, body.quat = position, quaternion


for _name, _kwargs, _description, _tags in (
    ("bring_ball", {"use_peg": False, "insert": False},
     "Bring a ball to a target with a planar arm", ("benchmarking", "hard")),
    ("bring_peg", {"use_peg": True, "insert": False},
     "Bring a peg to a target with a planar arm", ("hard",)),
    ("insert_ball", {"use_peg": False, "insert": True},
     "Put a ball in a cup with a planar arm", ("hard",)),
    ("insert_peg", {"use_peg": True, "insert": True},
     "Put a peg in a slot with a planar arm", ("hard",)),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry("manipulator", _name, Bring, _kwargs, TIME_LIMIT, _description, _tags)
    )
