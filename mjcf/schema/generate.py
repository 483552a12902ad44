"""Generate ``mjcf_schema.json``, MuJoCo's MJCF schema as data, from the installed mujoco.

    python -m mjcf.schema.generate            # rewrite mjcf/schema/mjcf_schema.json
    python -m mjcf.schema.generate --check    # exit 1 if the checked-in file is stale

Run it after upgrading mujoco and commit the result. Where the data comes from:

* the element tree, attribute names and order: ``XMLschema.rst`` in the wheel;
* attribute types, keywords, defaults, required-ness: ``XMLreference.rst`` and
  the ``modeling.rst`` sections it points to ("See :ref:`CSensor`");
* what the documentation does not say (which element a name refers to, which
  strings are file paths): the hand-kept tables in ``_annotations.py``; a string
  attribute they do not cover stops the generator with a list to decide on;
* what only MuJoCo's XML reader knows, probed with ``MjSpec.from_string``
  (``_probe.py``): how many numbers each attribute takes, which children
  ``worldbody``, ``frame`` and ``replicate`` accept, which object types name
  things. Every element, parent, attribute and keyword the documents give is
  also checked against the reader; where they disagree the reader wins and a
  note is logged.

The file maps element keys (MuJoCo's doc anchors: ``body-geom``,
``default-geom``, ``actuator-position``; plus ``worldbody``) to
``{"tag", "namespace", "repeated", "attributes", "children"}``. Attribute
specs have a ``type`` of ``identifier``, ``string``, ``file``, ``reference``
(``namespace``, or ``namespace_from``/``namespace_map``; ``list``),
``keyword`` (``values``) or ``int``/``real`` (``min``/``max`` numbers, ``max``
null when unbounded, ``multiple_of``), with ``required`` and ``default``.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import mujoco

from mjcf.schema import _annotations, _probe, _rst
from mjcf.schema._probe import Probe

OUTPUT = Path(__file__).with_name("mjcf_schema.json")
ROOT = "mujoco"
BODY = "body"
WORLDBODY = "worldbody"
DEFAULT = "default"
# Meta elements the reference documents outside XMLschema.rst (include is the
# parser's business, not the schema's).
META = ("body-frame", "replicate")
# Elements holding the kinematic tree; their children are probed.
TREE_HOLDERS = (WORLDBODY, BODY, *META)
ANY_OBJECT_TYPE = "(any element type that can be named)"
_ONCE_ICONS = {"!", "?", "dot", "star"}  # star: the root
_RECURSIVE_ICONS = {"@", "sync"}

logger = logging.getLogger(__name__)


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
    namespace: str | None = None
    namespace_from: str | None = None
    namespace_map: dict[str, str] = field(default_factory=dict)
    is_list: bool = False
    any_object_type: bool = False  # keyword over every type of named element
    description: str = ""  # the documentation text, for values listed there

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
        elif self.kind in ("int", "real"):
            spec["min"] = self.min
            spec["max"] = self.max
            if self.multiple_of:
                spec["multiple_of"] = self.multiple_of
        spec["required"] = self.required
        if self.kind in ("string", "keyword", "int", "real"):
            spec["default"] = self.default
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

    def to_json(self) -> dict:
        """The element's entry in the JSON file."""
        return {
            "tag": self.tag,
            "namespace": self.namespace,
            "repeated": self.repeated,
            "attributes": {name: a.to_json() for name, a in self.attributes.items()},
            "children": self.children,
        }


# -- the documents ----------------------------------------------------------------


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


def classify_strings(elements: dict[str, Element]) -> None:
    """Give each string attribute its kind: identifier, reference, file or string."""
    unclassified = []
    for key, element in elements.items():
        for name, attribute in element.attributes.items():
            if attribute.kind != "string":
                continue
            choice = _annotations.BY_ELEMENT.get((key, name))
            if name == "name" or (key == DEFAULT and name == "class"):
                attribute.kind = "identifier"
            elif choice is None and name in _annotations.NAMESPACE_FROM:
                attribute.kind = "reference"
                attribute.namespace_from = _annotations.NAMESPACE_FROM[name]
            elif choice in (None, "string", "file"):
                choice = choice or _annotations.REFERENCES.get(name)
                if choice is None and name in _annotations.FILES:
                    choice = "file"
                if choice is None and name in _annotations.PLAIN_STRINGS:
                    choice = "string"
                if choice is None:
                    unclassified.append(f"{key}/{name}")
                elif choice in ("string", "file"):
                    attribute.kind = choice
                else:
                    attribute.kind, attribute.namespace = "reference", choice
            else:
                attribute.kind, attribute.namespace = "reference", choice
            if attribute.kind not in ("reference", "keyword"):
                attribute.is_list = False
    if unclassified:
        raise SchemaError(
            "string attributes not classified in _annotations.py (reference, file or "
            "plain string?): " + ", ".join(unclassified)
        )


def assign_namespaces(elements: dict[str, Element], object_types: list[str]) -> None:
    """The namespace of each element's name: its object type, or its section's."""
    parents: dict[str, list[str]] = {}
    for key, element in elements.items():
        for child in element.children:
            parents.setdefault(child, []).append(key)
    problems = []
    for key, element in elements.items():
        if key == DEFAULT:
            element.namespace = DEFAULT
        elif key in _annotations.ELEMENT_NAMESPACES:
            element.namespace = _annotations.ELEMENT_NAMESPACES[key]
        elif "name" in element.attributes:
            # A grouping section without attributes named for an object type
            # (<sensor>, <actuator>) names the kinds below it (<touch>, <motor>).
            sections = [
                elements[p].tag
                for p in parents.get(key, [])
                if not elements[p].attributes and elements[p].tag in object_types
            ]
            if sections:
                element.namespace = sections[0]
            elif element.tag in object_types:
                element.namespace = element.tag
            else:
                problems.append(key)
    if problems:
        raise SchemaError("named elements without a namespace: " + ", ".join(problems))
    namespaces = {e.namespace for e in elements.values() if e.namespace}
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.namespace_from:
                selector = element.attributes[attribute.namespace_from]
                attribute.namespace_map = {
                    value: _annotations.OBJECT_TYPE_ALIASES.get(value, value)
                    for value in selector.values
                }
                targets = set(attribute.namespace_map.values())
            elif attribute.kind == "reference":
                targets = {attribute.namespace}
            else:
                continue
            if not targets <= namespaces:
                raise SchemaError(
                    f"{key}/{attribute.name} refers to unknown {targets - namespaces}"
                )


# -- the reader ---------------------------------------------------------------------


def complete_with_probes(elements: dict[str, Element], edges: list[tuple[str, str]]) -> None:
    """Check the documented schema against MuJoCo's reader and fill in what it knows."""
    prober = _probe.Prober(elements, ROOT)
    prober.set_paths()
    _object_types(prober, elements)
    _tree_holders(prober, elements)
    _required(prober, elements)
    _enumerated_strings(prober, elements)
    _minimal(prober, elements)
    _edges(prober, elements, edges)
    _values(prober, elements)
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind in ("int", "real"):
                _arity(prober, key, attribute)
    logger.info("probed MuJoCo's reader with %d documents", prober.parses)


def _object_types(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Keywords over every named type; then the element namespaces that build on them."""
    documented = [
        (key, a)
        for key, element in elements.items()
        for a in element.attributes.values()
        if a.any_object_type
    ]
    accepted = {
        (key, a.name): _probe.accepted_keywords(prober, key, a.name, _probe.OBJECT_TYPES)
        for key, a in documented
    }
    object_types = [t for t in _probe.OBJECT_TYPES if all(t in ok for ok in accepted.values())]
    for key, attribute in documented:
        attribute.values = object_types
        if len(accepted[key, attribute.name]) == len(_probe.OBJECT_TYPES):
            _note(f"{key}/{attribute.name}: the reader accepts any object type name")
    assign_namespaces(elements, object_types)


def _tree_holders(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Children of worldbody, body, frame, replicate, default; worldbody's attributes."""
    body, default = elements[BODY], elements[DEFAULT]
    candidates = list(body.children)
    for key in TREE_HOLDERS:
        documented = list(elements[key].children)
        allowed = _probe.allowed_children(prober, key, candidates)
        elements[key].children = allowed
        if key == BODY and allowed != documented:
            _note(f"body: documented children {documented}, the reader accepts {allowed}")
    by_tag = {elements[key].tag: key for key in candidates}
    by_tag.update({elements[key].tag: key for key in default.children})
    allowed = _probe.allowed_children(prober, DEFAULT, list(by_tag.values()))
    if set(allowed) != set(default.children):
        raise SchemaError(f"default: documented {default.children}, reader accepts {allowed}")
    accepted = _probe.accepted_attributes(prober, WORLDBODY, list(body.attributes.values()))
    elements[WORLDBODY].attributes = {name: body.attributes[name] for name in accepted}


def _enumerated_strings(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Strings the reader looks up in a list are keywords; their values are in the docs."""
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "string":
                continue
            error = prober.error(Probe(key, {attribute.name: "probe_text"}))
            if error is None:
                continue
            if not _probe.bad_keyword(error, "probe_text"):
                _note(f"{key}/{attribute.name}: the reader checks the text: {error}")
                continue
            values = re.findall(r"^(?:\* - )?:at(?:-val)?:`(\w+)`", attribute.description, re.M)
            if not values:
                raise SchemaError(f"{key}/{attribute.name}: a keyword, but no values documented")
            _note(f"{key}/{attribute.name}: documented string, the reader takes keywords {values}")
            attribute.kind, attribute.values = "keyword", values


def _required(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Attributes the reader requires that the documentation calls optional."""
    pending = list(elements)
    while pending:
        keys, pending = pending, []
        errors = prober.errors([Probe(key) for key in keys])
        for key, error in zip(keys, errors, strict=True):
            missing = re.search(r"required attribute missing: '(\w+)'", error or "")
            if missing:
                _note(f"{key}/{missing.group(1)}: documented optional, the reader requires it")
                elements[key].attributes[missing.group(1)].required = True
                pending.append(key)


def _minimal(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Each element with its required attributes is accepted; without one, rejected."""
    prober.require_accepted([Probe(key) for key in elements])
    for key, element in elements.items():
        for attribute in element.attributes.values():
            omitted = Probe(key, omit=(attribute.name,))
            if attribute.required and prober.error(omitted) is None:
                _note(
                    f"{key}/{attribute.name}: documented required, the reader does not require it"
                )
                attribute.required = False


def _edges(
    prober: _probe.Prober, elements: dict[str, Element], edges: list[tuple[str, str]]
) -> None:
    """Each documented child is accepted under its parent, repeated if it may repeat."""
    probes = [
        Probe(child, parent=parent, copies=2 if elements[child].repeated else 1)
        for parent, child in edges
    ]
    prober.require_accepted(probes)
    for parent, child in edges:
        once = not elements[child].repeated
        if once and prober.error(Probe(child, parent=parent, copies=2)) is None:
            _note(f"{child}: documented once per {parent}, the reader accepts two")
            elements[child].repeated = True


def _values(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Each attribute and each keyword value is known to the reader.

    A probe whose value the reader reads and then rejects for what it means
    (a mesh ``builtin`` without its ``params``) still shows the attribute and
    the keyword are known; only errors about them count against the schema.
    """
    probes = []
    for key, element in elements.items():
        for attribute in element.attributes.values():
            values = attribute.values if attribute.kind == "keyword" else [prober.value(attribute)]
            probes.extend((key, attribute, value) for value in values)
            if key in META and not _probe.has_effect(prober, key, attribute):
                raise SchemaError(f"{key}/{attribute.name}: MuJoCo ignores this attribute")
    errors = prober.errors([Probe(key, {a.name: value}) for key, a, value in probes])
    unknown = []
    for (key, attribute, value), error in zip(probes, errors, strict=True):
        if error and _probe.unrecognized(error, attribute.name):
            unknown.append(f"{key}/{attribute.name}")
        elif error and _probe.bad_keyword(error, value):
            _note(f"{key}/{attribute.name}: the reader rejects documented keyword {value!r}")
            attribute.values.remove(value)
    if unknown:
        raise SchemaError("documented attributes MuJoCo's reader does not know: " + str(unknown))
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "keyword" or attribute.any_object_type:
                continue
            if _accepts(prober, key, attribute.name, "probe_keyword"):
                _note(f"{key}/{attribute.name}: the reader accepts any keyword")
            pair = " ".join(attribute.values[:2])
            if len(attribute.values) > 1 and _accepts(prober, key, attribute.name, pair):
                attribute.is_list = True


def _accepts(prober: _probe.Prober, key: str, name: str, value: str) -> bool:
    """Whether the reader takes ``value`` for keyword attribute ``name`` of ``key``."""
    error = prober.error(Probe(key, {name: value}))
    return error is None or not _probe.bad_keyword(error, value, name)


def _arity(prober: _probe.Prober, key: str, attribute: Attribute) -> None:
    arity = _probe.arity(prober, key, attribute)
    attribute.min, attribute.max = arity.min, arity.max
    documented = f"documented {attribute.count or 'model-dependent'} numbers"
    if attribute.count is not None and arity.max != attribute.count:
        _note(f"{key}/{attribute.name}: {documented}, the reader takes up to {arity.max}")
    if arity.gaps:
        _note(
            f"{key}/{attribute.name}: the reader rejects {arity.gaps} of {arity.min}..{arity.max}"
        )


def _note(message: str) -> None:
    logger.info("note: %s", message)


# -- output -------------------------------------------------------------------------


def build(docs: Path | None = None) -> dict:
    """The schema of the installed mujoco, as the JSON-ready dictionary."""
    elements, edges = elements_from_docs(docs or doc_dir())
    classify_strings(elements)
    complete_with_probes(elements, edges)
    return {
        "mujoco_version": mujoco.__version__,
        "root": ROOT,
        "elements": {key: element.to_json() for key, element in elements.items()},
    }


def dumps(schema: dict) -> str:
    """The JSON text: one line per attribute, so diffs show what changed."""
    lines = ["{"]
    lines.append(f'  "mujoco_version": {json.dumps(schema["mujoco_version"])},')
    lines.append(f'  "root": {json.dumps(schema["root"])},')
    lines.append('  "elements": {')
    items = list(schema["elements"].items())
    for position, (key, element) in enumerate(items):
        lines.append(f"    {json.dumps(key)}: {{")
        for field_name in ("tag", "namespace", "repeated"):
            lines.append(f"      {json.dumps(field_name)}: {json.dumps(element[field_name])},")
        attributes = list(element["attributes"].items())
        if attributes:
            lines.append('      "attributes": {')
            for index, (name, spec) in enumerate(attributes):
                comma = "," if index < len(attributes) - 1 else ""
                lines.append(f"        {json.dumps(name)}: {json.dumps(spec)}{comma}")
            lines.append("      },")
        else:
            lines.append('      "attributes": {},')
        lines.append(f'      "children": {json.dumps(element["children"])}')
        lines.append("    }" + ("," if position < len(items) - 1 else ""))
    lines.extend(["  }", "}"])
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Command line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="fail if the JSON file is stale")
    parser.add_argument("--output", type=Path, default=OUTPUT, help="file to write or check")
    parser.add_argument("-q", "--quiet", action="store_true", help="do not log notes")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING if args.quiet else logging.INFO, format="%(message)s")
    text = dumps(build())
    if args.check:
        current = args.output.read_text() if args.output.exists() else ""
        if current != text:
            logger.error("%s is stale; run `python -m mjcf.schema.generate`", args.output)
            return 1
        return 0
    args.output.write_text(text)
    logger.info("wrote %s", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
