"""Variators: apply variations to MJCF attributes (before compiling) or to physics fields
(after compiling), once per episode.

    variator = MJCFVariator()                     # in an entity's _build
    variator.bind_attributes(geom, size=Uniform(0.05, 0.1), rgba=colors.GrayVariation(0.5))
    variator.apply_variations(random_state)       # in initialize_episode_mjcf: recompiles
    physics_variator.apply_variations(physics, random_state)   # in initialize_episode

Promise: attributes are evaluated in the order bound, so a seeded random state gives
dm_control's values; one an element lacks raises VariationAttributeError.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

import mjcf
from composer import errors
from composer.variation.variation_values import evaluate


class VariationAttributeError(errors.VariationError, AttributeError):
    """A variator was bound to an attribute, or a physics field, its element does not
    have."""


class _Bound:
    """A bound variation and the initial value it is given (None: not read yet)."""

    __slots__ = ("initial_value", "variation")

    def __init__(self, variation: Any, initial_value: Any = None) -> None:
        self.variation = variation
        self.initial_value = initial_value


def _bind(
    bound: dict[mjcf.Element, dict[str, _Bound]], element: mjcf.Element, name: str, variation: Any
) -> bool:
    """Forget `name` for a None variation that is bound; True when it is to be bound."""
    if variation is None and name in bound.get(element, {}):
        del bound[element][name]
        return False
    return True


class MJCFVariator:
    """Varies attributes of MJCF elements; a changed model is recompiled by the environment
    at the next reset. An entity using both kinds of variator:

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
    """

    def __init__(self) -> None:
        """An empty variator."""
        self._variations: dict[mjcf.Element, dict[str, _Bound]] = {}

    def bind_attributes(self, element: mjcf.Element, **variations: Any) -> None:
        """Vary `element.<attribute>` by each variation (a value or callable
        `f(initial_value, current_value, random_state)`); its current value is the initial
        value. Binding an attribute again replaces its variation; binding it to None
        forgets it. Raises VariationAttributeError for an attribute the element does not
        have (nothing is bound then)."""
        initial = {}
        for name in variations:
            try:
                initial[name] = copy.copy(getattr(element, name))
            except AttributeError as e:
                raise VariationAttributeError(f"{element.path}: cannot vary {name!r}: {e}") from e
        for name, variation in variations.items():
            if _bind(self._variations, element, name, variation):
                self._variations.setdefault(element, {})[name] = _Bound(variation, initial[name])

    def apply_variations(self, random_state: Any) -> None:
        """Set every bound attribute to a new value: each element's attributes evaluated in
        the order bound, elements in the order first bound, so a seeded random state gives
        dm_control's values. Raises VariationError naming the element and attribute when a
        value is invalid for it; then no attribute changes."""
        updates = []
        for element, attributes in self._variations.items():
            values = {}
            for name, bound in attributes.items():
                current = getattr(element, name)
                if bound.initial_value is None:
                    bound.initial_value = copy.copy(current)
                values[name] = evaluate(bound.variation, bound.initial_value, current, random_state)
            updates.append((element, values))
        done: list[tuple[mjcf.Element, dict[str, Any]]] = []
        for element, values in updates:
            previous = {name: copy.copy(getattr(element, name)) for name in values}
            try:
                element.set_attributes(**values)
            except mjcf.Error as e:
                for changed, old in reversed(done):
                    changed.set_attributes(**old)
                raise errors.VariationError(
                    f"MJCFVariator could not apply {sorted(values)}: {e}"
                ) from e
            done.append((element, previous))

    def clear(self) -> None:
        """Forget every bound attribute (their values stay as last set)."""
        self._variations.clear()

    def reset_initial_values(self) -> None:
        """Take each attribute's value at the next `apply_variations` as its initial
        value."""
        for attributes in self._variations.values():
            for bound in attributes.values():
                bound.initial_value = None


class PhysicsVariator:
    """Varies simulation fields of bound elements (`physics.bind(element).<field>`), e.g.
    `mass`, `friction`, `rgba`, `damping`; no recompile needed. The initial value of a
    field is its value in the compiled model when first applied, read again after the
    model is recompiled (unlike dm_control, which keeps the first model's)."""

    def __init__(self) -> None:
        """An empty variator."""
        self._variations: dict[mjcf.Element, dict[str, _Bound]] = {}
        self._model: Any = None

    def bind_attributes(self, element: mjcf.Element, **variations: Any) -> None:
        """Vary field `<name>` of `element`'s binding by each variation (a value or
        callable); the field is checked when first applied. Binding a field again replaces
        its variation; binding it to None forgets it."""
        for name, variation in variations.items():
            if _bind(self._variations, element, name, variation):
                self._variations.setdefault(element, {})[name] = _Bound(variation)

    def apply_variations(self, physics: mjcf.Physics, random_state: Any) -> None:
        """Write a new value to every bound field, evaluated in the order
        `MJCFVariator.apply_variations` says. Raises VariationAttributeError for a
        field the element's binding does not have, VariationError for a value it cannot
        take (then no field changes)."""
        if physics.model is not self._model:  # compiled anew: its values are the initial ones
            self.reset_initial_values()
            self._model = physics.model
        updates = []
        for element, fields in self._variations.items():
            binding = physics.bind(element)
            for name, bound in fields.items():
                current = _read(binding, element, name)
                if bound.initial_value is None:
                    bound.initial_value = current.copy()
                value = evaluate(bound.variation, bound.initial_value, current, random_state)
                updates.append((element, binding, name, value, current))
        for done, (element, binding, name, value, _) in enumerate(updates):
            try:
                setattr(binding, name, value)
            except mjcf.Error as e:
                for _, written, field, _, previous in reversed(updates[:done]):
                    setattr(written, field, previous)
                raise errors.VariationError(
                    f"{element.path}: cannot set physics field {name!r} to {value!r}: {e}"
                ) from e

    def clear(self) -> None:
        """Forget every bound field (their values stay as last set)."""
        self._variations.clear()

    def reset_initial_values(self) -> None:
        """Take each field's value at the next `apply_variations` as its initial value."""
        for fields in self._variations.values():
            for bound in fields.values():
                bound.initial_value = None


def _read(binding: Any, element: mjcf.Element, name: str) -> np.ndarray:
    """A copy of `binding.<name>`; raises VariationAttributeError naming the element."""
    try:
        return np.array(getattr(binding, name))
    except AttributeError as e:
        raise VariationAttributeError(
            f"{element.path}: cannot vary physics field {name!r}: {e}"
        ) from e
