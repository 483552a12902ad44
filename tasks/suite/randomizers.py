"""Random joint positions as the Control Suite draws them (`suite.utils.randomizers`).

    randomize_limited_and_rotational_joints(physics, random_state)   # the same draws, in order

Joints are visited in model order: a limited hinge or slide is drawn uniformly within its
range; a limited ball joint gets a rotation about a random axis (normalised `randn(3)`) by
`rand() * range[1]`; an unlimited hinge is drawn uniformly in [-pi, pi]; an unlimited ball
joint is a normalised `randn(4)`; an unlimited free joint keeps its position and gets a
normalised `rand(4)` as its quaternion (dm_control keeps that draw, though not uniform on
rotations, so that published results stay comparable). Unlimited slides keep theirs.
"""

from __future__ import annotations

import mujoco
import numpy as np

import mjcf

_HINGE, _SLIDE = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
_BALL, _FREE = int(mujoco.mjtJoint.mjJNT_BALL), int(mujoco.mjtJoint.mjJNT_FREE)


def random_limited_quaternion(random_state: np.random.RandomState, limit: float) -> np.ndarray:
    """A unit quaternion (4,) rotating by up to `limit` radians about a random axis."""
    axis = random_state.randn(3)
    axis /= np.linalg.norm(axis)
    angle = random_state.rand() * limit
    quaternion = np.zeros(4)
    mujoco.mju_axisAngle2Quat(quaternion, axis, angle)
    return quaternion


def randomize_limited_and_rotational_joints(
    physics: mjcf.Physics, random_state: np.random.RandomState
) -> None:
    """Write random positions of `physics`' joints into its qpos (module docstring)."""
    model, qpos = physics.model, physics.data.qpos
    for joint in range(model.njnt):
        kind, start = int(model.jnt_type[joint]), int(model.jnt_qposadr[joint])
        low, high = model.jnt_range[joint]
        if model.jnt_limited[joint]:
            if kind in (_HINGE, _SLIDE):
                qpos[start] = random_state.uniform(low, high)
            elif kind == _BALL:
                qpos[start : start + 4] = random_limited_quaternion(random_state, high)
        elif kind == _HINGE:
            qpos[start] = random_state.uniform(-np.pi, np.pi)
        elif kind == _BALL:
            quaternion = random_state.randn(4)
            qpos[start : start + 4] = quaternion / np.linalg.norm(quaternion)
        elif kind == _FREE:
            quaternion = random_state.rand(4)
            qpos[start + 3 : start + 7] = quaternion / np.linalg.norm(quaternion)
