"""Checking a document's names and references without building its elements: the fast
way `mjcf.parser` reads a model.

    found = indexer.index(xml_root, sections, check_references=True)
    if found is None:      # a document to read element by element
        ...
    names, referenced = found
    names['joint']['hip']  # the lxml element of the joint called 'hip'

After the XML Schema (`mjcf.xsd`) has accepted the document, this pass checks in Python
what reading element by element checks beyond it: names unique in their namespace,
references naming elements that exist, elements that may appear once appearing once,
rules between attributes, and the values the schema leaves to the converters. It
handles the common document; for anything else (an empty name or reference, a '/',
generated or clashing names, a `<replicate>`, any error ...) it returns None and the
element-by-element reader reads the document, which raises the error naming the
element, or reads what this pass does not handle.
The elements themselves are built when first used (see `Element._defer`).
"""

from __future__ import annotations

from collections import defaultdict
from typing import TYPE_CHECKING

from mjcf import values, xsd
from mjcf.namescope import NAMED_AFTER_FILE, PREFIX_SEPARATOR, WORLD, name_from_file
from mjcf.references import ANY_NAMESPACE

if TYPE_CHECKING:
    from lxml import etree

    from mjcf.schema import AttributeSpec, ElementSpec

# Elements whose contents MuJoCo names itself: read element by element.
_GENERATING = frozenset({"replicate", "attach"})


class _Fallback(Exception):
    """The document is one for the element-by-element reader."""


class _Plan:
    """What the pass does for an element of one spec, worked out once per spec."""

    __slots__ = (
        "children",
        "crashing",
        "dynamic",
        "identifier",
        "implicit",
        "loose",
        "many_references",
        "namespace",
        "rare",
        "reference_items",
        "references",
        "rule_names",
        "rules",
        "single",
        "unchecked",
    )

    def __init__(self, spec: ElementSpec) -> None:
        self.namespace = spec.namespace
        self.identifier = spec.identifier if spec.namespace is not None else None
        self.implicit = spec.tag in NAMED_AFTER_FILE
        static: list[tuple[str, str]] = []
        dynamic: list[AttributeSpec] = []
        # References inside default classes are resolved where a class is used: they are
        # only recorded (`referenced`), not checked.
        self.loose = tuple(spec.references) if spec.key.startswith("default-") else ()
        if not self.loose:
            for name in spec.references:
                attribute = spec.attributes[name]
                if attribute.namespace_from is None and not attribute.is_list:
                    if attribute.namespace is not None:
                        static.append((name, attribute.namespace))
                else:
                    dynamic.append(attribute)
        self.references = dict(static)  # attribute -> namespace
        self.reference_items = tuple(static)
        self.many_references = len(static) > 5
        self.dynamic = tuple(dynamic)
        self.unchecked = xsd.unchecked(spec)
        self.single = not spec.repeated
        # Rules between attributes ("at most one of quat, euler ..."), checked only when
        # more than one of their attributes is set, or when one must be.
        self.rules = spec.rules
        self.rule_names = spec.rule_names
        self.crashing = spec.crashing_children  # what crashes MuJoCo (see _refusals)
        self.rare = bool(
            self.dynamic
            or self.unchecked
            or self.single
            or self.rules
            or self.crashing
            or self.loose
        )
        self.children: dict[str, _Plan] = {}


_plans: dict[int, _Plan] = {}


def _plan(spec: ElementSpec) -> _Plan:
    plan = _plans.get(id(spec))
    if plan is None:
        plan = _plans[id(spec)] = _Plan(spec)
        plan.children = {
            tag: _plan(child) for tag, child in spec.children.items() if tag not in _GENERATING
        }
    return plan


def index(
    xml_root: etree._Element, sections: dict[str, ElementSpec], check_references: bool
) -> tuple[dict[str, dict[str, etree._Element]], dict[str, frozenset[str]]] | None:
    """({namespace: {name: lxml element}}, {namespace: the names references name}) of
    the document under `xml_root`, whose top-level sections have `sections` (by tag),
    once each; those of default classes under ANY_NAMESPACE. None if the document is one
    for the element-by-element reader (see the module docstring)."""
    names: defaultdict[str, dict[str, etree._Element]] = defaultdict(dict)
    implicit: defaultdict[str, dict[str, etree._Element]] = defaultdict(dict)
    references: defaultdict[str, list[str]] = defaultdict(list)
    loose: set[str] = set()

    def walk(plans: dict[str, _Plan], xml_parent: etree._Element) -> None:
        singles = None
        for xml in xml_parent:
            tag = xml.tag
            plan = plans.get(tag)  # not a str for entities: not found
            if plan is None:
                raise _Fallback
            identifier = plan.identifier
            namespace = plan.namespace
            if identifier is not None and namespace is not None:  # both, or no identifier
                name = xml.get(identifier)
                if name is not None:
                    table = names[namespace]
                    if name in table or PREFIX_SEPARATOR in name or not name:
                        raise _Fallback
                    table[name] = xml
                elif plan.implicit:
                    name = name_from_file(xml.get("file"))
                    if name is not None:
                        implicit[namespace].setdefault(name, xml)
            if plan.many_references:  # one call for every attribute, not one each
                selected = plan.references
                for attribute, text in xml.items():
                    namespace = selected.get(attribute)
                    if namespace is not None:
                        if PREFIX_SEPARATOR in text or not text:
                            raise _Fallback
                        references[namespace].append(text)
            else:
                for attribute, namespace in plan.reference_items:
                    text = xml.get(attribute)
                    if text is not None:
                        if PREFIX_SEPARATOR in text or not text:
                            raise _Fallback
                        references[namespace].append(text)
            if plan.rare:  # few elements need any of these
                for attribute in plan.loose:
                    text = xml.get(attribute)
                    if text:
                        loose.update(text.split())
                if plan.dynamic:
                    _dynamic_references(xml, plan.dynamic, references)
                if plan.unchecked:
                    _check_values(xml, plan.unchecked)
                if plan.rules:
                    _check_rules(xml, plan)
                for attribute, tag, child_attribute, _ in plan.crashing:
                    if attribute is None or xml.get(attribute) is not None:
                        for child in xml.iterchildren(tag):
                            if child_attribute is None or child.get(child_attribute) is not None:
                                raise _Fallback
                if plan.single:
                    if singles is None:
                        singles = set()
                    elif tag in singles:
                        raise _Fallback
                    singles.add(tag)
            if len(xml):
                walk(plan.children, xml)

    try:
        for xml_section in xml_root:
            walk(_plan(sections[xml_section.tag]).children, xml_section)
    except _Fallback:
        return None
    for namespace, table in implicit.items():
        named = names[namespace]
        if not named.keys().isdisjoint(table):
            return None  # which of them keeps the name depends on their order
        named.update(table)
    if WORLD in names.get("body", ()):
        return None  # the world body's name
    referenced = {namespace: frozenset(targets) for namespace, targets in references.items()}
    if check_references:
        allowed = {"body": {WORLD}, "default": {"main"}}
        for namespace, targets in referenced.items():
            missing = targets.difference(names.get(namespace, ()), allowed.get(namespace, ()))
            if missing:
                return None
    referenced[ANY_NAMESPACE] = frozenset(loose)
    return dict(names), referenced


def _check_values(xml: etree._Element, attributes: tuple[AttributeSpec, ...]) -> None:
    """Check the values the XML Schema leaves to the converters."""
    for attribute in attributes:
        text = xml.get(attribute.name)
        if text is not None:
            try:
                attribute.converter.check_text(text)
            except values.InvalidValue:
                raise _Fallback from None


def _check_rules(xml: etree._Element, plan: _Plan) -> None:
    """Check the rules between the attributes of `xml` (see `ElementSpec.rules`)."""
    names = plan.rule_names.intersection(xml.keys())
    if (len(names) > 1 or any(rule.kind != "at_most_one" for rule in plan.rules)) and any(
        rule.broken_by(xml.attrib) for rule in plan.rules
    ):
        raise _Fallback


def _dynamic_references(
    xml: etree._Element,
    attributes: tuple[AttributeSpec, ...],
    references: defaultdict[str, list[str]],
) -> None:
    """Record the references of `xml` whose namespace another attribute selects, or that
    name several elements."""
    for attribute in attributes:
        text = xml.get(attribute.name)
        if text is None:
            continue
        if PREFIX_SEPARATOR in text:
            raise _Fallback
        namespace = attribute.reference_namespace(xml.attrib)
        if namespace is not None:
            targets = text.split() if attribute.is_list else [text]
            references[namespace].extend(targets)
