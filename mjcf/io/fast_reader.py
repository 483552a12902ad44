"""Reading a document the fast way: checked whole, its elements built when first used.

    if fast_reader.read(root, xml_root, filename, escape_separators, resolve, exact):
        ...       # read: names loaded, each section's children built when first used
    else:
        ...       # declined, nothing changed: `mjcf.io.element_reader` reads it

Three checks of the whole document, each of which may decline it: it pays to make the XML
Schema (`_ELEMENTS_BEFORE_SCHEMA`); libxml2 accepts it against that schema in C
(`mjcf.io.xsd`); the indexer accepts its names and references (`mjcf.io.indexer`).
"""

from __future__ import annotations

from lxml import etree

from mjcf.io import indexer, xsd
from mjcf.io.element_reader import ElementReader, main_class
from mjcf.tree import builder, debugging, references
from mjcf.tree.element import tree_children
from mjcf.tree.root import RootElement

# Making the XML Schema the fast way checks documents with (`mjcf.io.xsd`) costs about 8 ms of
# CPU time, once a thread; reading element by element costs about 10 us an element more
# than reading fast. Until a process has read this many elements element by element, it
# goes on doing so; then it makes the schema: a process pays at most about twice the
# cheaper of the two ways (the ski-rental rule), and one that reads one model pays none.
_ELEMENTS_BEFORE_SCHEMA = 1000
_elements_read_slowly = 0  # by this process, while no XML Schema was made


def read(
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
    reader = ElementReader(root, filename, escape_separators)
    sections = {section.tag: section for section in tree_children(root)}
    firsts: dict[str, etree._Element] = {}
    # The sections' own attributes are read as element by element; each section is then
    # given the lxml element its children are built from when first used.
    for xml_section in xml_root:
        tag = xml_section.tag
        section = sections[tag]
        spec = section.spec
        if xml_section.attrib or tag == "default" or spec.required or spec.rules:
            attrib = dict(xml_section.attrib)
            if tag == "default":
                main_class(attrib, xml_section, filename)
            reader.set_attributes(section, attrib, xml_section)
        first = firsts.setdefault(tag, xml_section)
        if first is not xml_section:
            # A repeated section, which MuJoCo reads as one: its children join the first
            # copy's, in order (the indexer has checked them as one section's).
            first.extend(list(xml_section))
    for tag, first in firsts.items():
        if len(first):
            builder.defer(sections[tag], first)
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
