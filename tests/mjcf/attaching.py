"""Helpers of the attachment tests: what a model's compiled values are, and which of them
an attachment changed."""

from __future__ import annotations

import mujoco
import numpy as np

from mjcf.sim import fields

Obj = mujoco.mjtObj
_KINDS = (Obj.mjOBJ_BODY, Obj.mjOBJ_JOINT, Obj.mjOBJ_GEOM, Obj.mjOBJ_SITE, Obj.mjOBJ_ACTUATOR)
# Where a model is put: its top-level bodies, and its world body's geoms and sites.
_PLACEMENT = frozenset({"body_pos", "body_quat", "geom_pos", "geom_quat", "site_pos", "site_quat"})


def element_values(model: mujoco.MjModel, kind: Obj, name: str) -> dict[str, np.ndarray]:
    """The float MjModel rows of one named object."""
    index = mujoco.mj_name2id(model, kind, name)
    assert index >= 0, f"{name!r} is not in the model"
    rows = {}
    for field in set(fields.kind_fields(kind).values()):
        if field.struct == "model" and field.address is None:
            values = getattr(model, field.name)
            if values.dtype.kind == "f":
                rows[field.name] = values[index]
    return rows


def differences_from_alone(
    alone: mujoco.MjModel, composed: mujoco.MjModel, prefix: str, placed: set[str] = frozenset()
) -> list[str]:
    """Every compiled value of a named body, joint, geom, site or actuator of `alone`
    that differs in `composed`, where its names start with `prefix` (the placement of
    the bodies in `placed` and of the world body's geoms and sites is left out)."""
    found = []
    static = {Obj.mjOBJ_GEOM: alone.geom_bodyid, Obj.mjOBJ_SITE: alone.site_bodyid}
    for kind in _KINDS:
        for index in range(fields.count(alone, kind)):
            name = mujoco.mj_id2name(alone, kind, index)
            if not name or name == "world":
                continue
            mine = element_values(alone, kind, name)
            # A generated '//unnamed_geom_0' is 'prefix//unnamed_geom_0' when attached.
            scoped = prefix + name[1:] if name.startswith("//") else prefix + name
            theirs = element_values(composed, kind, scoped)
            is_placed = name in placed or (kind in static and static[kind][index] == 0)
            for field, value in mine.items():
                if is_placed and field in _PLACEMENT:
                    continue
                if not np.allclose(value, theirs[field], rtol=1e-9, atol=1e-12):
                    found.append(f"{prefix}{name} {field}: {value} != {theirs[field]}")
    return found


def top_bodies(model: mujoco.MjModel) -> set[str]:
    """The names of the bodies whose parent is the world body."""
    return {
        mujoco.mj_id2name(model, Obj.mjOBJ_BODY, b)
        for b in range(1, model.nbody)
        if model.body_parentid[b] == 0
    }
