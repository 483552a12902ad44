"""A top-level `<default>` that appears more than once, read as MuJoCo reads it.

    <default><default class="a"><geom friction=".5"/></default></default>
    <default class="main"><geom margin=".01"/></default>     <!-- class a keeps margin 0 -->

MuJoCo copies a class's parent into the class when the class is defined, so a second
top-level `<default>` changes the global defaults after the first one's classes copied
them. `merge_section` merges it into the one global default class and gives each class
defined before it the value it copied ("pinned"): the model compiles as the file does.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from lxml import etree

from mjcf import errors, schema
from mjcf.compose.defaults import LateDefault, overlay
from mjcf.schema.tracked_array import track
from mjcf.tree import builder
from mjcf.tree.element import Element, single_child, stored_attributes, tree_children, value_of

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec

_ACTUATOR_TAGS = frozenset(schema.MUJOCO.child("actuator").children)


def merge_section(
    main: Element,
    xml_section: etree._Element,
    read_attributes: Callable[[Element, dict, etree._Element], None],
    read_classes: Callable[[Element, list[etree._Element]], None],
    where: Callable[[etree._Element], str],
) -> None:
    """Merge a second (third ...) top-level `<default>` into the global defaults `main`:
    its settings (checked by `read_attributes`, as the parser reads attributes), with
    the classes defined before pinned, actuator settings kept as late settings, then
    its classes (read by `read_classes`). Raises mjcf.ParseError for a built-in value
    MuJoCo cannot report.

    Within one `<default>` element MuJoCo's copying of a parent class is invisible (the
    parent's own settings are read before its classes); a second section (often from an
    included file that sets `<default class="main">`) is not. Actuator defaults, which
    MuJoCo builds from a sequence of shortcuts, cannot be pinned: a later section that
    changes them after classes were defined (or after the global defaults set them) is
    kept as it is, a `mjcf.compose.defaults.LateDefault` after those classes, and written
    as a section of its own, as the file had it."""
    earlier = [child for child in tree_children(main) if child.spec.tag == "default"]
    classes = []
    for xml in xml_section:
        if not isinstance(xml.tag, str):
            continue
        if xml.tag == "default":
            classes.append(xml)
            continue
        if xml.tag in _ACTUATOR_TAGS:
            late = earlier or single_child(main, xml.tag) is not None
            kind = LateDefault if late else Element
            builder.children_to_fill(main).append(_read(main, xml, read_attributes, where, kind))
            continue
        setting = _read(main, xml, read_attributes, where)
        for default_class in earlier:
            _pin(default_class, main, setting, xml, where)
        _merge(main, setting)
    read_classes(main, classes)


def _read(
    main: Element,
    xml: etree._Element,
    read_attributes: Callable[[Element, dict, etree._Element], None],
    where: Callable[[etree._Element], str],
    kind: type[Element] = Element,
) -> Element:
    spec = main.spec.children.get(xml.tag)
    if spec is None:
        raise errors.SchemaError(f"{where(xml)}: <default> cannot have a <{xml.tag}> child")
    if len(xml):
        raise errors.SchemaError(f"{where(xml)}: a default <{xml.tag}> has no children")
    setting = builder.new_element(kind, spec, main, main.root)
    read_attributes(setting, dict(xml.attrib), xml)
    return setting


def _merge(main: Element, setting: Element) -> None:
    """Set `setting`'s attributes on the global default of its tag, numbers overlaying
    the numbers already there as MuJoCo reads them."""
    existing = single_child(main, setting.spec.tag)
    if existing is None:
        builder.children_to_fill(main).append(setting)
        return
    for name in stored_attributes(setting):
        attribute = setting.spec.attributes[name]
        value = value_of(setting, attribute)
        if name in stored_attributes(existing):
            value = overlay(name, value_of(existing, attribute), value)
        builder.attributes_to_fill(existing)[name] = track(value, existing)


def _pin(
    default_class: Element,
    main: Element,
    setting: Element,
    xml: etree._Element,
    where: Callable[[etree._Element], str],
) -> None:
    """Give `default_class` (defined before `setting` changes the global defaults) the
    values it copied of the attributes `setting` changes: the global value it had then,
    or MuJoCo's built-in default (`_built_in`). A value the class sets itself is kept,
    filled up from the pinned value when it has fewer numbers than the attribute holds."""
    tag = setting.spec.tag
    before = single_child(main, tag)
    own = single_child(default_class, tag)
    pins: dict[str, Any] = {}
    for name, text in stored_attributes(setting).items():
        attribute = setting.spec.attributes[name]
        mine = (
            value_of(own, attribute) if own is not None and name in stored_attributes(own) else None
        )
        if mine is not None and not _partial(attribute, mine):
            continue
        copied = (
            value_of(before, attribute)
            if before is not None and name in stored_attributes(before)
            else None
        )
        if copied is None or _partial(attribute, copied):
            built_in = _built_in(tag, attribute, str(text), where(xml))
            if built_in is None:
                continue  # the built-in value is the new one: nothing changes
            copied = built_in if copied is None else overlay(name, built_in, copied)
        pins[name] = copied if mine is None else overlay(name, copied, mine)
    if not pins:
        return
    if own is None:
        own = builder.new_element(
            type(default_class), setting.spec, default_class, default_class.root
        )
        builder.children_to_fill(default_class).insert(0, own)
    attrs = builder.attributes_to_fill(own)
    for name, value in pins.items():
        attrs[name] = track(value, own)


def _partial(attribute: AttributeSpec, value: Any) -> bool:
    """Whether `value` has fewer numbers than the attribute holds, so that MuJoCo keeps
    the rest from the class it copied."""
    return (
        isinstance(value, np.ndarray)
        and attribute.name != "user"
        and attribute.max is not None
        and value.size < attribute.max
    )


def _built_in(tag: str, attribute: AttributeSpec, new_text: str, where: str) -> Any:
    """MuJoCo's built-in default of `attribute` of a default `<tag>`, all its numbers;
    None when it cannot differ from `new_text` (nothing to pin). Numbers come from
    MuJoCo's own default class (`MjSpec().default`), keywords from MuJoCo's writer, asked
    once per attribute. Raises mjcf.ParseError if MuJoCo cannot say."""
    converter = attribute.converter
    if converter.unset_is_empty:
        return "" if new_text else None
    if converter.numbers:
        numbers = _spec_default(tag, attribute.name)
        if numbers is not None:
            numbers = numbers[: attribute.max] if attribute.max is not None else numbers
            if not converter.reals:
                numbers = numbers.astype(int)
            return numbers[0].item() if attribute.scalar else numbers
    text = _built_in_text(tag, attribute.name, new_text)
    if text is _UNKNOWN:
        raise errors.ParseError(
            f"{where}: a top-level <default> sets <{tag} {attribute.name}> after classes were "
            "defined, and MuJoCo's built-in value of it (which those classes keep) cannot be "
            "read back; set it in the first <default> section"
        )
    return None if text is None else attribute.converter.from_text(text)


@functools.cache
def _spec_defaults() -> Any:
    return mujoco.MjSpec().default


def _spec_default(tag: str, name: str) -> np.ndarray | None:
    """The built-in numbers of a default `<tag name>` as MuJoCo's spec holds them, where
    the spec field has the attribute's name; None otherwise."""
    element = getattr(_spec_defaults(), tag, None)
    value = getattr(element, name, None) if element is not None else None
    if isinstance(value, bool) or not isinstance(value, int | float | np.ndarray):
        return None
    numbers = np.atleast_1d(np.asarray(value, dtype=float)).ravel()
    return numbers.copy() if numbers.size else None


_UNKNOWN = object()


@functools.cache
def _built_in_text(tag: str, name: str, new_text: str) -> Any:
    """Ask MuJoCo's writer: a class defined before the global defaults set `name` to
    `new_text` keeps the built-in value, which the writer writes for it when it differs.
    Returns its text, None if they are equal, or _UNKNOWN if MuJoCo writes it otherwise."""
    probe = (
        '<mujoco><compiler angle="radian"/><default><default class="probe"/></default>'
        f"<default><{tag} {name}={_quoted(new_text)}/></default></mujoco>"
    )
    try:
        written = mujoco.MjSpec.from_string(probe).to_xml()
    except ValueError:
        return _UNKNOWN
    tree = etree.fromstring(written.encode())
    found = tree.find(f".//default[@class='probe']/{tag}")
    if found is None:
        return None
    if name in found.attrib:
        return found.attrib[name]
    return _UNKNOWN


def _quoted(text: str) -> str:
    return '"' + text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;") + '"'
