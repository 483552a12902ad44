"""dm_control's reward shaping: `tolerance`, 1 inside bounds and a sigmoid of the distance
to them outside (`from composer.utils import rewards`).

    rewards.tolerance(x, margin=2.0)                                 # 1 at 0, 0.1 at |x| = 2
    standing = rewards.Tolerance(bounds=(1.2, float("inf")), margin=0.6)     # built once
    standing(heights)                                                # every step, any shape
    rewards.ColumnTolerance([standing, upright])(hu)   # (n, 2): two terms in one's calls

Promise: dm_control's values to the last bit, with its sigmoids (`SIGMOIDS`); bad parameters
raise `composer.utils.RewardError` (a ValueError) with dm_control's messages.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from composer.errors import RewardError

__all__ = ["SIGMOIDS", "ColumnTolerance", "Tolerance", "tolerance"]

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


# Each sigmoid of the scaled distance s = d * scale (d in margins; the reciprocal's is
# abs(d) * scale, as dm_control writes it): 1 at s = 0, value_at_1 at |d| = 1. The numbers
# `n` are the 0-d arrays unless given (the general formula gives Python's literals).
def _gaussian(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return np.exp(n.minus_half * s**2)


def _hyperbolic(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return n.one / np.cosh(s)


def _long_tail(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return n.one / (s**2 + n.one)


def _reciprocal(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return n.one / (s + n.one)


def _cosine(s: Any, n: _Numbers = _ARRAYS) -> Any:
    with np.errstate(invalid="ignore"):  # cos(inf) is NaN, and masked out below
        cosine = np.cos(n.pi * s)
    return np.where(abs(s) < n.one, (n.one + cosine) / n.two, n.zero)


# dm_control writes these two as `where(|s| < 1, 1 - s, 0)` and `where(|s| < 1, 1 - s**2, 0)`.
# The same bits, with two numpy calls fewer: below 1, 1 - s and 1 - s**2 round to a positive
# number; from 1 on, to 0 or less, which fmax makes 0.0; fmax makes NaN 0.0 as the mask does.
# (The distance d is never negative where a sigmoid's value is used: inside the bounds
# `tolerance` takes 1 instead.)
def _linear(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return np.fmax(n.one - s, n.zero)


def _quadratic(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return np.fmax(n.one - s**2, n.zero)


def _tanh_squared(s: Any, n: _Numbers = _ARRAYS) -> Any:
    return n.one - np.tanh(s) ** 2


_SIGMOID_FUNCTIONS: dict[str, Callable[[Any, _Numbers], Any]] = {
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
        if margin == 0:
            self._fast_distance = "inside"  # 1 inside the bounds, else 0
        elif lower == upper == 0:
            self._fast_distance = "signed" if sigmoid in _EVEN else "absolute"
        elif all(finite):
            self._fast_distance = "clamped"
        else:
            self._fast_distance = "below" if finite[0] else "above"
        fast = margin == 0 or (
            scale is not None and margin > 0 and any(finite) and math.isfinite(scale)
        )
        # The float64 arrays' way, made once: a call is then its numpy calls alone.
        self._fast: Callable[[np.ndarray], np.ndarray] | None = None
        if fast:
            # As 0-d float64 arrays: numpy's arithmetic on small arrays takes a third less
            # time with these than with Python numbers, to the same values.
            constants = (np.array(c, dtype=np.float64) for c in self._constants())
            self._fast = _fast_formula(self._fast_distance, self._sigmoid, *constants)

    def _constants(self) -> tuple[Any, Any, Any, Any]:
        """The numbers of the float64 formula: the bounds, the margin and the scale (1
        where no sigmoid is used)."""
        scale = 1.0 if self._scale is None else self._scale
        return (*self._bounds, self._margin, scale)

    def _form(self) -> tuple[str, str | None]:
        """What decides the float64 formula's operations: the kind of distance, and the
        sigmoid where one is used."""
        kind = self._fast_distance
        return kind, None if kind == "inside" else self._sigmoid_name

    def __call__(self, x: Any) -> Any:
        """1 where x is within the bounds, the sigmoid of the distance in margins
        outside them: a float for a number, an array for an array (0-d included)."""
        fast = self._fast
        if fast is not None and type(x) is np.ndarray and x.dtype is _FLOAT64 and x.ndim:
            return fast(x)
        lower, upper = self._bounds
        in_bounds = np.logical_and(lower <= x, x <= upper)
        if self._sigmoid is None:
            value = np.where(in_bounds, 1.0, 0.0)
        else:
            distance = np.where(x < lower, lower - x, x - upper) / self._margin
            if self._sigmoid is _reciprocal:
                distance = abs(distance)
            outside = self._sigmoid(distance * self._scale, _LITERALS)
            value = np.where(in_bounds, 1.0, outside)
        return float(value) if np.isscalar(x) else value

    def __reduce__(self) -> tuple[Any, ...]:
        # Made again from its parameters: its float64 formula is a closure.
        return Tolerance, (self._bounds, self._margin, self._sigmoid_name, self._value_at_margin)

    def __repr__(self) -> str:
        lower, upper = self._bounds
        return (
            f"Tolerance(bounds=({lower}, {upper}), margin={self._margin}, "
            f"sigmoid={self._sigmoid_name!r}, value_at_margin={self._value_at_margin})"
        )


def _fast_formula(
    distance: str, sigmoid: Any, lower: Any, upper: Any, margin: Any, scale: Any
) -> Callable[[np.ndarray], np.ndarray]:
    """`Tolerance.__call__` of a float64 array of one or more dimensions, to the same bits
    (see the module docstring): the distance `distance` names, in margins, scaled, then
    `sigmoid`. The constants are float64 arrays: 0-d, or one value a column of the last
    axis. A margin or scale of exactly 1 is not divided or multiplied by (x / 1 and x * 1
    are x), so `Tolerance(margin=1, value_at_margin=0, sigmoid='quadratic')`, dm_control's
    small control, costs two numpy calls fewer."""
    zero = _ARRAYS.zero
    if distance == "inside":  # margin 0: dm_control's where(in_bounds, 1.0, 0.0)
        return lambda x: np.logical_and(lower <= x, x <= upper).astype(np.float64)
    stages: list[Callable[[Any], Any]] = []
    if distance == "absolute":  # bounds (0, 0): dm_control's 0 - x or x - 0
        stages.append(np.absolute)
    elif distance == "below":  # (lower, inf): how far below the lower bound
        stages.append(lambda x: np.maximum(lower - x, zero))
    elif distance == "above":  # (-inf, upper): how far above the upper one
        stages.append(lambda x: np.maximum(x - upper, zero))
    elif distance == "clamped":
        stages.append(lambda x: np.maximum(np.maximum(lower - x, x - upper), zero))
    # ("signed": x itself, the sigmoid squaring it, so that its sign does not matter.)
    if not np.all(margin == 1):
        stages.append(lambda d: d / margin)
    if sigmoid is _reciprocal:
        stages.append(np.absolute)
    if not np.all(scale == 1):
        stages.append(lambda d: d * scale)
    stages.append(sigmoid)
    if len(stages) == 1:
        return sigmoid
    if len(stages) == 2:
        first, second = stages
        return lambda x: second(first(x))
    if len(stages) == 3:
        first, second, third = stages
        return lambda x: third(second(first(x)))

    def formula(x: np.ndarray) -> np.ndarray:
        for stage in stages:
            x = stage(x)
        return x

    return formula


# The shapes a ColumnTolerance keeps a formula for (one environment's, a vector's ...).
_SHAPES_KEPT = 16


class ColumnTolerance:
    """Several `Tolerance`s, one a column of the last axis, in the numpy calls of one:

        terms = ColumnTolerance([Tolerance(margin=2), Tolerance(margin=5)])
        terms(x)        # x (n, 2) float64: column 0 as Tolerance(margin=2), column 1 ...

    Each column's value is its Tolerance's, to the last bit (the same operations on the
    same numbers, each element on its own). The terms must all have a margin of 0, or all
    a margin above 0 with a finite scale and share their sigmoid and the kind of their
    bounds (both finite, only the lower or the upper, or (0, 0)); RewardError otherwise,
    and for a call with anything but a float64 array of one column a term."""

    __slots__ = ("_columns", "_form", "_formulas", "_terms", "_width")

    def __init__(self, terms: Sequence[Tolerance]) -> None:
        """Compute column k with `terms[k]`. Raises RewardError for terms that cannot be
        computed together (see the class docstring)."""
        terms = list(terms)
        if not terms:
            raise RewardError("ColumnTolerance needs at least one Tolerance")
        first = terms[0]
        for term in terms:
            if not isinstance(term, Tolerance) or term._fast is None:
                raise RewardError(
                    "ColumnTolerance takes Tolerances with a margin of 0, or above 0 with a "
                    f"finite bound and a finite scale, got {term!r}"
                )
            if term._form() != first._form():
                raise RewardError(
                    f"ColumnTolerance's terms must share their sigmoid and kind of bounds: "
                    f"{first!r} and {term!r} do not"
                )
        self._terms = tuple(terms)
        self._width = (len(terms),)
        self._form = (first._fast_distance, first._sigmoid)
        # Each term's constants, converted as Tolerance converts them, one a column.
        self._columns = [
            np.array(numbers, dtype=np.float64)
            for numbers in zip(*(term._constants() for term in terms), strict=True)
        ]
        self._formulas: dict[tuple[int, ...], Callable[[np.ndarray], np.ndarray]] = {}

    def _formula(self, shape: tuple[int, ...]) -> Callable[[np.ndarray], np.ndarray]:
        """The formula for arrays of `shape`: a constant all terms share as a 0-d array,
        others as arrays of that shape, since numpy's calls on small arrays cost twice as
        much when they broadcast (the same values either way)."""
        constants = [
            np.array(column[0]) if (column == column[0]).all()
            else np.broadcast_to(column, shape).copy()
            for column in self._columns
        ]  # fmt: skip
        formula = _fast_formula(*self._form, *constants)
        if len(self._formulas) < _SHAPES_KEPT:
            self._formulas[shape] = formula
        return formula

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Each column of `x` (float64, (..., k) for k terms) through its term. Raises
        RewardError for anything else."""
        if type(x) is np.ndarray and x.dtype is _FLOAT64:
            formula = self._formulas.get(x.shape)
            if formula is not None:
                return formula(x)
            if x.shape[-1:] == self._width:
                return self._formula(x.shape)(x)
        raise RewardError(
            f"ColumnTolerance of {self._width[0]} terms takes a float64 array of shape "
            f"(..., {self._width[0]}), got {type(x).__name__} {getattr(x, 'dtype', '')}"
            f"{getattr(x, 'shape', '')}"
        )

    def __reduce__(self) -> tuple[Any, ...]:
        return ColumnTolerance, (self._terms,)

    def __repr__(self) -> str:
        return f"ColumnTolerance({list(self._terms)!r})"


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
