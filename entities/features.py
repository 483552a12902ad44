"""Observables the entities share: features derived from bound MJCF elements.

    arm.observables.add_observable('angles', HingeAngles([shoulder, elbow]))   # cos, sin
    walker.observables.add_observable('height', BodyHeight(torso))

Each binds its elements once per compile (`reader`) and then reads the live simulation
arrays, so sampling costs a few numpy operations per step.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import mjcf
from composer import observation


class HingeAngles(observation.Observable):
    """The angles of hinge joints as (cos q1.., sin q1..): bounded in [-1, 1], continuous
    across a full turn, unlike the angles themselves."""

    def __init__(self, joints: Sequence[mjcf.Element], **options: Any) -> None:
        """Read the hinge `joints`; options as `composer.observation.Observable`."""
        options.setdefault("bounds", (-1.0, 1.0))
        super().__init__(**options)
        self.joints = list(joints)

    def reader(self, physics: mjcf.Physics) -> Callable[[], np.ndarray]:
        """Bind the joints once; each call computes cos and sin of their qpos."""
        binding = physics.bind(self.joints)
        return lambda: np.concatenate([np.cos(binding.qpos), np.sin(binding.qpos)])


class BodyHeight(observation.Observable):
    """The world height (z) of a body's frame, shape (1,)."""

    def __init__(self, body: mjcf.Element, **options: Any) -> None:
        """Read `body`'s xpos z; options as `composer.observation.Observable`."""
        super().__init__(**options)
        self.body = body

    def reader(self, physics: mjcf.Physics) -> Callable[[], np.ndarray]:
        """Bind the body once; each call returns its height."""
        binding = physics.bind(self.body)
        return lambda: binding.xpos[2:3]


class BodyUpright(observation.Observable):
    """How upright a body is: the z component of its local z axis, 1 when upright, -1
    upside down; shape (1,), bounded in [-1, 1]."""

    def __init__(self, body: mjcf.Element, **options: Any) -> None:
        """Read `body`'s xmat; options as `composer.observation.Observable`."""
        options.setdefault("bounds", (-1.0, 1.0))
        super().__init__(**options)
        self.body = body

    def reader(self, physics: mjcf.Physics) -> Callable[[], np.ndarray]:
        """Bind the body once; each call returns xmat[2, 2]."""
        binding = physics.bind(self.body)
        return lambda: binding.xmat[8:9]
