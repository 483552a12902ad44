"""Reward shaping for the shipped tasks: `tolerance` and `Tolerance`, dm_control's smooth
1-inside, falling-outside bump (`composer.utils.rewards` owns them; re-exported here), and
`squared_norms`, sums of squares a batched reward takes as a single one does.

    tolerance(0.3, bounds=(0, 0.5))                      # 1.0: inside the bounds
    tolerance(x, margin=2.0)                             # 1 at 0, 0.1 at |x| = 2, gaussian
    tolerance(u, margin=1.0, value_at_margin=0.0, sigmoid='quadratic')   # 0 at |u| >= 1
    small_control = Tolerance(margin=1.0, value_at_margin=0.0, sigmoid='quadratic')
    small_control(u)                                     # the same, checked once
    squared_norms(controls)                              # (n,): np.dot(u, u) of each row
"""

from __future__ import annotations

from typing import Any

import numpy as np

from composer.utils.rewards import SIGMOIDS, Tolerance, tolerance

__all__ = ["SIGMOIDS", "Tolerance", "squared_norms", "tolerance"]


def squared_norms(vectors: np.ndarray) -> Any:
    """The sum of squares of a vector, or of each one along the last axis (shape
    `vectors.shape[:-1]`), to the last bit as `np.dot(v, v)` gives it for each: numpy's
    matmul of two vectors runs the same dot routine, row by row. So a batched reward using
    it equals a single environment's using `np.dot`."""
    vectors = np.asarray(vectors, dtype=np.float64)
    return np.matmul(vectors[..., None, :], vectors[..., :, None])[..., 0, 0]
