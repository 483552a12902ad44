"""dm_control's rotation helpers: quaternions ([w, x, y, z], MuJoCo's order), rotation
matrices, Euler angles and axis-angle vectors (`from composer.utils import transformations`).

    quat = transformations.euler_to_quat([0.1, 0.2, 0.3], ordering="XYZ")
    transformations.quat_mul(quat, transformations.quat_inv(quat))   # [1, 0, 0, 0]
    transformations.quat_dist(quats_a, quats_b)                      # (n, 1): batched

Promise: every public function of dm_control's module, its values to the last bit. Raises
TransformationError (a ValueError) for a quaternion whose scalar part is outside [-1, 1],
EulerOrderingError (a KeyError too) for an ordering it cannot invert.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from composer.errors import EulerOrderingError, TransformationError
from mjcf.sim.frame_poses import multiply

__all__ = [
    "axisangle_to_quat",
    "euler_to_quat",
    "euler_to_rmat",
    "mat_to_quat",
    "quat_conj",
    "quat_diff",
    "quat_dist",
    "quat_inv",
    "quat_log",
    "quat_mul",
    "quat_rotate",
    "quat_to_axisangle",
    "quat_to_euler",
    "quat_to_mat",
    "rmat_to_euler",
    "rotation_matrix_2d",
    "rotation_x_axis",
    "rotation_y_axis",
    "rotation_z_axis",
]

_LOG = logging.getLogger(__name__)
# dm_control's constants: a sine beyond _POLE_LIMIT is a pole; _TOL is its tolerance
# for a cosine slightly out of [-1, 1], and the norm below which a quaternion is zero.
_POLE_LIMIT = 1.0 - 1e-6
_TOL = 1e-10
_WARNING_INTERVAL = 60.0  # seconds between two pole warnings of one message
_last_warned: dict[str, float] = {}


def _warn_rate_limited(message: str) -> None:
    now = time.monotonic()
    if now - _last_warned.get(message, -_WARNING_INTERVAL) >= _WARNING_INTERVAL:
        _last_warned[message] = now
        _LOG.warning(message)


def _within(number: Any, what: str, precision: float = _TOL) -> Any:
    """`number`, a cosine, clipped to [-1, 1]; raises TransformationError naming `what`
    if it is outside by more than `precision` (rounding is clipped, a wrong input is not)."""
    if np.any(number < -1.0 - precision) or np.any(number > 1.0 + precision):
        raise TransformationError(
            f"{what} must be within [-1, 1] (to {precision}), got {number}: "
            "a unit quaternion was expected"
        )
    return np.clip(number, -1.0, 1.0)


# -- quaternions -----------------------------------------------------------------------------


def quat_conj(quat: Any) -> np.ndarray:
    """The conjugate [w, -x, -y, -z] of quaternions `quat` (..., 4), as float64: the
    inverse rotation of a unit quaternion. Over leading axes."""
    quat = np.asarray(quat)
    return np.concatenate([quat[..., :1], -quat[..., 1:]], axis=-1).astype(np.float64)


def quat_inv(quat: Any) -> np.ndarray:
    """The inverses of quaternions `quat` (..., 4): the conjugate over the squared norm.
    Over leading axes."""
    quat = np.asarray(quat)
    return quat_conj(quat) / np.sum(quat * quat, axis=-1, keepdims=True)


def quat_mul(quat1: Any, quat2: Any) -> np.ndarray:
    """The Hamilton products `quat1 * quat2` (..., 4): the rotation `quat2`, then
    `quat1`. Over leading axes of either."""
    # dm_control's formula in its order, shared with mjcf's frames: its values to the last bit.
    return multiply(quat1, quat2)


def quat_diff(source: Any, target: Any) -> np.ndarray:
    """The rotation from `source` to `target` (unit quaternions, ..., 4):
    conj(source) * target. Over leading axes."""
    return quat_mul(quat_conj(source), target)


def quat_log(quat: Any, tol: float = _TOL) -> np.ndarray:
    """The logarithms of quaternions `quat` (..., 4): [log |q|, v / |v| * acos(w) / |q|]
    (`tol` keeps the norms of zero vectors from 0). Over leading axes. Raises
    TransformationError if w is beyond [-1, 1] by more than 2 tol."""
    quat = np.asarray(quat)
    norm = np.linalg.norm(quat + tol, axis=-1, keepdims=True)
    scalar = quat[..., 0:1]
    vector = np.stack([quat[..., 1], quat[..., 2], quat[..., 3]], axis=-1)
    # w - tol is kept within [-1, 1] to 2 tol: the tolerance subtracted, and rounding.
    angle = np.arccos(_within(scalar - tol, "quat_log: w - tol", precision=2.0 * tol))
    vector = vector / np.linalg.norm(vector + tol, axis=-1, keepdims=True) * angle / norm
    return np.stack([np.log(norm[..., 0]), vector[..., 0], vector[..., 1], vector[..., 2]], axis=-1)


def quat_dist(source: Any, target: Any) -> np.ndarray:
    """The angle-like distance between unit quaternions `source` and `target` (..., 4):
    the norm of the log of source * target^-1, shape (..., 1). Over leading axes."""
    product = quat_mul(source, quat_inv(target))
    product /= np.linalg.norm(product, axis=-1, keepdims=True)
    return np.linalg.norm(quat_log(product), axis=-1, keepdims=True)


def quat_rotate(quat: Any, vec: Any) -> np.ndarray:
    """The 3-vector `vec` rotated by one quaternion `quat` (4,): the vector part of
    q (0, v) conj(q) (also scaled by |q|^2 when q is not a unit quaternion)."""
    pure = np.hstack([[0], vec])
    return quat_mul(quat_mul(quat, pure), quat_conj(quat))[1:]


def quat_to_axisangle(quat: Any) -> np.ndarray:
    """The axis-angle vector (3,) of one unit quaternion (4,): the axis times the angle
    wrapped into [-pi, pi); zeros below an angle of 1e-10. Raises TransformationError for
    a scalar part beyond [-1, 1] by more than 1e-10."""
    angle = 2 * np.arccos(_within(quat[0], "quat_to_axisangle: the scalar part w"))
    if angle < _TOL:
        return np.zeros(3)
    half_sine = np.sin(angle / 2)
    angle = (angle + np.pi) % (2 * np.pi) - np.pi
    return quat[1:4] / half_sine * angle


def quat_to_mat(quat: Any) -> np.ndarray:
    """The 4x4 homogeneous matrix of the rotation of one quaternion (4,), normalized
    first; the identity for a quaternion of squared norm below 1e-10."""
    q = np.array(quat, dtype=np.float64, copy=True)
    squared_norm = np.dot(q, q)
    if squared_norm < _TOL:
        return np.identity(4)
    q *= np.sqrt(2.0 / squared_norm)
    p = np.outer(q, q)  # p[i, j] = 2 q_i q_j / |q|^2
    return np.array(
        (
            (1.0 - p[2, 2] - p[3, 3], p[1, 2] - p[3, 0], p[1, 3] + p[2, 0], 0.0),
            (p[1, 2] + p[3, 0], 1.0 - p[1, 1] - p[3, 3], p[2, 3] - p[1, 0], 0.0),
            (p[1, 3] - p[2, 0], p[2, 3] + p[1, 0], 1.0 - p[1, 1] - p[2, 2], 0.0),
            (0.0, 0.0, 0.0, 1.0),
        ),
        dtype=np.float64,
    )


def quat_to_euler(quat: Any, ordering: str = "XYZ") -> np.ndarray:
    """The Euler angles (3,) of one quaternion (4,), in `ordering` (see `rmat_to_euler`)."""
    return rmat_to_euler(quat_to_mat(quat)[0:3, 0:3], ordering=ordering)


def mat_to_quat(mat: Any) -> np.ndarray:
    """The quaternion (4,) of a rotation matrix (3, 3) or homogeneous transform (4, 4),
    by the largest of its trace and diagonal (Shepperd's method); its sign is whichever
    that gives."""
    mat = np.asarray(mat)
    if mat.shape == (3, 3):
        homogeneous = np.eye(4)
        homogeneous[0:3, 0:3] = mat
        mat = homogeneous
    q = np.empty((4,), dtype=np.float64)
    t = np.trace(mat)
    if t > mat[3, 3]:
        q[0] = t
        q[3] = mat[1, 0] - mat[0, 1]
        q[2] = mat[0, 2] - mat[2, 0]
        q[1] = mat[2, 1] - mat[1, 2]
    else:
        i, j, k = 0, 1, 2  # i: the largest diagonal entry; (i, j, k) cyclic
        if mat[1, 1] > mat[0, 0]:
            i, j, k = 1, 2, 0
        if mat[2, 2] > mat[i, i]:
            i, j, k = 2, 0, 1
        t = mat[i, i] - (mat[j, j] + mat[k, k]) + mat[3, 3]
        q[i + 1] = t
        q[j + 1] = mat[i, j] + mat[j, i]
        q[k + 1] = mat[k, i] + mat[i, k]
        q[0] = mat[k, j] - mat[j, k]
    q *= 0.5 / np.sqrt(t * mat[3, 3])
    return q


def axisangle_to_quat(axisangle: Any, tol: float = 0.0) -> np.ndarray:
    """The unit quaternions (..., 4) of axis-angle vectors (..., 3): the rotation by
    |v| about v; the identity where |v| <= `tol`. Over leading axes."""
    axisangle = np.asarray(axisangle)
    angle = np.linalg.norm(axisangle, axis=-1, keepdims=True)
    small = angle <= tol
    with np.errstate(divide="ignore", invalid="ignore"):  # 0 / 0: replaced just below
        axis = np.where(small, [1.0, 0.0, 0.0], axisangle / angle)
    angle = np.where(small, [0.0], angle)
    return np.concatenate([np.cos(angle / 2), axis * np.sin(angle / 2)], axis=-1)


# -- rotation matrices -----------------------------------------------------------------------


def _axis_rotations(theta: Any, full: bool, rows: Callable[..., list[Any]]) -> np.ndarray:
    """Rotation matrices about one axis by angles `theta`: (3, 3), or (n, 3, 3) for n > 1
    angles ((4, 4) and (n, 4, 4) if `full`). `rows(c, s, zeros)` gives the 3 rows of the
    3x3 part for cosines c, sines s."""
    count = 1 if np.ndim(theta) == 0 else len(theta)
    cosine, sine = np.cos(theta), np.sin(theta)
    size = 4 if full else 3
    matrices = np.zeros((count, size, size))
    if full:
        matrices[:, 3, 3] = 1.0
    for row, values in enumerate(rows(cosine, sine, np.zeros(count))):
        matrices[:, row, 0:3] = np.vstack(values).T
    return matrices.squeeze()


def rotation_x_axis(theta: Any, full: bool = False) -> np.ndarray:
    """The rotation matrix about X by `theta` radians: (3, 3), (n, 3, 3) for n angles,
    (4, 4) / (n, 4, 4) homogeneous if `full`."""
    return _axis_rotations(theta, full, lambda c, s, o: [[o + 1, o, o], [o, c, -s], [o, s, c]])


def rotation_y_axis(theta: Any, full: bool = False) -> np.ndarray:
    """The rotation matrix about Y by `theta` radians (shapes as `rotation_x_axis`)."""
    return _axis_rotations(theta, full, lambda c, s, o: [[c, o, s], [o, o + 1, o], [-s, o, c]])


def rotation_z_axis(theta: Any, full: bool = False) -> np.ndarray:
    """The rotation matrix about Z by `theta` radians (shapes as `rotation_x_axis`)."""
    return _axis_rotations(theta, full, lambda c, s, o: [[c, -s, o], [s, c, o], [o, o, o + 1]])


def rotation_matrix_2d(theta: Any) -> np.ndarray:
    """The 2x2 rotation matrix by `theta` radians ((2, 2, n) for n angles)."""
    cosine, sine = np.cos(theta), np.sin(theta)
    return np.array([[cosine, -sine], [sine, cosine]])


_AXIS_ROTATIONS = {"X": rotation_x_axis, "Y": rotation_y_axis, "Z": rotation_z_axis}


def euler_to_rmat(euler_vec: Any, ordering: str = "ZXZ", full: bool = False) -> np.ndarray:
    """The rotation matrix (3, 3) of Euler angles `euler_vec` (3,) about the axes of
    `ordering`, any three of 'X', 'Y', 'Z': rot(ordering[0]) @ rot(ordering[1]) @
    rot(ordering[2]); (n, 3, 3) for angles (n, 3); (4, 4) homogeneous if `full`. Raises
    EulerOrderingError for another letter."""
    unknown = [axis for axis in ordering if axis not in _AXIS_ROTATIONS]
    if unknown or len(ordering) != 3:
        raise EulerOrderingError(
            f"Euler ordering {ordering!r}: three of the axes 'X', 'Y', 'Z' were expected"
        )
    angles = np.atleast_2d(euler_vec)
    first, second, third = (
        _AXIS_ROTATIONS[axis](angles[:, i], full) for i, axis in enumerate(ordering)
    )
    if first.ndim == 3:
        product = np.einsum("bij,bjk->bik", first, second)
        return np.einsum("bij,bjk->bik", product, third).squeeze()
    return first.dot(second).dot(third)


class _Atan2(NamedTuple):
    """`atan2(R[y], R[x])`, negated if `negated`."""

    y: tuple[int, int]
    x: tuple[int, int]
    negated: bool = False

    def of(self, rmat: np.ndarray) -> Any:
        angle = np.arctan2(rmat[self.y], rmat[self.x])
        return -angle if self.negated else angle


class _TaitBryan(NamedTuple):
    """How dm_control reads the angles of rot(a) @ rot(b) @ rot(c) about three different
    axes off the matrix R: b from the sine R[sine] (negated if `sine_negated`), a and c by
    `first` and `last`; at a pole (|sine| > 1 - 1e-6), a = 0, b = +-`north` and c by
    `pole_last`."""

    sine: tuple[int, int]
    sine_negated: bool
    first: _Atan2
    last: _Atan2
    pole_last: _Atan2
    north: float

    def angles(self, rmat: np.ndarray) -> np.ndarray:
        sine = rmat[self.sine]
        if sine > _POLE_LIMIT:
            _warn_rate_limited("Angle at North Pole")
            return np.array([0.0, self.north, self.pole_last.of(rmat)])
        if sine < -_POLE_LIMIT:
            _warn_rate_limited("Angle at South Pole")
            return np.array([0.0, -self.north, self.pole_last.of(rmat)])
        middle = np.arcsin(sine)
        middle = -middle if self.sine_negated else middle
        return np.array([self.first.of(rmat), middle, self.last.of(rmat)])


_HALF_PI = np.pi / 2
# dm_control's formulas for each ordering, entry by entry (its pole formulas follow no one
# pattern, so they are listed rather than derived).
_TAIT_BRYAN = {
    "XYZ": _TaitBryan(
        (0, 2), False, _Atan2((1, 2), (2, 2), True), _Atan2((0, 1), (0, 0), True),
        _Atan2((1, 0), (1, 1)), _HALF_PI,
    ),
    "ZYX": _TaitBryan(
        (2, 0), True, _Atan2((1, 0), (0, 0)), _Atan2((2, 1), (2, 2)),
        _Atan2((0, 1), (0, 2)), -_HALF_PI,
    ),
    "XZY": _TaitBryan(
        (0, 1), True, _Atan2((2, 1), (1, 1)), _Atan2((0, 2), (0, 0)),
        _Atan2((1, 2), (1, 0)), -_HALF_PI,
    ),
    "YZX": _TaitBryan(
        (1, 0), False, _Atan2((2, 0), (0, 0), True), _Atan2((1, 2), (1, 1), True),
        _Atan2((0, 2), (0, 1), True), _HALF_PI,
    ),
    "ZXY": _TaitBryan(
        (2, 1), False, _Atan2((0, 1), (1, 1), True), _Atan2((2, 0), (2, 2), True),
        _Atan2((0, 2), (0, 0)), _HALF_PI,
    ),
    "YXZ": _TaitBryan(
        (1, 2), True, _Atan2((0, 2), (2, 2)), _Atan2((1, 0), (1, 1)),
        _Atan2((0, 1), (0, 0), True), -_HALF_PI,
    ),
}  # fmt: skip


def _xyx_angles(rmat: np.ndarray) -> np.ndarray:
    """The angles of rot_x(a) @ rot_y(b) @ rot_x(c): b from the cosine R[0, 0]; where it
    is +-1 only a - c or a + c is determined, and c is 0."""
    cosine = rmat[0, 0]
    if -1.0 < cosine < 1.0:
        first = np.arctan2(rmat[1, 0], -rmat[2, 0])
        middle = np.arccos(cosine)
        return np.array([first, middle, np.arctan2(rmat[0, 1], rmat[0, 2])])
    first = -np.arctan2(-rmat[1, 2], rmat[1, 1])
    return np.array([first, np.pi if cosine < 1.0 else 0.0, 0.0])


def _to_euler_functions() -> dict[str, Callable[[np.ndarray], np.ndarray]]:
    functions = {ordering: spec.angles for ordering, spec in _TAIT_BRYAN.items()}
    return {"XYZ": functions.pop("XYZ"), "XYX": _xyx_angles, **functions}  # dm_control's order


# The orderings `rmat_to_euler` inverts (dm_control's tests read this name).
_eulermap = _to_euler_functions()


def rmat_to_euler(rmat: Any, ordering: str = "ZXZ") -> np.ndarray:
    """The Euler angles (3,) in `ordering` of one rotation matrix (3, 3) (or the rotation
    part of a 4x4 transform): `euler_to_rmat` inverted, angles in (-pi, pi] (the middle
    one in [-pi/2, pi/2], or [0, pi] for 'XYX'). Raises EulerOrderingError for an
    ordering other than 'XYZ', 'XYX', 'ZYX', 'XZY', 'YZX', 'ZXY', 'YXZ': the default,
    'ZXZ', is dm_control's, which it does not invert either, so pass one. Near a pole
    (gimbal lock) the first angle is set to 0 and a warning is logged (the
    `composer.utils.transformations` logger, at most once a minute per message)."""
    to_euler = _eulermap.get(ordering)
    if to_euler is None:
        raise EulerOrderingError(
            f"rmat_to_euler cannot invert the Euler ordering {ordering!r}; it inverts "
            f"{', '.join(_eulermap)}"
        )
    return to_euler(np.asarray(rmat))


def euler_to_quat(euler_vec: Any, ordering: str = "XYZ") -> np.ndarray:
    """The quaternion (4,) of Euler angles `euler_vec` (3,) about the axes of `ordering`
    (see `euler_to_rmat`)."""
    return mat_to_quat(euler_to_rmat(euler_vec, ordering=ordering))
