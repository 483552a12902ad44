"""The checks an element makes before a change: of a name (valid, free in its model's
scope, which `mjcf.tree.element_names` keeps the element in) and of the rules
between values (at most one orientation of a body ...: MuJoCo's reader's rules; what
crashes MuJoCo, see `mjcf.schema._refusals`). A part of `Element` (see
`mjcf.tree.element`); each raises the `mjcf.Error` that says what is wrong, before
anything changes.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any, cast

from mjcf import errors
from mjcf.tree.element_names import ElementNames
from mjcf.tree.namescope import check_identifier

if TYPE_CHECKING:
    from mjcf.schema import ElementSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement


def _element(checks: ElementChecks) -> Element:
    """`checks` as the `Element` it is (ElementChecks is only a base of Element)."""
    return cast("Element", checks)


class ElementChecks(ElementNames):
    """The checks of an element's names and rules; a base of `Element`, not used alone."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element the checks use on `self`
        _spec: ElementSpec
        _parent: Element | None
        _root: RootElement
        _attrs: dict[str, Any]

        @property
        def path(self) -> str: ...
        def _is_registered(self) -> bool: ...
        def _children_attributes(self) -> list[tuple[str, Mapping[str, Any]]]: ...

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

    def _check_crash(self, setting: list[str]) -> None:
        """Raise mjcf.SchemaError if setting the attributes `setting` makes this element,
        or its parent, one MuJoCo crashes on (`ElementSpec.crash`)."""
        if self._spec.crashing_children:
            crash = self._spec.crash([*self._attrs, *setting], self._children_attributes())
            if crash is not None:
                raise errors.SchemaError(f"{self.path}: {crash}")
        parent = self._parent
        if parent is not None and parent.spec.crashing_children:
            parent._check_child(self._spec.tag, [*self._attrs, *setting])

    def _check_child(self, tag: str, attributes: list[str]) -> None:
        """Raise mjcf.SchemaError if a child `tag` with `attributes` set makes this
        element one MuJoCo crashes on (`ElementSpec.crash`)."""
        children = self._children_attributes()
        crash = self._spec.crash(self._attrs, [*children, (tag, attributes)])
        if crash is not None:
            raise errors.SchemaError(f"{self.path}: {crash}")

    def _check_rules(self, setting: set[str], removing: Iterable[str]) -> None:
        """Raise mjcf.AttributeValueError if setting the attributes `setting` (and
        removing `removing`) would set two of a group MuJoCo allows one of (two
        orientations of a body, say)."""
        names = (self._attrs.keys() - set(removing)) | setting
        rule = self._spec.conflict(names)
        if rule is not None:
            shown = ", ".join(sorted(rule.names & names))
            raise errors.AttributeValueError(
                f"{self.path}: {shown} cannot be set together: {rule.describe()} (remove "
                "one, e.g. `del element.name`, before setting another)"
            )
