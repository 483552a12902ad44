"""The current poses of a compiled model's `<frame>`s, and moving a frame with all it holds.

    poses = frame_poses.of(physics)                  # one per physics and compiled model
    pos, quat = poses.offset(compiled, chain)         # a frame's pose in the body it is in
    held = frame_poses.Contents(physics, compiled, line, holder_line)
    poses.move(compiled, chain, held, pos, quat, undo)   # moves the frame and all it holds

MuJoCo leaves nothing of a `<frame>` in the compiled model, only the poses of its contents.
A frame's pose is read from the compiled text until it is moved (`FramePoses`); moving it
moves everything compiled from inside it, as compiling the moved frame would (`Contents`).
"""

from __future__ import annotations

import copy
import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from lxml import etree

from mjcf import errors

if TYPE_CHECKING:
    from mjcf.sim.compiler import Compiled
    from mjcf.sim.physics import Physics
    from mjcf.tree.element import Element

Pose = tuple[np.ndarray, np.ndarray]  # (pos (3,), unit quat (4,))
Undo = list[Callable[[], None]]

_ORIENTATIONS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
_START_TAG = re.compile(r"\s*<(\w+)([^>]*?)(/?)>\s*")
_END_TAG = re.compile(r"\s*</\w+>\s*")
# Tags compiled to objects with a pose in their body, and the field that turns with it.
_POSED = {"body": "quat", "geom": "quat", "site": "quat", "camera": "quat",
          "light": "dir", "joint": "axis"}  # fmt: skip
_UNBOUND = ("replicate", "attach", "flexcomp")  # compile to objects no element names
_FREE = int(mujoco.mjtJoint.mjJNT_FREE)


def of(physics: Physics) -> FramePoses:
    """The frame poses of `physics`' current model, made when first needed."""
    poses = physics._frame_poses
    if poses is None or poses.model is not physics.model:
        poses = physics._frame_poses = FramePoses(physics.model)
    return poses


class FramePoses:
    """The current pose of each compiled frame of one MjModel in its parent. `version`
    counts the moves, for caches of derived poses.

    MuJoCo folds a `<frame>` into what it holds when it compiles: nothing of the frame is
    left in the model, only the poses of its contents in the body it is in. A frame's pose
    in its parent (the frame or body it is in) is read from the compiled text (the frame's
    start tag, with the compiled model's angle units and euler sequence) until it is moved;
    then it is the moved one. Frames are named by the line of the compiled text their start
    tag is on (`Compiled.lines`), so a pose belongs to what was compiled, whatever the tree
    has become since.

    The store belongs to one MjModel: a physics holds it as `Physics._frame_poses`, and
    makes a new one (from the text) when it holds another model; copies of a physics
    sharing its MjModel share it, other copies and unpickled physics get their own copy."""

    __slots__ = ("_local", "_text", "model", "version")

    def __init__(self, model: mujoco.MjModel, local: dict[int, Pose] | None = None) -> None:
        """The poses of `model`'s frames: as compiled, but for those in `local`
        ({compiled line: pose in its parent})."""
        self.model = model
        self.version = 0
        self._local: dict[int, Pose] = dict(local or {})
        self._text: tuple[str, list[str], dict[int, int]] | None = None

    def __reduce__(self) -> tuple[Any, ...]:
        return FramePoses, (self.model, self._local)

    def __deepcopy__(self, memo: dict[int, Any]) -> FramePoses:
        # A copy of a physics that shares the model shares its frames' poses with it.
        model = memo.get(id(self.model))
        if model is self.model:
            return self
        if model is None:
            model = copy.deepcopy(self.model, memo)
        local = {line: (pos.copy(), quat.copy()) for line, (pos, quat) in self._local.items()}
        return FramePoses(model, local)

    def lines(self, compiled: Compiled) -> tuple[list[str], dict[int, int]]:
        """The compiled text's lines, and {id of an element: the line of its start tag}."""
        if self._text is None or self._text[0] is not compiled.xml:
            line_of = {id(e): n for n, e in enumerate(compiled.lines) if e is not None}
            self._text = (compiled.xml, compiled.xml.splitlines(), line_of)
        return self._text[1], self._text[2]

    def line(self, compiled: Compiled, element: Element) -> int:
        """The line of `element`'s start tag in the compiled text; raises BindingError for
        an element that was not compiled."""
        line = self.lines(compiled)[1].get(id(element))
        if line is None:
            raise errors.BindingError(
                f"{element.path}: was added after the model was compiled; compile it again"
            )
        return line

    def local(self, compiled: Compiled, line: int) -> Pose:
        """The current pose of the frame on `line` in its parent."""
        pose = self._local.get(line)
        if pose is None:
            pose = self._local[line] = _compiled_pose(compiled, self.lines(compiled)[0][line])
        return pose

    def offset(self, compiled: Compiled, chain: list[int]) -> Pose:
        """The pose, in the body they are in, of the innermost of the nested frames on
        the lines of `chain` (outermost first)."""
        pos, quat = self.local(compiled, chain[0])
        for line in chain[1:]:
            pos, quat = compose((pos, quat), self.local(compiled, line))
        return pos, quat

    def move(
        self,
        compiled: Compiled,
        chain: list[int],
        held: Contents,
        pos: np.ndarray | None,
        quat: np.ndarray | None,
        undo: Undo,
    ) -> None:
        """Give the innermost frame of `chain` (see `offset`) the position `pos` and/or
        unit quaternion `quat` in its body (None keeps one), moving what it holds, `held`,
        with it. Appends to `undo` what restores everything. Raises BindingError."""
        old = self.offset(compiled, chain)
        new = (old[0] if pos is None else pos, old[1] if quat is None else quat)
        line = chain[-1]
        local = new
        if len(chain) > 1:
            local = compose(inverse(self.offset(compiled, chain[:-1])), new)
        held.move(compose(new, inverse(old)), undo)
        previous = self._local[line]

        def restore() -> None:
            self._local[line] = previous
            self.version += 1

        undo.append(restore)
        self._local[line] = (local[0].copy(), local[1].copy())
        self.version += 1


class Contents:
    """What the frame on one line of the compiled text holds, bound in one physics.

    Moving a frame applies one rigid transform, in the body it is in, to the model pose of
    everything compiled from inside it: its top-level bodies, geoms, sites, cameras, lights
    and joints, those of the frames nested in it (attached models' world bodies included),
    and the inertial frame of its body when an `<inertial>` is in it; what is inside a body
    moves with that body. Free bodies and mocap bodies move too: their state (the free
    joint's qpos, its qpos0 and spring reference, its linear velocity turned with it; the
    mocap pose) goes where compiling the moved frame would put it. Writes go through
    bindings, so `mj_setConst` and the dirty tracking follow as for any model write."""

    def __init__(self, physics: Physics, compiled: Compiled, line: int, holder: int | None) -> None:
        """Find it in the text (`holder`: the line of the body the frame is in, None for
        the world body). Raises BindingError for elements removed since the compile."""
        text = of(physics).lines(compiled)[0]
        frame = compiled.lines[line]
        assert frame is not None, "a frame's line holds its start tag"
        parts, joints, inertial, refusal = _scan(compiled, text, line)
        self._refusal = refusal
        self._posed = [
            (physics.bind(tuple(elements)), _POSED[tag]) for tag, elements in parts.items()
        ]
        self._inertial = self._free = self._mocap = None
        if holder is not None:
            body = compiled.lines[holder]
            assert body is not None, "a body's line holds its start tag"
            setting = compiled.composition.merged_settings("compiler").attributes
            from_geoms = str(setting.get("inertiafromgeom", "auto")).lower()
            own_inertial = _scan(compiled, text, holder)[2]
            geoms_weigh = from_geoms == "true" or (from_geoms == "auto" and not own_inertial)
            if parts.get("geom") and geoms_weigh:
                self._refusal = self._refusal or (
                    f"it holds geoms whose mass makes part of the inertia of {body.path}, which "
                    "MuJoCo computes when compiling: give those geoms a body of their own or "
                    "the body an <inertial>, or move the frame in the model and compile again"
                )
            if inertial and from_geoms != "true":
                self._inertial = physics.bind(body)
        if joints:
            bound = physics.bind(tuple(joints))
            kinds = np.atleast_1d(bound.type)
            free = [joint for joint, kind in zip(joints, kinds, strict=True) if kind == _FREE]
            if free and holder is not None:
                self._refusal = self._refusal or (
                    f"it holds a free body ({free[0].path}) inside a body: its position is "
                    "in the world, not in that body"
                )
            self._free = physics.bind(tuple(free)) if free else None
        bodies = parts.get("body", [])
        if bodies and holder is None:
            ids = np.atleast_1d(physics.bind(tuple(bodies)).mocapid)
            mocap = [body for body, i in zip(bodies, ids, strict=True) if i >= 0]
            self._mocap = physics.bind(tuple(mocap)) if mocap else None
        if self._refusal is not None:
            self._refusal = f"{frame.path} cannot be moved: {self._refusal}"

    def check(self) -> None:
        """Raise BindingError, before anything changes, if this frame cannot be moved: it
        holds a `<replicate>`, `<attach>` or `<flexcomp>` (their objects have no element to
        bind), geoms whose mass makes part of the inertia of a body other than the world
        (MuJoCo computes it when compiling), or a free body inside a body."""
        if self._refusal is not None:
            raise errors.BindingError(self._refusal)

    def move(self, transform: Pose, undo: Undo) -> None:
        """Apply the rigid `transform` (in the body the frame is in) to all of it; append
        to `undo` what restores each field written."""
        self.check()
        shift, turn = transform
        rotation = matrix(turn)
        for binding, orientation in self._posed:
            _write(binding, "pos", np.asarray(binding.pos) @ rotation.T + shift, undo)
            turned = np.asarray(getattr(binding, orientation))
            if orientation == "quat":
                _write(binding, "quat", multiply(turn, turned), undo)
            else:
                _write(binding, orientation, turned @ rotation.T, undo)
        if self._inertial is not None:
            body = self._inertial
            _write(body, "ipos", rotation @ np.asarray(body.ipos) + shift, undo)
            _write(body, "iquat", multiply(turn, np.asarray(body.iquat)), undo)
        if self._free is not None:
            for field in ("qpos0", "qpos_spring", "qpos"):
                poses = np.array(getattr(self._free, field)).reshape(-1, 7)
                poses[:, :3] = poses[:, :3] @ rotation.T + shift
                poses[:, 3:] = multiply(turn, poses[:, 3:])
                _write(self._free, field, poses.reshape(-1), undo)
            velocities = np.array(self._free.qvel).reshape(-1, 6)
            velocities[:, :3] = velocities[:, :3] @ rotation.T  # in the world; angular: own
            _write(self._free, "qvel", velocities.reshape(-1), undo)
        if self._mocap is not None:
            mocap = self._mocap
            _write(mocap, "mocap_pos", np.asarray(mocap.mocap_pos) @ rotation.T + shift, undo)
            _write(mocap, "mocap_quat", multiply(turn, np.asarray(mocap.mocap_quat)), undo)


def _write(binding: Any, field: str, value: np.ndarray, undo: Undo) -> None:
    old = np.array(getattr(binding, field))
    setattr(binding, field, value)
    undo.append(lambda: setattr(binding, field, old))


def _scan(
    compiled: Compiled, text: list[str], line: int
) -> tuple[dict[str, list[Element]], list[Element], bool, str | None]:
    """What the frame or body on `line` holds, through the frames in it, up to the
    bodies in it: ({tag: elements with a pose}, the joints of the bodies among them,
    whether an `<inertial>` is among them, why they cannot be moved or None)."""
    parts: dict[str, list[Element]] = {}
    joints: list[Element] = []
    inertial, refusal = False, None
    open_tags: list[str] = []  # the tags open inside the frame, outermost first
    for number in range(line + 1, len(text)):
        if _END_TAG.fullmatch(text[number]):
            if not open_tags:
                break
            open_tags.pop()
            continue
        match = _START_TAG.fullmatch(text[number])
        assert match is not None, "a compiled line holds one tag"
        tag, element = match.group(1), compiled.lines[number]
        assert element is not None, "a start tag's line names its element"
        inside = [t for t in open_tags if t != "frame"]
        if not inside:
            if tag in _POSED:
                parts.setdefault(tag, []).append(element)
            elif tag == "inertial":
                inertial = True
            elif tag in _UNBOUND and refusal is None:
                refusal = f"it holds a <{tag}> ({element.path}), whose objects no element names"
        elif inside == ["body"] and tag in ("joint", "freejoint"):
            joints.append(element)
        if not match.group(3):
            open_tags.append(tag)
    return parts, joints, inertial, refusal


def _compiled_pose(compiled: Compiled, start_tag: str) -> Pose:
    """The pose a frame's compiled `start_tag` gives it in its parent, as MuJoCo reads it
    (with the compiled model's angle units and euler sequence)."""
    match = _START_TAG.fullmatch(start_tag)
    assert match is not None, "a compiled line holds one start tag"
    attributes = etree.fromstring(f"<frame{match.group(2)}/>").attrib
    pose = " ".join(f'{name}="{attributes[name]}"' for name in ("pos", *_ORIENTATIONS)
                    if name in attributes)  # fmt: skip
    compiler = compiled.composition.merged_settings("compiler").attributes
    settings = " ".join(
        f'{name}="{compiler[name]}"' for name in ("angle", "eulerseq") if name in compiler
    )
    probe = mujoco.MjModel.from_xml_string(
        f'<mujoco><compiler {settings}/><worldbody><body {pose}><geom size="1"/></body>'
        "</worldbody></mujoco>"
    )
    return probe.body_pos[1].copy(), probe.body_quat[1].copy()


# -- rigid transforms ----------------------------------------------------------------------


def compose(outer: Pose, inner: Pose) -> Pose:
    """The pose `inner`, given in the frame of pose `outer`, in `outer`'s parent."""
    pos, quat = np.empty(3), np.empty(4)
    mujoco.mju_mulPose(pos, quat, outer[0], outer[1], inner[0], inner[1])
    return pos, quat


def inverse(pose: Pose) -> Pose:
    """The pose whose composition with `pose` is the identity."""
    pos, quat = np.empty(3), np.empty(4)
    mujoco.mju_negPose(pos, quat, pose[0], pose[1])
    return pos, quat


def matrix(quat: np.ndarray) -> np.ndarray:
    """The (3, 3) rotation matrix of unit quaternion `quat`."""
    out = np.empty(9)
    mujoco.mju_quat2Mat(out, quat)
    return out.reshape(3, 3)


def multiply(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Quaternion products `left * right` (w first), over the leading axes of either:
    shape (..., 4).

    Computed as the matrix of multiplying by `left` times `right`, as dm_control's
    `transformations.quat_mul` computes it, so that `composer.utils.transformations` (which
    uses this) gives dm_control's values to the last bit: numpy's matrix product rounds
    differently from the four sums written out."""
    left, right = np.asarray(left), np.asarray(right)
    return ((left[..., _LEFT_INDEX] * _LEFT_SIGN) @ right[..., None])[..., 0]


def _left_multiplication() -> tuple[np.ndarray, np.ndarray]:
    """Where each entry of the matrix L(q), with L(q) @ p = q * p, comes from: the component
    of q = (w, x, y, z) at index[r, c], times sign[r, c]."""
    w, x, y, z = 0, 1, 2, 3
    index = np.array([[w, x, y, z], [x, w, z, y], [y, z, w, x], [z, y, x, w]])
    sign = np.array([[1, -1, -1, -1], [1, 1, -1, 1], [1, 1, 1, -1], [1, -1, 1, 1]])
    index.flags.writeable = sign.flags.writeable = False
    return index, sign


_LEFT_INDEX, _LEFT_SIGN = _left_multiplication()
