"""Structural equality of elements: `element.is_same_as(other)`, as dm_control defines it.

    copy.deepcopy(model).is_same_as(model)          # True
    arm_a.find('body', 'hand').is_same_as(arm_b.find('body', 'hand'))

Two elements are the same when they have the same schema (the same tag in the same kind of
place), the same attribute values (numbers by value, references by what they point to) and
the same children. Unlike dm_control, models attached inside are compared too.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from mjcf.compose import attachment
from mjcf.tree.element import Element, stored_attributes, tree_children, value_of, written_empty
from mjcf.tree.root import RootElement

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec


def is_same_as(element: Element, other: object) -> bool:
    """Whether `other` is an element structurally equal to `element`: the same schema (the
    same tag in the same kind of place), the same attribute values and the same children.
    Numbers compare by value (`pos="0 0 1"` read from a file equals `pos=[0, 0, 1]` set in
    Python), references by what they point to, named relative to each element's own model
    (`joint=hinge` equals `joint="hinge"`). Repeated children compare in order among those
    of one tag (a body's geoms in order, its sites in order, geoms and sites in any
    interleaving); the children of a tendon path compare in strict order, since that
    order is the path. A model compares its sections, not its name. Unlike dm_control,
    models attached inside are compared too: their attachment frames in order, with the
    models they hold."""
    if not isinstance(other, Element) or other.spec is not element.spec:
        return False
    is_root = isinstance(element, RootElement)
    if is_root != isinstance(other, RootElement):
        return False
    if not is_root and not _same_attributes(element, other):
        return False
    if isinstance(element, attachment.AttachmentFrame) and not is_same_as(
        element.attached_model,
        other.attached_model,
    ):
        return False
    if _is_tendon_path(element):
        return _same_sequence(tree_children(element), tree_children(other))
    return _same_children(element, other)


def _same_attributes(element: Element, other: Element) -> bool:
    attributes = element.spec.attributes
    for name in stored_attributes(element).keys() | stored_attributes(other).keys():
        attribute = attributes[name]
        if not _same_value(
            attribute, _comparable(element, attribute), _comparable(other, attribute)
        ):
            return False
    return True


def _comparable(element: Element, attribute: AttributeSpec) -> Any:
    """The value of `attribute` of `element` in a form that compares across models:
    numbers as numbers, references as the names of their targets in the element's model."""
    value = value_of(element, attribute)
    if value is None or not attribute.converter.refers:
        return value
    items = value if isinstance(value, list) else [value]
    names: list[str | None] = []
    for item in items:
        if isinstance(item, str):
            names.extend(item.split() if attribute.is_list else [item])
        else:
            names.append(_target_name(element, item))
    return tuple(names)


def _target_name(element: Element, target: Element) -> str | None:
    """The name of reference target `target` as seen from `element`'s model."""
    if target.root is element.root or _attached_inside(target.root, element.root):
        return target.prefixed_identifier(element.root)
    return target.full_identifier


def _attached_inside(model: Element, root: Element) -> bool:
    scope = model.namescope.parent
    while scope is not None:
        if scope is root.namescope:
            return True
        scope = scope.parent
    return False


def _same_value(attribute: AttributeSpec, a: Any, b: Any) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return attribute.converter.same(a, b)


def _is_tendon_path(element: Element) -> bool:
    parent = element.parent
    return parent is not None and parent.spec.tag == "tendon" and parent.parent is element.root


def _same_sequence(children: Sequence[Element], others: Sequence[Element]) -> bool:
    return len(children) == len(others) and all(
        is_same_as(child, other) for child, other in zip(children, others, strict=True)
    )


def _same_children(element: Element, other: Element) -> bool:
    """Children compare tag by tag, in order within a tag; a once-only child that is
    empty is the same as one that is absent, where it is not written then."""
    mine = _by_tag(element)
    theirs = _by_tag(other)
    for tag in mine.keys() | theirs.keys():
        if not _same_sequence(mine.get(tag, []), theirs.get(tag, [])):
            return False
    return True


def _by_tag(element: Element) -> dict[str, list[Element]]:
    groups: dict[str, list[Element]] = {}
    for child in tree_children(element):
        if not stored_attributes(child) and not tree_children(child) and not written_empty(child):
            continue
        groups.setdefault(child.spec.tag, []).append(child)
    return groups
