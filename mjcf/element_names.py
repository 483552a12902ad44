"""What an element's name changes in its model's name scope: the part of `Element` that
tells the scope (`mjcf.namescope`, which owns the rules for names) what changes, when an
element is named, renamed, given another file (an unnamed asset is named after it) or
taken out of its model.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any, cast

from mjcf import errors
from mjcf.model_operations import ModelOperations
from mjcf.namescope import NAMED_AFTER_FILE, check_identifier, name_from_file

if TYPE_CHECKING:
    from mjcf.element import Element
    from mjcf.root import RootElement
    from mjcf.schema import ElementSpec


def _element(names: ElementNames) -> Element:
    """`names` as the `Element` it is (ElementNames is only a base of Element)."""
    return cast("Element", names)


class ElementNames(ModelOperations):
    """The name of an element in its model's scope; a base of `Element`, not used alone.

    Internal protocol: the tree builders (see `Element`) record a new element's name with
    `_register()` (which raises mjcf.NameClashError if another element has it) and forget
    a subtree's names with `_unregister_subtree()`, and ask `_implicit()` (named after its
    file, by MuJoCo) to give a copy's name the same standing. Whether an element is in its
    model's tree is `Element.is_removed`."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element the names use on `self`
        _spec: ElementSpec
        _parent: Element | None
        _root: RootElement
        _attrs: dict[str, Any]
        _children: list[Element]

        @property
        def identifier(self) -> str | None: ...
        @property
        def path(self) -> str: ...
        def iter(self) -> Iterator[Element]: ...

    def _check_name(self, name: str) -> None:
        """Raise mjcf.NameClashError for a name that holds the scopes' separator, and
        mjcf.AttributeValueError for a name of the top-level default class, which MuJoCo
        does not let a model rename ('main')."""
        check_identifier(name, _element(self))
        if self._spec.tag == "default" and self._parent is self._root and name != "main":
            raise errors.AttributeValueError(
                f"{self.path}: the top-level default class is 'main', which MuJoCo does not "
                f"let a model rename, got {name!r}; add a class inside it instead"
            )

    def _check_free(self, name: str) -> None:
        namespace = self._spec.namespace
        if namespace is None or not self._is_registered():
            return
        if self._named_in_model():
            self._root.namescope.check_free(namespace, name, _element(self), renaming=True)
        else:
            self._check_free_in_parent(name)

    # The children of an element whose class sets this False (an attachment frame's
    # joints) are named within it, not among their model's names (see mjcf.attachment).
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

    def _is_registered(self) -> bool:
        """Whether this element is part of its model's tree (not removed)."""
        element: ElementNames = self
        while element._parent is not None:
            element = element._parent
        return element is self._root

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
