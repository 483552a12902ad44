"""The names MuJoCo sees: `full_identifier`, and the names of elements nobody named.

    body = model.worldbody.add('body')          # no name
    body.full_identifier                       # '//unnamed_body_0'
    scene.attach(model)                        # model 'robot'
    body.full_identifier                       # 'robot//unnamed_body_0'

As in dm_control, an element that can carry a name but has none is written in every output
(so the compiled model has it) as '/unnamed_<namespace>_<i>' after its model's prefix; the
name is stable while the model does not change, and reading it back leaves it unnamed.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from mjcf.compose import attachment
from mjcf.tree.element import stored_attributes, tree_children
from mjcf.tree.element_list import attached_models
from mjcf.tree.namescope import PREFIX_SEPARATOR, WORLD
from mjcf.tree.namescope import unescape as _unescape
from mjcf.tree.root import frame_of, numbering_of, own_version, set_numbering

if TYPE_CHECKING:
    from mjcf.compose.attachment import AttachmentFrame
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# A generated name as the outermost model writes it: '//unnamed_body_3'.
GENERATED = re.compile(r"//unnamed_([a-z_]+)_(\d+)")
# Elements below these tags are templates or copies, not one compiled object each.
_NOT_ONE_OBJECT = frozenset({"replicate", "default"})


def scoped_name(element: Element, prefix_root: RootElement | None = None) -> str | None:
    """The name `element` has in the output of `prefix_root` (default: the outermost
    model it is attached into); None for elements that cannot carry a name, and for
    unnamed ones that are removed or replicated."""
    if element.spec.tag == "worldbody" and element.parent is element.root:
        return _world_body_name(element, prefix_root)
    if isinstance(element, attachment.AttachmentFrame):
        return frame_name(element, _prefix(element, prefix_root))
    parent = element.parent
    if isinstance(parent, attachment.AttachmentFrame) and element.identifier is not None:
        return frame_child_name(element, parent, _prefix(element, prefix_root))
    name = element.identifier
    if name is not None:
        return _prefix(element, prefix_root) + _unescape(name)
    return written_name(element, _prefix(element, prefix_root))


def identifier(element: Element, prefix_root: RootElement | None = None) -> str | None:
    """`element.full_identifier` (with `prefix_root`: `prefixed_identifier`): the name
    it is written with (`scoped_name`), but for the world body of an attached model,
    dm_control's name of it, its attachment frame's ('arm/'), where `scoped_name` gives
    the compiled body its contents are in."""
    if element.spec.tag == "worldbody" and element.parent is element.root:
        frame = frame_of(element.root)
        if frame is not None and element.root is not prefix_root:
            return frame_name(frame, _prefix(frame, prefix_root))
    return scoped_name(element, prefix_root)


def written_name(element: Element, prefix: str) -> str | None:
    """The name written for `element`, which has no name of its own, in an output where
    its model's prefix is `prefix` ('' for the output model); None if it is written
    without one.

    It is '/unnamed_<namespace>_<i>' after the prefix ('/' for the outermost model), where
    i is the element's position among all elements of that namespace in its own model
    (see `_numbers`), so that reading a written model and writing it again gives the same
    names. Reading such a name back (`from_xml_string(model.to_xml_string())`) leaves the
    element unnamed again, references to it pointing at it. Exceptions: meshes, textures,
    height fields and skins without a name are called after their file, as MuJoCo calls
    them; elements inside a `<replicate>` stay unnamed (MuJoCo compiles several objects
    from each, numbering only named ones) and have no `full_identifier`; the joints of an
    attachment frame are named after the frame, as in dm_control ('robot/' for its first
    unnamed joint, 'robot/root_x/' for one named 'root_x': each frame holds its joints'
    names, so every attached model may have a 'root_x')."""
    parent = element.parent
    if isinstance(parent, attachment.AttachmentFrame):
        return _frame_joint_name(element, parent, prefix)
    number = _numbers(element.root).get(element)
    if number is None:
        return None
    namespace = element.spec.namespace
    return (prefix or PREFIX_SEPARATOR) + f"{PREFIX_SEPARATOR}unnamed_{namespace}_{number}"


def is_replicated(element: Element) -> bool:
    """Whether `element` is inside a `<replicate>`, so that it compiles to several
    objects (MuJoCo numbers their names) rather than one."""
    parent = element.parent
    while parent is not None:
        if parent.spec.tag == "replicate":
            return True
        parent = parent.parent
    return False


def frame_name(frame: attachment.AttachmentFrame, prefix: str) -> str:
    """The name of an attachment frame: its own, or its model's scope ('robot/'), which
    no user name can take."""
    own = stored_attributes(frame).get("name")
    if own is not None:
        return prefix + _unescape(own)
    return prefix + frame.attached_model.model + PREFIX_SEPARATOR


def frame_child_name(child: Element, frame: AttachmentFrame, prefix: str) -> str:
    """The name of a named joint of an attachment frame, scoped to the frame as in
    dm_control: 'arm/root_x/' for joint 'root_x' of the frame of model 'arm' (and
    'mount/root_x/' for a frame named 'mount')."""
    base = frame_name(frame, prefix)
    if not base.endswith(PREFIX_SEPARATOR):
        base += PREFIX_SEPARATOR
    return base + _unescape(stored_attributes(child)["name"]) + PREFIX_SEPARATOR


def _frame_joint_name(joint: Element, frame: AttachmentFrame, prefix: str) -> str | None:
    """dm_control names the unnamed joint of an attachment frame after the frame; a
    second unnamed joint of one frame gets a name no scope can produce."""
    if joint.spec.namespace != "joint":
        return None
    unnamed = [
        c for c in tree_children(frame) if c.spec.namespace == "joint" and c.identifier is None
    ]
    index = next(i for i, c in enumerate(unnamed) if c is joint)
    base = frame_name(frame, prefix)
    return base if index == 0 else f"{base}{PREFIX_SEPARATOR}frame_joint_{index}"


def _prefix(element: Element, prefix_root: RootElement | None) -> str:
    scope = None if prefix_root is None else prefix_root.namescope
    return element.root.namescope.prefix(scope)


def _world_body_name(worldbody: Element, prefix_root: RootElement | None) -> str:
    """'world' for the output model; for an attached model, the compiled body its world
    body's contents belong to: its attachment frame when that is written as a body,
    else the body the frame is in."""
    model = worldbody.root
    frame = frame_of(model)
    if frame is None or model is prefix_root:
        return WORLD
    if frame.compiles_to_body():
        return frame_name(frame, _prefix(frame, prefix_root))
    holder = frame.parent
    while holder is not None and holder.spec.tag == "frame":  # MuJoCo's <frame>s are no bodies
        holder = holder.parent
    assert holder is not None, "a frame in a tree is inside a body"
    return scoped_name(holder, prefix_root) or WORLD


def unnamed_elements(root: RootElement) -> list[Element]:
    """The elements of `root`'s own tree that are written with a generated name: its
    numbered unnamed elements and the unnamed joints of its attachment frames."""
    found = list(_numbers(root))
    for frame in attachment.frames(root):
        found.extend(
            c for c in tree_children(frame) if c.spec.namespace == "joint" and c.identifier is None
        )
    return found


def _numbers(root: RootElement) -> dict[Element, int]:
    """{unnamed element: its position in its namespace} for the elements of `root`'s
    own tree that get a generated name; recomputed when the model (or a model attached
    to it) changes.

    The position counts every element written before it in the model's sections, those of
    the models attached inside it too, where they are written: an attachment frame as the
    `<body>` or `<frame>` it is written as (dm_control counts it as one body instead), its
    joints, then the attached world body's contents. Reading the written model back makes
    those elements its own, under the names they were written with, so it numbers its
    unnamed elements alike: writing, reading and writing again gives the same text."""
    models = attached_models(root)
    key = (own_version(root), tuple((id(model), own_version(model)) for model in models))
    cached = numbering_of(root)
    if cached is not None and cached[0] == key:
        return cached[1]
    counts: dict[str, int] = {}
    numbers: dict[Element, int] = {}
    stack: list[tuple[Element, bool]] = [(child, True) for child in reversed(tree_children(root))]
    while stack:
        element, own = stack.pop()
        spec = element.spec
        if isinstance(element, attachment.AttachmentFrame):
            written = "body" if element.compiles_to_body() else "frame"
            counts[written] = counts.get(written, 0) + 1
            inside = tree_children(element.attached_model.worldbody)
            stack.extend((child, False) for child in reversed(inside))
            # Its joints are named after it (see `written_name`): counted, not numbered.
            stack.extend((child, False) for child in reversed(tree_children(element)))
            continue
        if spec.tag in _NOT_ONE_OBJECT:
            continue
        namespace = spec.namespace
        if namespace is not None:
            count = counts.get(namespace, 0)
            counts[namespace] = count + 1
            if own and element.identifier is None:
                numbers[element] = count
        stack.extend((child, own) for child in reversed(tree_children(element)))
    set_numbering(root, (key, numbers))
    return numbers
