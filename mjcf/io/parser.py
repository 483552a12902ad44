"""Reading MJCF: `from_path`, `from_xml_string`, `from_file`.

    model = mjcf.from_path('robot.xml')                    # <include>s merged
    model = mjcf.from_xml_string('<mujoco>...</mujoco>', model_dir='assets/')
    model = mjcf.from_xml_string(xml, assets={'mesh.stl': stl_bytes})

Every element and attribute is checked against MuJoCo's schema while reading; errors name
the file, line and element. No DTD, entity or network is ever read. One path, top to bottom
in `_parse`: lxml reads the text, `<include>`s are merged, and the document is read one of
two ways, decided once: `mjcf.io.fast_reader`, or if it declines, `mjcf.io.element_reader`.
"""

from __future__ import annotations

import os
from typing import IO

from lxml import etree

from mjcf import errors
from mjcf.io import element_reader, fast_reader, xsd
from mjcf.io.element_reader import where as _where
from mjcf.tree import assets as _assets
from mjcf.tree import bulk, references
from mjcf.tree.namescope import PREFIX_SEPARATOR
from mjcf.tree.root import RootElement, confine_files

_MAX_INCLUDES = 1000
# How many elements deep MuJoCo's XML reader (tinyxml2) reads a document, <mujoco> the first:
# a model nested deeper is refused when read (mjcf.ParseError) and when written
# (mjcf.SchemaError), as MuJoCo refuses it (tests/mjcf/test_hostile_input.py checks both
# against MuJoCo's reader).
MAX_DEPTH = 499


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
    renames and removals (see `mjcf.tree.references`); with False they stay text, as
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
    """The model read from MJCF text `data`, the one path every reader takes: lxml reads
    the text (refusing DTDs and entities: no external entity, no "billion laughs", never
    the network, and documents nested deeper than MuJoCo's reader reads, `MAX_DEPTH`
    elements: the writer refuses the same), `<include>`s are merged, the model is made,
    and the document is read one of two ways, decided once: the fast way
    (`mjcf.io.fast_reader`: checked whole, elements built when first used), or, when it
    declines, element by element (`mjcf.io.element_reader`), which raises the error naming
    the element or reads what the fast way leaves to it. Either checks every element and
    attribute against MuJoCo's schema: unknown names with a "did you mean", wrong numbers,
    bad keywords, duplicate names, and references to elements that do not exist."""
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
    confine_files(root, confine)
    references.start_reading(root, resolve_references)
    # The one decision: the fast way reads the document or declines it, changing nothing.
    if strict_paths or not fast_reader.read(
        root, xml_root, filename, escape_separators, resolve_references, exact
    ):
        element_reader.read(
            root, xml_root, filename, escape_separators, resolve_references, strict_paths
        )
    return root


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
