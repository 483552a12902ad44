"""The pose of an entity attached without joints, moved in a compiled simulation.

    frame = FixedFrame.of(entity, physics)     # cached per compiled model
    position, quaternion = frame.pose()        # relative to the body it is attached in
    frame.set_pose(position, quaternion)       # moves everything the entity compiled to
    xmat = frame.world_xmat()                  # (3, 3) orientation in the world

dm_control compiles every attachment frame to a body and moves a fixed entity by writing
that body's pos and quat. Here a frame without joints compiles to a MuJoCo `<frame>`,
which leaves nothing in the model: its pose is folded into the poses of what the attached
model puts in the parent body (its top-level bodies, geoms, sites, cameras and lights,
and those of the models attached to its world body without joints). `FixedFrame` keeps
each of those relative to the frame, as compiled, and moving the frame writes their
model poses (through bindings, so MuJoCo's derived constants follow), which is what
dm_control's moved body gives.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

import mjcf
from composer import errors

if TYPE_CHECKING:
    from composer.entity import Entity

_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_POSED = frozenset({"body", "geom", "site", "camera", "light"})


def frame_pose(frame: mjcf.Element) -> tuple[np.ndarray, np.ndarray]:
    """(pos (3,), unit quat (4,)) of an MJCF `<frame>` or attachment frame in its parent,
    from its attributes as its model's compiler reads them (angle units, euler sequence)."""
    position = np.zeros(3) if frame.pos is None else np.asarray(frame.pos, np.float64)
    given = [(name, getattr(frame, name)) for name in _ORIENTATIONS]
    given = [(name, value) for name, value in given if value is not None]
    if not given:
        return position, np.array([1.0, 0, 0, 0])
    name, value = given[0]
    compiler = frame.root.compiler
    angle = compiler.angle or "degree"
    sequence = compiler.eulerseq or "xyz"
    text = " ".join(repr(float(x)) for x in np.ravel(value))
    xml = (
        f'<mujoco><compiler angle="{angle}" eulerseq="{sequence}"/><worldbody>'
        f'<body {name}="{text}"><geom size="1"/></body></worldbody></mujoco>'
    )
    return position, mujoco.MjModel.from_xml_string(xml).body_quat[1].copy()


def _compose(
    pos: np.ndarray, quat: np.ndarray, local_pos: np.ndarray, local_quat: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The pose `local` given in frame (pos, quat), in the frame's parent."""
    out_pos, out_quat = np.empty(3), np.empty(4)
    mujoco.mju_rotVecQuat(out_pos, local_pos, quat)
    mujoco.mju_mulQuat(out_quat, quat, local_quat)
    return pos + out_pos, out_quat


def _inverse(pos: np.ndarray, quat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pose whose composition with (pos, quat) is the identity."""
    inverse_quat, inverse_pos = np.empty(4), np.empty(3)
    mujoco.mju_negQuat(inverse_quat, quat)
    mujoco.mju_rotVecQuat(inverse_pos, -pos, inverse_quat)
    return inverse_pos, inverse_quat


def _top_level(model: mjcf.RootElement) -> list[mjcf.Element]:
    """What `model` puts in the body it is attached in: its world body's children, those
    of `<frame>`s in it, and those of models attached to it through frames without
    joints, recursively; not what lies inside bodies."""
    found: list[mjcf.Element] = []
    pending = list(model.worldbody.all_children())
    while pending:
        element = pending.pop(0)
        if isinstance(element, mjcf.AttachmentFrame):
            if element.compiles_to_body():
                found.append(element)
            else:
                pending.extend(element.attached_model.worldbody.all_children())
        elif element.tag == "frame":
            pending.extend(element.all_children())
        elif element.tag in _POSED:
            found.append(element)
    return found


class FixedFrame:
    """The attachment frame of an entity attached without joints, in one compiled model."""

    def __init__(self, entity: Entity, physics: mjcf.Physics) -> None:
        """Read the frame's pose from the MJCF and its contents' poses from `physics`.
        Raises EntityError for an entity that is not attached."""
        frame = entity.attachment_frame
        if frame is None:
            raise errors.EntityError(
                f"entity {entity.name!r} is not attached: it has no pose to get or set"
            )
        self._frame = frame
        self._model = physics.model
        self._physics = physics
        self._position, self._quaternion = frame_pose(frame)
        inverse = _inverse(self._position, self._quaternion)
        self._parts = []
        for element in _top_level(entity.mjcf_model):
            binding = physics.bind(element)
            if element.tag == "light":
                local_pos = _compose(*inverse, np.array(binding.pos), np.array([1.0, 0, 0, 0]))[0]
                direction = np.empty(3)
                mujoco.mju_rotVecQuat(direction, np.array(binding.dir), inverse[1])
                self._parts.append((binding, True, local_pos, direction))
            else:
                local = _compose(*inverse, np.array(binding.pos), np.array(binding.quat))
                self._parts.append((binding, False, *local))

    @classmethod
    def of(cls, entity: Entity, physics: mjcf.Physics) -> FixedFrame:
        """`entity`'s FixedFrame in `physics`, made once per compiled model."""
        found = entity.__dict__.get("_composer_fixed_frame")
        if found is None or found._model is not physics.model or found._physics is not physics:
            found = entity.__dict__["_composer_fixed_frame"] = cls(entity, physics)
        return found

    def pose(self) -> tuple[np.ndarray, np.ndarray]:
        """(position, quaternion) of the frame in its parent body, copies."""
        return self._position.copy(), self._quaternion.copy()

    def set_pose(self, position: Any = None, quaternion: Any = None) -> None:
        """Move the frame (None keeps a part) and everything it holds."""
        if position is not None:
            self._position = np.array(position, dtype=np.float64).reshape(3)
        if quaternion is not None:
            quaternion = np.array(quaternion, dtype=np.float64).reshape(4)
            self._quaternion = quaternion / np.linalg.norm(quaternion)
        identity = np.array([1.0, 0, 0, 0])
        for binding, is_light, local_pos, local_orientation in self._parts:
            if is_light:  # a direction, not a quaternion
                direction = np.empty(3)
                mujoco.mju_rotVecQuat(direction, local_orientation, self._quaternion)
                binding.pos = _compose(self._position, self._quaternion, local_pos, identity)[0]
                binding.dir = direction
            else:
                binding.pos, binding.quat = _compose(
                    self._position, self._quaternion, local_pos, local_orientation
                )

    def world_xmat(self) -> np.ndarray:
        """The frame's orientation in the world, (3, 3): its parent body's, then its own."""
        parent = self._frame.parent
        if parent is None or parent.tag == "frame":
            raise errors.EntityError(
                f"{self._frame.path}: a frame inside a <frame> has no world orientation here"
            )
        parent_xmat = np.asarray(self._physics.bind(parent).xmat).reshape(3, 3)
        own = np.empty(9)
        mujoco.mju_quat2Mat(own, self._quaternion)
        return parent_xmat @ own.reshape(3, 3)


class BodyFrame:
    """The attachment frame of an entity attached with joints other than a free one: a
    body of the compiled model, whose model pos and quat are its pose (as in dm_control)."""

    def __init__(self, frame: mjcf.Element, physics: mjcf.Physics) -> None:
        """Bind `frame`'s body in `physics`."""
        self._binding = physics.bind(frame)

    def pose(self) -> tuple[np.ndarray, np.ndarray]:
        """(position, quaternion) of the body in its parent, copies."""
        return np.array(self._binding.pos), np.array(self._binding.quat)

    def set_pose(self, position: Any = None, quaternion: Any = None) -> None:
        """Move the body in its parent (None keeps a part); the quaternion is normalized."""
        if position is not None:
            self._binding.pos = position
        if quaternion is not None:
            quaternion = np.asarray(quaternion, dtype=np.float64)
            self._binding.quat = quaternion / np.linalg.norm(quaternion)
