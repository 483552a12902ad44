"""mjcf: a Python object model of MuJoCo's MJCF, with composition and simulation.

    import mjcf
    arm = mjcf.RootElement(model='arm')
    upper = arm.worldbody.add('body', name='upper', pos=[0, 0, 1])
    hinge = upper.add('joint', name='shoulder', type='hinge', axis=[0, 1, 0])
    upper.add('geom', type='capsule', size=[0.05, 0.2])
    arm.actuator.add('motor', joint=hinge, gear=[10])        # elements as references

    scene = mjcf.from_path('scene.xml')                      # or from_xml_string
    scene.worldbody.attach(arm)                              # names become 'arm/...'
    physics = mjcf.Physics.from_mjcf_model(scene)            # MjModel + MjData
    physics.bind(hinge).qpos = 0.3                           # live, per element
    physics.named.data.qpos['arm/shoulder']                  # or by scoped name

What it promises: every change is validated against the installed MuJoCo's schema
when it is made, and a failed change leaves the model as it was; errors are
`mjcf.Error` subclasses naming the element and attribute. A model written with
`to_xml_string()` compiles in stock MuJoCo to the same model, unnamed elements named
as dm_control names them ('//unnamed_geom_0', see `mjcf.compose.naming`). Attached models
keep their own trees; composition happens when a model is written or compiled, but for the
global settings (`<option>`, `<size>`, `<visual>` ...), which are merged when a model is
attached and shared from then on, as in dm_control (see `mjcf.compose.global_settings`).

No exception name shadows a Python builtin, so `from mjcf import *` is safe:
`NameClashError`, `UnknownAttributeError` and `InvalidReferenceError` were called
`NameError`, `AttributeError` and `ReferenceError` in the previous release; those old
names still work (`mjcf.NameError`), with a DeprecationWarning, until the next release.

How the package is built (docs/architecture.md): five layers, each a folder importing
only the ones below it: `mjcf.schema` (what MJCF allows, what a value is), `mjcf.tree`
(elements and models), `mjcf.compose` (attaching, defaults, settings, copies, names),
`mjcf.io` (reading and writing MJCF text) and `mjcf.sim` (compiling, `Physics`,
bindings). `mjcf.element`, `mjcf.physics`, `mjcf.parser`, `mjcf.traversal_utils` ...
are dm_control's module paths, re-exporting these names.
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
    `InvalidReferenceError`, with a DeprecationWarning (see `mjcf.errors`)."""
    return _deprecated_name(__name__, name)
