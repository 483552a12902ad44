"""dm_control's inverse kinematics on an `mjcf.Physics`: joint positions that put a site at
a target position, orientation or both (`from composer.utils import inverse_kinematics`).

    result = inverse_kinematics.qpos_from_site_pose(
        physics, "arm/pinch", target_pos=[0.4, 0.0, 0.3], target_quat=[0, 1, 0, 0],
        joint_names=["arm/shoulder", "arm/elbow", "arm/wrist"], inplace=True)
    result.success, result.err_norm, result.qpos   # an IKResult; qpos: the physics' now

Promise: dm_control's values to the last bit; without `inplace` the physics is not changed
(`qpos_from_site_pose` says each step, and what `inplace` leaves).
"""

from __future__ import annotations

import collections
import logging
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from composer.errors import InverseKinematicsError

if TYPE_CHECKING:
    import mjcf

__all__ = ["IKResult", "nullspace_method", "qpos_from_site_pose"]

_LOG = logging.getLogger(__name__)

# dm_control's tests read these two names for the messages they expect.
_INVALID_JOINT_NAMES_TYPE = (
    "qpos_from_site_pose: `joint_names` must be None, a list, a tuple or a numpy array of "
    "joint names; got {}."
)
_REQUIRE_TARGET_POS_OR_QUAT = (
    "qpos_from_site_pose needs a target: `target_pos`, `target_quat` or both."
)

IKResult = collections.namedtuple("IKResult", ["qpos", "err_norm", "steps", "success"])
IKResult.__doc__ = """What `qpos_from_site_pose` found: `qpos` (nq,), `err_norm` (the
weighted error at the last step), `steps` (the index of the last step taken) and `success`
(whether `err_norm` got below `tol`)."""

# Degrees of freedom of each joint type (mjtJoint: free, ball, slide, hinge).
_JOINT_DOFS = np.array([6, 3, 1, 1])


def _dof_indices(model: mujoco.MjModel, joint_names: Any) -> Any:
    """The columns of the Jacobian the given joints move: every one for None; for names,
    each joint's degrees of freedom in the order given (dm_control's named indexing);
    integers are taken as degree-of-freedom indices, as dm_control takes them. Raises
    InverseKinematicsError for another type or no joints, mjcf.NotFoundError for a name
    the model does not have."""
    if joint_names is None:
        return slice(None)
    if not isinstance(joint_names, list | tuple | np.ndarray):
        raise InverseKinematicsError(_INVALID_JOINT_NAMES_TYPE.format(type(joint_names)))
    names = list(np.ravel(joint_names) if isinstance(joint_names, np.ndarray) else joint_names)
    if not names:
        raise InverseKinematicsError("qpos_from_site_pose: `joint_names` names no joint")
    if not isinstance(names[0], str):
        return names
    dofs: list[int] = []
    for name in names:
        joint = model.name2id(str(name), "joint")
        start = int(model.jnt_dofadr[joint])
        dofs.extend(range(start, start + int(_JOINT_DOFS[model.jnt_type[joint]])))
    return dofs


def qpos_from_site_pose(
    physics: mjcf.Physics,
    site_name: str,
    target_pos: Any = None,
    target_quat: Any = None,
    joint_names: Any = None,
    tol: float = 1e-14,
    rot_weight: float = 1.0,
    regularization_threshold: float = 0.1,
    regularization_strength: float = 3e-2,
    max_update_norm: float = 2.0,
    progress_thresh: float = 20.0,
    max_steps: int = 100,
    inplace: bool = False,
) -> IKResult:
    """Joint positions that put site `site_name` at `target_pos` (3,) and/or
    `target_quat` (4,) (None: not constrained), moving only `joint_names` (None: every
    joint); the steps and the options are dm_control's. Returns an IKResult; its `qpos` is
    a copy unless `inplace`, which leaves the result in the physics (a view of its qpos).

    Each step measures the error (the site's position error, plus `rot_weight` times its
    rotation error as an angular velocity over one second), and stops with success once it is
    below `tol`. Otherwise it solves for a joint update from the site's Jacobian over the given
    joints' degrees of freedom (`nullspace_method`: least squares, damped by
    `regularization_strength` while the error is above `regularization_threshold`), gives up
    if the error is more than `progress_thresh` times the update (stuck), scales the update
    down to `max_update_norm`, and integrates it into the positions (quaternions of ball and
    free joints included). Joint limits are not considered, as in dm_control. After
    `max_steps` steps without success a warning is logged (the
    `composer.utils.inverse_kinematics` logger).

    The values are dm_control's to the last bit: the same MuJoCo functions and numpy linear
    algebra in the same order (tests/composer/test_utils_reference.py runs dm_control's own
    module on the same physics). Without `inplace` the physics is not changed (a copy of its
    MjData is worked on); with it, its positions are the result's, its position-dependent
    quantities in `physics.data` are those of the result (as `mj_fwdPosition` leaves them),
    and it is marked dirty, so that bindings and named access recompute the rest when read.

    Raises InverseKinematicsError for no target, `joint_names` of another type than a
    list, tuple or numpy array (or naming none) and `max_steps` below 1;
    mjcf.NotFoundError for a site or joint name the model does not have."""
    if target_pos is None and target_quat is None:
        raise InverseKinematicsError(_REQUIRE_TARGET_POS_OR_QUAT)
    if max_steps < 1:
        raise InverseKinematicsError(
            f"qpos_from_site_pose: max_steps must be 1 or more, got {max_steps}"
        )
    model = physics.model
    dofs = _dof_indices(model, joint_names)
    site = model.name2id(site_name, "site")
    data = physics.data
    if not inplace:
        data = mujoco.MjData(model)
        mujoco.mj_copyData(data, model, physics.data)
    mujoco.mj_fwdPosition(model, data)
    # Views of MjData: mj_fwdPosition updates them in place.
    site_xpos, site_xmat = data.site_xpos[site], data.site_xmat[site]

    both = target_pos is not None and target_quat is not None
    jac = np.empty((6 if both else 3, model.nv))
    err = np.empty(6 if both else 3)
    jac_pos = err_pos = jac_rot = err_rot = None
    if target_pos is not None:
        target_pos = np.asarray(target_pos, dtype=np.float64)
        jac_pos, err_pos = jac[:3], err[:3]
    if target_quat is not None:
        target_quat = np.asarray(target_quat, dtype=np.float64)
        jac_rot, err_rot = jac[-3:], err[-3:]
    site_xquat, inverse_xquat, error_quat = np.empty(4), np.empty(4), np.empty(4)
    update = np.zeros(model.nv)

    success, err_norm = False, 0.0
    for steps in range(max_steps):  # noqa: B007 (the index of the last step is returned)
        err_norm = 0.0
        if err_pos is not None:
            err_pos[:] = target_pos - site_xpos
            err_norm += np.linalg.norm(err_pos)
        if err_rot is not None:
            mujoco.mju_mat2Quat(site_xquat, site_xmat)
            mujoco.mju_negQuat(inverse_xquat, site_xquat)
            mujoco.mju_mulQuat(error_quat, target_quat, inverse_xquat)
            mujoco.mju_quat2Vel(err_rot, error_quat, 1)
            err_norm += np.linalg.norm(err_rot) * rot_weight
        if err_norm < tol:
            success = True
            break
        mujoco.mj_jacSite(model, data, jac_pos, jac_rot, site)
        strength = regularization_strength if err_norm > regularization_threshold else 0.0
        update_joints = nullspace_method(jac[:, dofs], err, regularization_strength=strength)
        update_norm = np.linalg.norm(update_joints)
        if err_norm / update_norm > progress_thresh:
            break  # the error is large for the step: stuck in a local minimum
        if update_norm > max_update_norm:
            update_joints *= max_update_norm / update_norm
        update[dofs] = update_joints
        mujoco.mj_integratePos(model, data.qpos, update, 1)
        mujoco.mj_fwdPosition(model, data)

    if not success and steps == max_steps - 1:
        _LOG.warning("Failed to converge after %i steps: err_norm=%3g", steps, err_norm)
    if not inplace:
        return IKResult(qpos=data.qpos.copy(), err_norm=err_norm, steps=steps, success=success)
    physics.mark_as_dirty()  # positions written behind the bindings' back
    return IKResult(qpos=data.qpos, err_norm=err_norm, steps=steps, success=success)


def nullspace_method(
    jac_joints: np.ndarray, delta: np.ndarray, regularization_strength: float = 0.0
) -> np.ndarray:
    """The joint velocities (nv,) that best achieve the end-effector change `delta`
    (ndelta,) through the Jacobian `jac_joints` (ndelta, nv): the least-squares solution
    of J^T J dq = J^T delta, with `regularization_strength` times the identity added to
    J^T J when positive (damped least squares: Buss, "Introduction to inverse kinematics
    with Jacobian transpose, pseudoinverse and damped least squares methods", 2004)."""
    hessian = jac_joints.T.dot(jac_joints)
    joint_delta = jac_joints.T.dot(delta)
    if regularization_strength > 0:
        hessian += np.eye(hessian.shape[0]) * regularization_strength
        return np.linalg.solve(hessian, joint_delta)
    return np.linalg.lstsq(hessian, joint_delta, rcond=-1)[0]
