"""dm_control's accessors on MuJoCo's own MjModel and MjData, which `physics.model` and
`physics.data` are.

    physics.model.ptr is physics.model            # dm_control code passes .ptr to mujoco
    mujoco.mj_step(physics.model.ptr, physics.data.ptr)
    physics.model.name2id("elbow", "joint")       # 3; type names or mujoco.mjtObj values
    physics.model.id2name(3, mujoco.mjtObj.mjOBJ_JOINT)   # 'elbow' ('' when unnamed)

Here they are the raw structs themselves, so field access costs what it costs in mujoco:
importing `mjcf` adds these names to them (`install`), unless mujoco already defines them.
"""

from __future__ import annotations

import mujoco

from mjcf import errors

_TYPE_NAMES = {
    name[len("mjOBJ_") :].lower(): member
    for name, member in mujoco.mjtObj.__members__.items()
    if name.startswith("mjOBJ_")
}


def to_mjtobj(object_type: str | int | mujoco.mjtObj) -> mujoco.mjtObj:
    """`object_type` ('joint', 'body' ..., or a mujoco.mjtObj / int) as a mujoco.mjtObj;
    raises mjcf.NotFoundError for an unknown type."""
    if isinstance(object_type, str):
        found = _TYPE_NAMES.get(object_type.lower().removeprefix("mjobj_"))
        if found is None:
            hint = errors.did_you_mean(object_type.lower(), _TYPE_NAMES)
            raise errors.NotFoundError(
                f"no MuJoCo object type {object_type!r}{hint}; types: {', '.join(_TYPE_NAMES)}"
            )
        return found
    try:
        return mujoco.mjtObj(int(object_type))
    except ValueError:
        raise errors.NotFoundError(f"no MuJoCo object type {object_type!r}") from None


def name2id(model: mujoco.MjModel, name: str, object_type: str | int | mujoco.mjtObj) -> int:
    """The id of the object of `object_type` called `name`; raises mjcf.NotFoundError."""
    kind = to_mjtobj(object_type)
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        raise errors.NotFoundError(
            f"the model has no {kind.name[len('mjOBJ_') :].lower()} named {name!r}"
        )
    return index


def id2name(model: mujoco.MjModel, object_id: int, object_type: str | int | mujoco.mjtObj) -> str:
    """The name of object `object_id` of `object_type`, '' if it has none or does not exist."""
    return mujoco.mj_id2name(model, to_mjtobj(object_type), int(object_id)) or ""


def _ptr(self: object) -> object:
    """The raw struct itself (dm_control's wrappers hold it here)."""
    return self


def install() -> None:
    """Add `ptr`, `name2id`, `id2name` to mujoco.MjModel and `ptr` to mujoco.MjData where
    mujoco does not define them (mujoco's own are left in place).

    dm_control wraps MjModel/MjData in Python objects with a `.ptr` to the raw struct.
    MuJoCo's pybind11 classes cannot be subclassed onto an existing instance (`__class__`
    assignment is refused), and a wrapper would add a Python call to every field read, so
    the names are added to the classes themselves."""
    additions: dict[type, dict[str, object]] = {
        mujoco.MjModel: {"ptr": property(_ptr), "name2id": name2id, "id2name": id2name},
        mujoco.MjData: {"ptr": property(_ptr)},
    }
    for cls, names in additions.items():
        for name, value in names.items():
            if not hasattr(cls, name):
                setattr(cls, name, value)
