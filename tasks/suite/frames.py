"""World vectors expressed in a body's frame, as the Control Suite computes them, batched.

    xmat = physics.bind(torso).xmat                      # (n, 9)
    offsets = physics.bind(feet).xpos - physics.bind(torso).xpos[:, None]   # (n, k, 3)
    in_frame(offsets, xmat)                              # (n, k, 3): v.dot(R) of each

dm_control writes `vector.dot(xmat.reshape(3, 3))` per vector. numpy's `matmul` (and `dot`
of a stack) reach that product through BLAS, which rounds differently (fused
multiply-adds); the three products summed left to right here round as the 3-vector `dot`
does, so the batched values equal dm_control's to the last bit.
"""

from __future__ import annotations

import numpy as np


def in_frame(vectors: np.ndarray, xmat: np.ndarray) -> np.ndarray:
    """`vectors` (n, k, 3) in the frames whose orientations are `xmat` (n, 9), row-major
    as MuJoCo's: each `vector.dot(R)`, shape (n, k, 3)."""
    frames = np.asarray(xmat).reshape(-1, 1, 3, 3)
    vectors = np.asarray(vectors)
    return (
        vectors[..., 0:1] * frames[..., 0, :]
        + vectors[..., 1:2] * frames[..., 1, :]
        + vectors[..., 2:3] * frames[..., 2, :]
    )
