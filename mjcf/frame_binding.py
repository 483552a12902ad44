"""Bindings of elements that compile to a MuJoCo `<frame>`: an attachment frame without
joints, the world body of a model attached there, a `<frame>` of the model.

    frame = scene.find('site', 'mount').attach(arm)    # no joints: a MuJoCo <frame>
    physics.bind(arm.worldbody).xpos                    # where the arm is: the frame's pose
    physics.bind(frame).xquat                           # the same frame
    physics.bind(frame).pos = [0, 0, 1]                 # BindingError: fixed when compiled

dm_control makes every attachment frame a body, so these elements have body fields
there. MuJoCo 4 folds a `<frame>` into the bodies inside it when it compiles: the frame
has no state of its own, and its pose is the pose of the body it is in composed with its
fixed offset. A binding of such elements gives exactly that, read-only: `xpos` (3,),
`xquat` (4,), `xmat` (9,) in the world, and `pos` (3,), `quat` (4,), the offset from that
body, as the compiled model holds it (read from the text that was compiled, whatever the
tree has become since). A list of n elements gives (n, ...) arrays. Everything else, and
every write, raises BindingError saying why; never the numbers of another object.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from lxml import etree

from mjcf import attachment, errors
from mjcf.binding import POS_BEHIND

if TYPE_CHECKING:
    from mjcf.compiler import Compiled
    from mjcf.element import Element
    from mjcf.physics import Physics
    from mjcf.root import RootElement

_ORIENTATIONS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
_FIELDS = ("xpos", "xquat", "xmat", "pos", "quat")
_START_TAG = re.compile(r"\s*<(\w+)([^>]*?)/?>\s*")


def compiles_to_frame(element: Element, output: RootElement | None = None) -> bool:
    """Whether `element` compiles to a MuJoCo `<frame>` in the output of model `output`
    (default: the outermost model it is attached into); see the module docstring."""
    if isinstance(element, attachment.AttachmentFrame):
        return not element.compiles_to_body()
    tag = element._spec.tag
    if tag == "frame":
        return True
    if tag == "worldbody" and element._parent is element._root and element._root is not output:
        frame = attachment.frame_of(element._root)
        return frame is not None and not frame.compiles_to_body()
    return False


def bind_frames(physics: Physics, elements: list[Element], single: bool) -> FrameBinding | None:
    """The binding of `elements` if they compile to `<frame>`s, None if none does; raises
    BindingError if some do and others not, or as `FrameBinding`."""
    compiled: Compiled | None = physics.__dict__.get("_compiled")
    output = None if compiled is None else compiled.composition.root
    frames = [element for element in elements if compiles_to_frame(element, output)]
    if not frames:
        return None
    if len(frames) != len(elements):
        raise errors.BindingError(
            f"{frames[0].path} compiles to a MuJoCo <frame>, bound as a pose alone: bind it "
            "apart from elements of other kinds"
        )
    return FrameBinding(physics, elements, single)


class FrameBinding:
    """The read-only pose of elements compiled to MuJoCo `<frame>`s (module docstring)."""

    __slots__ = ("_holders", "_label", "_offset_pos", "_offset_quat", "_physics", "_single")

    _physics: Physics
    _single: bool
    _holders: np.ndarray  # (n,) the compiled ids of the bodies the frames are in
    _offset_pos: np.ndarray  # (n, 3) each frame's position in its body
    _offset_quat: np.ndarray  # (n, 4) and orientation
    _label: str

    def __init__(self, physics: Physics, elements: list[Element], single: bool) -> None:
        """Raises BindingError for an element whose frame is not in the compiled model."""
        compiled: Compiled | None = physics.__dict__.get("_compiled")
        if compiled is None or any(not _compiled_from(compiled, e) for e in elements):
            raise errors.BindingError(
                f"{elements[0].path}: compiles to a MuJoCo <frame>, whose pose only the text "
                "it was compiled from holds: bind it on a physics made with "
                "Physics.from_mjcf_model(model)"
            )
        holders, offsets = [], []
        for element in elements:
            holder, chain = _placement(element, compiled.composition.root)
            holders.append(compiled.id_of(holder, mujoco.mjtObj.mjOBJ_BODY))
            offsets.append(_offset(compiled, chain))
        object.__setattr__(self, "_physics", physics)
        object.__setattr__(self, "_single", single)
        object.__setattr__(self, "_holders", np.asarray(holders, dtype=np.intp))
        object.__setattr__(self, "_offset_pos", np.array([pos for pos, _ in offsets]))
        object.__setattr__(self, "_offset_quat", np.array([quat for _, quat in offsets]))
        object.__setattr__(
            self, "_label", elements[0].path if single else f"{len(elements)} frames"
        )

    def __getattr__(self, name: str) -> np.ndarray:
        if name not in _FIELDS:
            raise errors.BindingError(
                f"{self._label}: compiles to a MuJoCo <frame>, which has no '{name}': a frame "
                f"has a pose only ({', '.join(_FIELDS)}); bind the bodies inside it for the rest"
            )
        physics = self._physics
        if name in ("pos", "quat"):
            value = self._offset_pos if name == "pos" else self._offset_quat
        else:
            if physics._stale & POS_BEHIND:
                physics._refresh()
            value = self._world(name, physics._data)
        out = value[0].copy() if self._single else value.copy()
        out.flags.writeable = False  # a copy: writing into it would change nothing
        return out

    def _world(self, name: str, data: Any) -> np.ndarray:
        holders = self._holders
        rotation = data.xmat[holders].reshape(-1, 3, 3)
        if name == "xpos":
            return data.xpos[holders] + np.einsum("nij,nj->ni", rotation, self._offset_pos)
        offset = np.empty((len(holders), 9))
        for row, quat in enumerate(self._offset_quat):
            mujoco.mju_quat2Mat(offset[row], quat)
        matrix = np.einsum("nij,njk->nik", rotation, offset.reshape(-1, 3, 3))
        if name == "xmat":
            return matrix.reshape(-1, 9)
        quats = np.empty((len(holders), 4))
        for row in range(len(holders)):
            mujoco.mju_mulQuat(quats[row], data.xquat[holders[row]], self._offset_quat[row])
        return quats

    def __setattr__(self, name: str, value: Any) -> None:
        raise errors.BindingError(
            f"{self._label}: compiles to a MuJoCo <frame>, fixed when the model was compiled "
            f"(a frame has no state at run time), so '{name}' cannot be written; to move it, "
            "give the attachment frame a joint (frame.add('freejoint')) and write that, or "
            "change the model and compile it again"
        )

    def __getitem__(self, index: Any) -> np.ndarray:
        name = index[0] if isinstance(index, tuple) else index
        value = getattr(self, str(name))
        return value[..., index[1]] if isinstance(index, tuple) else value

    def __setitem__(self, index: Any, value: Any) -> None:
        name = index[0] if isinstance(index, tuple) else index
        self.__setattr__(str(name), value)

    def __repr__(self) -> str:
        return f"<FrameBinding {self._label}>"


def _compiled_from(compiled: Compiled, element: Element) -> bool:
    try:
        compiled.composition.context(element.root)
    except errors.InvalidReferenceError:
        return False
    return element._is_registered() or element is element.root.worldbody


def _placement(element: Element, output: RootElement) -> tuple[Element, list[Element]]:
    """(the body whose pose `element` is placed in, in the output of model `output`: a
    body, an attachment frame compiled as a body or the world body; the frames between
    them, innermost first)."""
    chain: list[Element] = []
    current: Element | None = element
    while current is not None:
        if isinstance(current, attachment.AttachmentFrame):
            if current.compiles_to_body():
                return current, chain
            chain.append(current)
        else:
            tag = current._spec.tag
            if tag == "worldbody" and current._parent is current._root:
                frame = attachment.frame_of(current._root)
                if frame is None or current._root is output:
                    return current, chain  # the world
                current = frame
                continue
            if tag == "body":
                return current, chain
            if tag == "replicate":
                raise errors.BindingError(
                    f"{element.path}: is inside a <replicate>, which compiles it several times"
                )
            if tag == "frame":
                chain.append(current)
        current = current._parent
    raise errors.BindingError(f"{element.path}: is not in its model")


def _offset(compiled: Compiled, chain: list[Element]) -> tuple[np.ndarray, np.ndarray]:
    """The pose (pos (3,), quat (4,)) of the innermost frame of `chain` in the body they
    are in, from the frames' text as compiled."""
    pos, quat = np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])
    for frame in reversed(chain):  # the outermost first
        local_pos, local_quat = _local_pose(compiled, frame)
        new_pos, new_quat = np.empty(3), np.empty(4)
        mujoco.mju_mulPose(new_pos, new_quat, pos, quat, local_pos, local_quat)
        pos, quat = new_pos, new_quat
    return pos, quat


def _local_pose(compiled: Compiled, frame: Element) -> tuple[np.ndarray, np.ndarray]:
    """The pose of `frame` in its parent, as MuJoCo reads it from its compiled start tag
    (with the compiled model's angle units and euler sequence)."""
    try:
        line = compiled.lines.index(frame)
    except ValueError:
        raise errors.BindingError(
            f"{frame.path}: was added after the model was compiled; compile it again"
        ) from None
    match = _START_TAG.fullmatch(compiled.xml.splitlines()[line])
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
