"""Reading a document element by element: each element built and checked as it is read,
errors naming the file, line and element.

    element_reader.read(root, xml_root, filename, escape_separators, resolve, strict_paths)

The path of every document the fast way (`mjcf.io.fast_reader`) declines: one with an error
(which this reader reports), a repeated top-level `<default>` (`mjcf.io.default_sections`),
`strict_paths`, debug mode (which records where each element was read), and the first
documents a process reads. Names are checked unique as read, references once all is read.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from lxml import etree

from mjcf import errors
from mjcf.compose import naming
from mjcf.io import default_sections
from mjcf.schema import AttributeSpec, ElementSpec
from mjcf.schema import values as _values
from mjcf.schema.suggestions import suggest, suggest_child
from mjcf.tree import assets as _assets
from mjcf.tree import builder, debugging, references
from mjcf.tree.element import Element, single_child, stored_attributes, tree_children
from mjcf.tree.namescope import PREFIX_SEPARATOR
from mjcf.tree.root import RootElement


def read(
    root: RootElement,
    xml_root: etree._Element,
    filename: str | None,
    escape_separators: bool,
    resolve_references: bool,
    strict_paths: bool,
) -> None:
    """Read the document under `xml_root` into the new model `root`, element by element;
    raises the mjcf error of the first thing wrong, naming the file, line and element."""
    reader = ElementReader(root, filename, escape_separators)
    reader.build(xml_root)
    reader.link_unnamed()
    references.record_read_names(root, reader.referenced())
    if resolve_references:
        reader.check_references()
    if strict_paths:
        reader.check_files()


def main_class(attrib: dict[str, str], xml: etree._Element, filename: str | None) -> None:
    """Take `class` out of a top-level <default>'s attributes: it is 'main', which MuJoCo
    does not let a model rename; raises mjcf.AttributeValueError for another name."""
    name = attrib.pop("class", None)
    if name not in ("main", "", None):  # an empty name is none, as MuJoCo reads it
        raise errors.AttributeValueError(
            f"{where(filename, xml)}: <default>: 'class' of the top-level default is "
            f"'main', which cannot be renamed, got {name!r}"
        )


def where(filename: str | None, element: etree._Element) -> str:
    """'file:line' of lxml element `element` of the document read from `filename`."""
    source = getattr(element, "base", None) or filename or "<string>"
    return f"{source}:{element.sourceline}"


class ElementReader:
    """Turns an lxml tree into elements of one model."""

    def __init__(self, root: RootElement, filename: str | None, escape_separators: bool) -> None:
        self.root = root
        self.filename = filename
        self.escape = escape_separators
        # Elements that set references, with their specs and attributes (kept here: the
        # checks after reading look at each of them twice).
        self.with_references: list[tuple[Element, ElementSpec, Mapping[str, Any]]] = []
        self.generated_names = False  # <replicate>/<attach> make names we do not see
        # Elements written with a name mjcf generated ('//unnamed_geom_0'), which are
        # read back unnamed, and the elements whose references name one.
        self.unnamed: dict[tuple[str, str], Element] = {}
        self.to_unnamed: list[Element] = []

    def build(self, xml_root: etree._Element) -> None:
        root = self.root
        for name in xml_root.attrib:
            if name != "model" and not name.startswith("{"):
                raise errors.UnknownAttributeError(
                    f"{where(self.filename, xml_root)}: <mujoco> has no attribute {name!r}"
                )
        sections = {section.tag: section for section in tree_children(root)}
        seen: set[str] = set()
        for xml_section in xml_root:
            tag = xml_section.tag
            if not isinstance(tag, str):
                continue
            section = sections.get(tag)
            if section is None:
                raise errors.SchemaError(
                    f"{where(self.filename, xml_section)}: <mujoco> cannot have a <{tag}> child"
                    + suggest(tag, sections)
                )
            attrib = dict(xml_section.attrib)
            if tag == "default":
                main_class(attrib, xml_section, self.filename)
            self.set_attributes(section, attrib, xml_section)
            if tag == "default" and tag in seen:
                default_sections.merge_section(
                    section,
                    xml_section,
                    self.set_attributes,
                    self._add_children,
                    lambda xml: where(self.filename, xml),
                )
            else:
                self._add_children(section, xml_section)
            seen.add(tag)

    def set_attributes(self, element: Element, attrib: dict, xml: etree._Element) -> None:
        spec = element.spec
        attributes = spec.attributes
        for name, text in list(attrib.items()):
            attribute = attributes.get(name)
            if attribute is None:
                if name.startswith("{"):  # namespaced, e.g. xsi:noNamespaceSchemaLocation
                    del attrib[name]
                    continue
                raise errors.UnknownAttributeError(
                    f"{where(self.filename, xml)}: {element.path}: <{spec.tag}> has no attribute "
                    f"{name!r}" + suggest(name, attributes)
                )
            converter = attribute.converter
            if converter.names:
                if not text and not attribute.required:
                    del attrib[name]  # MuJoCo reads an empty name as no name
                elif text[:2] == "//" and spec.namespace and naming.GENERATED.fullmatch(text):
                    self.unnamed[(spec.namespace, text)] = element
                    del attrib[name]
                else:
                    attrib[name] = self._name_text(element, attribute, text, xml)
            elif converter.refers:
                refused = attribute.refused.get(text)
                if refused is not None:
                    raise errors.AttributeValueError(
                        f"{where(self.filename, xml)}: {element.path}: {name!r} {refused}"
                    )
                attrib[name] = self._reference_text(element, attribute, text, xml)
            elif attribute.checks_text:
                try:
                    converter.check_text(text)
                except _values.InvalidValue as error:
                    raise errors.AttributeValueError(
                        f"{where(self.filename, xml)}: {element.path}: {name!r} {error}"
                    ) from None
        stored = builder.attributes_to_fill(element)
        if attrib is not stored:  # a later copy of the element, merged: its values win
            stored.update(attrib)
        if spec.required or spec.rules:
            problem = spec.unmet(stored_attributes(element))
            if problem is not None:
                raise errors.AttributeValueError(
                    f"{where(self.filename, xml)}: {element.path}: {problem}"
                )

    def _reference_text(
        self, element: Element, attribute: AttributeSpec, text: str, xml: etree._Element
    ) -> str:
        if "//" not in text:  # no generated name: the common case
            return self._name_text(element, attribute, text, xml)
        items = text.split() if attribute.is_list else [text]
        generated = [naming.GENERATED.fullmatch(item) is not None for item in items]
        if not any(generated):
            return self._name_text(element, attribute, text, xml)
        self.to_unnamed.append(element)
        return " ".join(
            item if is_generated else self._name_text(element, attribute, item, xml)
            for item, is_generated in zip(items, generated, strict=True)
        )

    def _name_text(
        self, element: Element, attribute: AttributeSpec, text: str, xml: etree._Element
    ) -> str:
        if PREFIX_SEPARATOR in text:
            if not self.escape:
                raise errors.NameClashError(
                    f"{where(self.filename, xml)}: {element.path}: {attribute.name!r} is "
                    f"{text!r}, which contains '/', the separator of attached models' names; "
                    "parse with escape_separators=True to keep it"
                )
            text = text.replace(PREFIX_SEPARATOR, "\\" + PREFIX_SEPARATOR)
        return text

    def _add_children(self, parent: Element, xml_parent: etree._Element | list) -> None:
        specs = parent.spec.children
        root = self.root
        make = builder.new_element
        placed = builder.children_to_fill(parent)
        filename = self.filename
        singles: set[str] | None = None  # tags of this XML parent that may appear once
        for xml in xml_parent:
            tag = xml.tag
            if not isinstance(tag, str):
                if isinstance(xml, etree._Entity):
                    raise errors.ParseError(
                        f"{where(filename, xml_parent)}: entities are not allowed"
                    )
                continue
            spec = specs.get(tag)
            if spec is None:
                raise errors.SchemaError(
                    f"{where(filename, xml)}: {parent.path}: <{parent.tag}> cannot have a "
                    f"<{tag}> child" + suggest_child(tag, specs)
                )
            if tag == "replicate" or tag == "attach":
                self.generated_names = True
            if not spec.repeated:
                if singles is None:
                    singles = set()
                elif tag in singles:
                    raise errors.SchemaError(
                        f"{where(filename, xml)}: {parent.path}: <{parent.tag}> may have "
                        f"only one <{tag}>"
                    )
                singles.add(tag)
                existing = single_child(parent, tag)
                if existing is not None:  # from an earlier copy of a repeated section
                    self._merge(existing, xml)
                    continue
            element = make(Element, spec, parent, root)
            if debugging.is_debug_mode():
                builder.set_created_at(
                    element, debugging.xml_site(xml.base or filename, xml.sourceline)
                )
            attrib = xml.attrib
            if attrib:
                attrs = builder.attributes_to_fill(element)
                attrs.update(attrib)
                self.set_attributes(element, attrs, xml)  # checked in place
                if spec.references and not spec.references.isdisjoint(attrs):
                    self.with_references.append((element, spec, attrs))
            elif spec.checked_on_write:
                self.set_attributes(element, {}, xml)  # raises: something is missing
            placed.append(element)
            if spec.namespace is not None:
                try:
                    builder.register(element)
                except errors.NameClashError as error:
                    raise errors.NameClashError(f"{where(filename, xml)}: {error}") from None
            if len(xml):
                self._add_children(element, xml)
                if spec.crashing_children:
                    children = [(c.tag, stored_attributes(c)) for c in tree_children(element)]
                    crash = spec.crash(stored_attributes(element), children)
                    if crash is not None:
                        raise errors.SchemaError(f"{where(filename, xml)}: {element.path}: {crash}")

    def link_unnamed(self) -> None:
        """References that name an element by the name mjcf generated for it point at
        that element, which is read back unnamed."""
        for element in self.to_unnamed:
            attrs = builder.attributes_to_fill(element)  # names replaced by elements below
            spec = element.spec
            for name in spec.references.intersection(attrs):
                attribute = spec.attributes[name]
                namespace = attribute.reference_namespace(attrs)
                text = attrs[name]
                if namespace is None or not isinstance(text, str):
                    continue
                items = text.split() if attribute.is_list else [text]
                targets = [self.unnamed.get((namespace, item), item) for item in items]
                if attribute.is_list:
                    attrs[name] = targets
                elif isinstance(targets[0], Element):
                    attrs[name] = targets[0]

    def _merge(self, element: Element, xml: etree._Element) -> None:
        """Apply a later copy of an element that may appear once (a second `<map>` in a
        second `<visual>`) as MuJoCo does: its attributes override, in order (a second
        top-level `<default>` is merged by `default_sections`)."""
        if xml.attrib:
            self.set_attributes(element, dict(xml.attrib), xml)
            spec = element.spec
            attrs = stored_attributes(element)
            if spec.references and not spec.references.isdisjoint(attrs):
                self.with_references.append((element, spec, attrs))
        if len(xml):
            self._add_children(element, xml)

    def referenced(self) -> dict[str, frozenset[str]]:
        """{namespace: the names the references read name} (those of default classes
        under `references.ANY_NAMESPACE` too), for `mjcf.tree.references`."""
        found: dict[str, set[str]] = {references.ANY_NAMESPACE: set()}
        for _, spec, attrs in self.with_references:
            loose = spec.key.startswith("default-")
            for name in spec.references.intersection(attrs):
                value = attrs[name]
                if not isinstance(value, str):
                    continue
                attribute = spec.attributes[name]
                namespace = attribute.reference_namespace(attrs)
                words = value.split() if attribute.is_list else [value]
                if namespace is not None:
                    found.setdefault(namespace, set()).update(words)
                if loose or namespace is None:
                    found[references.ANY_NAMESPACE].update(words)
        return {namespace: frozenset(words) for namespace, words in found.items()}

    def check_files(self) -> None:
        """Raise mjcf.AssetError for a file attribute naming a file outside the model's
        folder (strict paths)."""
        for element in self.root.iter():
            attrs = stored_attributes(element)
            for name in element.spec.file_attributes.intersection(attrs):
                value = attrs[name]
                if value not in self.root.assets:
                    _assets.file_path(element, value)

    def check_references(self) -> None:
        """Raise mjcf.InvalidReferenceError for references to elements that do not exist."""
        if self.generated_names:
            return
        scope = self.root.namescope
        dangling = []
        for element, spec, attrs in self.with_references:
            if spec.key.startswith("default-"):
                continue  # resolved where an element uses the class, as MuJoCo does
            for name in spec.references.intersection(attrs):
                attribute = spec.attributes[name]
                namespace = attribute.reference_namespace(attrs)
                if namespace is None:
                    continue
                value = attrs[name]
                if isinstance(value, Element):
                    continue
                if isinstance(value, list):
                    targets = value
                else:
                    targets = value.split() if attribute.is_list else [value]
                for target in targets:
                    if isinstance(target, Element) or (namespace == "default" and target == "main"):
                        continue
                    if not target and namespace != "default":
                        continue  # no reference, as MuJoCo reads an empty one
                    if scope.lookup(namespace, target) is None:
                        dangling.append(
                            f"{element.path}: {name}={target!r} (no {namespace} of that name)"
                        )
        if dangling:
            shown = "; ".join(dangling[:5]) + (
                f"; and {len(dangling) - 5} more" if len(dangling) > 5 else ""
            )
            raise errors.InvalidReferenceError(
                f"{self.filename or '<string>'}: dangling references: {shown}"
            )
