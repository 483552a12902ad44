"""Observables the entities share: bounded features of bound MJCF elements.

    arm.observables.add_observable('angles', HingeAngles([shoulder, elbow]))   # cos, sin
    speed = Clipped('qvel', joints, -VELOCITY_LIMIT, VELOCITY_LIMIT)
    height = Clipped('xpos', torso, -POSITION_LIMIT, POSITION_LIMIT, index=slice(2, 3))

Every feature has finite bounds and is clipped to them, so observations lie in the
observation space (Gymnasium's checker rejects infinite bounds). Each is written once,
batched (`batch_reader`, bound once per compile): a `composer.VectorEnvironment` reads all
its environments at once, with no per-environment observables; a single one, a batch of one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import mjcf
from composer import BatchError, BatchPhysics, observation

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

    def batch_reader(self, physics: BatchPhysics) -> Callable[[], np.ndarray]:
        """Bind the joints once; each call gives every environment's (cos, sin) of their
        qpos: rows of shape (2 * joints,)."""
        binding = physics.bind(self.joints)

        def read() -> np.ndarray:
            qpos = binding.qpos
            return np.concatenate([np.cos(qpos), np.sin(qpos)], axis=1)

        return read

    def field_rows(self) -> observation.FieldRows:
        """The joints' qpos as (cos, sin)."""
        return observation.FieldRows("qpos", self.joints, angles=True)


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

    def batch_reader(self, physics: BatchPhysics) -> Callable[[], np.ndarray] | None:
        """Bind the elements once; each call gives every environment's clipped value,
        (n, *shape). None (read per environment) for a field MuJoCo's batch does not hold;
        raises mjcf.BindingError now for an unknown field."""
        binding = physics.bind(self.elements)
        kind = self.kind
        low, high = np.asarray(self.low, dtype=np.float64), np.asarray(self.high, dtype=np.float64)
        try:
            getattr(binding, kind)
        except BatchError:
            return None
        if self.index is None:
            return lambda: clip(getattr(binding, kind), low, high)
        index = self.index if isinstance(self.index, tuple) else (self.index,)
        rows = (slice(None), *index)
        return lambda: clip(getattr(binding, kind)[rows], low, high)

    def field_rows(self) -> observation.FieldRows:
        """Field `kind` of the elements, part `index` of it, clipped."""
        bounds = (np.asarray(self.low, dtype=np.float64), np.asarray(self.high, dtype=np.float64))
        return observation.FieldRows(self.kind, self.elements, self.index, bounds=bounds)


def clip(values: Any, low: Any, high: Any) -> np.ndarray:
    """np.clip(values, low, high), bit for bit (NaN stays NaN), at a third of its cost on
    the small arrays observables are (with bounds as arrays, not Python numbers)."""
    return np.minimum(np.maximum(values, low), high)


def velocities(joints: Sequence[mjcf.Element] | mjcf.Element) -> Clipped:
    """The joints' qvel within +-VELOCITY_LIMIT."""
    return Clipped("qvel", joints, -VELOCITY_LIMIT, VELOCITY_LIMIT)


def angles(joints: Sequence[mjcf.Element]) -> Clipped:
    """Hinge joints' qpos within +-2 pi (limited joints stay well inside)."""
    return Clipped("qpos", joints, -2 * np.pi, 2 * np.pi)


def positions(element: mjcf.Element, index: Any = None) -> Clipped:
    """An element's world position xpos (part `index`) within +-POSITION_LIMIT."""
    return Clipped("xpos", element, -POSITION_LIMIT, POSITION_LIMIT, index=index)
