"""Observations that are rows of one bound MjData field, declared so (`FieldRows`).

    BoundField('qvel', joints)                        # physics.bind(joints).qvel, (n, nv)
    BoundField('xpos', head, index=2)                 # the head's height, (n,)
    BoundField('xmat', torso, index=slice(6, 9))      # its z axis, (n, 3)
    Concatenated([BoundField('qpos', hinges), BoundField('qvel', hinges)])   # (n, 2 * k)

A `VectorEnvironment` reads one with its batched reader, as a `BatchGeneric`; a single
environment reads all of a task's together, one gather per MjData field, to the same bits
(`composer.observation.fused`, checked against the reader at each compile).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import composer
import mjcf
from composer import observation


class BoundField(observation.Observable):
    """Field `field` of bound `elements` (one element or a sequence of one kind), part
    `index` of one environment's value, through `function` (a numpy ufunc, e.g. np.log1p)
    and flattened with `flat`: `function(physics.bind(elements).<field>[:, *index])` of n
    environments, shape (n, ...)."""

    def __init__(
        self,
        field: str,
        elements: mjcf.Element | Sequence[mjcf.Element],
        index: Any = None,
        flat: bool = False,
        function: np.ufunc | None = None,
        **options: Any,
    ) -> None:
        """Observe `field` of `elements` (part `index` of it, None: all; `function` of it;
        flattened with `flat`); options as `composer.observation.Observable`."""
        super().__init__(**options)
        self.field = field
        self.elements = elements if isinstance(elements, mjcf.Element) else list(elements)
        self.index = index
        self.flat = flat
        self.function = function

    def batch_reader(self, physics: composer.BatchPhysics) -> Callable[[], np.ndarray]:
        """Bind the elements once; each call reads the field's rows (a new array)."""
        binding = physics.bind(self.elements)
        field, index, flat, function = self.field, self.index, self.flat, self.function
        key = (slice(None), *(index if isinstance(index, tuple) else (index,)))
        if not flat and function is None:
            if index is None:
                return lambda: getattr(binding, field)
            return lambda: getattr(binding, field)[key]

        def read() -> np.ndarray:
            rows = getattr(binding, field) if index is None else getattr(binding, field)[key]
            if function is not None:
                rows = function(rows)
            return rows.reshape(len(rows), -1) if flat else rows

        return read

    def field_rows(self) -> observation.FieldRows:
        """Field `field` of the elements, part `index` of it, `function` of it, flattened
        with `flat`."""
        return observation.FieldRows(
            self.field, self.elements, self.index, flat=self.flat, function=self.function
        )


class Concatenated(observation.Observable):
    """`BoundField`s' values side by side: each one's batched read, concatenated along the
    last axis, shape (n, their widths summed); read together with the others by a single
    environment too."""

    def __init__(self, parts: Sequence[BoundField], **options: Any) -> None:
        """Observe `parts` (their own options are not used) as one value; options as
        `composer.observation.Observable`."""
        super().__init__(**options)
        self.parts = tuple(parts)

    def batch_reader(self, physics: composer.BatchPhysics) -> Callable[[], np.ndarray]:
        """Each part's batched reader; each call concatenates their reads."""
        reads = [part.batch_reader(physics) for part in self.parts]
        return lambda: np.concatenate([read() for read in reads], axis=-1)

    def field_rows(self) -> tuple[observation.FieldRows, ...]:
        """Each part's field rows, in order."""
        return tuple(part.field_rows() for part in self.parts)
