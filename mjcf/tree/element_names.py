"""An element's name in its model's scope, which `mjcf.tree.namescope` keeps: recorded when
the element joins the tree, changed with its name (or with the file an asset is named
after) and forgotten when it leaves; an attachment frame's joints are named within the
frame instead. A part of `Element` (see `mjcf.tree.element`); its checks of a name before a
change are `mjcf.tree.element_checks`'.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any, cast

from mjcf import errors
from mjcf.tree.model_operations import ModelOperations
from mjcf.tree.namescope import NAMED_AFTER_FILE, name_from_file

if TYPE_CHECKING:
    from mjcf.schema import ElementSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement


def _element(names: ElementNames) -> Element:
    """`names` as the `Element` it is (ElementNames is only a base of Element)."""
    return cast("Element", names)


class ElementNames(ModelOperations):
    """An element's name in its model's scope; a base of `Element`, not used alone."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element these methods use on `self`
        _spec: ElementSpec
        _parent: Element | None
        _root: RootElement
        _attrs: dict[str, Any]

        @property
        def identifier(self) -> str | None: ...
        @property
        def path(self) -> str: ...
        def iter(self) -> Iterator[Element]: ...
        def _is_registered(self) -> bool: ...

    # The children of an element whose class sets this False (an attachment frame's
    # joints) are named within it, not among their model's names (see
    # mjcf.compose.attachment).
    _names_children_in_model = True

    def _named_in_model(self) -> bool:
        """Whether this element's name is one of its model's names: not for a child of
        an attachment frame, whose name is its own within the frame."""
        parent = self._parent
        return parent is None or parent._names_children_in_model

    def _check_free_in_parent(self, name: str) -> None:
        """Raise mjcf.NameClashError if another child of this element's parent has
        `name` in the same namespace (for names kept within their parent)."""
        parent = self._parent
        assert parent is not None, "named within its parent"
        for sibling in parent._children:
            if (
                sibling is not self
                and sibling.spec.namespace == self._spec.namespace
                and sibling.identifier == name
            ):
                raise errors.NameClashError(
                    f"{self.path}: the name {name!r} is already used by another "
                    f"{self._spec.namespace} of {parent.path}: {sibling.path}"
                )

    def _register(self) -> None:
        """Record this element's name in its model's scope; raises mjcf.NameClashError
        if another element has it."""
        namespace = self._spec.namespace
        if namespace is None:
            return
        if not self._named_in_model():
            if self.identifier:
                self._check_free_in_parent(self.identifier)
            return
        name = self.identifier
        if name:  # an empty name (kept where MuJoCo requires the attribute) is no name
            self._root.namescope.add(namespace, name, _element(self), self._implicit())

    def _implicit(self) -> bool:
        return self._spec.identifier is not None and self._attrs.get(self._spec.identifier) is None

    def _unregister_subtree(self) -> None:
        scope = self._root.namescope
        for element in self.iter():
            namespace = element.spec.namespace
            name = element.identifier
            if namespace is not None and name is not None and element._named_in_model():
                scope.remove(namespace, name, element)

    def _rename(self, new_name: str | None) -> None:
        namespace = self._spec.namespace
        if namespace is None or not self._is_registered():
            return
        if not self._named_in_model():
            if new_name is not None:
                self._check_free_in_parent(new_name)
            return
        scope = self._root.namescope
        scope.rename(namespace, self.identifier, new_name, _element(self))
        if new_name is None and self._spec.tag in NAMED_AFTER_FILE:
            implicit = name_from_file(self._attrs.get("file"))
            if implicit is not None:
                scope.add(namespace, implicit, _element(self), implicit=True)

    def _rename_after_file(self, file_value: object) -> None:
        namespace = self._spec.namespace  # an asset's: never None
        if namespace is None or self._attrs.get("name") is not None or not self._is_registered():
            return
        scope = self._root.namescope
        old = self.identifier
        if old is not None:
            scope.remove(namespace, old, _element(self))
        new = name_from_file(file_value)
        if new is not None:
            scope.add(namespace, new, _element(self), implicit=True)
