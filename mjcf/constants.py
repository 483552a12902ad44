"""Names dm_control's `mjcf.constants` gives to the separators, tags and settings that
user code refers to:

    from mjcf import constants
    if body.tag == constants.WORLDBODY: ...
    model.to_xml_string(precision=constants.XML_DEFAULT_PRECISION)
"""

from mjcf.tree.namescope import PREFIX_SEPARATOR

# An escaped separator ('\\/') in a name read with escape_separators is a plain '/'.
PREFIX_SEPARATOR_ESCAPE = "\\"

# Attribute names; `dclass` is how Python code spells MJCF's `class`.
CHILDCLASS = "childclass"
CLASS = "class"
DCLASS = "dclass"

# Tags.
ACTUATOR = "actuator"
BODY = "body"
DEFAULT = "default"
MESH = "mesh"
SITE = "site"
SKIN = "skin"
TENDON = "tendon"
WORLDBODY = "worldbody"

# Significant digits that write every double exactly (`to_xml_string`'s default).
XML_DEFAULT_PRECISION = 17

__all__ = [
    "ACTUATOR",
    "BODY",
    "CHILDCLASS",
    "CLASS",
    "DCLASS",
    "DEFAULT",
    "MESH",
    "PREFIX_SEPARATOR",
    "PREFIX_SEPARATOR_ESCAPE",
    "SITE",
    "SKIN",
    "TENDON",
    "WORLDBODY",
    "XML_DEFAULT_PRECISION",
]
