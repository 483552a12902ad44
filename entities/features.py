"""Observables the entities share: bounded features of bound MJCF elements.

    arm.observables.add_observable('angles', HingeAngles([shoulder, elbow]))   # cos, sin
    speed = Clipped('qvel', joints, -VELOCITY_LIMIT, VELOCITY_LIMIT)
    height = Clipped('xpos', torso, -POSITION_LIMIT, POSITION_LIMIT, index=slice(2, 3))

Every feature here has finite bounds, and its value is clipped to them, so observations
always lie in the observation space (Gymnasium's checker rejects infinite bounds). Each
binds its elements once per compile (`reader`) and then reads the live simulation; each
also reads every environment of a `composer.VectorEnvironment` at once (`batch_reader`,
the same values row by row), so tasks built on them need no per-environment observables.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import mjcf
from composer import observation
from composer.vector import BatchError, BatchPhysics

VELOCITY_LIMIT = 100.0  # m/s or rad/s: far beyond what the robots here reach
POSITION_LIMIT = 100.0  # m from the world origin


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

    def batch_reader(self, physics: BatchPhysics) -> Callable[[], np.ndarray]:
        """Every environment's (cos, sin) at once: rows of shape (2 * joints,)."""
        binding = physics.bind(self.joints)

        def read() -> np.ndarray:
            qpos = binding.qpos
            return np.concatenate([np.cos(qpos), np.sin(qpos)], axis=1)

        return read


class Clipped(observation.Observable):
    """`physics.bind(elements).<kind>[index]` clipped to [low, high], its bounds."""

    def __init__(
        self, kind: str, elements: Any, low: Any, high: Any, index: Any = None, **options: Any
    ) -> None:
        """Read field `kind` ('qpos', 'xpos' ...) of `elements` (one or a list), part
        `index` of it if given; options as `composer.observation.Observable`."""
        options.setdefault("bounds", (low, high))
        super().__init__(**options)
        self.kind = kind
        self.elements = elements
        self.low, self.high = low, high
        self.index = index

    def reader(self, physics: mjcf.Physics) -> Callable[[], np.ndarray]:
        """Bind the elements once; raises mjcf.BindingError now for an unknown field."""
        binding = physics.bind(self.elements)
        kind, index, low, high = self.kind, self.index, self.low, self.high
        getattr(binding, kind)
        if index is None:
            return lambda: np.clip(getattr(binding, kind), low, high)
        return lambda: np.clip(getattr(binding, kind)[index], low, high)

    def batch_reader(self, physics: BatchPhysics) -> Callable[[], np.ndarray] | None:
        """Every environment's clipped value at once, (n, *shape); None (read per
        environment) for a field MuJoCo's batch does not bind."""
        binding = physics.bind(self.elements)
        kind, low, high = self.kind, self.low, self.high
        try:
            getattr(binding, kind)
        except BatchError:
            return None
        if self.index is None:
            return lambda: np.clip(getattr(binding, kind), low, high)
        index = self.index if isinstance(self.index, tuple) else (self.index,)
        rows = (slice(None), *index)
        return lambda: np.clip(getattr(binding, kind)[rows], low, high)


def velocities(joints: Sequence[mjcf.Element] | mjcf.Element) -> Clipped:
    """The joints' qvel within +-VELOCITY_LIMIT."""
    return Clipped("qvel", joints, -VELOCITY_LIMIT, VELOCITY_LIMIT)


def angles(joints: Sequence[mjcf.Element]) -> Clipped:
    """Hinge joints' qpos within +-2 pi (limited joints stay well inside)."""
    return Clipped("qpos", joints, -2 * np.pi, 2 * np.pi)


def positions(element: mjcf.Element, index: Any = None) -> Clipped:
    """An element's world position xpos (part `index`) within +-POSITION_LIMIT."""
    return Clipped("xpos", element, -POSITION_LIMIT, POSITION_LIMIT, index=index)
