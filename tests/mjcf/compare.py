"""Comparing compiled models: equal sizes, equal numeric arrays, equal trajectories."""

from __future__ import annotations

import mujoco
import numpy as np

# Fields that hold where files were found, not what the model is.
_PATH_FIELDS = frozenset({"paths", "name_pathadr", "npaths", "nbuffer"})


def model_differences(a: mujoco.MjModel, b: mujoco.MjModel, rtol: float = 1e-9) -> list[str]:
    """Every size and array of MjModel that differs between `a` and `b`."""
    differences = []
    for name in dir(a):
        if name.startswith("_") or name in _PATH_FIELDS or name.endswith("_pathadr"):
            continue
        try:
            first = getattr(a, name)
        except Exception:
            continue
        if callable(first):
            continue
        second = getattr(b, name)
        if isinstance(first, int | float | np.integer) and not isinstance(first, bool):
            if first != second:
                differences.append(f"{name}: {first} != {second}")
        elif isinstance(first, np.ndarray):
            if first.shape != second.shape:
                differences.append(f"{name}: shape {first.shape} != {second.shape}")
            elif first.dtype.kind in "fc":
                if not np.allclose(first, second, rtol=rtol, atol=1e-12, equal_nan=True):
                    differences.append(f"{name}: values differ")
            elif not np.array_equal(first, second):
                differences.append(f"{name}: values differ")
    return differences


def trajectories_match(a: mujoco.MjModel, b: mujoco.MjModel, steps: int = 100) -> bool:
    """Whether both models, stepped with the same controls, reach the same qpos."""
    data_a, data_b = mujoco.MjData(a), mujoco.MjData(b)
    rng = np.random.default_rng(0)
    for _ in range(steps):
        controls = rng.uniform(-1, 1, size=a.nu)
        data_a.ctrl[:] = controls
        data_b.ctrl[:] = controls
        mujoco.mj_step(a, data_a)
        mujoco.mj_step(b, data_b)
    return bool(np.allclose(data_a.qpos, data_b.qpos, rtol=1e-9, atol=1e-12))
