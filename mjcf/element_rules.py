"""The rules an element keeps beyond each value's own: between its attributes (at most
one orientation of a body ...: MuJoCo's reader's rules) and with its children (what
crashes MuJoCo, see `mjcf.schema._refusals`). A part of `Element`.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from mjcf import errors
from mjcf.element_names import ElementNames

if TYPE_CHECKING:
    from mjcf.element import Element


class ElementRules(ElementNames):
    """The checks of the rules between an element's values; a base of `Element`, not
    used alone."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element the rules use on `self`
        _children: list[Element]

    def _check_crash(self, setting: list[str]) -> None:
        """Raise mjcf.SchemaError if setting the attributes `setting` makes this element,
        or its parent, one MuJoCo crashes on (`ElementSpec.crash`)."""
        if self._spec.crashing_children:
            children = [(child.spec.tag, child._attrs) for child in self._children]
            crash = self._spec.crash([*self._attrs, *setting], children)
            if crash is not None:
                raise errors.SchemaError(f"{self.path}: {crash}")
        parent = self._parent
        if parent is not None and parent.spec.crashing_children:
            parent._check_child(self._spec.tag, [*self._attrs, *setting])

    def _check_child(self, tag: str, attributes: list[str]) -> None:
        """Raise mjcf.SchemaError if a child `tag` with `attributes` set makes this
        element one MuJoCo crashes on (`ElementSpec.crash`)."""
        children = [(child.spec.tag, child._attrs) for child in self._children]
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
