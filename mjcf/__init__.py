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
as dm_control names them ('//unnamed_geom_0', see `mjcf.naming`). Attached models keep
their own trees; composition happens when a model is written or compiled, but for the
global settings (`<option>`, `<size>`, `<visual>` ...), which are merged when a model is
attached and shared from then on, as in dm_control (see `mjcf.global_settings`).

No exception name shadows a Python builtin, so `from mjcf import *` is safe:
`NameClashError`, `UnknownAttributeError` and `InvalidReferenceError` were called
`NameError`, `AttributeError` and `ReferenceError` in the previous release; those old
names still work (`mjcf.NameError`), with a DeprecationWarning, until the next release.

How the package is built: its modules form layers, each importing only from its own layer
and the layers listed before it. Values and names come first (what an attribute holds,
what MJCF allows, how names scope), then the element tree, then how trees compose
(attachment, defaults, settings, copies), then reading and writing MJCF text, then
compiling and simulating. A module calls one of a later layer only through
`mjcf.upcalls` (`Element.find`, `attach`, `to_xml_string` ... are carried out above the
tree), which this package fills when it is imported, so no module imports another that
imports it, not even inside a function; private members of another module's objects are
used only through the internal protocol their class documents (`Element`, `RootElement`,
`Physics`). tests/mjcf/test_architecture.py checks all three on the real source:

    values:       errors upcalls debugging mujoco_log bulk fields assets archives values
                  schema xsd namescope
    tree:         element_list references model_operations element_names element_rules
                  element root base constants
    composition:  settings global_settings attachment naming traversal frames defaults
                  traversal_utils copying sameness keyframes sharing composition
    text:         default_sections indexer parser serializer export
    simulation:   tracking binding named validity render_meshes rendering raw_access
                  tree_binding budget compiler model_constants frame_poses frame_binding
                  physics_state physics
"""

# The modules above the tree whose functions it calls (see `_install_upcalls`), and
# dm_control's module paths (`mjcf.traversal_utils.get_freejoint`, `mjcf.constants`).
from mjcf import archives as archives
from mjcf import attachment, compiler, copying, naming, sameness, serializer, traversal
from mjcf import base as base
from mjcf import budget as budget
from mjcf import constants as constants
from mjcf import traversal_utils as traversal_utils
from mjcf.assets import Asset
from mjcf.attachment import AttachmentFrame
from mjcf.debugging import disable_debug_mode, enable_debug_mode, is_debug_mode
from mjcf.defaults import commit_defaults
from mjcf.element import Element
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
from mjcf.export import export_with_assets, export_with_assets_as_zip, from_zip
from mjcf.frames import get_attachment_frame, get_frame_freejoint, get_frame_joints, get_freejoint
from mjcf.namescope import PREFIX_SEPARATOR
from mjcf.parser import from_file, from_path, from_xml_string
from mjcf.physics import Physics
from mjcf.root import RootElement
from mjcf.upcalls import ABOVE as _ABOVE

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


def _install_upcalls() -> None:
    """Give the tree the functions of the layers above it (see `mjcf.upcalls`)."""
    _ABOVE.identifier = naming.identifier
    _ABOVE.find = traversal.find
    _ABOVE.find_all = traversal.find_all
    _ABOVE.is_same_as = sameness.is_same_as
    _ABOVE.attach = attachment.attach
    _ABOVE.detach = attachment.detach
    _ABOVE.remove = attachment.remove
    _ABOVE.attached_models = attachment.attached_models
    _ABOVE.include_copy = copying.include_copy
    _ABOVE.deepcopy_element = copying.deepcopy_element
    _ABOVE.to_xml_string = serializer.to_xml_string
    _ABOVE.attribute_text = serializer.attribute_text
    _ABOVE.serialize = serializer.serialize
    _ABOVE.file_name_of = serializer.file_name_of
    _ABOVE.from_zip = from_zip
    _ABOVE.serialize_for_compile = serializer.serialize_for_compile
    _ABOVE.compile_composition = compiler.compile_composition
    _ABOVE.compile_model = Physics.from_mjcf_model
    _ABOVE.element_class = Element
    _ABOVE.root_class = RootElement


_install_upcalls()


def __getattr__(name: str) -> type[Error]:
    """`mjcf.NameError`, `mjcf.AttributeError` and `mjcf.ReferenceError`, the previous
    release's names of `NameClashError`, `UnknownAttributeError` and
    `InvalidReferenceError`, with a DeprecationWarning (see `mjcf.errors`)."""
    return _deprecated_name(__name__, name)
