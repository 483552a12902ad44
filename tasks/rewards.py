"""Reward shaping: `tolerance`, a smooth 1-inside, falling-outside bump used by the tasks,
and `squared_norms`, sums of squares a batched reward takes as a single one does.

    tolerance(0.3, bounds=(0, 0.5))                      # 1.0: inside the bounds
    tolerance(x, margin=2.0)                             # 1 at 0, 0.1 at |x| = 2, gaussian
    tolerance(u, margin=1.0, value_at_margin=0.0, sigmoid='quadratic')   # 0 at |u| >= 1
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
    single one to the last bit. Raises composer.TaskError for bounds out of order, a
    negative margin, an unknown sigmoid or value_at_margin outside [0, 1) ((0, 1) for
    'gaussian')."""
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
    x = np.asarray(x, dtype=np.float64)
    if margin == 0:
        value = np.where((lower <= x) & (x <= upper), 1.0, 0.0)
    else:
        # The distance to the bounds, 0 inside them, where every sigmoid is exactly 1.
        if lower == upper == 0.0:
            outside = np.abs(x)  # max(0 - x, x - 0, 0), exactly
        else:
            outside = np.maximum(np.maximum(lower - x, x - upper), 0.0)
        value = _falloff(outside / _constant(margin), sigmoid, value_at_margin)
    return float(value) if value.ndim == 0 else value


def _falloff(distance: np.ndarray, sigmoid: str, value_at_margin: float) -> np.ndarray:
    """A function of distance >= 0 that is 1 at 0 and `value_at_margin` at 1 (0 for a NaN
    distance but with the gaussian, which gives NaN)."""
    if sigmoid == "gaussian":
        scaled = distance * _gaussian_scale(value_at_margin)
        return np.exp(_MINUS_HALF * (scaled * scaled))
    if sigmoid == "quadratic":
        scaled = distance * _quadratic_scale(value_at_margin)
        return np.fmax(_ONE - scaled * scaled, _ZERO)
    return np.fmax(_ONE - distance * _constant(1.0 - value_at_margin), _ZERO)


# Numbers as 0-d arrays: numpy takes a third less time per operation on small arrays with
# one of these than with a Python float, to the same result. Rewards run every step.
_ONE, _ZERO, _MINUS_HALF = np.array(1.0), np.array(0.0), np.array(-0.5)


@functools.cache
def _constant(value: float) -> np.ndarray:
    return np.array(value, dtype=np.float64)


@functools.cache
def _gaussian_scale(value_at_margin: float) -> np.ndarray:
    return np.asarray(np.sqrt(-2.0 * np.log(value_at_margin)))


@functools.cache
def _quadratic_scale(value_at_margin: float) -> np.ndarray:
    return np.asarray(np.sqrt(1.0 - value_at_margin))


def squared_norms(vectors: np.ndarray) -> Any:
    """The sum of squares of a vector, or of each one along the last axis (shape
    `vectors.shape[:-1]`), to the last bit as `np.dot(v, v)` gives it for each: numpy's
    matmul of two vectors runs the same dot routine, row by row. So a batched reward using
    it equals a single environment's using `np.dot`."""
    vectors = np.asarray(vectors, dtype=np.float64)
    return np.matmul(vectors[..., None, :], vectors[..., :, None])[..., 0, 0]
