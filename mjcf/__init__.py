"""mjcf: a Python object model of MuJoCo's MJCF, composed and simulated (docs/architecture.md).

    arm = mjcf.RootElement(model='arm')
    hinge = arm.worldbody.add('body', name='upper').add('joint', name='shoulder')
    scene = mjcf.from_path('scene.xml'); scene.worldbody.attach(arm)   # names: 'arm/...'
    physics = mjcf.Physics.from_mjcf_model(scene)                     # MjModel + MjData
    physics.bind(hinge).qpos = 0.3; physics.named.data.qpos['arm/shoulder']

Every change is checked against MuJoCo's schema when made (an `mjcf.Error` naming element
and attribute, the model unchanged); written models compile in stock MuJoCo to the same model.
"""

# dm_control's module paths (`mjcf.traversal_utils.get_freejoint`, `mjcf.element`), and the
# limits on untrusted input users set (`mjcf.archives.LIMITS`, `mjcf.budget.LIMITS`).
from mjcf import base as base
from mjcf import constants as constants
from mjcf import debugging as debugging
from mjcf import element as element
from mjcf import namescope as namescope
from mjcf import parser as parser
from mjcf import physics as physics
from mjcf import traversal_utils as traversal_utils
from mjcf.compose.attachment import AttachmentFrame
from mjcf.compose.defaults import commit_defaults
from mjcf.compose.frames import (
    get_attachment_frame,
    get_frame_freejoint,
    get_frame_joints,
    get_freejoint,
)
from mjcf.errors import (
    AssetError,
    AttachmentError,
    AttributeValueError,
    BindingError,
    BudgetError,
    CompileError,
    Error,
    InvalidReferenceError,
    MissingFileError,
    NameClashError,
    NamespaceError,
    NotFoundError,
    ParseError,
    PhysicsError,
    RenderError,
    SchemaError,
    StateError,
    UnknownAttributeError,
    UnpackLimitError,
)
from mjcf.errors import deprecated_name as _deprecated_name
from mjcf.io import archives as archives
from mjcf.io.export import export_with_assets, export_with_assets_as_zip, from_zip
from mjcf.io.parser import from_file, from_path, from_xml_string
from mjcf.sim import budget as budget
from mjcf.sim.physics import Physics
from mjcf.tree.assets import Asset
from mjcf.tree.debugging import disable_debug_mode, enable_debug_mode, is_debug_mode
from mjcf.tree.element import Element
from mjcf.tree.namescope import PREFIX_SEPARATOR
from mjcf.tree.root import RootElement

__all__ = [
    "PREFIX_SEPARATOR",
    "Asset",
    "AssetError",
    "AttachmentError",
    "AttachmentFrame",
    "AttributeValueError",
    "BindingError",
    "BudgetError",
    "CompileError",
    "Element",
    "Error",
    "InvalidReferenceError",
    "MissingFileError",
    "NameClashError",
    "NamespaceError",
    "NotFoundError",
    "ParseError",
    "Physics",
    "PhysicsError",
    "RenderError",
    "RootElement",
    "SchemaError",
    "StateError",
    "UnknownAttributeError",
    "UnpackLimitError",
    "commit_defaults",
    "disable_debug_mode",
    "enable_debug_mode",
    "export_with_assets",
    "export_with_assets_as_zip",
    "from_file",
    "from_path",
    "from_xml_string",
    "from_zip",
    "get_attachment_frame",
    "get_frame_freejoint",
    "get_frame_joints",
    "get_freejoint",
    "is_debug_mode",
    "traversal_utils",
]


def __getattr__(name: str) -> type[Error]:
    """`mjcf.NameError`, `mjcf.AttributeError` and `mjcf.ReferenceError`, the previous
    release's names of `NameClashError`, `UnknownAttributeError` and
    `InvalidReferenceError`, with a DeprecationWarning, until the next release (see
    `mjcf.errors`)."""
    return _deprecated_name(__name__, name)
