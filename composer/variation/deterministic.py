"""Deterministic variations: a constant, a repeating sequence, the current value.

Constant(0.5)                          # always 0.5 (handy in tests)
Sequence([1, 2, Uniform(0, 1)])        # 1, 2, a draw, 1, 2, a draw ...
Identity()                             # the attribute's current value
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from composer.variation import base
from composer.variation.variation_values import evaluate


class Constant(base.Variation):
    """Always `value`."""

    def __init__(self, value: Any) -> None:
        """Give `value` at every call."""
        self._value = value

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The constant."""
        return self._value

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Constant):
            return False
        return base.equal(self._value, other._value)

    def __str__(self) -> str:
        return f"{self._value}"

    def __repr__(self) -> str:
        return f"Constant({self._value!r})"


class Sequence(base.Variation):
    """The items of `values` in turn, starting again after the last; an item that is a
    variation is evaluated."""

    def __init__(self, values: Iterable[Any]) -> None:
        """Cycle through `values` (iterated again at each cycle)."""
        self._values = values
        self._iterator = iter(values)

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The next item, evaluated with these arguments."""
        try:
            item = next(self._iterator)
        except StopIteration:
            self._iterator = iter(self._values)
            item = next(self._iterator)
        return evaluate(
            item,
            initial_value=initial_value,
            current_value=current_value,
            random_state=random_state,
        )


class Identity(base.Variation):
    """The attribute's current value, unchanged."""

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """`current_value`."""
        return current_value

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Identity)
