"""Checking a document's names and references without building its elements: the fast
way `mjcf.io.parser` reads a model, after the XML Schema (`mjcf.io.xsd`) accepted it.

    found = indexer.index(xml_root, check_references=True)
    if found is None: ...  # a document to read element by element
    names, referenced = found
    names['joint']['hip']  # the lxml element of the joint called 'hip'

It checks what the element-by-element reader checks beyond the schema, and returns None
for any error and anything it does not handle, so that reader raises or reads it.
"""

from __future__ import annotations

from collections import defaultdict
from typing import TYPE_CHECKING

from mjcf import schema
from mjcf.io import xsd
from mjcf.schema import values
from mjcf.tree.namescope import NAMED_AFTER_FILE, PREFIX_SEPARATOR, WORLD, name_from_file
from mjcf.tree.references import ANY_NAMESPACE

if TYPE_CHECKING:
    from lxml import etree

    from mjcf.schema import AttributeSpec, ElementSpec

# Elements whose contents MuJoCo names itself: read element by element.
_GENERATING = frozenset({"replicate", "attach"})
# Actions a plan keeps, at most (a real model has a few per plan).
_MOST_ACTIONS = 256


class _Fallback(Exception):
    """The document is one for the element-by-element reader."""


class _Plan:
    """What the pass does for an element of one spec, worked out once per spec: an
    element that may have an identifier or a few references, and nothing else to
    check, is read attribute by attribute (`direct`); any other is read by the
    `_Action` for the attributes it has."""

    __slots__ = (
        "actions",
        "crashing",
        "direct",
        "dynamic",
        "identifier",
        "implicit",
        "loose",
        "namespace",
        "reference_items",
        "rules",
        "single",
        "spec",
        "unchecked",
    )

    def __init__(self, spec: ElementSpec) -> None:
        self.spec = spec
        # The namespace of its names ('' for elements that have none, whose plans have no
        # identifier either).
        self.namespace = spec.namespace or ""
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
        self.reference_items = tuple(static)  # (attribute, namespace)
        self.dynamic = tuple(dynamic)
        self.unchecked = xsd.unchecked(spec)
        self.single = not spec.repeated
        self.rules = spec.rules
        self.crashing = spec.crashing_children  # what crashes MuJoCo (see _refusals)
        rare = self.dynamic or self.unchecked or self.rules or self.crashing or self.loose
        self.direct = not (rare or self.single or self.implicit or len(static) > 2)
        self.actions: dict[tuple[str, ...], _Action] = {}

    def action(self, keys: tuple[str, ...]) -> _Action:
        """The action for an element with attributes `keys`, made once."""
        found = self.actions.get(keys)
        if found is None:
            if len(self.actions) >= _MOST_ACTIONS:  # a document making up combinations
                self.actions.clear()
            found = self.actions[keys] = _Action(self, frozenset(keys))
        return found


class _Action:
    """What the pass does for an element of one plan with one set of attributes: the
    attributes to read, and the checks that depend on more than which attributes are
    set (rules that depend on which attributes are set are decided here, once)."""

    __slots__ = (
        "broken",
        "checks",
        "crashing",
        "dynamic",
        "identifier",
        "implicit",
        "loose",
        "rare",
        "references",
        "rules",
        "single",
        "unchecked",
    )

    def __init__(self, plan: _Plan, keys: frozenset[str]) -> None:
        identifier = plan.identifier
        self.identifier = identifier if identifier in keys else None
        self.implicit = identifier is not None and self.identifier is None and plan.implicit
        self.references = tuple(item for item in plan.reference_items if item[0] in keys)
        self.loose = tuple(name for name in plan.loose if name in keys)
        self.dynamic = tuple(a for a in plan.dynamic if a.name in keys)
        self.unchecked = tuple(a for a in plan.unchecked if a.name in keys)
        # A rule that counts blank values as not given may depend on the values, when
        # the attributes it needs are set; every other rule on which attributes are set.
        self.rules = tuple(
            rule
            for rule in plan.rules
            if rule.blank_is_none
            and (
                (rule.kind == "requires" and rule.groups[0][0] in keys)
                or (rule.kind == "one_of" and any(keys.issuperset(g) for g in rule.groups))
            )
        )
        present = dict.fromkeys(keys, "given")
        self.broken = any(rule.broken_by(present) for rule in plan.rules if rule not in self.rules)
        self.crashing = tuple(item for item in plan.crashing if item[0] is None or item[0] in keys)
        self.single = plan.single
        self.checks = bool(  # see _check_rare
            self.broken
            or self.loose
            or self.dynamic
            or self.unchecked
            or self.rules
            or self.crashing
        )
        self.rare = self.checks or self.single


class _ByParent:
    """The plans of a tag that has different specs in one section, by its parent's tag."""

    __slots__ = ("plans",)

    def __init__(self, specs: dict[str, ElementSpec]) -> None:
        self.plans = {parent: _plan(spec) for parent, spec in specs.items()}

    def of(self, xml: etree._Element) -> _Plan:
        plan = self.plans.get(xml.getparent().tag)
        if plan is None:
            raise _Fallback
        return plan


class _SectionPlans:
    """The plans of the elements of one top-level section: `known`, {tag: the plan of
    that tag's elements anywhere in the section (a `_ByParent` for a tag with different
    specs; None for a tag read element by element)}, each made (`make`) when a document
    first has that tag. A plain dict, whose lookups cost the least.

    They let `index` be one loop over each section's elements in document order, not a
    walk down the tree: within one top-level section a tag has one spec wherever it
    appears (the schema has put it only where it may be), the few tags that do not are
    told apart by their parent's tag, and what is checked of an element of each spec is
    worked out the first time a document has one (`_Plan`)."""

    def __init__(self, section: ElementSpec) -> None:
        self.known: dict[object, _Plan | _ByParent | None] = {}
        # {tag: {parent tag: spec}} from the section's part of the schema; None for a
        # tag with two specs under parents of one tag.
        self.specs: defaultdict[str, dict[str, ElementSpec] | None] = defaultdict(dict)
        pending, seen = [section], {id(section)}
        while pending:
            parent = pending.pop()
            for tag, spec in parent.children.items():
                if tag in _GENERATING:
                    continue
                by_parent = self.specs[tag]
                if by_parent is not None and by_parent.setdefault(parent.tag, spec) is not spec:
                    self.specs[tag] = None
                if id(spec) not in seen:
                    seen.add(id(spec))
                    pending.append(spec)

    def make(self, tag: object) -> _Plan | _ByParent | None:
        """The plan for `tag`, made now and known from then on."""
        by_parent = self.specs.get(tag) if isinstance(tag, str) else None  # not for entities
        plan: _Plan | _ByParent | None = None
        if by_parent:
            distinct = {id(spec): spec for spec in by_parent.values()}
            if len(distinct) == 1:
                plan = _plan(next(iter(distinct.values())))
            else:
                plan = _ByParent(by_parent)
        self.known[tag] = plan
        return plan


_plans: dict[int, _Plan] = {}
_sections: dict[str, _SectionPlans] = {}


def _plan(spec: ElementSpec) -> _Plan:
    plan = _plans.get(id(spec))
    if plan is None:
        plan = _plans[id(spec)] = _Plan(spec)
    return plan


def _section_plans(tag: str) -> _SectionPlans:
    plans = _sections.get(tag)
    if plans is None:
        plans = _sections[tag] = _SectionPlans(schema.MUJOCO.children[tag])
    return plans


def index(
    xml_root: etree._Element, check_references: bool
) -> tuple[dict[str, dict[str, etree._Element]], dict[str, frozenset[str]]] | None:
    """({namespace: {name: lxml element}}, {namespace: the names references name}) of
    the document under `xml_root`, a `<mujoco>` whose children are top-level sections
    (a section may be repeated: its copies count as one); the names references in
    default classes name are under ANY_NAMESPACE. None if the document is one for the
    element-by-element reader.

    It checks in Python what reading element by element checks beyond the XML Schema:
    names unique in their namespace, references naming elements that exist, elements that
    may appear once appearing once (once in a section repeated at the top level too, whose
    copies MuJoCo merges), rules between attributes, and the values the schema leaves to
    the converters. It handles the common document; for anything else (an empty name or
    reference, a '/', generated or clashing names, a `<replicate>`, any error ...) it
    returns None, and the element-by-element reader reads the document, which raises the
    error naming the element, or reads what this pass does not handle."""
    names: defaultdict[str, dict[str, etree._Element]] = defaultdict(dict)
    implicit: defaultdict[str, dict[str, etree._Element]] = defaultdict(dict)
    references: defaultdict[str, list[str]] = defaultdict(list)
    loose: set[str] = set()
    singles: set[tuple[etree._Element, str]] = set()  # (parent, tag) of once-only elements
    first_copy: dict[etree._Element, etree._Element] = {}  # repeated sections: each -> first
    seen: dict[str, etree._Element] = {}
    for xml_section in xml_root:
        first_copy[xml_section] = seen.setdefault(xml_section.tag, xml_section)
    try:
        for xml_section in xml_root:
            plans = _section_plans(xml_section.tag)
            known = plans.known
            for xml in xml_section.iterdescendants():
                try:
                    found = known[xml.tag]
                except KeyError:
                    found = plans.make(xml.tag)
                if isinstance(found, _Plan):
                    plan = found
                elif found is None:
                    raise _Fallback
                else:
                    plan = found.of(xml)
                if plan.direct:
                    identifier = plan.identifier
                    reference_items = plan.reference_items
                else:
                    keys = tuple(xml.keys())
                    action = plan.actions.get(keys) or plan.action(keys)
                    identifier = action.identifier
                    reference_items = action.references
                    if action.implicit:
                        name = name_from_file(xml.get("file"))
                        if name is not None:
                            implicit[plan.namespace].setdefault(name, xml)
                    if action.rare:  # few elements need any of these
                        if action.checks:
                            _check_rare(xml, action, loose, references)
                        if action.single:
                            parent = xml.getparent()
                            key = (first_copy.get(parent, parent), xml.tag)
                            if key in singles:
                                raise _Fallback
                            singles.add(key)
                if identifier is not None:
                    name = xml.get(identifier)
                    if name is not None:
                        table = names[plan.namespace]
                        if name in table or PREFIX_SEPARATOR in name or not name:
                            raise _Fallback
                        table[name] = xml
                for attribute, namespace in reference_items:
                    text = xml.get(attribute)
                    if text is not None:
                        if PREFIX_SEPARATOR in text or not text:
                            raise _Fallback
                        references[namespace].append(text)
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


def _check_rare(
    xml: etree._Element,
    action: _Action,
    loose: set[str],
    references: defaultdict[str, list[str]],
) -> None:
    """Record the references of default classes and those whose namespace another
    attribute selects; check values, rules and children that crash MuJoCo."""
    if action.broken:
        raise _Fallback
    for name in action.loose:
        text = xml.get(name)
        if text:
            loose.update(text.split())
    if action.dynamic:
        _dynamic_references(xml, action.dynamic, references)
    for attribute in action.unchecked:
        try:
            attribute.converter.check_text(xml.get(attribute.name, ""))
        except values.InvalidValue:
            raise _Fallback from None
    if action.rules:
        attributes = xml.attrib
        if any(rule.broken_by(attributes) for rule in action.rules):
            raise _Fallback
    for needed, tag, child_attribute, _ in action.crashing:
        if needed is None or xml.get(needed) is not None:
            for child in xml.iterchildren(tag):
                if child_attribute is None or child.get(child_attribute) is not None:
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
