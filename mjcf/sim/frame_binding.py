"""Bindings of elements that compile to a MuJoCo `<frame>`: an attachment frame without
joints, the world body of a model attached there, a `<frame>` of the model.

    frame = scene.find('site', 'mount').attach(arm)    # no joints: a MuJoCo <frame>
    physics.bind(arm.worldbody).xpos                    # where the arm is: the frame's pose
    physics.bind(frame).pos = [0, 0, 1]                 # moves the frame and all it holds
    physics.bind(frame).quat[0] = 0.5                   # so does an item write (normalized)

MuJoCo 4 folds a `<frame>` into what it holds, so these bindings have a pose's fields
(`FrameBinding`); what they cannot do raises BindingError saying why, changing nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.compose import attachment
from mjcf.sim import fields, frame_poses
from mjcf.sim.binding import POS_BEHIND, bring_up_to_date
from mjcf.tree.root import frame_of

if TYPE_CHECKING:
    from mjcf.sim.compiler import Compiled
    from mjcf.sim.physics import Physics
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# Each field and the MuJoCo field whose columns it has (names: see mjcf.sim.fields).
_FIELDS = {"pos": "body_pos", "quat": "body_quat", "xpos": "xpos", "xquat": "xquat",
           "xmat": "xmat"}  # fmt: skip
_WIDTH = {"pos": 3, "quat": 4}  # the fields that can be written


def compiles_to_frame(element: Element, output: RootElement | None = None) -> bool:
    """Whether `element` compiles to a MuJoCo `<frame>` in the output of model `output`
    (default: the outermost model it is attached into): an attachment frame without
    joints, the world body of a model attached there, or a `<frame>` of the model."""
    if isinstance(element, attachment.AttachmentFrame):
        return not element.compiles_to_body()
    tag = element.spec.tag
    if tag == "frame":
        return True
    if tag == "worldbody" and element.parent is element.root and element.root is not output:
        frame = frame_of(element.root)
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
    """The pose of elements compiled to MuJoCo `<frame>`s.

    dm_control makes every attachment frame a body, so these elements have body fields
    there. MuJoCo 4 folds a `<frame>` into what it holds when it compiles: the frame has no
    state of its own, and its pose in the world is the pose of the body it is in composed
    with its offset from that body. A binding of such elements has the fields of a pose:

    - `pos` (3,) and `quat` (4,): the frame's offset from the body it is in, as dm_control's
      body `pos` and `quat`. For a frame nested in other frames it is still the offset from
      that body (not from the frame around it). Writing either moves the frame, and with it
      everything compiled from inside it (`mjcf.sim.frame_poses`), as a compile with the
      frame there would place it; quaternions are normalized (a zero one raises).
    - `xpos` (3,), `xquat` (4,), `xmat` (9,): the frame's pose in the world, derived from
      those and from the body it is in (brought up to date first, as body fields are);
      read-only.

    The offset is kept per physics and compiled model: every binding of the frame (or of
    the world body of the model attached there) sees it, and so do the frames nested in it.
    A frame never moved has the offset the compiled text gives it, whatever the tree has
    become since; a recompile starts again from the text. A list of n elements gives (n,
    ...) arrays; written, nested frames move outermost first, so that each ends where it is
    asked. Reads are copies: those of `pos` and `quat` write the whole field back when an
    item of them is assigned; the others are read-only. Everything else raises BindingError
    saying why, as does a write that cannot be made, which then changes nothing; never the
    numbers of another object."""

    __slots__ = (
        "_chains", "_compiled", "_contents", "_holder_lines", "_holders", "_label", "_model",
        "_offsets", "_physics", "_single",
    )  # fmt: skip

    _physics: Physics
    _model: mujoco.MjModel  # the model the binding was made for
    _compiled: Compiled
    _single: bool
    _holders: np.ndarray  # (n,) the compiled ids of the bodies the frames are in
    _holder_lines: list[int | None]  # their lines in the compiled text (None: the world)
    _chains: list[list[int]]  # the lines of each element's frames, outermost first
    _contents: dict[int, frame_poses.Contents]  # what the frame on each line holds
    _offsets: tuple[Any, ...]  # (poses, version, pos (n, 3), quat (n, 4), mat (n, 3, 3))
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
        poses = frame_poses.of(physics)
        holders, holder_lines, chains = [], [], []
        for element in elements:
            holder, chain = _placement(element, compiled.composition.root)
            holders.append(compiled.id_of(holder, mujoco.mjtObj.mjOBJ_BODY))
            holder_lines.append(None if holders[-1] == 0 else poses.line(compiled, holder))
            chains.append([poses.line(compiled, frame) for frame in reversed(chain)])
        for name, value in (
            ("_physics", physics), ("_model", physics._model), ("_compiled", compiled),
            ("_single", single), ("_holders", np.asarray(holders, dtype=np.intp)),
            ("_holder_lines", holder_lines), ("_chains", chains), ("_contents", {}),
            ("_offsets", (None,)),
            ("_label", elements[0].path if single else f"{len(elements)} frames"),
        ):  # fmt: skip
            object.__setattr__(self, name, value)

    def __getattr__(self, name: str) -> np.ndarray:
        if name.startswith("_"):  # dunder lookups, and slots not set yet
            raise AttributeError(name)
        if name not in _FIELDS:
            raise errors.BindingError(
                f"{self._label}: compiles to a MuJoCo <frame>, which has no '{name}': a frame "
                f"has a pose only ({', '.join(_FIELDS)}); bind the bodies inside it for the rest"
            )
        _, _, pos, quat, rotation = self._current()
        if name in _WIDTH:
            value = (pos if name == "pos" else quat).view(_PoseArray)
            out = value[0].copy() if self._single else value.copy()
            out._write_back = (self, name)
            return out
        physics = self._physics
        bring_up_to_date(physics, POS_BEHIND)
        data, holders = physics.data, self._holders
        if name == "xpos":
            world = data.xpos[holders] + np.einsum(
                "nij,nj->ni", data.xmat[holders].reshape(-1, 3, 3), pos
            )
        elif name == "xquat":
            world = frame_poses.multiply(data.xquat[holders], quat)
        else:
            world = np.einsum(
                "nij,njk->nik", data.xmat[holders].reshape(-1, 3, 3), rotation
            ).reshape(-1, 9)
        out = world[0].copy() if self._single else world
        out.flags.writeable = False  # derived: write pos or quat
        return out

    def _current(self) -> tuple[Any, ...]:
        """The offsets of the frames now (cached until one of the model's frames moves);
        raises BindingError once the physics holds another model."""
        physics = self._physics
        if physics._model is not self._model:
            raise errors.BindingError(
                f"{self._label}: this binding was made for a model the physics no longer "
                "holds; bind again"
            )
        poses = frame_poses.of(physics)
        offsets = self._offsets
        if offsets[0] is not poses or offsets[1] != poses.version:
            found = [poses.offset(self._compiled, chain) for chain in self._chains]
            pos = np.array([p for p, _ in found])
            quat = np.array([q for _, q in found])
            rotation = np.array([frame_poses.matrix(q) for q in quat])
            offsets = (poses, poses.version, pos, quat, rotation)
            object.__setattr__(self, "_offsets", offsets)
        return offsets

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _WIDTH:
            self._write(name, value)
        elif name in _FIELDS:
            raise errors.BindingError(
                f"{self._label}: '{name}' is derived from the frame's pose in the body it is "
                "in and that body's pose, so it cannot be written: write 'pos' or 'quat'"
            )
        else:
            raise errors.BindingError(
                f"{self._label}: compiles to a MuJoCo <frame>, which has no '{name}' to write: "
                "write its 'pos' or 'quat' to move it"
            )

    def _write(self, name: str, value: Any) -> None:
        """Move the frames to the positions or orientations `value`; raises BindingError,
        having changed nothing, for a value of the wrong shape, not finite, a zero
        quaternion, or frames that cannot be moved (see mjcf.sim.frame_poses)."""
        width, count = _WIDTH[name], len(self._chains)
        try:
            values = np.array(np.broadcast_to(np.asarray(value, dtype=np.float64), (count, width)))
        except (ValueError, TypeError) as e:
            shape = "(3,)" if width == 3 else "(4,)"
            expected = shape if self._single else f"({count}, {width}) or {shape}"
            raise errors.BindingError(
                f"cannot write {value!r} to '{name}' of {self._label}: expected {expected} numbers"
            ) from e
        if not np.isfinite(values).all():
            raise errors.BindingError(
                f"cannot write '{name}' of {self._label}: not finite: {values.tolist()}"
            )
        if name == "quat":
            norms = np.linalg.norm(values, axis=1)
            if not norms.all():
                raise errors.BindingError(
                    f"cannot write 'quat' of {self._label}: a zero quaternion is no orientation"
                )
            values /= norms[:, None]
        self._current()  # raises if the physics holds another model
        order = sorted(range(count), key=lambda row: len(self._chains[row]))
        held = [self._held(row) for row in order]
        for contents in held:
            contents.check()
        poses = frame_poses.of(self._physics)
        undo: frame_poses.Undo = []
        try:
            for row, contents in zip(order, held, strict=True):
                new = values[row]
                pos, quat = (new, None) if name == "pos" else (None, new)
                poses.move(self._compiled, self._chains[row], contents, pos, quat, undo)
        except BaseException:
            for restore in reversed(undo):
                restore()
            raise

    def _held(self, row: int) -> frame_poses.Contents:
        line = self._chains[row][-1]
        contents = self._contents.get(line)
        if contents is None:
            contents = frame_poses.Contents(
                self._physics, self._compiled, line, self._holder_lines[row]
            )
            self._contents[line] = contents
        return contents

    def __getitem__(self, index: Any) -> np.ndarray:
        """`binding['pos']` and `binding['xpos', columns]` (index, slice, list, names)."""
        name, columns = _split(index)
        value = getattr(self, name)
        if columns is None:
            return value
        return np.asarray(value)[..., _columns(name, columns)]

    def __setitem__(self, index: Any, value: Any) -> None:
        """`binding['pos'] = v`, `binding['pos', 'z'] = 1`: moves the frames."""
        name, columns = _split(index)
        if columns is None:
            self.__setattr__(name, value)
            return
        current = np.array(getattr(self, name))
        current[..., _columns(name, columns)] = value
        self.__setattr__(name, current)

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *_FIELDS})

    def __repr__(self) -> str:
        return f"<FrameBinding {self._label}>"


class _PoseArray(np.ndarray):
    """A frame's `pos` or `quat` as read: assigning an item writes the whole value back
    (moving the frame). Arrays derived from it (slices, results) are plain copies."""

    __slots__ = ("_write_back",)

    _write_back: tuple[FrameBinding, str]

    def __setitem__(self, key: Any, value: Any) -> None:
        write_back = getattr(self, "_write_back", None)
        if write_back is None:
            np.ndarray.__setitem__(self, key, value)
            return
        new = self.view(np.ndarray).copy()
        new[key] = value
        binding, name = write_back
        binding.__setattr__(name, new)
        np.ndarray.__setitem__(self, Ellipsis, np.asarray(getattr(binding, name)))

    def __repr__(self) -> str:
        return repr(self.view(np.ndarray))


def _split(index: Any) -> tuple[str, Any]:
    if isinstance(index, tuple):
        if len(index) != 2:
            raise errors.BindingError(
                f"index a binding as binding['field'] or binding['field', columns], got {index!r}"
            )
        return str(index[0]), index[1]
    return str(index), None


def _columns(name: str, columns: Any) -> Any:
    """Column names ('x', ['qw', 'qz']) of field `name` as indices; others pass through.
    Raises BindingError for a name the field's columns do not have."""
    names = fields.column_names(_FIELDS.get(name, "")) or ()
    listed = columns if isinstance(columns, list | tuple) else [columns]
    if not any(isinstance(column, str) for column in listed):
        return columns
    unknown = [c for c in listed if not isinstance(c, str) or c not in names]
    if unknown:
        raise errors.BindingError(
            f"'{name}' has no column named {unknown[0]!r}: its columns are {list(names)}"
        )
    indices = [names.index(c) for c in listed]
    return indices[0] if isinstance(columns, str) else indices


def _compiled_from(compiled: Compiled, element: Element) -> bool:
    try:
        compiled.composition.context(element.root)
    except errors.InvalidReferenceError:
        return False
    return not element.is_removed or element is element.root.worldbody


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
            tag = current.spec.tag
            if tag == "worldbody" and current.parent is current.root:
                frame = frame_of(current.root)
                if frame is None or current.root is output:
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
        current = current.parent
    raise errors.BindingError(f"{element.path}: is not in its model")
