"""Finding the frames, free joints and joints that place models and bodies.

frame = mjcf.get_attachment_frame(arm)        # where model `arm` is attached
mjcf.get_frame_freejoint(frame)               # its free joint, if it floats
mjcf.get_frame_joints(frame)                  # all joints of the frame (None: not attached)
mjcf.get_freejoint(body)                      # a body's free joint, or None
"""

from __future__ import annotations

from mjcf.compose import attachment
from mjcf.tree.element import Element, stored_attributes, tree_children
from mjcf.tree.root import RootElement, frame_of


def get_attachment_frame(model: RootElement) -> Element | None:
    """The attachment frame of `model` in the model it is attached to, or None."""
    return frame_of(model)


def get_freejoint(element: Element | None) -> Element | None:
    """The free joint of a body or attachment frame (a `<freejoint>`, or a `<joint
    type="free">`), or None."""
    if element is None or not (
        element.tag == "body" or isinstance(element, attachment.AttachmentFrame)
    ):
        return None
    for child in tree_children(element):
        if child.tag == "freejoint" or (
            child.tag == "joint" and stored_attributes(child).get("type") == "free"
        ):
            return child
    return None


def get_frame_freejoint(frame: Element | None) -> Element | None:
    """The free joint of an attachment frame (or of the frame of an attached model, as
    dm_control code passes it), or None."""
    return get_freejoint(_as_frame(frame))


def get_frame_joints(frame: Element | None) -> list[Element] | None:
    """Every joint (including a free joint) of an attachment frame (or of the frame of
    an attached model), in order; None for a model that is not attached, as dm_control
    returns."""
    frame = _as_frame(frame)
    if frame is None:
        return None
    return [child for child in tree_children(frame) if child.spec.namespace == "joint"]


def _as_frame(element: Element | None) -> Element | None:
    if isinstance(element, RootElement):
        return frame_of(element)
    return element
