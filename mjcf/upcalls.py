"""The calls a lower layer of mjcf makes into the layers above it, installed once.

`Element` lives in the tree layer, but most of what a user asks of one is done above it:
`element.find(...)` by `mjcf.traversal`, `element.attach(...)` by `mjcf.attachment`,
`element.to_xml_string()` by `mjcf.serializer`, `root.compile_model()` by
`mjcf.physics`; and composing a model (settings, keyframes) needs it compiled. A module
cannot import the modules that import it without an import circle, so the lower layers
call these through `ABOVE`, whose members `mjcf/__init__.py` sets to the functions of
the layers above when the package is imported (before any element exists: importing any
mjcf module imports the package first):

    upcalls.ABOVE.find(element, 'joint', 'arm/shoulder')

Each member has the signature and the errors of the function it names (see `Above`);
tests/mjcf/test_architecture.py checks that every one is installed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from mjcf.assets import Asset
    from mjcf.composition import Composition
    from mjcf.element import Element
    from mjcf.physics import Physics
    from mjcf.root import RootElement


class Above:
    """The functions of the layers above the tree that it calls, one member each:

    `identifier`: `mjcf.naming.identifier`; `find`, `find_all`: `mjcf.traversal`'s;
    `is_same_as`: `mjcf.sameness.is_same_as`; `attach`, `detach`, `remove`,
    `attached_models`: `mjcf.attachment`'s; `include_copy`, `deepcopy_element`:
    `mjcf.copying`'s; `to_xml_string`, `attribute_text`, `serialize`, `file_name_of`,
    `serialize_for_compile`: `mjcf.serializer`'s; `from_zip`: `mjcf.export.from_zip`;
    `compile_composition`: `mjcf.compiler.compile_composition`; `compile_model`:
    `mjcf.Physics.from_mjcf_model`; and the classes `element_class` (`mjcf.Element`, for
    `mjcf.values`) and `root_class` (`mjcf.RootElement`, for `mjcf.element.RootElement`,
    where dm_control has it).
    """

    identifier: Callable[[Element, RootElement | None], str | None]
    find: Callable[[Element, str, str], Element | None]
    find_all: Callable[[Element, str, bool, bool], list[Element]]
    is_same_as: Callable[[Element, object], bool]
    attach: Callable[[Element, RootElement], Element]
    detach: Callable[[RootElement], None]
    remove: Callable[[Element, bool], None]
    attached_models: Callable[[RootElement], list[RootElement]]
    include_copy: Callable[[Element, Element, bool], None]
    deepcopy_element: Callable[[Element, dict[int, Any]], Element]
    to_xml_string: Callable[..., str]
    attribute_text: Callable[..., str]
    serialize: Callable[..., tuple[str, dict[str, bytes]]]
    file_name_of: Callable[[RootElement, Asset], str | None]
    from_zip: Callable[..., RootElement]
    serialize_for_compile: Callable[
        [RootElement], tuple[str, dict[str, bytes], Composition, list[Element | None]]
    ]
    compile_composition: Callable[[RootElement], Any]
    compile_model: Callable[[RootElement], Physics]
    element_class: type[Element]
    root_class: type[RootElement]


ABOVE = Above()
