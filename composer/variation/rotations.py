"""Rotations: variations of quaternions ([w, x, y, z], MuJoCo's order).

    UniformQuaternion()                                               # any orientation
    QuaternionFromAxisAngle(axis=(0, 0, 1), angle=Uniform(-np.pi, np.pi, single_sample=True))
    QuaternionPreMultiply(QuaternionFromAxisAngle((1, 0, 0), 0.1))   # tilt the initial quat
    QuaternionRotate(quat=UniformQuaternion(), vec=(1, 0, 0))        # a rotated vector

`single_sample=True` on a scalar distribution inside matters when the varied attribute is
a quaternion: without it the distribution draws one value per element of the initial
value (four angles instead of one).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from composer.utils import transformations
from composer.variation import base
from composer.variation.variation_values import evaluate

IDENTITY_QUATERNION = np.array([1.0, 0.0, 0.0, 0.0])


class UniformQuaternion(base.Variation):
    """Unit quaternions uniformly distributed over rotations (one per call)."""

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """A random unit quaternion: three uniform draws (Shoemake's method)."""
        u1, u2, u3 = base.random_state_or_global(random_state).uniform(
            [0.0] * 3, [1.0, 2.0 * np.pi, 2.0 * np.pi]
        )
        far, near = np.sqrt(1.0 - u1), np.sqrt(u1)
        return np.array([far * np.sin(u2), far * np.cos(u2), near * np.sin(u3), near * np.cos(u3)])

    def __eq__(self, other: object) -> bool:
        return isinstance(other, UniformQuaternion)

    def __repr__(self) -> str:
        return "UniformQuaternion()"


class QuaternionFromAxisAngle(base.Variation):
    """The quaternion rotating by `angle` (radians) about `axis`; either may vary."""

    def __init__(self, axis: Any, angle: Any) -> None:
        """Rotate about `axis` (a 3-vector, taken as given: pass a unit one) by `angle`."""
        self._axis = axis
        self._angle = angle

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The quaternion of axis * angle (axis first, then angle, evaluated)."""
        axis = evaluate(self._axis, initial_value, current_value, random_state)
        angle = evaluate(self._angle, initial_value, current_value, random_state)
        return transformations.axisangle_to_quat(np.asarray(axis) * angle)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QuaternionFromAxisAngle):
            return False
        return base.equal(self._axis, other._axis) and base.equal(self._angle, other._angle)

    def __repr__(self) -> str:
        return f"QuaternionFromAxisAngle(axis={self._axis}, angle={self._angle})"


class QuaternionPreMultiply(base.Variation):
    """`quat * q` for the initial quaternion q (the current one when `cumulative`)."""

    def __init__(self, quat: Any, cumulative: bool = False) -> None:
        """Pre-multiply by `quat`, a variation or constant quaternion."""
        self._quat = quat
        self._cumulative = cumulative

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The product of a new `quat` and the base quaternion."""
        quat = evaluate(self._quat, initial_value, current_value, random_state)
        base_quat = current_value if self._cumulative else initial_value
        return transformations.quat_mul(np.asarray(quat), np.asarray(base_quat))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QuaternionPreMultiply):
            return False
        return base.equal(self._quat, other._quat) and self._cumulative == other._cumulative

    def __repr__(self) -> str:
        return f"QuaternionPreMultiply(quat={self._quat}, cumulative={self._cumulative})"


class QuaternionRotate(base.Variation):
    """A vector rotated by `quat`: `vec` (a variation or constant) when given, else the
    initial value (the current one when `cumulative`)."""

    def __init__(self, quat: Any, vec: Any = None, cumulative: bool = False) -> None:
        """Rotate `vec`, or the varied attribute, by `quat`."""
        self._quat = quat
        self._vec = vec
        self._cumulative = cumulative

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The rotated 3-vector (the quaternion evaluated first, then the vector)."""
        quat = evaluate(self._quat, initial_value, current_value, random_state)
        if self._vec is None:
            vec = current_value if self._cumulative else initial_value
        else:
            vec = evaluate(self._vec, initial_value, current_value, random_state)
        return transformations.quat_rotate(np.asarray(quat), np.asarray(vec))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QuaternionRotate):
            return False
        return (
            base.equal(self._quat, other._quat)
            and base.equal(self._vec, other._vec)
            and self._cumulative == other._cumulative
        )

    def __repr__(self) -> str:
        return (
            f"QuaternionRotate(quat={self._quat}, vec={self._vec}, cumulative={self._cumulative})"
        )
