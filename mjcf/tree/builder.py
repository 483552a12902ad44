"""Writing elements' slots without the setters' checks: besides `element`, the one module that does.

    element = builder.new_element(Element, spec, parent, parent.root)  # made, not placed
    builder.attributes_to_fill(element).update({'name': 'arm'})       # values as stored
    builder.children_to_fill(parent).append(element)                   # placed
    builder.register(element)          # its name in its model's scope (or NameClashError)
    builder.cut(element)               # out of the tree, its subtree's names forgotten

Its users check a whole document, plan or model first, then build here what they checked
and `count_change` it; everything else uses elements' public methods (docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import MutableMapping
from typing import TYPE_CHECKING, Any, TypeVar

from mjcf.tree.element import Element

if TYPE_CHECKING:
    from mjcf.schema import ElementSpec
    from mjcf.tree.debugging import SourceLocation
    from mjcf.tree.root import RootElement

_E = TypeVar("_E", bound=Element)


def new_element(kind: type[_E], spec: ElementSpec, parent: Element | None, root: RootElement) -> _E:
    """A new element of class `kind` (`Element`, or a subclass such as an attachment
    frame) with schema `spec`, its parent `parent` (None: outside the tree) in model
    `root`: no attributes, no children, not yet among `parent`'s children nor named."""
    return kind._make(spec, parent, root)


def attributes_to_fill(element: Element) -> dict[str, Any]:
    """`element`'s stored attributes (see `mjcf.tree.element.stored_attributes`), to fill
    or change in place with values checked already."""
    return element._attrs


def replace_attributes(element: Element, storage: MutableMapping[str, Any]) -> None:
    """Make `storage` the stored attributes of `element` (a settings element of an
    attached model takes the outermost model's, shared: see
    `mjcf.compose.global_settings`)."""
    object.__setattr__(element, "_attrs", storage)


def change_class(element: Element, kind: type[Element]) -> None:
    """Make `element` an instance of `kind`: `Element`, or a subclass of it with no slots
    of its own (`mjcf.compose.global_settings.SharedSettings`), keeping all it holds."""
    element.__class__ = kind


def children_to_fill(element: Element) -> list[Element]:
    """`element`'s children in its own model's tree, to fill or change in place with
    elements made for it (`new_element` with it as parent)."""
    return element._children


def register(element: Element) -> None:
    """Record `element`'s name (if it has one) in its model's scope, once it is in the
    tree; raises mjcf.NameClashError, changing nothing, if another element has it."""
    element._register()


def unregister_subtree(element: Element) -> None:
    """Forget the names of `element` and its subtree in their model's scope."""
    element._unregister_subtree()


def is_named_after_file(element: Element) -> bool:
    """Whether `element` has no name of its own (an unnamed mesh, texture ... is named after
    its file, as MuJoCo names it): a copy's name has the same standing."""
    return element._implicit()


def keep(element: Element) -> None:
    """Count `element` as put there, even if it was made by reading `parent.<tag>` (see
    `mjcf.tree.element.written_empty`)."""
    element._keep()


def cut(element: Element) -> Element:
    """Take `element` and its subtree out of the tree, forgetting their names; returns
    the parent it had."""
    return element._cut()


def defer(element: Element, xml: Any) -> None:
    """Make `element`'s children from lxml element `xml` (checked by the reader) when they
    are first used, instead of now (see `Element`)."""
    element._defer(xml)


def set_created_at(element: Element, site: SourceLocation | None) -> None:
    """Record where `element` was made, for debug mode (see `mjcf.tree.debugging`)."""
    object.__setattr__(element, "_source", site)


def cache_text(element: Element, entry: tuple[tuple, str] | None) -> None:
    """Keep the writer's attribute text of `element`: ((model version, context, number
    format), text), which the writer alone reads (see `mjcf.io.serializer`)."""
    object.__setattr__(element, "_text", entry)
