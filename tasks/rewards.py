"""Reward shaping for the shipped tasks: dm_control's `tolerance` and `Tolerance`, a smooth
bump that is 1 inside its bounds (`composer.utils.rewards` owns them; re-exported here),
and per-row reductions a batched reward takes to the bit as a single one does.

    tolerance(x, margin=2.0)                             # 1 at 0, 0.1 at |x| = 2, gaussian
    small_control = Tolerance(margin=1.0, value_at_margin=0.0, sigmoid='quadratic')
    small_control(u)                                     # 0 at |u| >= 1; checked once
    squared_norms(controls)                              # (n,): np.dot(u, u) of each row
    row_means(values), row_norms(vectors)                # (n,): v.mean(), np.linalg.norm(v)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from composer.utils.rewards import SIGMOIDS, ColumnTolerance, Tolerance, tolerance

__all__ = [
    "SIGMOIDS",
    "ColumnTolerance",
    "Tolerance",
    "row_means",
    "row_norms",
    "squared_norms",
    "tolerance",
]


def squared_norms(vectors: np.ndarray) -> Any:
    """The sum of squares of a vector, or of each one along the last axis (shape
    `vectors.shape[:-1]`), to the last bit as `np.dot(v, v)` gives it for each: numpy's
    matmul of two vectors runs the same dot routine, row by row. So a batched reward using
    it equals a single environment's using `np.dot`."""
    vectors = np.asarray(vectors, dtype=np.float64)
    return np.matmul(vectors[..., None, :], vectors[..., :, None])[..., 0, 0]


# numpy's `ndarray.mean(axis=...)` and `linalg.norm(..., axis=...)` are Python functions
# around a ufunc reduction, costing 1 to 1.5 us more than the reduction on a batch of one
# (a step computes a few). These are their reductions, written out as numpy writes them.


def row_means(values: np.ndarray) -> np.ndarray:
    """The mean of each row of `values` (n, k), shape (n,), to the last bit as
    `values.mean(axis=1)` (numpy's: the sum along the row over the count)."""
    count = values.shape[1]
    divisor = _COUNTS.get(count) if values.dtype == np.float64 else count
    if divisor is None:
        divisor = _COUNTS.setdefault(count, np.array(float(count)))
    return np.add.reduce(values, axis=1) / divisor


# Row lengths as 0-d float64 arrays, which numpy divides float64 sums by in half the time a
# Python int takes on small arrays (the same value: counts are far below 2**53; other
# dtypes are divided by the int, which keeps their dtype).
_COUNTS: dict[int, np.ndarray] = {}


def row_norms(vectors: np.ndarray) -> np.ndarray:
    """The Euclidean norm of each row of real `vectors` (n, k), shape (n,), to the last bit
    as `np.linalg.norm(vectors, axis=1)` (numpy's: the root of the row's summed squares)."""
    return np.sqrt(np.add.reduce(vectors * vectors, axis=1))
