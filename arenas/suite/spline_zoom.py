"""Cubic B-spline zoom of a 2-D array, as `scipy.ndimage.zoom(values, zoom)` computes it by
default (order 3, mode 'constant', grid_mode False), to the last bit, in numpy.

    spline_zoom(bumps, 201 / 30)       # (30, 30) -> (201, 201): scipy.ndimage.zoom's values

The Control Suite's quadruped escape task smooths random bumps into terrain with scipy's
zoom; this is the same computation without the dependency, in the same floating-point
operations in the same order (tests/tasks/suite compares the two on random arrays).
"""

from __future__ import annotations

import math

import numpy as np

# sqrt(3) - 2, the cubic B-spline filter's pole, to double precision (as the reference
# writes it: sqrt(3.0) - 2.0 in doubles is one unit in the last place off).
_POLE = -0.267949192431122706472553658494127633


def spline_zoom(values: np.ndarray, zoom: float) -> np.ndarray:
    """`values` (rows, columns) zoomed by `zoom` on both axes with cubic splines: shape
    (round(rows * zoom), round(columns * zoom)), float64, scipy's values to the last bit.

    1. Prefilter each axis in turn (rows' axis first) into B-spline coefficients (Unser,
       Aldroubi and Eden, 1991): scale by the filter's gain, run the causal recursion with
       the pole z = sqrt(3) - 2 from an initial value summed over the whole line as if it
       were mirrored about its ends, then the anticausal recursion from its mirrored
       initial value.
    2. Sample: output index k of an axis of n inputs and m outputs sits at
       k * (n - 1) / (m - 1) in input coordinates (nothing beyond the last input: the
       output there is 0, the constant mode's value); each output sums its 4 x 4
       neighbouring coefficients (indices mirrored about the array's ends) weighted by the
       cubic B-spline's weights of its fractional position, row taps outer, column taps
       inner, each term (coefficient x row weight) x column weight.
    """
    values = np.asarray(values, dtype=np.float64)
    out_shape = tuple(round(size * zoom) for size in values.shape)
    coefficients = _prefilter(_prefilter(values, axis=0), axis=1)
    rows, row_weights, row_inside = _taps(values.shape[0], out_shape[0])
    columns, column_weights, column_inside = _taps(values.shape[1], out_shape[1])
    total = np.zeros(out_shape)
    for i in range(4):
        # (outputs' rows, 4 column taps): each row's i-th tap, at every output column.
        tapped = coefficients[rows[:, i]]
        for j in range(4):
            term = tapped[:, columns[:, j]] * row_weights[:, i, None]
            total += term * column_weights[None, :, j]
    total[~row_inside] = 0.0
    total[:, ~column_inside] = 0.0
    return total


def _prefilter(values: np.ndarray, axis: int) -> np.ndarray:
    """The B-spline coefficients of every line of `values` along `axis` (step 1)."""
    c = np.moveaxis(values, axis, 0).copy()  # c[i]: the i-th sample of every line
    n, z = len(c), _POLE
    c *= (1.0 - z) * (1.0 - 1.0 / z)
    if n > 1:
        z_last = math.pow(z, n - 1)
        first = c[0] + z_last * c[n - 1]
        z_i = z
        for i in range(1, n - 1):
            first += z_i * (c[i] + z_last * c[n - 1 - i])
            z_i *= z
        c[0] = first / (1 - z_last * z_last)
        for i in range(1, n):
            c[i] += z * c[i - 1]
        c[n - 1] = (z * c[n - 2] + c[n - 1]) * z / (z * z - 1)
        for i in range(n - 2, -1, -1):
            c[i] = z * (c[i + 1] - c[i])
    return np.moveaxis(c, 0, axis)


def _taps(inputs: int, outputs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each output index of an axis: its 4 input indices (outputs, 4), their weights
    (outputs, 4) and whether it lies within the inputs (outputs,) (step 2)."""
    scale = (inputs - 1) / (outputs - 1) if outputs > 1 else 1.0
    position = np.arange(outputs, dtype=np.float64) * scale
    inside = (position >= 0) & (position <= inputs - 1)
    start = np.floor(position).astype(np.int64) - 1
    indices = start[:, None] + np.arange(4)
    if inputs > 1:
        period = 2 * inputs - 2
        indices = np.abs(indices) % period
        indices = np.where(indices >= inputs, period - indices, indices)
    else:
        indices = np.zeros_like(indices)
    x = position - np.floor(position)
    y, z = x, 1.0 - x
    weights = np.empty((outputs, 4))
    weights[:, 1] = (y * y * (y - 2.0) * 3.0 + 4.0) / 6.0
    weights[:, 2] = (z * z * (z - 2.0) * 3.0 + 4.0) / 6.0
    weights[:, 0] = z * z * z / 6.0
    weights[:, 3] = 1.0 - weights[:, 0] - weights[:, 1] - weights[:, 2]
    return indices, weights, inside
