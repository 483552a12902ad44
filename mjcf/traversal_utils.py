"""dm_control's `mjcf.traversal_utils`, under its name: the frame and default helpers of
`mjcf.frames` and `mjcf.defaults`, so that `mjcf.traversal_utils.get_attachment_frame(m)`
in dm_control code runs unchanged. New code can call them as `mjcf.get_attachment_frame`.
"""

from mjcf.defaults import commit_defaults
from mjcf.frames import get_attachment_frame, get_frame_freejoint, get_frame_joints, get_freejoint

__all__ = [
    "commit_defaults",
    "get_attachment_frame",
    "get_frame_freejoint",
    "get_frame_joints",
    "get_freejoint",
]
