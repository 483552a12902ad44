"""dm_control's `mjcf.traversal_utils` module path, for code that imports it:

    from mjcf import traversal_utils
    frame = traversal_utils.get_attachment_frame(arm)
    traversal_utils.commit_defaults(geom, attributes=['rgba'])

The functions are those of `mjcf.compose.frames` and `mjcf.compose.defaults`, also
exported by `mjcf`.
"""

from mjcf.compose.defaults import commit_defaults
from mjcf.compose.frames import (
    get_attachment_frame,
    get_frame_freejoint,
    get_frame_joints,
    get_freejoint,
)

__all__ = [
    "commit_defaults",
    "get_attachment_frame",
    "get_frame_freejoint",
    "get_frame_joints",
    "get_freejoint",
]
