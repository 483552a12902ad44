"""Keyframes of composed models: every key keeps its scoped name and its values.

    scene.attach(arm)                 # arm has <key name="home" qpos="...">
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.reset(keyframe='arm/home')

A key's vectors (qpos, qvel, act, ctrl, mpos, mquat) are laid out for its model's own
joints, actuators and mocap bodies, or for its model with all attached inside it (their
length tells). Composed, they move to where its model's entries land; every other entry
keeps the composed model's default (qpos0, zeros, mocap poses), as MuJoCo's attach does.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

import mujoco
import numpy as np

from mjcf import errors
from mjcf.compose import attachment
from mjcf.schema.values import format_number
from mjcf.tree import above
from mjcf.tree.element import stored_attributes, tree_children, value_of

if TYPE_CHECKING:
    from collections.abc import Callable

    from mjcf.compose.composition import Composition, ModelContext
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

_VECTORS = ("qpos", "qvel", "act", "ctrl", "mpos", "mquat")


def _all_keys(composition: Composition) -> list[tuple[Element, ModelContext]]:
    """Every key of the output with its model's context, in writing order."""
    contexts = [composition.context(composition.root), *composition.attached_contexts()]
    return [(key, context) for context in contexts for key in tree_children(context.model.keyframe)]


def keys_to_write(
    composition: Composition, for_compile: bool
) -> list[tuple[Element, ModelContext, dict | None]]:
    """(key, context, attribute override) for every key of the output. A model without
    attachments writes its keys as they are. With attachments, keys are written with their
    name and time only when compiling (their vectors are filled into the compiled model by
    `fill`), and with vectors laid out for the composed model otherwise."""
    keys = _all_keys(composition)
    if not composition.has_attachments or not keys:
        return [(key, context, None) for key, context in keys]
    padded = None if for_compile else _padded_vectors(composition)
    out: list[tuple[Element, ModelContext, dict | None]] = []
    for key, context in keys:
        override = context.rewrite(key) or {}
        override.update(dict.fromkeys(_VECTORS) if padded is None else padded[id(key)])
        out.append((key, context, override))
    return out


def fill(model: mujoco.MjModel, composition: Composition, compiled_id: Callable) -> None:
    """Write the key vectors of a composed model into the compiled `model`, whose keys
    hold defaults; raises mjcf.AttributeValueError for a vector that fits neither its
    model's own layout nor its layout with attachments."""
    if not composition.has_attachments:
        return
    layouts: dict[int, tuple[dict, dict]] = {}
    for index, (key, context) in enumerate(_all_keys(composition)):
        owner = context.model
        if id(owner) not in layouts:
            layouts[id(owner)] = (
                _layout(model, owner, compiled_id, with_attached=False),
                _layout(model, owner, compiled_id, with_attached=True),
            )
        _fill_key(model, key, index, owner, layouts[id(owner)])


def _fill_key(
    model: mujoco.MjModel, key: Element, index: int, owner: RootElement, layouts: tuple[dict, dict]
) -> None:
    targets = {
        "qpos": model.key_qpos, "qvel": model.key_qvel, "act": model.key_act,
        "ctrl": model.key_ctrl, "mpos": model.key_mpos, "mquat": model.key_mquat,
    }  # fmt: skip
    own, full = layouts
    for name in _VECTORS:
        if name not in stored_attributes(key):
            continue
        values = np.atleast_1d(np.asarray(value_of(key, key.spec.attributes[name]), dtype=float))
        if values.size == own[name].size:
            destination = own[name]
        elif values.size == full[name].size:
            destination = full[name]
        else:
            sizes = sorted({own[name].size, full[name].size})
            raise errors.AttributeValueError(
                f"{key.path}: {name!r} has {values.size} numbers, but model {owner.model!r} "
                f"has {' or '.join(map(str, sizes))} (without or with its attached models)"
            )
        targets[name][index][destination] = values


def _layout(
    model: mujoco.MjModel, owner: RootElement, compiled_id: Callable, with_attached: bool
) -> dict[str, np.ndarray]:
    """Indices into the composed model's vectors of `owner`'s entries, in `owner`'s own
    order."""
    qpos: list[int] = []
    qvel: list[int] = []
    for joint in _ordered_joints(owner, with_attached):
        index = _id(compiled_id, joint, mujoco.mjtObj.mjOBJ_JOINT)
        width_q, width_v = joint_widths(int(model.jnt_type[index]))
        qpos.extend(range(model.jnt_qposadr[index], model.jnt_qposadr[index] + width_q))
        qvel.extend(range(model.jnt_dofadr[index], model.jnt_dofadr[index] + width_v))
    ctrl: list[int] = []
    act: list[int] = []
    for actuator in owner.find_all("actuator", exclude_attachments=not with_attached):
        index = _id(compiled_id, actuator, mujoco.mjtObj.mjOBJ_ACTUATOR)
        ctrl.append(index)
        start = model.actuator_actadr[index]
        if start >= 0:
            act.extend(range(start, start + model.actuator_actnum[index]))
    mpos: list[int] = []
    mquat: list[int] = []
    for body in owner.find_all("body", exclude_attachments=not with_attached):
        mocap = model.body_mocapid[_id(compiled_id, body, mujoco.mjtObj.mjOBJ_BODY)]
        if mocap >= 0:
            mpos.extend(range(3 * mocap, 3 * mocap + 3))
            mquat.extend(range(4 * mocap, 4 * mocap + 4))
    lists = {"qpos": qpos, "qvel": qvel, "ctrl": ctrl, "act": act, "mpos": mpos, "mquat": mquat}
    return {name: np.asarray(values, dtype=int) for name, values in lists.items()}


def _ordered_joints(owner: RootElement, with_attached: bool) -> list[Element]:
    """`owner`'s joints in MuJoCo's order: by body, bodies depth first, each body's
    joints in document order."""
    joints: list[Element] = []
    for body in _bodies_in_order(owner.worldbody, with_attached):
        joints.extend(_own_joints(body))
    return joints


def _bodies_in_order(start: Element, with_attached: bool) -> list[Element]:
    """Bodies below `start`, depth first; with the attached models' (and the attachment
    frames written as bodies, whose joints exist only once a model is attached)."""
    found = []
    stack = list(reversed(_kinematic_children(start, with_attached)))
    while stack:
        element = stack.pop()
        if element.spec.tag == "body" or (
            isinstance(element, attachment.AttachmentFrame) and element.compiles_to_body()
        ):
            found.append(element)
        stack.extend(reversed(_kinematic_children(element, with_attached)))
    return found


def _kinematic_children(element: Element, with_attached: bool) -> list[Element]:
    children = [
        c for c in tree_children(element)
        if (c.spec.tag in ("body", "frame") and not isinstance(c, attachment.AttachmentFrame))
        or (with_attached and isinstance(c, attachment.AttachmentFrame))
    ]  # fmt: skip
    if with_attached and isinstance(element, attachment.AttachmentFrame):
        children += [
            c for c in tree_children(element.attached_model.worldbody)
            if c.spec.tag in ("body", "frame") or isinstance(c, attachment.AttachmentFrame)
        ]  # fmt: skip
    return children


def _own_joints(body: Element) -> list[Element]:
    """A body's joints: its own, and those of the plain frames it contains."""
    joints = []
    for child in tree_children(body):
        if child.spec.namespace == "joint":
            joints.append(child)
        elif child.spec.tag == "frame" and not isinstance(child, attachment.AttachmentFrame):
            joints.extend(_own_joints(child))
    return joints


def _id(compiled_id: Callable, element: Element, kind: mujoco.mjtObj) -> int:
    index = compiled_id(element, kind)
    if index < 0:
        raise errors.InvalidReferenceError(f"{element.path} is not in the compiled model")
    return index


_padded: dict[bytes, list[dict[str, str | None]]] = {}


def _padded_vectors(composition: Composition) -> dict[int, dict[str, str | None]]:
    """Full-length key vectors of every key of a composed model, computed by compiling
    it, once for each composed model and key values (writing the same model again
    does not compile it again)."""
    keys = _all_keys(composition)
    digest = hashlib.sha1(above.serialize_for_compile(composition.root)[0].encode())
    for key, _ in keys:
        for name in _VECTORS:
            if name in stored_attributes(key):
                text = key.get_attribute_xml_string(name)
                digest.update(f"{name}={text};".encode())
        digest.update(b"|")
    rows = _padded.get(digest.digest())
    if rows is None:
        model = above.compile_composition(composition.root).model
        sources = {
            "qpos": model.key_qpos, "qvel": model.key_qvel, "act": model.key_act,
            "ctrl": model.key_ctrl, "mpos": model.key_mpos, "mquat": model.key_mquat,
        }  # fmt: skip
        rows = [
            {
                name: " ".join(format_number(v) for v in source[index].tolist()) or None
                for name, source in sources.items()
            }
            for index in range(len(keys))
        ]
        if len(_padded) >= 32:
            _padded.clear()
        _padded[digest.digest()] = rows
    return {id(key): rows[index] for index, (key, _) in enumerate(keys)}


def joint_widths(joint_type: int) -> tuple[int, int]:
    """(qpos, qvel) entries of a joint of MuJoCo type `joint_type`."""
    if joint_type == mujoco.mjtJoint.mjJNT_FREE:
        return 7, 6
    if joint_type == mujoco.mjtJoint.mjJNT_BALL:
        return 4, 3
    return 1, 1
