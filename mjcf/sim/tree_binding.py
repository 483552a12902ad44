"""From model elements to compiled objects: which kind and index an element has in a
compiled model, and carrying simulation state over to a recompiled model.

Used by `Physics.bind(element)` and `Physics.reload_from_mjcf_model(model)`; elements
map to objects by their compiled index (`compiler.Compiled.id_of`), or by their full
identifiers on a physics not compiled from their model, once per element list, so a bound
read afterwards costs one numpy index.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

from mjcf import errors
from mjcf.compose import attachment, naming
from mjcf.compose.keyframes import joint_widths
from mjcf.sim import fields

if TYPE_CHECKING:
    from mjcf.sim.compiler import Compiled
    from mjcf.tree.element import Element


def kind_of(element: Element) -> mujoco.mjtObj:
    """The MuJoCo object kind of `element`; raises mjcf.BindingError for elements that
    compile to no object (defaults, frames, sections ...)."""
    if element.tag == "worldbody":
        return mujoco.mjtObj.mjOBJ_BODY
    if isinstance(element, attachment.AttachmentFrame):
        if element.compiles_to_body():
            return mujoco.mjtObj.mjOBJ_BODY
        raise errors.BindingError(
            f"{element.path}: this attachment frame has no joints, so it compiles to a MuJoCo "
            "<frame>, which leaves nothing in the compiled model to bind; bind the attached "
            "model's bodies instead"
        )
    namespace = element.spec.namespace
    kind = getattr(mujoco.mjtObj, f"mjOBJ_{(namespace or '').upper()}", None)
    if kind is None or kind not in fields.KINDS:
        raise errors.BindingError(
            f"{element.path}: a <{element.tag}> is not an object of the compiled model, so it "
            "cannot be bound"
        )
    return kind


def element_ids(
    compiled: Compiled | None, model: mujoco.MjModel, elements: list[Element]
) -> tuple[mujoco.mjtObj, np.ndarray]:
    """The kind and compiled ids of `elements` (all of one kind, at least one).

    Elements of the model `compiled` was compiled from are found by their compiled index
    (unnamed ones too); others (or all, when `compiled` is None: a physics made from XML or
    an MjModel) by their full identifier, as dm_control binds. Raises mjcf.BindingError for
    mixed kinds, or an element the compiled model does not have, naming it."""
    kinds = {kind_of(element) for element in elements}
    if len(kinds) > 1:
        names = sorted(fields.kind_name(k) for k in kinds)
        raise errors.BindingError(
            "Cannot bind to a collection containing multiple element types: elements of "
            f"different kinds cannot be bound together: {names}"
        )
    kind = kinds.pop()
    ids = np.empty(len(elements), dtype=np.intp)
    for i, element in enumerate(elements):
        if compiled is not None and _compiled_from(compiled, element):
            index = compiled.id_of(element, kind)
            if index < 0:
                raise errors.BindingError(
                    f"{element.path}: not in the compiled model (was it added after compiling? "
                    "recompile with Physics.from_mjcf_model or physics.reload_from_mjcf_model)"
                )
            ids[i] = index
        else:
            ids[i] = _id_by_name(model, kind, element)
    return kind, ids


def _compiled_from(compiled: Compiled, element: Element) -> bool:
    """Whether `element`'s model is part of the composition `compiled` was compiled from."""
    try:
        compiled.composition.context(element.root)
    except errors.InvalidReferenceError:
        return False
    return True


def _id_by_name(model: mujoco.MjModel, kind: mujoco.mjtObj, element: Element) -> int:
    """The id of the object of `kind` named as `element` is in its outermost model."""
    name = element.full_identifier
    if name is None and isinstance(element, attachment.AttachmentFrame):
        name = element.attached_model.namescope.prefix()  # the frame body: 'arm/'
    kind_name = fields.kind_name(kind)
    if name is None:
        raise errors.BindingError(
            f"{element.path}: this physics was not compiled from this element's model, so "
            f"elements are found by name, and this {kind_name} has none; name it, or bind "
            "on a physics made with Physics.from_mjcf_model(model)"
        )
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        raise errors.BindingError(
            f"{element.path}: the physics' model has no {kind_name} named {name!r} (this "
            "physics was not compiled from this element's model, so elements are found by "
            "their full identifiers)"
        )
    return index


def write_refusal(compiled: Compiled, elements: list[Element]) -> str | None:
    """Why bindings of `elements` may not be written: one of them is a mesh or texture
    compiled once for several copies of a model (`mjcf.compose.sharing`), which a write would
    change for all of them; None if none is.

    Binding a copy's mesh or texture (`physics.bind(arm_7_mesh)`) reaches the one asset all
    the copies compile to: it reads as ever, but a write through it is refused, through any
    copy, the first too. To write one copy's asset at run time, compile without sharing:
    `mjcf.Physics.from_mjcf_model(scene, share_assets=False)` (or
    `physics.reload_from_mjcf_model(scene, share_assets=False)`), which compiles every copy's
    meshes and textures apart, at the cost of the memory sharing saves. Named access
    (`physics.named.model.mesh_scale['arm/base']`) and `physics.model` address the compiled
    asset itself, by the first copy's name, as MuJoCo's own API does: what they write is
    what every copy compiled to."""
    for element in elements:
        sharers = compiled.sharers(element)
        if len(sharers) > 1:
            names = ", ".join(repr(e.full_identifier) for e in sharers[1:4])
            more = f" and {len(sharers) - 4} more" if len(sharers) > 4 else ""
            return (
                f"{element.path} is compiled once for {len(sharers)} copies of it (shared "
                f"with {names}{more}, see mjcf/compose/sharing.py), so a write through it would "
                "change them all: read it freely, or compile with Physics.from_mjcf_model(model, "
                "share_assets=False) to give each copy its own"
            )
    return None


def transfer_state(
    old_model: mujoco.MjModel,
    old_data: mujoco.MjData,
    new_model: mujoco.MjModel,
    new_data: mujoco.MjData,
    unnamed: dict[tuple[int, int], int] | None = None,
) -> None:
    """Copy time and the state of every joint, actuator and mocap body that exists in
    both models (matched by name, or for those with generated names by `unnamed`:
    {(kind, new id): old id}, see `compiler.unnamed_pairs`) from the old simulation to
    the new one."""
    new_data.time = old_data.time
    pairs = unnamed or {}
    joint = mujoco.mjtObj.mjOBJ_JOINT
    for new_id in range(new_model.njnt):
        old_id = _same_name(old_model, new_model, joint, new_id, pairs)
        if old_id < 0 or old_model.jnt_type[old_id] != new_model.jnt_type[new_id]:
            continue
        width_q, width_v = joint_widths(int(new_model.jnt_type[new_id]))
        new_q, old_q = new_model.jnt_qposadr[new_id], old_model.jnt_qposadr[old_id]
        new_data.qpos[new_q : new_q + width_q] = old_data.qpos[old_q : old_q + width_q]
        new_v, old_v = new_model.jnt_dofadr[new_id], old_model.jnt_dofadr[old_id]
        new_data.qvel[new_v : new_v + width_v] = old_data.qvel[old_v : old_v + width_v]
    actuator = mujoco.mjtObj.mjOBJ_ACTUATOR
    for new_id in range(new_model.nu):
        old_id = _same_name(old_model, new_model, actuator, new_id, pairs)
        if old_id < 0:
            continue
        new_data.ctrl[new_id] = old_data.ctrl[old_id]
        count = new_model.actuator_actnum[new_id]
        if count and count == old_model.actuator_actnum[old_id]:
            new_a, old_a = new_model.actuator_actadr[new_id], old_model.actuator_actadr[old_id]
            new_data.act[new_a : new_a + count] = old_data.act[old_a : old_a + count]
    body = mujoco.mjtObj.mjOBJ_BODY
    for new_body in np.flatnonzero(new_model.body_mocapid >= 0):
        old_id = _same_name(old_model, new_model, body, int(new_body), pairs)
        if old_id >= 0 and old_model.body_mocapid[old_id] >= 0:
            new_m, old_m = new_model.body_mocapid[new_body], old_model.body_mocapid[old_id]
            new_data.mocap_pos[new_m] = old_data.mocap_pos[old_m]
            new_data.mocap_quat[new_m] = old_data.mocap_quat[old_m]


def _same_name(
    old_model: mujoco.MjModel,
    new_model: mujoco.MjModel,
    kind: mujoco.mjtObj,
    new_id: int,
    unnamed: dict[tuple[int, int], int],
) -> int:
    paired = unnamed.get((int(kind), new_id))
    if paired is not None:  # a generated name, which can shift: matched by element
        return paired
    name = mujoco.mj_id2name(new_model, kind, new_id)
    if not name or naming.GENERATED.search(name):
        return -1
    return mujoco.mj_name2id(old_model, kind, name)
