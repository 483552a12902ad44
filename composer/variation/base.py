"""`Variation`, the base of every variation, and the operations that combine them.

    noise = Normal(0, 0.01)
    scaled = 2 * noise + 1                  # a BinaryOperation: draws noise, then computes
    first = UniformPointOnSphere()[0]       # a GetItemOperation
    value = scaled(initial_value=..., current_value=..., random_state=random_state)

Promise: each operand that is a variation is evaluated with the call's arguments, left
operand first, and the operator applied to the values as they are (`Variation` says more).
"""

from __future__ import annotations

import abc
import operator
from collections.abc import Callable
from typing import Any

import numpy as np

from composer.variation.variation_values import evaluate


def random_state_or_global(random_state: Any) -> Any:
    """The state to draw from: `random_state`, or numpy's global one (the `numpy.random`
    module, as dm_control draws) when it is None."""
    return np.random if random_state is None else random_state


def equal(first: Any, second: Any) -> bool:
    """Whether two parameters of variations are equal; arrays and nested lists compare by
    shape and value instead of raising as `==` on arrays does."""
    if isinstance(first, np.ndarray) or isinstance(second, np.ndarray):
        return np.shape(first) == np.shape(second) and bool(np.array_equal(first, second))
    if isinstance(first, list | tuple) and isinstance(second, list | tuple):
        return (
            type(first) is type(second)
            and len(first) == len(second)
            and all(equal(a, b) for a, b in zip(first, second, strict=True))
        )
    if isinstance(first, dict) and isinstance(second, dict):
        return first.keys() == second.keys() and all(equal(first[k], second[k]) for k in first)
    return bool(first == second)


class Variation(metaclass=abc.ABCMeta):
    """A value drawn anew at each call; subclasses implement `__call__`.

    A variation is called as `variation(initial_value, current_value, random_state)`: the value
    the varied attribute had at first (when bound, or when compiled), its value now, and the
    numpy random state to draw from. Each argument may be omitted (None) by variations that do
    not use it. `+ - * / // **`, unary `-` and `[index]` make new variations; each operand that
    is a variation (or any callable) is evaluated with the same arguments, left operand first,
    and the operator is applied to the values as they are (lists are not turned into arrays).
    """

    @abc.abstractmethod
    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """A new value, given the attribute's first and current values; random draws come
        from `random_state` (numpy's global random state when None)."""

    def __add__(self, other: Any) -> Variation:
        return BinaryOperation(operator.add, self, other)

    def __radd__(self, other: Any) -> Variation:
        return BinaryOperation(operator.add, other, self)

    def __sub__(self, other: Any) -> Variation:
        return BinaryOperation(operator.sub, self, other)

    def __rsub__(self, other: Any) -> Variation:
        return BinaryOperation(operator.sub, other, self)

    def __mul__(self, other: Any) -> Variation:
        return BinaryOperation(operator.mul, self, other)

    def __rmul__(self, other: Any) -> Variation:
        return BinaryOperation(operator.mul, other, self)

    def __truediv__(self, other: Any) -> Variation:
        return BinaryOperation(operator.truediv, self, other)

    def __rtruediv__(self, other: Any) -> Variation:
        return BinaryOperation(operator.truediv, other, self)

    def __floordiv__(self, other: Any) -> Variation:
        return BinaryOperation(operator.floordiv, self, other)

    def __rfloordiv__(self, other: Any) -> Variation:
        return BinaryOperation(operator.floordiv, other, self)

    def __pow__(self, other: Any) -> Variation:
        return BinaryOperation(operator.pow, self, other)

    def __rpow__(self, other: Any) -> Variation:
        return BinaryOperation(operator.pow, other, self)

    def __getitem__(self, index: Any) -> Variation:
        return GetItemOperation(self, index)

    def __neg__(self) -> Variation:
        return UnaryOperation(operator.neg, self)


class UnaryOperation(Variation):
    """`op(value)` of a variation's value."""

    def __init__(self, op: Callable[[Any], Any], variation: Any) -> None:
        """Apply `op` to what `variation` gives."""
        self._op = op
        self._variation = variation

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """`op` of the variation evaluated with these arguments."""
        return self._op(evaluate(self._variation, initial_value, current_value, random_state))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, UnaryOperation):
            return False
        return self._op == other._op and equal(self._variation, other._variation)

    def __str__(self) -> str:
        return f"{self._op.__name__}({self._variation})"

    def __repr__(self) -> str:
        return f"UnaryOperation({self._op.__name__}({self._variation}))"


class BinaryOperation(Variation):
    """`op(first, second)` of two variations or constants, evaluated first to second."""

    def __init__(self, op: Callable[[Any, Any], Any], first: Any, second: Any) -> None:
        """Combine what `first` and `second` give with `op`."""
        self._op = op
        self._first = first
        self._second = second

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """Evaluate both operands with these arguments, then apply the operator."""
        first = evaluate(self._first, initial_value, current_value, random_state)
        second = evaluate(self._second, initial_value, current_value, random_state)
        return self._op(first, second)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, BinaryOperation):
            return False
        return (
            self._op == other._op
            and equal(self._first, other._first)
            and equal(self._second, other._second)
        )

    def __str__(self) -> str:
        return f"{self._op.__name__}({self._first}, {self._second})"

    def __repr__(self) -> str:
        return f"BinaryOperation({self._op.__name__}({self._first!r}, {self._second!r}))"


class GetItemOperation(Variation):
    """`value[index]` of a variation's value (taken as a numpy array)."""

    def __init__(self, variation: Any, index: Any) -> None:
        """Index what `variation` gives with `index` (anything numpy indexing takes)."""
        self._variation = variation
        self._index = index

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The indexed part of the variation evaluated with these arguments."""
        value = evaluate(self._variation, initial_value, current_value, random_state)
        return np.asarray(value)[self._index]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GetItemOperation):
            return False
        return equal(self._variation, other._variation) and equal(self._index, other._index)

    def __str__(self) -> str:
        return f"{self._variation}[{self._index}]"

    def __repr__(self) -> str:
        return f"GetItemOperation({self._variation!r}[{self._index}])"
