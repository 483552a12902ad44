"""Hand-kept facts about MJCF that MuJoCo's documentation does not state.

The generator reads everything else from the installed mujoco's XML reference
and its XML reader. These tables hold only what neither says in a form a program
can read: what a string attribute *is* (a name of another element, a file, or
free text), where a few attributes whose documentation gives no type have that
type documented, and the namespaces of the few elements not named after one.

When MuJoCo adds a string attribute, ``generate.py`` stops and lists it: add it
to ``REFERENCES``, ``FILES`` or ``PLAIN_STRINGS`` (or to an ``*_BY_ELEMENT``
override when the same attribute name means different things in different
elements).
"""

from __future__ import annotations

# String attributes that name another element of the model, by attribute name,
# and the namespace of that element. `class`/`childclass` name default classes.
REFERENCES: dict[str, str] = {
    "class": "default",
    "childclass": "default",
    "material": "material",
    "mesh": "mesh",
    "hfield": "hfield",
    "texture": "texture",
    "body": "body",
    "body1": "body",
    "body2": "body",
    "subtree1": "body",  # sensor/contact: the subtree rooted at this body
    "subtree2": "body",
    "target": "body",  # camera/light mode="targetbody(com)"
    "joint": "joint",
    "joint1": "joint",
    "joint2": "joint",
    "jointinparent": "joint",
    "geom": "geom",
    "geom1": "geom",
    "geom2": "geom",
    "site": "site",
    "site1": "site",
    "site2": "site",
    "refsite": "site",
    "sidesite": "site",
    "cranksite": "site",
    "slidersite": "site",
    "tendon": "tendon",
    "tendon1": "tendon",
    "tendon2": "tendon",
    "actuator": "actuator",
    "camera": "camera",
    "flex": "flex",
    "instance": "plugin",  # an <extension><plugin><instance name=...>
    "node": "body",  # flex nodes are bodies
}

# String attributes that are paths of files the model loads.
FILES: frozenset[str] = frozenset(
    {"file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"}
)

# String attributes that are free text: directories, formats, plugin library
# identifiers, key/value configuration, names that live outside this model.
PLAIN_STRINGS: frozenset[str] = frozenset(
    {
        "assetdir",
        "meshdir",
        "texturedir",
        "eulerseq",  # e.g. "xyz"
        "memory",  # e.g. "10M"
        "content_type",  # MIME type of an asset file
        "gridlayout",  # texture layout such as ".U..LFRB.D.."
        "builtin",  # mesh generator name; parameters in `params`
        "input",  # actuator input names
        "role",  # material layer role
        "data",  # custom text contents
        "plugin",  # plugin library identifier, e.g. "mujoco.elasticity.cable"
        "key",  # plugin configuration key/value
        "value",
        "prefix",  # attach: prefix given to the attached model's names
        "sep",  # replicate: separator before the replica number in names
    }
)

# String attributes the reader reads by a grammar of its own, by attribute name:
# the name of the grammar in `mjcf.schema.values.TEXT_FORMATS` (checked against the reader).
TEXT_FORMATS: dict[str, str] = {"memory": "memory size", "eulerseq": "three characters"}

# Where an attribute name means something else in one element (element key,
# attribute name) -> classification: a namespace name for a reference, or
# "string" / "file".
BY_ELEMENT: dict[tuple[str, str], str] = {
    ("mujoco", "model"): "string",  # the model's own name
    ("body-attach", "model"): "model",  # an <asset><model name=...>
    # attach body=/frame= name elements of the attached (child) model.
    ("body-attach", "body"): "string",
    ("body-attach", "frame"): "string",
}

# References whose namespace is chosen by another attribute's keyword value.
NAMESPACE_FROM: dict[str, str] = {"objname": "objtype", "refname": "reftype"}

# Object-type keywords that are not themselves namespace names.
OBJECT_TYPE_ALIASES: dict[str, str] = {
    "xbody": "body",  # the body's regular frame instead of its inertial frame
    "dof": "joint",  # degrees of freedom are named by their joint
}

# Namespaces of named elements whose tag (or grouping section) is not a MuJoCo
# object type: element key -> namespace.
ELEMENT_NAMESPACES: dict[str, str] = {
    "body-freejoint": "joint",
    "body-flexcomp": "flex",  # generates a flex of that name
    "asset-model": "model",
    "plugin-instance": "plugin",
}

# Attributes whose documentation gives no type and does not link to where it is
# documented (attribute name, or element-anchor-attribute) -> (label, name): the
# section label or element anchor, and the attribute name there, that documents it.
TYPE_SOURCES: dict[str, tuple[str, str]] = {
    "solref": ("CSolver", "solref"),
    "solimp": ("CSolver", "solimp"),
    "solreflimit": ("CSolver", "solref"),
    "solimplimit": ("CSolver", "solimp"),
    "solreffriction": ("CSolver", "solref"),
    "solimpfriction": ("CSolver", "solimp"),
    "o_solref": ("CSolver", "solref"),
    "o_solimp": ("CSolver", "solimp"),
    "o_friction": ("contact-pair", "friction"),  # "replace ... friction of contact pairs"
    "cutoff": ("CSensor", "cutoff"),  # collision sensors: same type, other meaning
    # Orientation alternatives of flexcomp ("can be used instead of quat").
    "axisangle": ("COrientation", "axisangle"),
    "xyaxes": ("COrientation", "xyaxes"),
    "zaxis": ("COrientation", "zaxis"),
    "euler": ("COrientation", "euler"),
    "flexcomp-edge-stiffness": ("flex-edge", "stiffness"),  # "passed through to the flex"
    "flexcomp-edge-damping": ("flex-edge", "damping"),
    # Plugin sensors take the object selectors of user sensors.
    "sensor-plugin-objtype": ("sensor-user", "objtype"),
    "sensor-plugin-objname": ("sensor-user", "objname"),
    "sensor-plugin-reftype": ("sensor-user", "objtype"),
    "sensor-plugin-refname": ("sensor-user", "objname"),
}
