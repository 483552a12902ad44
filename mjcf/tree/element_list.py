"""Lists of child elements, as `body.geom` or `model.actuator.motor` return them.

    body.geom[0], body.geom['tip']                 # by position or by name
    scene.attach(arm)
    scene.actuator.motor                           # scene's motors, then arm's
    scene.actuator.motor['arm/elbow']              # scoped names reach attached models

As in dm_control, a model's top-level sections but the world body and the defaults list
the children of the models attached into it after their own, in the order they were
attached (`all_children()` too). The lists are copies: change a model with `add`, `remove`.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, SupportsIndex, overload

from mjcf import errors

if TYPE_CHECKING:
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# Sections whose children are not merged from attached models: an attached model's
# world body is where it is attached, and its defaults stay its own.
OWN_SECTIONS = frozenset({"worldbody", "default"})


class ElementList(list["Element"]):
    """The repeated children of one tag: a list that is also indexable by name ('tip',
    or 'arm/elbow' for an element of an attached model)."""

    def __init__(self, elements: Iterable[Element] = (), root: RootElement | None = None) -> None:
        super().__init__(elements)
        self.root = root

    @overload
    def __getitem__(self, key: SupportsIndex | str) -> Element: ...
    @overload
    def __getitem__(self, key: slice) -> list[Element]: ...
    def __getitem__(self, key: SupportsIndex | str | slice) -> Element | list[Element]:
        if isinstance(key, str):
            for element in self:
                if element.root is self.root or self.root is None:
                    if element.identifier == key:
                        return element
                elif element.prefixed_identifier(self.root) == key:
                    return element
            raise errors.NotFoundError(f"no element named {key!r} among {self.tags()}")
        return super().__getitem__(key)

    def clear(self) -> None:
        """Remove the listed elements of this list's own model from the model, as
        dm_control's `model.actuator.motor.clear()` does (those of attached models stay)."""
        for element in [e for e in self if self.root is None or e.root is self.root]:
            element.remove()
            super().remove(element)

    def __delitem__(self, key: SupportsIndex | str | slice) -> None:
        """Remove the element(s) `key` picks from the model, as dm_control does."""
        found = self[key]
        for element in found if isinstance(found, list) else [found]:
            element.remove()
            super().remove(element)

    def tags(self) -> str:
        """The tags of the listed elements, for messages."""
        return ", ".join(sorted({f"<{e.tag}>" for e in self})) or "no elements"


def attached_models(model: RootElement) -> list[RootElement]:
    """Every model attached inside `model`: each attached model followed by those attached
    inside it, in the order they were attached. Sections other than the world body are
    written in this order."""
    found: list[RootElement] = []
    for scope in model.namescope.children.values():
        found.append(scope.model)
        found.extend(attached_models(scope.model))
    return found
