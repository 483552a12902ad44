"""ToolCenterPointInitializer: an arm's hand placed at a random pose by inverse kinematics.

    initializer = composer.initializers.ToolCenterPointInitializer(
        hand=hand, arm=arm,                                 # dm_control RobotHand, RobotArm
        position=variation.Uniform([-0.1, -0.1, 0.2], [0.1, 0.1, 0.4]),
    )
    initializer(physics, random_state)                      # in initialize_episode

Promise: a pose is kept only if the arm and hand touch nothing they may not (the class says
what); none found raises EpisodeInitializationError, the arm's joints put back as they were.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

import mjcf
from composer import errors
from composer.entity import Entity
from composer.initializers.base import Initializer
from composer.robot import DOWN_QUATERNION
from composer.variation import evaluate

_REJECTION_SAMPLING_FAILED = (
    "ToolCenterPointInitializer found no valid initial configuration of the robot after "
    "{max_rejection_samples} target poses, with up to {max_ik_attempts} inverse kinematics "
    "attempts each: widen the position distribution, or raise max_rejection_samples"
)


class ToolCenterPointInitializer(Initializer):
    """Sets the pose of a hand's tool center point.

    The arm must have dm_control's `RobotArm` interface: `joints`, `wrist_site` and
    `set_site_to_xpos(physics, random_state, site, target_pos, target_quat, max_ik_attempts)`;
    the hand (or None: the arm's wrist is the tool) a `tool_center_point` site. A target pose is
    drawn, the arm solves for it, and the pose is kept unless a contact at distance <= 0
    joins two of the arm's geoms, the arm and the hand, or the arm or hand and something
    without a free joint. After `max_rejection_samples` targets it raises
    EpisodeInitializationError (the environment retries the episode), the arm's joints put
    back as they were.
    """

    def __init__(
        self,
        hand: Entity | None,
        arm: Entity,
        position: Any,
        quaternion: Any = DOWN_QUATERNION,
        ignore_collisions: bool = False,
        max_ik_attempts: int = 10,
        max_rejection_samples: int = 10,
    ) -> None:
        """`position` and `quaternion` are constants or variations drawn per target;
        `ignore_collisions` keeps the first pose the arm reaches."""
        self._hand = hand
        self._arm = arm
        self._position = position
        self._quaternion = quaternion
        self._ignore_collisions = ignore_collisions
        self._max_ik_attempts = max_ik_attempts
        self._max_rejection_samples = max_rejection_samples

    def __call__(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Place the tool center point. Raises EpisodeInitializationError when no target
        gives a pose without relevant collisions."""
        arm = self._arm
        site = self._hand.tool_center_point if self._hand is not None else arm.wrist_site  # type: ignore[attr-defined]
        joints = physics.bind(arm.joints)  # type: ignore[attr-defined]
        initial_qpos = np.array(joints.qpos)
        for _ in range(self._max_rejection_samples):
            target_pos = evaluate(self._position, random_state=random_state)
            target_quat = evaluate(self._quaternion, random_state=random_state)
            reached = arm.set_site_to_xpos(  # type: ignore[attr-defined]
                physics=physics, random_state=random_state, site=site, target_pos=target_pos,
                target_quat=target_quat, max_ik_attempts=self._max_ik_attempts,
            )  # fmt: skip
            if reached:
                physics.forward()
                if self._ignore_collisions or not self._has_relevant_collisions(physics):
                    return
            joints.qpos = initial_qpos
        raise errors.EpisodeInitializationError(
            _REJECTION_SAMPLING_FAILED.format(
                max_rejection_samples=self._max_rejection_samples,
                max_ik_attempts=self._max_ik_attempts,
            )
        )

    def _has_relevant_collisions(self, physics: mjcf.Physics) -> bool:
        """Whether a contact at distance <= 0 joins arm and arm, arm and hand, or the arm
        or hand and a geom of a body that does not move freely."""
        contact = physics.data.contact
        if physics.data.ncon == 0:
            return False
        arm = _own_geom_ids(physics, self._arm)
        hand = _own_geom_ids(physics, self._hand) if self._hand is not None else arm[:0]
        robot = np.union1d(arm, hand)
        free = _free_geom_ids(physics.model)
        touching = contact.dist <= 0
        first, second = contact.geom1, contact.geom2
        in_arm1, in_arm2 = np.isin(first, arm), np.isin(second, arm)
        in_robot1, in_robot2 = np.isin(first, robot), np.isin(second, robot)
        fixed1 = ~in_robot1 & ~np.isin(first, free)
        fixed2 = ~in_robot2 & ~np.isin(second, free)
        relevant = (
            (in_arm1 & in_robot2) | (in_robot1 & in_arm2)
            | (in_robot1 & fixed2) | (fixed1 & in_robot2)
        )  # fmt: skip
        return bool(np.any(touching & relevant))


def _own_geom_ids(physics: mjcf.Physics, entity: Entity) -> np.ndarray:
    """The ids of the geoms of `entity`'s own model (not of models attached to it)."""
    geoms = entity.mjcf_model.find_all("geom", exclude_attachments=True)
    if not geoms:
        return np.zeros(0, np.intp)
    return np.atleast_1d(physics.bind(geoms).element_id)


def _free_geom_ids(model: mujoco.MjModel) -> np.ndarray:
    """The ids of the geoms of bodies whose tree hangs from a free joint at the world."""
    root_body = model.body_rootid[model.geom_bodyid]
    first_joint = model.body_jntadr[root_body]
    has_joint = first_joint >= 0
    free = np.zeros(model.ngeom, dtype=bool)
    free[has_joint] = model.jnt_type[first_joint[has_joint]] == mujoco.mjtJoint.mjJNT_FREE
    return np.flatnonzero(free)
