"""What mjcf refuses, on purpose, though MuJoCo 4.0.0's reader accepts it: documents that
crash or hang MuJoCo, and empty names that MuJoCo binds to an element nobody named.

The generated schema (``mjcf_schema.json``) says what MuJoCo's reader accepts; these
hand-kept facts are applied on top of it when the schema loads (`apply`), so that the XML
Schema, both readers, the Python API and the writer refuse them alike, with the reason.
Each entry is shown true of the installed MuJoCo by tests/mjcf/test_refusals.py, which
fails once a release no longer needs it; the differential check explains the
disagreements they make (``_judge``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from mjcf.schema.values import converter_for

if TYPE_CHECKING:
    from mjcf.schema import ElementSpec, Rule

# Crashes are SIGSEGVs inside MuJoCo 4.0.0, which kill Python.
_CRASH = "MuJoCo 4.0.0 crashes on it"

# Element key -> its reference attributes whose empty text MuJoCo binds to the first
# unnamed element of their namespace. MuJoCo looks these names up without checking they are
# empty, so "" finds the first element of that kind that has no name (a <pair> without geom1
# collides the first unnamed geom). mjcf names every element it writes (//unnamed_geom_0),
# so such a reference would point at nothing, or at another element: it is refused.
EMPTY_NAME_IS_FIRST_UNNAMED: dict[str, tuple[str, ...]] = {
    "contact-pair": ("geom1", "geom2"),
    "contact-exclude": ("body1", "body2"),
    "equality-connect": ("body1", "site1"),
    "equality-weld": ("body1", "site1"),
    "equality-joint": ("joint1",),
    "equality-tendon": ("tendon1",),
    "fixed-joint": ("joint",),
    "spatial-site": ("site",),
    "spatial-geom": ("geom",),
}
# Of those, the ones MuJoCo also binds so when they are left out: required here.
ABSENT_NAME_IS_FIRST_UNNAMED: dict[str, tuple[str, ...]] = {"contact-pair": ("geom1", "geom2")}
# (element key, attribute) -> keywords that crash MuJoCo: `frame` as the object type of a
# <tuple> element or a <user> or plugin sensor (frames are no objects of a compiled model).
CRASHING_KEYWORDS: dict[tuple[str, str], tuple[str, ...]] = {
    ("tuple-element", "objtype"): ("frame",),
    ("sensor-user", "objtype"): ("frame",),
    ("sensor-plugin", "objtype"): ("frame",),
    ("sensor-plugin", "reftype"): ("frame",),
}
# Element key -> (its attribute, child tag, the child's attribute), None for any: an
# element with that attribute and such a child crashes MuJoCo (a <mesh> with a file and a
# <plugin> child; a <replicate> of two plugins, even of count 1: a plugin there must name an
# instance).
CRASHING_CHILDREN: dict[str, tuple[tuple[str | None, str, str | None], ...]] = {
    "asset-mesh": (("file", "plugin", None),),
    "replicate": ((None, "plugin", "plugin"),),
}
# Numbers that must be finite: attribute name -> why (every element that has it). The full
# sweep of the differential check found these hangs: a muscle whose gear is infinite or NaN,
# or whose armature (or its joint's) is NaN.
_HANG = "MuJoCo 4.0.0's compile never ends computing the length range of a muscle"
FINITE: dict[str, str] = {
    "gear": f"{_HANG} whose gear is not finite",
    "armature": f"{_HANG} whose armature, or its joint's, is not finite",
}
# The plugin elements that name a plugin or an instance (not <extension>'s). One with
# neither crashes MuJoCo inside a <flexcomp> or a <replicate>, and MuJoCo's compile refuses
# it elsewhere, so every such plugin is refused.
_PLUGIN_NEEDS = ("plugin", "instance")


def apply(specs: Mapping[str, ElementSpec], rule_class: type[Rule]) -> None:
    """Add the refusals above to the loaded element specs (`rule_class`: `schema.Rule`,
    from the schema's loader, which this module cannot import: it imports this one)."""
    for key, names in EMPTY_NAME_IS_FIRST_UNNAMED.items():
        spec = specs[key]
        for name in names:
            attribute = spec.attributes[name]
            attribute.refused[""] = (
                f"is empty, which MuJoCo reads as the first {attribute.namespace} that has no "
                "name (mjcf names every element it writes); name that element and refer to it"
            )
    for key, names in ABSENT_NAME_IS_FIRST_UNNAMED.items():
        spec = specs[key]
        for name in names:
            spec.attributes[name].required = True
        spec.required = tuple(a.name for a in spec.attributes.values() if a.required)
        spec.checked_on_write = True
    for (key, name), words in CRASHING_KEYWORDS.items():
        attribute = specs[key].attributes[name]
        attribute.values = tuple(v for v in attribute.values if v not in words)
        for word in words:
            attribute.refused[word] = (
                f"takes no {word!r}: {_CRASH} (frames are no objects of a compiled model)"
            )
    for key, entries in CRASHING_CHILDREN.items():
        tag_of = specs[key].tag
        specs[key].crashing_children = tuple(
            (
                name,
                tag,
                child_name,
                f"a <{tag_of}>"
                + (f" with a {name!r}" if name else "")
                + f" cannot have a <{tag}>"
                + (f" with a {child_name!r}" if child_name else "")
                + f": {_CRASH}",
            )
            for name, tag, child_name in entries
        )
    for spec in specs.values():
        for name, why in FINITE.items():
            number = spec.attributes.get(name)
            if number is not None and number.converter.reals:
                number.finite = why
                number.converter = converter_for(number)
    for spec in specs.values():
        if spec.tag != "plugin" or not set(_PLUGIN_NEEDS) <= spec.attributes.keys():
            continue
        rule = rule_class(
            {
                "one_of": [[name] for name in _PLUGIN_NEEDS],
                "blank_is_none": True,  # instance="" names none: it crashes MuJoCo too
                "reason": f"{_CRASH} inside a <flexcomp> or <replicate>, and refuses it elsewhere",
            },
            spec.attributes,
        )
        spec.add_rule(rule)
