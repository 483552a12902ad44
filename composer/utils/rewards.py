"""dm_control's reward shaping: `tolerance`, 1 inside bounds and a sigmoid of the distance
to them outside (`from composer.utils import rewards`).

    rewards.tolerance(x, margin=2.0)                                 # 1 at 0, 0.1 at |x| = 2
    rewards.tolerance(u, margin=1, value_at_margin=0, sigmoid="quadratic")   # 0 at |u| >= 1
    standing = rewards.Tolerance(bounds=(1.2, float("inf")), margin=0.6)     # built once
    standing(heights)                                                # every step, any shape

Promise: dm_control's values to the last bit, with its sigmoids (`SIGMOIDS`); bad parameters
raise `composer.utils.RewardError` (a ValueError) with dm_control's messages.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from composer.errors import RewardError

__all__ = ["SIGMOIDS", "Tolerance", "tolerance"]

SIGMOIDS = (
    "gaussian",
    "hyperbolic",
    "long_tail",
    "reciprocal",
    "cosine",
    "linear",
    "quadratic",
    "tanh_squared",
)
# Sigmoids that reach 0 at a finite distance, so that value_at_margin may be 0.
_REACHING_ZERO = ("cosine", "linear", "quadratic")
# Sigmoids that use the distance only squared: a distance of either sign gives the same bits.
_EVEN = ("gaussian", "long_tail", "quadratic")


class _Numbers(NamedTuple):
    """The literal numbers of the sigmoids' formulas."""

    one: Any
    two: Any
    minus_half: Any
    pi: Any
    zero: Any


# As Python numbers, numpy keeps the input's dtype where dm_control's literals keep it.
_LITERALS = _Numbers(1.0, 2.0, -0.5, np.pi, 0.0)
# As 0-d float64 arrays: the same values for float64 arrays, and numpy's arithmetic on small
# arrays takes a third less time with these than with Python numbers. Rewards run every step.
_ARRAYS = _Numbers(*(np.array(value, dtype=np.float64) for value in _LITERALS))


def _scale(sigmoid: str, value_at_1: Any) -> Any:
    """The factor on the distance that makes `sigmoid` equal `value_at_1` at distance 1
    (numpy scalar or Python number as `value_at_1`'s arithmetic gives it)."""
    if sigmoid == "gaussian":
        return np.sqrt(-2 * np.log(value_at_1))
    if sigmoid == "hyperbolic":
        return np.arccosh(1 / value_at_1)
    if sigmoid == "long_tail":
        return np.sqrt(1 / value_at_1 - 1)
    if sigmoid == "reciprocal":
        return 1 / value_at_1 - 1
    if sigmoid == "cosine":
        return np.arccos(2 * value_at_1 - 1) / np.pi
    if sigmoid == "linear":
        return 1 - value_at_1
    if sigmoid == "quadratic":
        return np.sqrt(1 - value_at_1)
    return np.arctanh(np.sqrt(1 - value_at_1))  # tanh_squared


def _gaussian(d: Any, scale: Any, n: _Numbers) -> Any:
    return np.exp(n.minus_half * (d * scale) ** 2)


def _hyperbolic(d: Any, scale: Any, n: _Numbers) -> Any:
    return n.one / np.cosh(d * scale)


def _long_tail(d: Any, scale: Any, n: _Numbers) -> Any:
    return n.one / ((d * scale) ** 2 + n.one)


def _reciprocal(d: Any, scale: Any, n: _Numbers) -> Any:
    return n.one / (abs(d) * scale + n.one)


def _cosine(d: Any, scale: Any, n: _Numbers) -> Any:
    scaled = d * scale
    with np.errstate(invalid="ignore"):  # cos(inf) is NaN, and masked out below
        cosine = np.cos(n.pi * scaled)
    return np.where(abs(scaled) < n.one, (n.one + cosine) / n.two, n.zero)


# dm_control writes these two as `where(|s| < 1, 1 - s, 0)` and `where(|s| < 1, 1 - s**2, 0)`.
# The same bits, with two numpy calls fewer: below 1, 1 - s and 1 - s**2 round to a positive
# number; from 1 on, to 0 or less, which fmax makes 0.0; fmax makes NaN 0.0 as the mask does.
# (The distance d is never negative where a sigmoid's value is used: inside the bounds
# `tolerance` takes 1 instead.)
def _linear(d: Any, scale: Any, n: _Numbers) -> Any:
    return np.fmax(n.one - d * scale, n.zero)


def _quadratic(d: Any, scale: Any, n: _Numbers) -> Any:
    return np.fmax(n.one - (d * scale) ** 2, n.zero)


def _tanh_squared(d: Any, scale: Any, n: _Numbers) -> Any:
    return n.one - np.tanh(d * scale) ** 2


# Each sigmoid of the distance in margins d: 1 at d = 0, value_at_1 at |d| = 1.
_SIGMOID_FUNCTIONS: dict[str, Callable[[Any, Any, _Numbers], Any]] = {
    "gaussian": _gaussian,
    "hyperbolic": _hyperbolic,
    "long_tail": _long_tail,
    "reciprocal": _reciprocal,
    "cosine": _cosine,
    "linear": _linear,
    "quadratic": _quadratic,
    "tanh_squared": _tanh_squared,
}
_FLOAT64 = np.dtype(np.float64)


def _check(bounds: tuple[Any, Any], margin: Any, sigmoid: str, value_at_margin: Any) -> None:
    """dm_control's checks, in its order and with its messages; raises RewardError."""
    lower, upper = bounds
    if lower > upper:
        raise RewardError("Lower bound must be <= upper bound.")
    if margin < 0:
        raise RewardError("`margin` must be non-negative.")
    if margin == 0:
        return  # no sigmoid is used: dm_control checks neither it nor value_at_margin
    if sigmoid in _REACHING_ZERO:
        if not 0 <= value_at_margin < 1:
            raise RewardError(
                f"`value_at_1` must be nonnegative and smaller than 1, got {value_at_margin}."
            )
    elif not 0 < value_at_margin < 1:
        raise RewardError(f"`value_at_1` must be strictly between 0 and 1, got {value_at_margin}.")
    if sigmoid not in _SIGMOID_FUNCTIONS:
        raise RewardError(f"Unknown sigmoid type {sigmoid!r}.")


class Tolerance:
    """`tolerance` with its parameters checked and its constants computed once, so that a
    call is the arithmetic alone (a reward calls it every step).

        centered = Tolerance(margin=2.0)             # in a task's __init__
        centered(cart_positions)                     # every step: tolerance(x, margin=2.0)
    """

    __slots__ = (
        "_bounds",
        "_fast",
        "_fast_distance",
        "_fast_numbers",
        "_margin",
        "_scale",
        "_sigmoid",
        "_sigmoid_name",
        "_value_at_margin",
    )

    def __init__(
        self,
        bounds: tuple[float, float] = (0.0, 0.0),
        margin: float = 0.0,
        sigmoid: str = "gaussian",
        value_at_margin: float = 0.1,
    ) -> None:
        """Fix the bounds, margin, sigmoid and value at the margin (see `tolerance`).
        Raises RewardError as `tolerance` does."""
        _check(bounds, margin, sigmoid, value_at_margin)
        lower, upper = bounds
        self._bounds = (lower, upper)
        self._margin = margin
        self._sigmoid_name = sigmoid
        self._value_at_margin = value_at_margin
        self._sigmoid = _SIGMOID_FUNCTIONS.get(sigmoid) if margin != 0 else None
        scale = None if self._sigmoid is None else _scale(sigmoid, value_at_margin)
        self._scale = scale
        # The clamped distance equals dm_control's outside the bounds, and is 0 inside
        # them, where a finite scale makes every sigmoid exactly dm_control's 1.0. With one
        # infinite bound only the other one's distance is taken: at x = that infinity
        # dm_control's x - inf is not taken either (x is within the bounds).
        finite = [math.isfinite(bound) for bound in bounds]
        self._fast = bool(scale is not None and margin > 0 and any(finite) and math.isfinite(scale))
        if lower == upper == 0:
            self._fast_distance = "signed" if sigmoid in _EVEN else "absolute"
        elif all(finite):
            self._fast_distance = "clamped"
        else:
            self._fast_distance = "below" if finite[0] else "above"
        self._fast_numbers: tuple[Any, ...] | None = None

    def __call__(self, x: Any) -> Any:
        """1 where x is within the bounds, the sigmoid of the distance in margins
        outside them: a float for a number, an array for an array (0-d included)."""
        if self._fast and type(x) is np.ndarray and x.dtype is _FLOAT64 and x.ndim:
            return self._float64_array(x)
        lower, upper = self._bounds
        in_bounds = np.logical_and(lower <= x, x <= upper)
        if self._sigmoid is None:
            value = np.where(in_bounds, 1.0, 0.0)
        else:
            distance = np.where(x < lower, lower - x, x - upper) / self._margin
            outside = self._sigmoid(distance, self._scale, _LITERALS)
            value = np.where(in_bounds, 1.0, outside)
        return float(value) if np.isscalar(x) else value

    def _float64_array(self, x: np.ndarray) -> np.ndarray:
        """`__call__` of a float64 array of one or more dimensions, to the same bits."""
        numbers = self._fast_numbers
        if numbers is None:
            numbers = self._fast_numbers = tuple(
                np.array(value, dtype=np.float64)
                for value in (*self._bounds, self._margin, self._scale)
            )
        lower, upper, margin, scale = numbers
        if self._fast_distance == "signed":  # squared: the sign of x does not matter
            distance = x / margin
        elif self._fast_distance == "absolute":  # bounds (0, 0): dm_control's 0 - x or x - 0
            distance = np.absolute(x) / margin
        elif self._fast_distance == "below":  # (lower, inf): how far below the lower bound
            distance = np.maximum(lower - x, _ARRAYS.zero) / margin
        elif self._fast_distance == "above":  # (-inf, upper): how far above the upper one
            distance = np.maximum(x - upper, _ARRAYS.zero) / margin
        else:
            distance = np.maximum(np.maximum(lower - x, x - upper), _ARRAYS.zero) / margin
        return self._sigmoid(distance, scale, _ARRAYS)  # type: ignore[misc]

    def __repr__(self) -> str:
        lower, upper = self._bounds
        return (
            f"Tolerance(bounds=({lower}, {upper}), margin={self._margin}, "
            f"sigmoid={self._sigmoid_name!r}, value_at_margin={self._value_at_margin})"
        )


def tolerance(
    x: Any,
    bounds: tuple[float, float] = (0.0, 0.0),
    margin: float = 0.0,
    sigmoid: str = "gaussian",
    value_at_margin: float = 0.1,
) -> Any:
    """1 where `bounds[0] <= x <= bounds[1]` (inclusive; either bound may be infinite, or
    both equal); outside, with `margin` 0, 0, else `sigmoid` of the distance to the nearest
    bound divided by `margin`, which is `value_at_margin` at one margin out. `x` is a
    number (a float back) or an array of any shape (an array back, elementwise).

    Values are dm_control's to the last bit, for numbers and arrays of any dtype: the same
    formulas in the same order on the same numpy types (a float32 array stays float32 where
    dm_control's does). One consequence is dm_control's own: numpy squares a number with the C
    library's `pow` and an array with a multiplication, which can differ in the last bit, so
    `tolerance(x)` of a number and of an array holding it can too. `Tolerance` computes a
    float64 array (of one or more dimensions, within finite bounds) a faster way to the same
    bits: the distance clamped at 0 inside the bounds, where every sigmoid is exactly 1,
    instead of masked. tests/composer/test_utils_reference.py compares both with
    dm_control's own module. `tolerance` keeps the `Tolerance` of each set of parameters it
    was called with (and their types), so a reward calling it each step builds it once.

    Raises RewardError (a ValueError) with dm_control's messages for `bounds[0] >
    bounds[1]`, a negative margin, and, when the margin is not 0, an unknown sigmoid or
    `value_at_margin` outside (0, 1) ([0, 1) for 'cosine', 'linear' and 'quadratic')."""
    key = _parameters_key(bounds, margin, sigmoid, value_at_margin)
    built = None if key is None else _BUILT.get(key)
    if built is None:
        built = Tolerance(bounds, margin, sigmoid, value_at_margin)  # raises RewardError
        if key is not None and len(_BUILT) < _BUILT_LIMIT:
            _BUILT[key] = built
    return built(x)


# The Tolerances `tolerance` built, by their parameters: dm_control's rewards call it every
# step with the same few, and building one (checks, scale) costs more than its arithmetic.
_BUILT: dict[tuple[Any, ...], Tolerance] = {}
_BUILT_LIMIT = 256
_PLAIN_NUMBERS = (float, int)


def _parameters_key(
    bounds: Any, margin: Any, sigmoid: Any, value_at_margin: Any
) -> tuple[Any, ...] | None:
    """A key telling apart every set of parameters that may compute differently: Python
    floats and ints with their types (numpy's arithmetic keeps a float32 input's dtype with
    them, not with a numpy float64), the sigmoid's name; None for anything else (arrays,
    numpy numbers, lists of bounds), which is built afresh each call."""
    if type(bounds) is not tuple or len(bounds) != 2 or type(sigmoid) is not str:
        return None
    lower, upper = bounds
    numbers = (lower, upper, margin, value_at_margin)
    types = tuple(type(number) for number in numbers)
    if not all(kind in _PLAIN_NUMBERS for kind in types):
        return None
    return (*numbers, sigmoid, types)
