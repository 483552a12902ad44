"""Comparing compiled models: equal sizes, equal numeric arrays, equal trajectories."""

from __future__ import annotations

import mujoco
import numpy as np

from mjcf.compose.naming import GENERATED

# Fields that hold where files were found, not what the model is.
_PATH_FIELDS = frozenset({"paths", "name_pathadr", "npaths", "nbuffer"})
# Fields that hold names: compared object by object (see `_name_differences`).
_NAME_FIELDS = frozenset({"names", "nnames", "names_map", "nnames_map"})


def model_differences(a: mujoco.MjModel, b: mujoco.MjModel, rtol: float = 1e-9) -> list[str]:
    """Every size and array of MjModel that differs between `a` (compiled by stock
    MuJoCo from a file) and `b`, and every object whose name differs; an object `a` has
    unnamed may carry a generated name ('//unnamed_geom_0') in `b`."""
    differences = _name_differences(a, b)
    for name in dir(a):
        if (
            name.startswith("_")
            or name in _PATH_FIELDS
            or name in _NAME_FIELDS
            or name.endswith("_pathadr")
            or name.startswith("name_")
        ):
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


def _name_differences(a: mujoco.MjModel, b: mujoco.MjModel) -> list[str]:
    differences = []
    for kind, field in _COUNTS.items():
        count_a = int(getattr(a, field))
        if count_a != int(getattr(b, field)):
            continue  # the sizes differ: reported with the arrays
        for index in range(count_a):
            name_a = mujoco.mj_id2name(a, kind, index) or ""
            name_b = mujoco.mj_id2name(b, kind, index) or ""
            if name_a == name_b or (not name_a and GENERATED.fullmatch(name_b)):
                continue
            differences.append(f"{kind.name} {index}: name {name_a!r} != {name_b!r}")
    return differences


_COUNTS = {
    mujoco.mjtObj.mjOBJ_BODY: "nbody", mujoco.mjtObj.mjOBJ_JOINT: "njnt",
    mujoco.mjtObj.mjOBJ_GEOM: "ngeom", mujoco.mjtObj.mjOBJ_SITE: "nsite",
    mujoco.mjtObj.mjOBJ_CAMERA: "ncam", mujoco.mjtObj.mjOBJ_LIGHT: "nlight",
    mujoco.mjtObj.mjOBJ_FLEX: "nflex", mujoco.mjtObj.mjOBJ_MESH: "nmesh",
    mujoco.mjtObj.mjOBJ_SKIN: "nskin", mujoco.mjtObj.mjOBJ_HFIELD: "nhfield",
    mujoco.mjtObj.mjOBJ_TEXTURE: "ntex", mujoco.mjtObj.mjOBJ_MATERIAL: "nmat",
    mujoco.mjtObj.mjOBJ_PAIR: "npair", mujoco.mjtObj.mjOBJ_EXCLUDE: "nexclude",
    mujoco.mjtObj.mjOBJ_EQUALITY: "neq", mujoco.mjtObj.mjOBJ_TENDON: "ntendon",
    mujoco.mjtObj.mjOBJ_ACTUATOR: "nu", mujoco.mjtObj.mjOBJ_SENSOR: "nsensor",
    mujoco.mjtObj.mjOBJ_NUMERIC: "nnumeric", mujoco.mjtObj.mjOBJ_TEXT: "ntext",
    mujoco.mjtObj.mjOBJ_TUPLE: "ntuple", mujoco.mjtObj.mjOBJ_KEY: "nkey",
    mujoco.mjtObj.mjOBJ_PLUGIN: "nplugin",
}  # fmt: skip


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
