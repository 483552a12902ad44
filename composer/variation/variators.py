"""Variators: apply variations to MJCF attributes (before compile) or to physics fields
(after compile), once per episode.

    class Ball(composer.Entity):
        def _build(self):
            ...
            self._mjcf_variator = MJCFVariator()
            self._mjcf_variator.bind_attributes(self.geom, size=Uniform(0.05, 0.1),
                                                rgba=Uniform([0, 0, 0, 1], [1, 1, 1, 1]))
            self._physics_variator = PhysicsVariator()
            self._physics_variator.bind_attributes(self.body, mass=LogNormal(0, 0.2))

        def initialize_episode_mjcf(self, random_state):
            self._mjcf_variator.apply_variations(random_state)     # model changes: recompile

        def initialize_episode(self, physics, random_state):
            self._physics_variator.apply_variations(physics, random_state)   # no recompile

Each variation is called with the attribute's value when it was bound (MJCF) or when the
model was compiled (physics) as `initial_value`, and its value now as `current_value`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import mjcf
from composer import errors
from composer.variation.distributions import evaluate


def _copy(value: Any) -> Any:
    return value.copy() if isinstance(value, np.ndarray) else value


class MJCFVariator:
    """Varies attributes of MJCF elements; changing the model makes the environment
    recompile it at the next reset."""

    def __init__(self) -> None:
        """An empty variator."""
        self._bound: list[tuple[mjcf.Element, str, Any, Any]] = []

    def bind_attributes(self, element: mjcf.Element, **variations: Any) -> None:
        """Vary `element.<attribute>` by each variation; raises VariationError for an
        attribute the element does not have."""
        for attribute, variation in variations.items():
            try:
                initial = getattr(element, attribute)
            except mjcf.Error as e:
                raise errors.VariationError(
                    f"{element.path}: cannot vary {attribute!r}: {e}"
                ) from e
            self._bound.append((element, attribute, variation, _copy(initial)))

    def apply_variations(self, random_state: np.random.RandomState) -> None:
        """Set every bound attribute to a new value. Raises VariationError naming the
        element and attribute when the value is invalid for it."""
        for element, attribute, variation, initial in self._bound:
            current = getattr(element, attribute)
            value = evaluate(variation, initial, current, random_state)
            try:
                setattr(element, attribute, value)
            except mjcf.Error as e:
                raise errors.VariationError(
                    f"{element.path}: variation of {attribute!r} gave an invalid value: {e}"
                ) from e

    def clear(self) -> None:
        """Forget every bound attribute (their values stay as last set)."""
        self._bound.clear()


class PhysicsVariator:
    """Varies simulation fields of bound elements (`physics.bind(element).<field>`), e.g.
    `mass`, `friction`, `rgba`, `damping`; no recompile needed."""

    def __init__(self) -> None:
        """An empty variator."""
        self._bound: list[tuple[mjcf.Element, str, Any]] = []
        self._model: Any = None
        self._initial: list[Any] = []

    def bind_attributes(self, element: mjcf.Element, **variations: Any) -> None:
        """Vary field `<name>` of `element`'s binding by each variation."""
        for field, variation in variations.items():
            self._bound.append((element, field, variation))

    def apply_variations(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Write a new value to every bound field. Raises VariationError naming the element
        and field when it cannot be bound or written."""
        if physics.model is not self._model:  # compiled anew: its values are the initial ones
            self._initial = []
            self._model = physics.model
        for element, field, _ in self._bound[len(self._initial) :]:  # bound since
            self._initial.append(_read(physics, element, field))
        for (element, field, variation), initial in zip(self._bound, self._initial, strict=True):
            current = _read(physics, element, field)
            value = evaluate(variation, initial, current, random_state)
            try:
                setattr(physics.bind(element), field, value)
            except mjcf.Error as e:
                raise errors.VariationError(
                    f"{element.path}: cannot set physics field {field!r} to {value!r}: {e}"
                ) from e


def _read(physics: mjcf.Physics, element: mjcf.Element, field: str) -> np.ndarray:
    """A copy of `physics.bind(element).<field>`; raises VariationError naming both."""
    try:
        return np.array(getattr(physics.bind(element), field))
    except mjcf.Error as e:
        raise errors.VariationError(
            f"{element.path}: cannot vary physics field {field!r}: {e}"
        ) from e
