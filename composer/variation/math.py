"""Math over variations: numpy functions of their values.

    Log(Uniform(1, 10))                          # log of a draw
    Norm(UniformPointOnSphere() * 2)             # 2.0
    Max([Uniform(0, 1), Uniform(0, 1)])          # the larger of two draws
    Max(Uniform([0, 0], [1, 1]), axis=0)         # keywords are passed on

Positional and keyword arguments, variations or constants (nested structures too), are
evaluated with the call's arguments, then given to the function.
"""

from __future__ import annotations

import abc
from collections.abc import Callable
from typing import Any

import numpy as np

from composer.variation import base
from composer.variation.variation_values import evaluate


class MathOp(base.Variation):
    """A function of evaluated arguments; subclasses name it in `_callable`."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Keep the arguments, constants or variations."""
        self._args = args
        self._kwargs = kwargs

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The function of the arguments evaluated with these arguments."""
        args = evaluate(
            self._args,
            initial_value=initial_value,
            current_value=current_value,
            random_state=random_state,
        )
        kwargs = evaluate(
            self._kwargs,
            initial_value=initial_value,
            current_value=current_value,
            random_state=random_state,
        )
        return self._callable(*args, **kwargs)

    @property
    @abc.abstractmethod
    def _callable(self) -> Callable[..., Any]:
        """The function applied."""

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, type(self)):
            return False
        return base.equal(self._args, other._args) and base.equal(self._kwargs, other._kwargs)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(args={self._args}, kwargs={self._kwargs})"


class Log(MathOp):
    """`numpy.log` of the value."""

    @property
    def _callable(self) -> Callable[..., Any]:
        return np.log


class Max(MathOp):
    """`numpy.max` of the value."""

    @property
    def _callable(self) -> Callable[..., Any]:
        return np.max


class Min(MathOp):
    """`numpy.min` of the value."""

    @property
    def _callable(self) -> Callable[..., Any]:
        return np.min


class Norm(MathOp):
    """`numpy.linalg.norm` of the value."""

    @property
    def _callable(self) -> Callable[..., Any]:
        return np.linalg.norm
