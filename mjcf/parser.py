"""Reading MJCF: `from_path`, `from_xml_string`, `from_file`.

    model = mjcf.from_path('robot.xml')                    # <include>s merged
    model = mjcf.from_xml_string('<mujoco>...</mujoco>', model_dir='assets/')
    model = mjcf.from_xml_string(xml, assets={'mesh.stl': stl_bytes})

Every element and attribute is checked against MuJoCo's schema while reading (unknown
names with a "did you mean", wrong numbers, bad keywords, duplicate names, and
references to elements that do not exist); errors name the file, line and element.
A document is first checked whole, in C against an XML Schema generated from MuJoCo's
(`mjcf.xsd`), then for names and references (`mjcf.indexer`), and its elements are built
when first used (`Element._defer`): reading a model takes about as long as MuJoCo's own
`MjSpec.from_file`. A document that check does not accept is read element by element,
which raises the error naming the element (or reads what the fast way leaves to it).
So are the first documents a process reads, until it has read as many elements as it
could have read fast in the time the XML Schema takes to make (about 8 ms, once): a
script that reads one model does not pay for it. Attribute text is kept as read until
used.

The XML reader refuses DTDs and entities (no external entity, no "billion laughs"),
never touches the network, and reads documents nested as deep as MuJoCo's reader does
(`MAX_DEPTH` elements), no deeper: the writer refuses the same.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import IO, Any

from lxml import etree

from mjcf import assets as _assets
from mjcf import (
    bulk,
    debugging,
    default_sections,
    errors,
    indexer,
    naming,
    references,
    upcalls,
    xsd,
)
from mjcf import values as _values
from mjcf.element import Element, single_child, stored_attributes, tree_children
from mjcf.namescope import PREFIX_SEPARATOR
from mjcf.root import RootElement
from mjcf.schema import AttributeSpec, ElementSpec

_MAX_INCLUDES = 1000
# How many elements deep MuJoCo's XML reader (tinyxml2) reads a document, <mujoco> the first:
# a model nested deeper is refused when read (mjcf.ParseError) and when written
# (mjcf.SchemaError), as MuJoCo refuses it (tests/mjcf/test_hostile_input.py checks both
# against MuJoCo's reader).
MAX_DEPTH = 499
# Making the XML Schema the fast way checks documents with (`mjcf.xsd`) costs about 8 ms of
# CPU time, once a thread; reading element by element costs about 10 us an element more
# than reading fast. Until a process has read this many elements element by element, it
# goes on doing so; then it makes the schema: a process pays at most about twice the
# cheaper of the two ways (the ski-rental rule), and one that reads one model pays none.
_ELEMENTS_BEFORE_SCHEMA = 1000
_elements_read_slowly = 0  # by this process, while no XML Schema was made


def _xml_parser(huge: bool = False) -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        remove_comments=True,
        remove_pis=True,
        huge_tree=huge,
        # Whitespace between elements and xml:id are no part of MJCF: kept, they cost
        # about a tenth of the time to read a file.
        remove_blank_text=True,
        collect_ids=False,
    )


def from_xml_string(
    xml_string: str | bytes,
    escape_separators: bool = False,
    model_dir: str = "",
    resolve_references: bool = True,
    assets: dict[str, bytes] | None = None,
    strict_paths: bool = False,
) -> RootElement:
    """Parse MJCF text into a model. `model_dir` is where relative file names (meshes,
    includes) are found; `assets` supplies file contents by name; `escape_separators`
    accepts '/' in names (as '\\/'); `resolve_references` checks that every reference
    names an existing element and makes references point at their elements, following
    renames and removals (see `mjcf.references`); with False they stay text, as
    dm_control keeps them, until `model.resolve_references()`; `strict_paths` (for
    untrusted models) refuses included and asset files outside `model_dir`. Raises
    mjcf.ParseError for malformed XML and other mjcf errors for schema violations."""
    return _parse(
        xml_string, escape_separators, model_dir, resolve_references, assets, None, strict_paths
    )


def from_path(
    path: str | os.PathLike,
    escape_separators: bool = False,
    resolve_references: bool = True,
    assets: dict[str, bytes] | None = None,
    strict_paths: bool = False,
) -> RootElement:
    """Parse an MJCF file; its directory becomes the model's `model_dir`. Raises
    mjcf.ParseError if it cannot be read (see `from_xml_string` for the rest)."""
    path = os.fspath(path)
    try:
        data = _assets.read_file(path)
    except errors.AssetError as error:
        raise errors.ParseError(f"cannot read MJCF file: {error}") from None
    model_dir = os.path.dirname(os.path.abspath(path))
    return _parse(
        data, escape_separators, model_dir, resolve_references, assets, path, strict_paths
    )


# The parameters repeat from_xml_string's on purpose: both are dm_control's signatures,
# which code calls with positional arguments.
def from_file(
    file_object: IO | str | os.PathLike,
    escape_separators: bool = False,
    model_dir: str = "",
    resolve_references: bool = True,
    assets: dict[str, bytes] | None = None,
    strict_paths: bool = False,
) -> RootElement:
    """Parse MJCF from an open file (text or binary), or a file's path as dm_control
    (lxml) takes it too; `model_dir` defaults to the file's directory when it has a name
    (see `from_xml_string` for the rest)."""
    if isinstance(file_object, str | os.PathLike):
        path = os.fspath(file_object)
        try:
            contents = _assets.read_file(path)
        except errors.AssetError as error:
            raise errors.ParseError(f"cannot read MJCF file: {error}") from None
        directory = model_dir or os.path.dirname(os.path.abspath(path))
        return _parse(
            contents, escape_separators, directory, resolve_references, assets, path, strict_paths
        )
    if not callable(getattr(file_object, "read", None)):
        raise TypeError(f"from_file needs an open file or a path, got {type(file_object).__name__}")
    name = getattr(file_object, "name", None)
    try:
        data = _assets.read_limited(file_object, name)
    except errors.AssetError as error:
        raise errors.ParseError(f"cannot read MJCF file: {error}") from None
    if not model_dir and isinstance(name, str) and os.path.exists(name):
        model_dir = os.path.dirname(os.path.abspath(name))
    filename = name if isinstance(name, str) else None
    return _parse(
        data, escape_separators, model_dir, resolve_references, assets, filename, strict_paths
    )


@bulk.whole_tree
def _parse(
    data: str | bytes,
    escape_separators: bool,
    model_dir: str,
    resolve_references: bool,
    assets: dict[str, bytes] | None,
    filename: str | None,
    strict_paths: bool,
) -> RootElement:
    xml_root, exact = _read_xml(data, filename)
    if xml_root.tag != "mujoco":
        raise errors.ParseError(
            f"{_where(filename, xml_root)}: the root element of an MJCF model is <mujoco>, "
            f"got <{xml_root.tag}>"
        )
    model_dir = os.fspath(model_dir) if model_dir else ""
    included: set[str] = set()
    if filename is not None:
        included.add(os.path.abspath(filename))
    confine = os.path.realpath(model_dir or os.getcwd()) if strict_paths else None
    read = len(included)
    exact |= _expand_includes(
        xml_root, model_dir or os.getcwd(), filename, assets or {}, included, confine
    )
    if len(included) > read:  # each file was measured alone: the whole is measured too
        check_depth(xml_root, filename)
    name = xml_root.attrib.get("model")
    if name is not None and PREFIX_SEPARATOR in name:
        if not escape_separators:
            raise errors.NameClashError(
                f"{_where(filename, xml_root)}: model name {name!r} contains '/', which "
                "separates the names of attached models"
            )
        name = name.replace(PREFIX_SEPARATOR, "-")
    root = RootElement(model=name or None, model_dir=model_dir, assets=assets)
    object.__setattr__(root, "_confine_to", confine)
    references.start_reading(root, resolve_references)
    if not strict_paths and _read_fast(
        root, xml_root, filename, escape_separators, resolve_references, exact
    ):
        return root
    builder = _Builder(root, filename, escape_separators)
    builder.build(xml_root)
    builder.link_unnamed()
    references.record_read_names(root, builder.referenced())
    if resolve_references:
        builder.check_references()
    if strict_paths:
        builder.check_files()
    return root


def _read_fast(
    root: RootElement,
    xml_root: etree._Element,
    filename: str | None,
    escape_separators: bool,
    check_references: bool,
    exact: bool,
) -> bool:
    """Read the document under `xml_root` into the new model `root` the fast way: checked
    whole by the XML Schema (the one that counts digits if `exact`, see
    `xsd.needs_exact`) and the indexer, its sections' contents built when first used
    (see `Element._defer`). False, with `root` and `xml_root` untouched, for a document
    the element-by-element reader must read (to report an error, or to read what the
    fast way does not handle: a repeated top-level `<default>`, whose later copies change
    the classes read before them, see `default_sections`); debug mode, which records
    where each element was read, reads element by element too, as do the first documents
    a process reads (see `_ELEMENTS_BEFORE_SCHEMA`)."""
    if debugging.is_debug_mode() or not _schema_pays(xml_root, exact):
        return False
    tags = [xml.tag for xml in xml_root]
    if not all(isinstance(tag, str) for tag in tags):
        return False  # an entity
    if tags.count("default") > 1:
        return False  # see default_sections
    if not xsd.accepts(xml_root, exact):
        return False
    found = indexer.index(xml_root, check_references)
    if found is None:
        return False
    names, referenced = found
    builder = _Builder(root, filename, escape_separators)
    sections = {section.tag: section for section in tree_children(root)}
    firsts: dict[str, etree._Element] = {}
    for xml_section in xml_root:
        tag = xml_section.tag
        section = sections[tag]
        spec = section.spec
        if xml_section.attrib or tag == "default" or spec.required or spec.rules:
            attrib = dict(xml_section.attrib)
            if tag == "default":
                _main_class(attrib, xml_section, filename)
            builder._set_attributes(section, attrib, xml_section, merge=True)
        first = firsts.setdefault(tag, xml_section)
        if first is not xml_section:
            # A repeated section, which MuJoCo reads as one: its children join the first
            # copy's, in order (the indexer has checked them as one section's).
            first.extend(list(xml_section))
    for tag, first in firsts.items():
        if len(first):
            sections[tag]._defer(first)
    root.namescope.load(names)
    references.record_read_names(root, referenced)
    return True


def _schema_pays(xml_root: etree._Element, exact: bool) -> bool:
    """Whether the XML Schema the document under `xml_root` is checked with (see
    `xsd.accepts`) exists, or it is time to make it (see `_ELEMENTS_BEFORE_SCHEMA`); if
    not, its elements are counted as read element by element."""
    global _elements_read_slowly
    if xsd.is_made(exact) or _elements_read_slowly >= _ELEMENTS_BEFORE_SCHEMA:
        return True
    _elements_read_slowly += sum(1 for _ in xml_root.iter())
    return False


def _main_class(attrib: dict[str, str], xml: etree._Element, filename: str | None) -> None:
    """Take `class` out of a top-level <default>'s attributes: it is 'main', which MuJoCo
    does not let a model rename; raises mjcf.AttributeValueError for another name."""
    name = attrib.pop("class", None)
    if name not in ("main", "", None):  # an empty name is none, as MuJoCo reads it
        raise errors.AttributeValueError(
            f"{_where(filename, xml)}: <default>: 'class' of the top-level default is "
            f"'main', which cannot be renamed, got {name!r}"
        )


def _read_xml(data: str | bytes, filename: str | None) -> tuple[etree._Element, bool]:
    """The root of the XML document `data`, and whether its numbers need the XML Schema
    that counts digits (`xsd.needs_exact`); raises mjcf.ParseError for malformed XML
    and for a DTD."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    try:
        tree = etree.fromstring(data, _xml_parser(), base_url=filename)
    except etree.XMLSyntaxError as error:
        # libxml2 reads 256 levels unless told to read "huge" documents (2,048 levels):
        # those between are read again, and measured against MuJoCo's depth.
        if "Excessive depth" not in (error.msg or ""):
            raise _malformed(error, filename) from None
        try:
            tree = etree.fromstring(data, _xml_parser(huge=True), base_url=filename)
        except etree.XMLSyntaxError as deeper:
            raise _malformed(deeper, filename) from None
        check_depth(tree, filename)
    doctype = tree.getroottree().docinfo
    if doctype.internalDTD is not None or doctype.externalDTD is not None or doctype.doctype:
        raise errors.ParseError(
            f"{filename or '<string>'}: MJCF does not use DTDs, and models that declare one "
            "(or entities) are refused"
        )
    return tree, xsd.needs_exact(data, doctype.encoding)


def _malformed(error: etree.XMLSyntaxError, filename: str | None) -> errors.ParseError:
    line = error.lineno if error.lineno is not None else "?"
    return errors.ParseError(f"{filename or '<string>'}:{line}: malformed XML: {error.msg}")


def check_depth(root: etree._Element, filename: str | None) -> None:
    """Raise mjcf.ParseError if the document under `root` nests more than MAX_DEPTH
    elements (MuJoCo's reader refuses it)."""
    pending = [(root, 1)]
    while pending:
        element, depth = pending.pop()
        if depth > MAX_DEPTH:
            raise errors.ParseError(
                f"{_where(filename, element)}: <{element.tag}> is nested {depth} elements "
                f"deep; MuJoCo reads models nested at most {MAX_DEPTH} deep"
            )
        pending.extend((child, depth + 1) for child in element if isinstance(child.tag, str))


def _expand_includes(
    root: etree._Element,
    model_dir: str,
    filename: str | None,
    assets: dict,
    included: set[str],
    confine: str | None,
) -> bool:
    """Replace every <include file=...> below `root` by the children of the included
    file's root, recursively, as MuJoCo does. Files are read depth first, then each
    <include> is replaced once the file it names is whole, innermost first: a chain of
    a thousand nested files takes no Python recursion. Whether an included file's
    numbers need the XML Schema that counts digits (see `_read_xml`)."""
    exact = False
    found: list[tuple[etree._Element, etree._Element, str]] = []  # include, file root, where
    pending = [(root, filename)]
    while pending:
        tree, source = pending.pop()
        for include in list(tree.iter("include")):
            where = _where(source, include)
            if any(
                isinstance(child.tag, str) or isinstance(child, etree._Entity) for child in include
            ):
                raise errors.ParseError(
                    f"{where}: an <include> cannot have children (MuJoCo refuses them); put "
                    "them in the included file or next to the <include>"
                )
            file_attr = include.attrib.get("file")
            if not file_attr:
                raise errors.ParseError(f"{where}: <include> requires the attribute 'file'")
            data, path = _include_source(file_attr, model_dir, source, assets, where, confine)
            key = os.path.abspath(path) if path else "asset:" + file_attr
            if key in included:
                raise errors.ParseError(
                    f"{where}: {file_attr!r} is included more than once (or includes itself); "
                    "MuJoCo allows each file to be included once"
                )
            if len(included) > _MAX_INCLUDES:
                raise errors.ParseError(f"{where}: more than {_MAX_INCLUDES} included files")
            included.add(key)
            included_root, included_exact = _read_xml(data, path or file_attr)
            exact |= included_exact
            found.append((include, included_root, f"{where}: included file {file_attr!r}"))
            pending.append((included_root, path or file_attr))
    for include, included_root, where in reversed(found):
        children = [c for c in included_root if isinstance(c.tag, str)]
        if not children:
            raise errors.ParseError(f"{where} has no elements")
        parent = include.getparent()
        position = parent.index(include)
        parent.remove(include)
        for offset, child in enumerate(children):
            parent.insert(position + offset, child)
    return exact


def _include_source(
    file_attr: str,
    model_dir: str,
    filename: str | None,
    assets: dict,
    where: str,
    confine: str | None,
) -> tuple[bytes, str | None]:
    """The contents and path of an included file: from `assets`, else relative to the
    main model's directory, else to the including file's directory (MuJoCo's order);
    within `confine` (a real path) if given."""
    for key in (file_attr, os.path.basename(file_attr)):
        if key in assets:
            return assets[key], None
    if confine is not None:
        real = os.path.realpath(os.path.join(model_dir, file_attr))
        if os.path.isabs(file_attr) or not _assets.is_inside(real, confine):
            raise errors.ParseError(
                f"{where}: included file {file_attr!r} is outside the model's folder "
                f"{confine!r}, which strict_paths forbids"
            )
    candidates = [file_attr] if os.path.isabs(file_attr) else [os.path.join(model_dir, file_attr)]
    if filename is not None and not os.path.isabs(file_attr):
        candidates.append(os.path.join(os.path.dirname(os.path.abspath(filename)), file_attr))
    for candidate in candidates:
        if os.path.isfile(candidate):
            try:
                return _assets.read_file(candidate), candidate
            except errors.AssetError as error:
                raise errors.ParseError(f"{where}: {error}") from None
    looked = ", ".join(map(repr, candidates))
    raise errors.MissingFileError(
        f"{where}: included file {file_attr!r} not found (looked in {looked}, and among the "
        "assets given)"
    )


def _where(filename: str | None, element: etree._Element) -> str:
    source = getattr(element, "base", None) or filename or "<string>"
    return f"{source}:{element.sourceline}"


class _Builder:
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
                    f"{_where(self.filename, xml_root)}: <mujoco> has no attribute {name!r}"
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
                    f"{_where(self.filename, xml_section)}: <mujoco> cannot have a <{tag}> child"
                    + _values.suggest(tag, sections)
                )
            attrib = dict(xml_section.attrib)
            if tag == "default":
                _main_class(attrib, xml_section, self.filename)
            self._set_attributes(section, attrib, xml_section, merge=True)
            if tag == "default" and tag in seen:
                default_sections.merge_section(
                    section,
                    xml_section,
                    self._set_attributes,
                    self._add_children,
                    lambda xml: _where(self.filename, xml),
                )
            else:
                self._add_children(section, xml_section)
            seen.add(tag)

    def _set_attributes(
        self, element: Element, attrib: dict, xml: etree._Element, merge: bool = False
    ) -> None:
        spec = element.spec
        attributes = spec.attributes
        for name, text in list(attrib.items()):
            attribute = attributes.get(name)
            if attribute is None:
                if name.startswith("{"):  # namespaced, e.g. xsi:noNamespaceSchemaLocation
                    del attrib[name]
                    continue
                raise errors.UnknownAttributeError(
                    f"{_where(self.filename, xml)}: {element.path}: <{spec.tag}> has no attribute "
                    f"{name!r}" + _values.suggest(name, attributes)
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
                        f"{_where(self.filename, xml)}: {element.path}: {name!r} {refused}"
                    )
                attrib[name] = self._reference_text(element, attribute, text, xml)
            elif attribute.checks_text:
                try:
                    converter.check_text(text)
                except _values.InvalidValue as error:
                    raise errors.AttributeValueError(
                        f"{_where(self.filename, xml)}: {element.path}: {name!r} {error}"
                    ) from None
        if merge:
            element._attrs.update(attrib)
        else:
            object.__setattr__(element, "_attrs", attrib)
        if spec.required or spec.rules:
            problem = spec.unmet(stored_attributes(element))
            if problem is not None:
                raise errors.AttributeValueError(
                    f"{_where(self.filename, xml)}: {element.path}: {problem}"
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
                    f"{_where(self.filename, xml)}: {element.path}: {attribute.name!r} is "
                    f"{text!r}, which contains '/', the separator of attached models' names; "
                    "parse with escape_separators=True to keep it"
                )
            text = text.replace(PREFIX_SEPARATOR, "\\" + PREFIX_SEPARATOR)
        return text

    def _add_children(self, parent: Element, xml_parent: etree._Element | list) -> None:
        specs = parent.spec.children
        root = self.root
        make = Element._make
        filename = self.filename
        singles: set[str] | None = None  # tags of this XML parent that may appear once
        for xml in xml_parent:
            tag = xml.tag
            if not isinstance(tag, str):
                if isinstance(xml, etree._Entity):
                    raise errors.ParseError(
                        f"{_where(filename, xml_parent)}: entities are not allowed"
                    )
                continue
            spec = specs.get(tag)
            if spec is None:
                raise errors.SchemaError(
                    f"{_where(filename, xml)}: {parent.path}: <{parent.tag}> cannot have a "
                    f"<{tag}> child" + _values.suggest_child(tag, specs)
                )
            if tag == "replicate" or tag == "attach":
                self.generated_names = True
            if not spec.repeated:
                if singles is None:
                    singles = set()
                elif tag in singles:
                    raise errors.SchemaError(
                        f"{_where(filename, xml)}: {parent.path}: <{parent.tag}> may have "
                        f"only one <{tag}>"
                    )
                singles.add(tag)
                existing = single_child(parent, tag)
                if existing is not None:  # from an earlier copy of a repeated section
                    self._merge(existing, xml)
                    continue
            element = make(spec, parent, root)
            if debugging.is_debug_mode():
                object.__setattr__(
                    element, "_source", debugging.xml_site(xml.base or filename, xml.sourceline)
                )
            attrib = xml.attrib
            if attrib:
                attrs = dict(attrib)
                self._set_attributes(element, attrs, xml)  # which become its attributes
                if spec.references and not spec.references.isdisjoint(attrs):
                    self.with_references.append((element, spec, attrs))
            elif spec.checked_on_write:
                self._set_attributes(element, {}, xml)  # raises: something is missing
            parent._children.append(element)
            if spec.namespace is not None:
                try:
                    element._register()
                except errors.NameClashError as error:
                    raise errors.NameClashError(f"{_where(filename, xml)}: {error}") from None
            if len(xml):
                self._add_children(element, xml)
                if spec.crashing_children:
                    children = [(c.tag, stored_attributes(c)) for c in tree_children(element)]
                    crash = spec.crash(stored_attributes(element), children)
                    if crash is not None:
                        raise errors.SchemaError(
                            f"{_where(filename, xml)}: {element.path}: {crash}"
                        )

    def link_unnamed(self) -> None:
        """References that name an element by the name mjcf generated for it point at
        that element, which is read back unnamed."""
        for element in self.to_unnamed:
            attrs = element._attrs  # names replaced by elements below: the builder's to change
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
            self._set_attributes(element, dict(xml.attrib), xml, merge=True)
            spec = element.spec
            attrs = stored_attributes(element)
            if spec.references and not spec.references.isdisjoint(attrs):
                self.with_references.append((element, spec, attrs))
        if len(xml):
            self._add_children(element, xml)

    def referenced(self) -> dict[str, frozenset[str]]:
        """{namespace: the names the references read name} (those of default classes
        under `references.ANY_NAMESPACE` too), for `mjcf.references`."""
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


def __getattr__(name: str) -> object:
    """`mjcf.parser.from_zip`: reading a zip at dm_control's module path."""
    if name == "from_zip":
        return upcalls.ABOVE.from_zip
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
