"""The calls the lower layers of mjcf make to the layers above them, which import the tree:
the one module that imports inside functions (tests/mjcf/test_architecture.py checks it).

    above.find(element, 'joint', 'arm/shoulder')   # mjcf.compose.traversal.find

Each function imports the one function it names when called (later calls find its module
loaded: a dictionary lookup) and returns what that returns, with its signature and errors:
`element.find` is `mjcf.compose.traversal`'s, `attach` `mjcf.compose.attachment`'s,
`to_xml_string` `mjcf.io.serializer`'s, `compile_model` `mjcf.sim.physics`'s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from mjcf.compose.composition import Composition
    from mjcf.schema import AttributeSpec
    from mjcf.sim.compiler import Compiled
    from mjcf.sim.physics import Physics
    from mjcf.tree.assets import Asset
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement


def identifier(element: Element, prefix_root: RootElement | None) -> str | None:
    """`mjcf.compose.naming.identifier`: the name `element` is written with."""
    from mjcf.compose.naming import identifier

    return identifier(element, prefix_root)


def find(element: Element, namespace: str, identifier: str) -> Element | None:
    """`mjcf.compose.traversal.find`."""
    from mjcf.compose.traversal import find

    return find(element, namespace, identifier)


def find_all(
    element: Element, namespace: str, immediate_children_only: bool, exclude_attachments: bool
) -> list[Element]:
    """`mjcf.compose.traversal.find_all`."""
    from mjcf.compose.traversal import find_all

    return find_all(element, namespace, immediate_children_only, exclude_attachments)


def is_same_as(element: Element, other: object) -> bool:
    """`mjcf.compose.sameness.is_same_as`."""
    from mjcf.compose.sameness import is_same_as

    return is_same_as(element, other)


def attach(place: Element, child: RootElement) -> Element:
    """`mjcf.compose.attachment.attach`."""
    from mjcf.compose.attachment import attach

    return attach(place, child)


def detach(child: RootElement) -> None:
    """`mjcf.compose.attachment.detach`."""
    from mjcf.compose.attachment import detach

    detach(child)


def remove(element: Element, affect_attachments: bool) -> None:
    """`mjcf.compose.attachment.remove`."""
    from mjcf.compose.attachment import remove

    remove(element, affect_attachments)


def include_copy(target: Element, source: Element, override_attributes: bool) -> None:
    """`mjcf.compose.copying.include_copy`."""
    from mjcf.compose.copying import include_copy

    include_copy(target, source, override_attributes)


def deepcopy_element(element: Element, memo: dict[int, Any]) -> Element:
    """`mjcf.compose.copying.deepcopy_element`."""
    from mjcf.compose.copying import deepcopy_element

    return deepcopy_element(element, memo)


def to_xml_string(
    element: Element,
    prefix_root: RootElement | None,
    self_only: bool,
    pretty_print: bool,
    precision: int,
    zero_threshold: float,
    filename_with_hash: bool,
) -> str:
    """`mjcf.io.serializer.to_xml_string`."""
    from mjcf.io.serializer import to_xml_string

    return to_xml_string(
        element, prefix_root, self_only, pretty_print, precision, zero_threshold, filename_with_hash
    )


def attribute_text(
    element: Element, attribute: AttributeSpec, prefix_root: RootElement | None
) -> str:
    """`mjcf.io.serializer.attribute_text`."""
    from mjcf.io.serializer import attribute_text

    return attribute_text(element, attribute, prefix_root)


def serialize(root: RootElement, filename_with_hash: bool) -> tuple[str, dict[str, bytes]]:
    """`mjcf.io.serializer.serialize`."""
    from mjcf.io.serializer import serialize

    return serialize(root, filename_with_hash=filename_with_hash)


def file_name_of(root: RootElement, asset: Asset) -> str | None:
    """`mjcf.io.serializer.file_name_of`."""
    from mjcf.io.serializer import file_name_of

    return file_name_of(root, asset)


def serialize_for_compile(
    root: RootElement,
) -> tuple[str, dict[str, bytes], Composition, list[Element | None]]:
    """`mjcf.io.serializer.serialize_for_compile`."""
    from mjcf.io.serializer import serialize_for_compile

    return serialize_for_compile(root)


def compile_composition(root: RootElement) -> Compiled:
    """`mjcf.sim.compiler.compile_composition`: composing a model for writing needs it
    compiled (its keyframes, an attached model's `settotalmass`)."""
    from mjcf.sim.compiler import compile_composition

    return compile_composition(root)


def compile_model(root: RootElement) -> Physics:
    """`mjcf.Physics.from_mjcf_model`."""
    from mjcf.sim.physics import Physics

    return Physics.from_mjcf_model(root)
