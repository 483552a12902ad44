"""References between elements (`joint=`, `material=` ...) through renames and removals.

    motor = model.actuator.add('motor', joint='hip')   # 'hip' exists: motor.joint is it
    model.find('joint', 'hip').name = 'hip_x'           # the motor follows the rename
    model.find('joint', 'hip_x').remove()               # writing the motor now raises
    model = mjcf.from_path('arm.xml', resolve_references=False)   # text, as dm_control,
    model.resolve_references()                                    # until resolved

Read with `resolve_references=True` (the default), a model behaves as if every reference
were resolved when read; writing one to a removed element raises InvalidReferenceError.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mjcf.tree.element_list import attached_models

if TYPE_CHECKING:
    from collections.abc import Mapping

    from mjcf.schema import AttributeSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# How a model keeps its references (`ModelReferences.mode`). A model read from a file is
# not built whole, so references read are kept as text (UNPINNED) while no element of the
# model is renamed or removed, since text written by name then compiles to what the element
# would. Before the first name of a model changes (a rename, a removal, an unnamed asset
# given another file, a detach), every text reference that names an element is replaced by
# that element (`before_name_change`, which the name scope calls): renaming or removing an
# element then changes what every reference to it writes. A model read with
# `resolve_references=False` keeps text as text (BY_NAME), as dm_control does, until
# `resolve_references()`.
PINNED = 0  # every reference naming an element holds it, but those in `forward`
UNPINNED = 1  # references read from a file are text still (see above)
BY_NAME = 2  # read with resolve_references=False: text stays text
_MAIN_CLASS = "main"
ANY_NAMESPACE = "*"  # `referenced`'s key of names referenced from default classes


class ModelReferences:
    """This module's state of one model's references: `mode` (`PINNED`, `UNPINNED` or
    `BY_NAME`), `referenced` (the names references read from the model's file name, by
    namespace, `ANY_NAMESPACE` for those of default classes; None: any name) and `forward`
    (the elements of the model holding text references that named no element when set).

    `RootElement._references` holds it; only this module reads and changes it. The reader
    and copies set it up through `start_reading`, `record_read_names` and `copy_state`."""

    __slots__ = ("forward", "mode", "referenced")

    def __init__(self) -> None:
        self.mode = PINNED
        self.referenced: dict[str, frozenset[str]] | None = None
        self.forward: set[Element] = set()


def _state(model: RootElement) -> ModelReferences:
    return model._references


def start_reading(model: RootElement, resolve_references: bool) -> None:
    """The new, empty `model` is about to be read from a file: the references read are
    kept as text, until a name changes if `resolve_references`, else until
    `resolve_references()` (see `UNPINNED`)."""
    _state(model).mode = UNPINNED if resolve_references else BY_NAME


def record_read_names(model: RootElement, referenced: dict[str, frozenset[str]]) -> None:
    """Record the names that the references read from `model`'s file name, by namespace
    (`ANY_NAMESPACE`: from default classes, of any namespace): a change of another name
    leaves the references read as text."""
    _state(model).referenced = referenced


def copy_state(source: RootElement, copy: RootElement, copies: Mapping[int, Element]) -> None:
    """Give `copy`, a new copy of model `source`, the state of `source`'s references;
    `copies` maps `id(element)` of `source`'s elements to their copies."""
    state, copied = _state(source), _state(copy)
    copied.mode = state.mode
    copied.referenced = state.referenced
    copied.forward = {copies[id(e)] for e in state.forward if id(e) in copies}


def stored(element: Element, attribute: AttributeSpec, value: Any, attrs: Mapping[str, Any]) -> Any:
    """The value to store for reference `attribute` of `element` (whose stored attributes
    are `attrs`), given `value` (text, an element, or a list of them) through the API:
    names resolved to the elements that have them now, unless the model keeps references
    by name. A name that no element has yet is kept as text, which the element that takes
    the name later answers (as MuJoCo would read the written text), and which then follows
    that element as a resolved reference does (`forward`)."""
    root = element.root
    state = _state(root)
    if state.mode == BY_NAME or not _has_text(value):
        return value
    namespace = attribute.reference_namespace(attrs)
    if namespace is None:
        return value
    resolved, unresolved = _resolve(root, namespace, attribute, value)
    if unresolved:
        state.forward.add(element)
    return resolved


def read(element: Element, attribute: AttributeSpec, value: str, attrs: dict[str, Any]) -> Any:
    """What reading reference `attribute` of `element`, stored as text `value` in its
    stored attributes `attrs`, gives: the element (or elements) it names, which `attrs`
    then holds, or the text if it names none or the model keeps references by name."""
    root = element.root
    state = _state(root)
    if state.mode == BY_NAME or not value:
        return value
    namespace = attribute.reference_namespace(attrs)
    if namespace is None:
        return value
    resolved, unresolved = _resolve(root, namespace, attribute, value)
    if resolved is not value:
        attrs[attribute.name] = resolved
        if unresolved:  # a list naming some elements, and some not yet
            state.forward.add(element)
        else:
            state.forward.discard(element)
    return resolved


def before_name_change(model: RootElement, namespace: str | None, name: str | None) -> None:
    """Name `name` of `namespace` in `model`'s scope is about to change or go (None: the
    name of a model attached to it): every text reference that may name its element, in
    `model` and in the models it is attached into (whose scoped names reach into it), is
    replaced by the element it names first. References read from a file name elements
    of their own model only ('/' is no part of them), and only the names the reader
    recorded (`referenced`), so a name none of them names leaves the model unbuilt."""
    if _state(model).mode == UNPINNED and _read_reference(model, namespace, name):
        pin_model(model)
    current: RootElement | None = model
    while current is not None:
        _pin_forward(current)
        current = current.parent_model


def _read_reference(model: RootElement, namespace: str | None, name: str | None) -> bool:
    """Whether a reference read from `model`'s file may name `name` of `namespace` (none
    names an attached model's element)."""
    if namespace is None or name is None:
        return False
    referenced = _state(model).referenced
    if referenced is None:
        return True
    return name in referenced.get(namespace, ()) or name in referenced.get(ANY_NAMESPACE, ())


def pin_model(model: RootElement) -> None:
    """Make every text reference of `model` that names an element hold that element
    now, as reading it would (nothing for a model that keeps references by name)."""
    state = _state(model)
    if state.mode == UNPINNED:
        state.mode = PINNED
        for element in model.iter():
            _pin(element)
    else:
        _pin_forward(model)


def _pin_forward(model: RootElement) -> None:
    """Make the text references set through the API that named no element when set
    (`forward`) hold the elements they name now."""
    state = _state(model)
    if state.forward and state.mode != BY_NAME:
        for element in list(state.forward):
            if not element.is_removed:
                _pin(element)
            else:
                state.forward.discard(element)


def resolve_all(element: Element) -> None:
    """Replace every text reference of `element`'s subtree that names an element by
    that element (names that match none stay text); for a model, also those of the
    models attached to it, which then resolve the references they are given from now
    on (see `Element.resolve_references`)."""
    if element is element.root:
        models = [element.root, *attached_models(element.root)]
        for model in models:
            _state(model).mode = PINNED
            for item in model.iter():
                _pin(item)
        return
    for item in element.iter():
        _pin(item)


def _pin(element: Element) -> None:
    """Replace the text references of `element` that name an element by that element;
    remember `element` in its model's `forward` if some name none."""
    attrs = element._attrs
    spec = element.spec
    if not spec.references or spec.references.isdisjoint(attrs):
        return
    root = element.root
    unresolved = False
    for name in spec.references.intersection(attrs):
        value = attrs[name]
        if not _has_text(value):
            continue
        attribute = spec.attributes[name]
        namespace = attribute.reference_namespace(attrs)
        if namespace is None:
            continue
        resolved, missing = _resolve(root, namespace, attribute, value)
        attrs[name] = resolved
        unresolved = unresolved or missing
    forward = _state(root).forward
    if unresolved:
        forward.add(element)
    else:
        forward.discard(element)


def _has_text(value: Any) -> bool:
    """Whether reference `value` holds a non-empty name as text."""
    if type(value) is str:
        return bool(value)
    if isinstance(value, list):
        return any(type(item) is str and item for item in value)
    return False


def _resolve(
    root: RootElement, namespace: str, attribute: AttributeSpec, value: Any
) -> tuple[Any, bool]:
    """(`value` with its names replaced by the elements of `root` that have them,
    whether a name matched none). A list attribute's text becomes a list."""
    scope = root.namescope
    if not attribute.is_list:
        if type(value) is not str:
            return value, False
        target = scope.lookup(namespace, value)
        if target is None:  # the top default class, 'main', is no element to hold
            return value, not (namespace == "default" and value == _MAIN_CLASS)
        return target, False
    items = value.split() if type(value) is str else value
    resolved = []
    missing = False
    for item in items:
        if type(item) is str and item:
            target = scope.lookup(namespace, item)
            if target is None:
                missing = True
            else:
                item = target
        resolved.append(item)
    if not missing and type(value) is str and not items:
        return value, False
    return resolved, missing
