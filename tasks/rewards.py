"""Reward shaping: `tolerance`, a smooth 1-inside, falling-outside bump used by the tasks,
and `squared_norms`, sums of squares a batched reward takes as a single one does.

    tolerance(0.3, bounds=(0, 0.5))                      # 1.0: inside the bounds
    tolerance(x, margin=2.0)                             # 1 at 0, 0.1 at |x| = 2, gaussian
    tolerance(u, margin=1.0, value_at_margin=0.0, sigmoid='quadratic')   # 0 at |u| >= 1
    small_control = Tolerance(margin=1.0, value_at_margin=0.0, sigmoid='quadratic')
    small_control(u)                                     # the same, checked once
    squared_norms(controls)                              # (n,): np.dot(u, u) of each row

Outside `bounds` the value falls with the distance to the nearest bound, measured in
units of `margin`: at one margin it is `value_at_margin`. Works on floats and arrays.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

import composer

SIGMOIDS = ("gaussian", "quadratic", "linear")


class Tolerance:
    """`tolerance` with its shape fixed once: checked and its constants computed at
    construction, so that a call is the arithmetic alone (a reward calls it every step).

        centered = Tolerance(margin=2.0)             # in a task's __init__
        centered(x)                                  # every step: tolerance(x, margin=2.0)
    """

    __slots__ = ("_lower", "_margin", "_ramp", "_scale", "_sigmoid", "_span", "_upper")

    def __init__(
        self,
        bounds: tuple[float, float] = (0.0, 0.0),
        margin: float = 0.0,
        sigmoid: str = "gaussian",
        value_at_margin: float = 0.1,
    ) -> None:
        """Fix the bounds, margin, sigmoid and value at the margin (see `tolerance`).
        Raises composer.TaskError for bounds out of order, a negative margin, an unknown
        sigmoid or value_at_margin outside [0, 1) ((0, 1) for 'gaussian')."""
        lower, upper = bounds
        if lower > upper or margin < 0 or sigmoid not in SIGMOIDS:
            raise composer.TaskError(
                f"tolerance needs lower <= upper, margin >= 0 and a sigmoid in {SIGMOIDS}; got "
                f"bounds {bounds}, margin {margin}, sigmoid {sigmoid!r}"
            )
        low_ok = value_at_margin > 0 if sigmoid == "gaussian" else value_at_margin >= 0
        if not (low_ok and value_at_margin < 1):
            raise composer.TaskError(
                f"tolerance: value_at_margin must be in {'(0' if sigmoid == 'gaussian' else '[0'}"
                f", 1) for {sigmoid!r}, got {value_at_margin}"
            )
        self._lower, self._upper = lower, upper
        # None: a bump of width 0 (1 inside the bounds, 0 outside).
        self._margin = None if margin == 0 else _constant(margin)
        # Bounds (0, 0): the distance to them is |x|, exactly.
        self._span = not lower == upper == 0.0
        self._sigmoid = sigmoid
        if sigmoid == "gaussian":
            self._scale = np.asarray(np.sqrt(-2.0 * np.log(value_at_margin)))
        elif sigmoid == "quadratic":
            self._scale = np.asarray(np.sqrt(1.0 - value_at_margin))
        else:
            self._scale = _constant(1.0 - value_at_margin)

    def __call__(self, x: Any) -> Any:
        """1 where x is within the bounds, falling outside them: an array for an array,
        a float for a number, computed alike."""
        x = np.asarray(x, dtype=np.float64)
        if self._margin is None:
            lower, upper = self._lower, self._upper
            value = np.where((lower <= x) & (x <= upper), 1.0, 0.0)
        else:
            sigmoid = self._sigmoid
            if self._span:
                outside = np.maximum(np.maximum(self._lower - x, x - self._upper), 0.0)
            elif sigmoid == "linear":
                outside = np.abs(x)  # max(0 - x, x - 0, 0), exactly
            else:
                # The other sigmoids square the scaled distance, whose sign rounding never
                # changes: x's is as good as |x|'s, one numpy call less every step.
                outside = x
            # The distance to the bounds in margins, 0 inside them, where every sigmoid
            # is exactly 1.
            distance = outside / self._margin
            if sigmoid == "gaussian":
                scaled = distance * self._scale
                value = np.exp(_MINUS_HALF * (scaled * scaled))
            elif sigmoid == "quadratic":
                scaled = distance * self._scale
                value = np.fmax(_ONE - scaled * scaled, _ZERO)
            else:
                value = np.fmax(_ONE - distance * self._scale, _ZERO)
        return float(value) if value.ndim == 0 else value

    def __repr__(self) -> str:
        margin = 0.0 if self._margin is None else float(self._margin)
        return (
            f"Tolerance(bounds=({self._lower}, {self._upper}), margin={margin}, "
            f"sigmoid={self._sigmoid!r})"
        )


def tolerance(
    x: Any,
    bounds: tuple[float, float] = (0.0, 0.0),
    margin: float = 0.0,
    sigmoid: str = "gaussian",
    value_at_margin: float = 0.1,
) -> Any:
    """1 where `bounds[0] <= x <= bounds[1]`; outside, `sigmoid` of the distance to the
    bounds over `margin` (0 outside when margin is 0). An array for an array, a float for
    a number, computed alike (numpy's functions either way), so a batched reward equals a
    single one to the last bit. `Tolerance` is the same, checked once for calls every
    step. Raises composer.TaskError for bounds out of order, a negative margin, an unknown
    sigmoid or value_at_margin outside [0, 1) ((0, 1) for 'gaussian')."""
    return Tolerance(bounds, margin, sigmoid, value_at_margin)(x)


# Numbers as 0-d arrays: numpy takes a third less time per operation on small arrays with
# one of these than with a Python float, to the same result. Rewards run every step.
_ONE, _ZERO, _MINUS_HALF = np.array(1.0), np.array(0.0), np.array(-0.5)


@functools.cache
def _constant(value: float) -> np.ndarray:
    return np.array(value, dtype=np.float64)


def squared_norms(vectors: np.ndarray) -> Any:
    """The sum of squares of a vector, or of each one along the last axis (shape
    `vectors.shape[:-1]`), to the last bit as `np.dot(v, v)` gives it for each: numpy's
    matmul of two vectors runs the same dot routine, row by row. So a batched reward using
    it equals a single environment's using `np.dot`."""
    vectors = np.asarray(vectors, dtype=np.float64)
    return np.matmul(vectors[..., None, :], vectors[..., :, None])[..., 0, 0]
