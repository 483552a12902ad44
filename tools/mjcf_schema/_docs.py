"""MJCF as MuJoCo's documentation describes it: elements, attributes, types.

:func:`elements_from_docs` reads the element tree of ``XMLschema.rst`` and, for
every attribute anchor, the block of ``XMLreference.rst`` (or of the
``modeling.rst`` section it points to) that states its type and default. The
result is a draft that ``generate.py`` completes: string attributes are
classified with ``_annotations.py`` and the rest is checked against MuJoCo's reader.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import mujoco

from tools.mjcf_schema import _annotations, _rst

ROOT = "mujoco"
BODY = "body"
WORLDBODY = "worldbody"
DEFAULT = "default"
# Meta elements the reference documents outside XMLschema.rst (include is the
# parser's business, not the schema's).
META = ("body-frame", "replicate")
ANY_OBJECT_TYPE = "(any element type that can be named)"
_ONCE_ICONS = {"!", "?", "dot", "star"}  # star: the root
_RECURSIVE_ICONS = {"@", "sync"}


class SchemaError(RuntimeError):
    """The documentation says something the generator cannot turn into a schema."""


@dataclass
class Attribute:
    """One attribute of one element, as it is being worked out."""

    name: str
    kind: str  # identifier, string, file, reference, keyword, int, real
    required: bool = False
    default: str | None = None
    values: list[str] = field(default_factory=list)
    count: int | None = None  # documented count of numbers; None: depends on the model
    multiple_of: int | None = None
    min: int = 1
    max: int | None = 1
    gaps: list[int] = field(default_factory=list)  # counts between min and max refused
    namespace: str | None = None
    namespace_from: str | None = None
    namespace_map: dict[str, str] = field(default_factory=dict)
    is_list: bool = False
    any_object_type: bool = False  # keyword over every type of named element
    description: str = ""  # the documentation text, for values listed there
    # What only the reader tells (see _refine.py):
    float32: bool = False  # held as a C float: larger numbers are refused
    min_value: float | None = None
    min_exclusive: bool = False
    max_value: float | None = None
    max_exclusive: bool = False
    case_insensitive: bool = False
    integers: tuple[int, int] | None = None  # integer text the reader takes for keywords
    ordered: bool = False  # a keyword list must follow the order of `values`
    alone: list[str] = field(default_factory=list)  # keywords a list may hold only alone
    text_format: str | None = None  # a grammar of values.TEXT_FORMATS
    blank: bool | None = None  # whether blank text is read; None: as usual for the kind
    trims: bool = False  # keywords: spaces around them are ignored
    # How two models' values merge when one is attached to the other (min, max, or);
    # None where the documentation's merging table leaves them to agree.
    merge: str | None = None

    def to_json(self) -> dict:
        """The attribute's entry in the JSON file."""
        spec: dict = {"type": self.kind}
        if self.kind == "reference":
            if self.namespace_from:
                spec["namespace_from"] = self.namespace_from
                spec["namespace_map"] = self.namespace_map
            else:
                spec["namespace"] = self.namespace
            if self.is_list:
                spec["list"] = True
        elif self.kind == "keyword":
            spec["values"] = self.values
            if self.is_list:
                spec["list"] = True
            optional = {
                "case_insensitive": self.case_insensitive,
                "trims": self.trims,
                "integers": list(self.integers) if self.integers else None,
                "ordered": self.ordered,
                "alone": self.alone,
            }
            spec.update((key, value) for key, value in optional.items() if value)
        elif self.kind in ("int", "real"):
            spec["min"] = self.min
            spec["max"] = self.max
            if self.gaps:
                spec["gaps"] = self.gaps
            if self.multiple_of:
                spec["multiple_of"] = self.multiple_of
            if self.float32:
                spec["float32"] = True
            if self.min_value is not None:
                spec["min_value"] = self.min_value
                if self.min_exclusive:
                    spec["min_exclusive"] = True
            if self.max_value is not None:
                spec["max_value"] = self.max_value
                if self.max_exclusive:
                    spec["max_exclusive"] = True
        elif self.text_format is not None:
            spec["format"] = self.text_format
        if self.blank is not None:
            spec["blank"] = self.blank
        spec["required"] = self.required
        if self.kind in ("string", "keyword", "int", "real"):
            spec["default"] = self.default
        if self.merge is not None:
            spec["merge"] = self.merge
        return spec


@dataclass
class Element:
    """One element key of the schema, as it is being worked out."""

    key: str
    tag: str
    repeated: bool
    attributes: dict[str, Attribute] = field(default_factory=dict)
    children: list[str] = field(default_factory=list)
    namespace: str | None = None
    # Rules the reader keeps between attributes: {"at_most_one": [[names]...]},
    # {"one_of": [[names]...]} or {"requires": [name, name]}, with MuJoCo's "message".
    rules: list[dict] = field(default_factory=list)
    repeated_in: list[str] = field(default_factory=list)  # parents it may repeat under
    matters_empty: bool = False  # once-only, and changes the model when present empty

    def to_json(self) -> dict:
        """The element's entry in the JSON file."""
        entry: dict[str, object] = {
            "tag": self.tag,
            "namespace": self.namespace,
            "repeated": self.repeated,
            "attributes": {name: a.to_json() for name, a in self.attributes.items()},
            "children": self.children,
        }
        if self.repeated_in:
            entry["repeated_in"] = self.repeated_in
        if self.rules:
            entry["rules"] = self.rules
        if self.matters_empty:
            entry["matters_empty"] = True
        return entry


def doc_dir() -> Path:
    """The documentation directory of the installed mujoco wheel."""
    return Path(mujoco.__file__).parent / "doc"


def parse_value(name: str, text: str) -> Attribute:
    """An attribute from its documented value text, e.g. ``real(3), "0 0 0"``."""
    type_text, status = _split_first(text)
    attribute = Attribute(name, "string")
    keywords = re.fullmatch(r"\[(.*)\]", type_text)
    typed = re.fullmatch(r"(string|int|real)(?:\((.+)\))?", type_text)
    if keywords:
        attribute.kind = "keyword"
        attribute.values = [value.strip() for value in keywords.group(1).split(",")]
    elif type_text == "bool":
        attribute.kind, attribute.values = "keyword", ["false", "true"]
    elif type_text == ANY_OBJECT_TYPE:
        attribute.kind, attribute.any_object_type = "keyword", True
    elif typed:
        attribute.kind = typed.group(1)
        if typed.group(2) is not None:
            count, multiple_of = _count(typed.group(2))
            if attribute.kind == "string":
                attribute.is_list = True
            attribute.count, attribute.multiple_of = count, multiple_of
        elif attribute.kind != "string":
            attribute.count = 1
    else:
        raise SchemaError(f"attribute {name!r}: unknown type {type_text!r} in {text!r}")
    # "required (except at the top level)", "required for slider-crank
    # transmission": conditions the reader checks, not a required attribute.
    attribute.required = status == "required"
    default = re.match(r'"([^"]*)"', status)
    if default:
        attribute.default = _expand_default(default.group(1), attribute)
    return attribute


def _split_first(text: str) -> tuple[str, str]:
    """Split ``text`` at its first comma outside brackets: (type, status)."""
    depth = 0
    for index, char in enumerate(text):
        if char in "[(":
            depth += 1
        elif char in "])":
            depth -= 1
        elif char == "," and depth == 0:
            return text[:index].strip(), text[index + 1 :].strip()
    return text.strip(), ""


def _count(expression: str) -> tuple[int | None, int | None]:
    """(fixed count, multiple) from a documented size: "3", "1 or 3", "3*nvert"."""
    alternatives = [part.strip() for part in expression.split(" or ")]
    if all(part.isdigit() for part in alternatives):
        return max(int(part) for part in alternatives), None
    factors = []
    for part in alternatives:
        leading = re.match(r"(\d+)\*", part)
        factors.append(int(leading.group(1)) if leading else 1)
    multiple = math.gcd(*factors)
    return None, multiple if multiple > 1 else None


def _expand_default(text: str, attribute: Attribute) -> str | None:
    """Spell out "1 0 ... 0" for a fixed count; None when the count is the model's."""
    if attribute.kind not in ("int", "real") or "..." not in text:
        return text
    if attribute.count is None:
        return None
    head, tail = (part.split() for part in text.split("...", 1))
    fill = tail[0] if tail else head[-1]
    return " ".join(head + [fill] * (attribute.count - len(head) - len(tail)) + tail)


class _Resolver:
    """Finds the block documenting an attribute's type, following "see there" links."""

    def __init__(self, reference: _rst.Reference) -> None:
        self.reference = reference

    def find(self, anchor: str, name: str) -> _rst.AttributeDoc | None:
        """The documentation, with a value text, of attribute ``name`` at ``anchor``."""
        found = self._follow(anchor, name, set())
        if found is None:
            source = _annotations.TYPE_SOURCES.get(anchor) or _annotations.TYPE_SOURCES.get(name)
            if source is not None:
                found = self._at(*source, set())
        return found

    def _follow(self, anchor: str, name: str, seen: set[str]) -> _rst.AttributeDoc | None:
        doc = self.reference.attributes.get(anchor)
        if doc is None or anchor in seen:
            return None
        seen.add(anchor)
        if doc.value is not None:
            return doc
        for target in _rst.refs_in(doc.description):
            found = self._at(target, name, seen)
            if found is not None:
                return found
        return None

    def _at(self, label: str, name: str, seen: set[str]) -> _rst.AttributeDoc | None:
        """Attribute ``name`` of the element, or in the section, labelled ``label``."""
        element = self.reference.elements.get(label)
        if element is not None:
            for anchor in element.attribute_anchors:
                if anchor.rsplit("-", 1)[-1] == name:
                    found = self._follow(anchor, name, seen)
                    if found is not None:
                        return found
        return self.reference.sections.get(label, {}).get(name)


def elements_from_docs(docs: Path) -> tuple[dict[str, Element], list[tuple[str, str]]]:
    """Elements with their documented attributes and children; and the documented edges."""
    tree = _rst.parse_schema_tree((docs / "XMLschema.rst").read_text())
    reference = _rst.parse_reference((docs / "XMLreference.rst").read_text())
    _rst.parse_reference((docs / "modeling.rst").read_text(), reference)
    resolver = _Resolver(reference)
    elements: dict[str, Element] = {}
    edges: list[tuple[str, str]] = []
    unresolved: list[str] = []

    def attributes(pairs: list[tuple[str, str]]) -> dict[str, Attribute]:
        result = {}
        for name, anchor in pairs:
            doc = resolver.find(anchor, name)
            if doc is None or doc.value is None:
                unresolved.append(anchor)
            else:
                result[name] = parse_value(name, doc.value)
                result[name].description = doc.description
        return result

    def visit(node: _rst.SchemaNode, parent: str | None) -> str:
        key = WORLDBODY if node.anchor == BODY and parent == ROOT else node.anchor
        if parent is not None:
            edges.append((parent, key))
        if key == WORLDBODY:
            # The documented (world)body restricted; the probes say how.
            elements[key] = Element(key, WORLDBODY, node.icon not in _ONCE_ICONS)
            elements[key].children = [visit(node, WORLDBODY)]
            return key
        tag = node.label.removeprefix("(world)")
        element = Element(key, tag, node.icon not in _ONCE_ICONS)
        first = elements.setdefault(key, element)  # in document order
        element.attributes = attributes(node.attributes)
        element.children = [visit(child, key) for child in node.children]
        if node.icon in _RECURSIVE_ICONS:
            element.children.append(key)
            edges.append((key, key))
        if first.to_json() != element.to_json():
            raise SchemaError(f"element {key!r} is documented differently in two places")
        return key

    visit(tree, None)
    for key in META:
        doc = reference.elements[key]
        pairs = [(anchor.rsplit("-", 1)[-1], anchor) for anchor in doc.attribute_anchors]
        elements[key] = Element(key, doc.tag, doc.icon not in _ONCE_ICONS, attributes(pairs))
    if unresolved:
        raise SchemaError("no documented type for: " + ", ".join(unresolved))
    elements[BODY].children.extend(META)
    return elements, edges


# The merging table's behaviors (modeledit.rst, "Attribute Merging"), by their names there.
_MERGE_BEHAVIORS = {"Minimum": "min", "Maximum": "max", "OR (union)": "or", "Error": None}


def merge_rules_from_docs(docs: Path, elements: dict[str, Element]) -> None:
    """Give each attribute the documented way two models' values merge when one model is
    attached to the other (``compiler/conflict="merge"``: the table of
    ``programming/modeledit.rst``); a row naming a whole element (``option-flag``) gives
    it to each of its attributes."""
    text = (docs / "programming" / "modeledit.rst").read_text()
    table = re.search(r"\.\. list-table:: Attribute Merging Behavior.*?(?=\n\S)", text, re.S)
    if table is None:
        raise SchemaError("modeledit.rst has no Attribute Merging Behavior table")
    rows = re.split(r"\n\s*\* - ", table.group(0))[1:]
    for row in rows:
        heading = re.match(r"\*\*(.+?)\*\*", row)
        if heading is None or heading.group(1) == "Behavior":
            continue
        if heading.group(1) not in _MERGE_BEHAVIORS:
            raise SchemaError(f"unknown merging behavior {heading.group(1)!r} in modeledit.rst")
        rule = _MERGE_BEHAVIORS[heading.group(1)]
        fields = row.split("\n     - ")[1]  # the row's second cell: its fields
        for anchor in re.findall(r":ref:`[^`<]*<([\w-]+)>`", fields):
            for attribute in _anchored(anchor, elements):
                attribute.merge = rule


def _anchored(anchor: str, elements: dict[str, Element]) -> list[Attribute]:
    """The attributes a documentation anchor names: an element's, or one attribute."""
    if anchor in elements:
        return list(elements[anchor].attributes.values())
    key, _, name = anchor.rpartition("-")
    if key in elements and name in elements[key].attributes:
        return [elements[key].attributes[name]]
    raise SchemaError(f"the merging table of modeledit.rst names {anchor!r}, no attribute")


def listed_values(description: str) -> list[str]:
    """Values a description lists one per line (``:at-val:`sphere` (subdivision)``)."""
    return re.findall(r"^(?:\* - )?:at(?:-val)?:`(\w+)`", description, re.MULTILINE)
