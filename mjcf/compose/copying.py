"""Copies: `include_copy`, which merges a copy of another model (or element) into this one
without a name scope, as MuJoCo's `<include>` would, and `copy.deepcopy` of models.

    scene.include_copy(mjcf.from_path('floor.xml'))     # its names join scene's
    body.include_copy(other_body)                         # same-tag elements too
    twin = copy.deepcopy(arm); twin.model = 'right'       # a detached copy, to attach again

Everything is checked before anything changes. References in a copy point at the copies,
and objects copied in the same `deepcopy` call keep pointing at the copied elements.
"""

from __future__ import annotations

import copy
from typing import Any, TypeVar, cast

import numpy as np

from mjcf import errors
from mjcf.compose import attachment, global_settings
from mjcf.compose.settings import same as _same
from mjcf.schema.tracked_array import track
from mjcf.tree import assets, builder, bulk, references
from mjcf.tree.assets import Asset
from mjcf.tree.element import (
    Element,
    count_change,
    created_at,
    single_child,
    stored_attributes,
    tree_children,
    value_of,
    written_empty,
)
from mjcf.tree.namescope import NAMED_AFTER_FILE, name_from_file
from mjcf.tree.root import RootElement, own_version, set_own_version

_E = TypeVar("_E", bound=Element)


def include_copy(target: Element, source: Element, override_attributes: bool = False) -> None:
    """Merge a copy of `source` into `target`, as MuJoCo's `<include>` would: attributes
    are merged (a value both sides set differently is an error, unless
    `override_attributes`), children are copied, names must not collide (with
    `override_attributes`, a child named as an element of the same parent is merged into
    it, as dm_control does). Raises mjcf.SchemaError for elements of different tags,
    mjcf.AttachmentError for conflicting attribute values and mjcf.NameClashError for
    names already taken; everything is checked first, and the tree is unchanged then."""
    if target.tag != source.tag or isinstance(target, RootElement) != isinstance(
        source, RootElement
    ):
        raise errors.SchemaError(
            f"{target.path}: include_copy needs an element of the same kind, got {source.path}"
        )
    if _contains(source, target):
        raise errors.AttachmentError(f"{target.path}: cannot include a copy of its own ancestor")
    # The copy is of the source as if its references had been resolved when it was read.
    references.pin_model(source.root)
    plan: list[tuple[Element, Element, dict[str, Any], list[Element]]] = []
    _plan_merge(target, source, override_attributes, plan)
    renames = _check_names(target, plan)
    frames = [
        element
        for _, _, _, children in plan
        for child in children
        for element in child.iter()
        if isinstance(element, attachment.AttachmentFrame)
    ]
    merge = global_settings.SettingsMerge(target.root.root_model)
    for frame in frames:  # the copies of models attached inside join target's settings
        merge.add(frame.attached_model)
    if frames:
        merge.raise_problems(frames[0].attached_model, target.root)
    clones: dict[int, Element] = {}
    for destination, origin, attributes, children in plan:
        builder.attributes_to_fill(destination).update(attributes)
        if attributes:
            count_change(destination)  # of the model whose settings it shares, too
        if written_empty(origin):  # put there in the source: so it is in the copy
            builder.keep(destination)
        for child in children:
            clone = _clone(child, destination, clones)
            builder.children_to_fill(destination).append(clone)
            for element in clone.iter():
                builder.register(element)
    merge.apply()
    for frame in frames:
        global_settings.share(cast(attachment.AttachmentFrame, clones[id(frame)]).attached_model)
    scope = target.root.namescope
    for destination, (namespace, old, new) in renames.items():
        if old is not None:
            scope.remove(namespace, old, destination)
        scope.add(namespace, new, destination, implicit=builder.is_named_after_file(destination))
    _relink_references(clones, source.root)
    count_change(target)


def _contains(ancestor: Element, element: Element) -> bool:
    current: Element | None = element
    while current is not None:
        if current is ancestor:
            return True
        current = current.parent
    return False


def _plan_merge(target: Element, source: Element, override: bool, plan: list) -> None:
    attributes = {}
    for name, value in stored_attributes(source).items():
        if name == "model":
            continue
        mine = stored_attributes(target).get(name)
        if mine is not None and not override:
            spec = target.spec.attributes[name]
            if not _same(spec, value_of(target, spec), value_of(source, spec)):
                raise errors.AttachmentError(
                    f"{target.path}: Conflicting values for attribute `{name}`: "
                    f"{target.get_attribute_xml_string(name)!r} here and "
                    f"{source.get_attribute_xml_string(name)!r} in {source.path}; pass "
                    "override_attributes=True to take the included value"
                )
            continue
        attributes[name] = _copied_value(source, name, value)
    children = []
    for child in tree_children(source):
        if child.spec.repeated:
            existing = _named_alike(target, child) if override else None
            if existing is None:
                children.append(child)
            else:  # overriding: the element of that name takes the copy's values
                _plan_merge(existing, child, override, plan)
            continue
        existing = single_child(target, child.spec.tag)
        if existing is None:
            children.append(child)
        else:
            _plan_merge(existing, child, override, plan)
    plan.append((target, source, attributes, children))


def _named_alike(target: Element, child: Element) -> Element | None:
    """The child of `target` named as `child` (of the same namespace), as dm_control
    finds it to override; None if `child` is unnamed or no element has its name. Raises
    mjcf.AttachmentError if an element elsewhere in the model has it."""
    spec = child.spec
    name = stored_attributes(child).get(spec.identifier) if spec.identifier else None
    if not isinstance(name, str) or not name or spec.namespace is None:
        return None
    found = target.find(spec.namespace, name)
    if found is not None and found.parent is not target:
        raise errors.AttachmentError(
            f"{target.path}: <{spec.namespace}> with identifier {name!r} is already a child of "
            f"another element ({found.path}); include_copy overrides only elements of the "
            "same parent"
        )
    return found


def _check_names(target: Element, plan: list) -> dict[Element, tuple[str, str | None, str]]:
    """Raise mjcf.NameClashError if a copy would take a name that `target`'s model has
    (a copied element, or an element merged with one, which takes its name); returns
    {merged element: (namespace, its name, its name after the merge)} of those whose
    name changes."""
    scope = target.root.namescope
    renames = {}
    for destination, _, attributes, children in plan:
        namespace = destination.spec.namespace
        old = destination.identifier
        new = _merged_name(destination, attributes)
        if namespace is not None and new is not None and new != old:
            if not _merged_implicit(destination, attributes):
                scope.check_free(namespace, new, destination, renaming=True)
            renames[destination] = (namespace, old, new)
        for child in children:
            for element in child.iter():
                namespace = element.spec.namespace
                name = element.identifier
                named_in_frame = isinstance(element.parent, attachment.AttachmentFrame)
                if (
                    namespace is not None
                    and name is not None
                    and not builder.is_named_after_file(element)
                    and not named_in_frame
                ):
                    scope.check_free(namespace, name, element)
                if isinstance(element, attachment.AttachmentFrame):
                    scope.check_child_free(element.attached_model.model)
    return renames


def _merged_name(element: Element, attributes: dict[str, Any]) -> str | None:
    """The name `element` has once `attributes` are merged into it."""
    identifier = element.spec.identifier
    if identifier is None:
        return None
    merged = {**stored_attributes(element), **attributes}
    name = merged.get(identifier)
    if name is None and element.spec.tag in NAMED_AFTER_FILE:
        return name_from_file(merged.get("file"))
    return name


def _merged_implicit(element: Element, attributes: dict[str, Any]) -> bool:
    """Whether `element`'s name after the merge is the one MuJoCo gives after a file."""
    identifier = element.spec.identifier
    return (
        identifier is not None
        and {**stored_attributes(element), **attributes}.get(identifier) is None
    )


def _clone(element: Element, parent: Element, clones: dict[int, Element]) -> Element:
    cls = type(element)
    clone = builder.new_element(cls, element.spec, parent, parent.root)
    builder.attributes_to_fill(clone).update(
        {k: _copied_value(element, k, v) for k, v in stored_attributes(element).items()}
    )
    clones[id(element)] = clone
    if isinstance(element, attachment.AttachmentFrame):
        frame = cast(attachment.AttachmentFrame, clone)  # made by type(element)
        attachment.link(frame, copy.deepcopy(element.attached_model))
    for child in tree_children(element):
        builder.children_to_fill(clone).append(_clone(child, clone, clones))
    return clone


def _relink_references(clones: dict[int, Element], source: RootElement) -> None:
    """References to copied elements point at their copies; those to other elements of
    the `source` model are its names, as the included text would have them, which
    resolve in the copies' model (see `mjcf.tree.references`)."""

    def relinked(value: Any) -> Any:
        if isinstance(value, Element):
            clone = clones.get(id(value))
            if clone is not None:
                return clone
            if value.root is source and value.identifier is not None:
                return value.identifier
        return value

    for clone in clones.values():
        attrs = builder.attributes_to_fill(clone)
        spec = clone.spec
        for name in spec.references.intersection(attrs):
            value = attrs[name]
            value = [relinked(v) for v in value] if isinstance(value, list) else relinked(value)
            attrs[name] = references.stored(clone, spec.attributes[name], value, attrs)


def _copied_value(element: Element, name: str, value: Any) -> Any:
    """The value a copy of `element` gets for attribute `name`: a file as the `Asset`
    the source finds (its model's directory and assets are not the copy's), shared as
    dm_control shares it; arrays copied."""
    if type(value) is str:
        attribute = element.spec.attributes[name]
        if attribute.converter.files and value:
            return value_of(element, attribute)
        return value
    return value.copy() if hasattr(value, "copy") else value


# -- copy.deepcopy ------------------------------------------------------------------------


@bulk.whole_tree
def deepcopy_element(element: _E, memo: dict[int, Any]) -> _E:
    """`copy.deepcopy(element)`: deep-copying an element copies its whole model, with the
    models attached to it, and returns the element's copy. The copy is not attached
    anywhere, even if the original is. References between elements point at the copies,
    and other objects copied in the same `deepcopy` call (an entity holding a model and
    some of its elements) keep pointing at the copied elements (`memo`)."""
    found = memo.get(id(element))
    if found is not None:
        return found
    cloned: list[tuple[Element, Element]] = []
    if not element.is_removed:
        copied = _copy_model(element.root, memo, cloned)
        # Its attached models share its settings; the copy of an attached model has its own.
        global_settings.unshare(copied)
    else:  # a removed element: a removed copy, in a copy of its model
        root_copy = deepcopy_element(element.root, memo)
        copy_ = builder.new_element(type(element), element.spec, None, root_copy)
        _clone_into(element, copy_, memo, cloned)
    _relink_copies(cloned, memo)
    return memo[id(element)]


def _copy_model(root: RootElement, memo: dict[int, Any], cloned: list) -> RootElement:
    """A detached copy of `root` and the models attached to it, recorded in `memo`."""
    found = memo.get(id(root))
    if found is not None:
        return found
    new = type(root)(model_dir=root.model_dir, assets=root.assets)
    memo[id(root)] = new
    builder.attributes_to_fill(new).update(stored_attributes(root))
    builder.set_created_at(new, created_at(root))
    sections = {section.spec.tag: section for section in tree_children(new)}
    for section in tree_children(root):
        _clone_into(section, sections[section.spec.tag], memo, cloned)
    references.copy_state(root, new, memo)
    for element in new.iter():
        if element.parent is not None:
            builder.register(element)
    for frame in attachment.frames(root):  # in the order they were attached
        attachment.link(memo[id(frame)], _copy_model(frame.attached_model, memo, cloned))
    set_own_version(new, own_version(root))
    return new


def _clone_into(source: Element, target: Element, memo: dict[int, Any], cloned: list) -> None:
    """Copy the attributes and subtree of `source` into the new element `target`."""
    memo[id(source)] = target
    source_site = created_at(source)
    if source_site is not None:
        builder.set_created_at(target, source_site)
    source_attrs = stored_attributes(source)
    if source_attrs:
        attrs = builder.attributes_to_fill(target)
        attrs.update(source_attrs)  # text as read is immutable: shared
        converted = False
        for name, value in source_attrs.items():
            if type(value) is str:
                continue
            converted = True
            if hasattr(value, "shape"):
                attrs[name] = track(np.array(value), target)
            elif isinstance(value, Asset):
                attrs[name] = assets.owned_copy(value, target)
            elif isinstance(value, list):
                attrs[name] = list(value)
        if converted:
            cloned.append((source, target))
    root = target.root
    children = builder.children_to_fill(target)
    for child in tree_children(source):
        clone = builder.new_element(type(child), child.spec, target, root)
        children.append(clone)
        _clone_into(child, clone, memo, cloned)


def _relink_copies(cloned: list[tuple[Element, Element]], memo: dict[int, Any]) -> None:
    """References to copied elements point at their copies."""
    for _, clone in cloned:
        attrs = builder.attributes_to_fill(clone)
        for name, value in attrs.items():
            if isinstance(value, Element):
                attrs[name] = memo.get(id(value), value)
            elif isinstance(value, list):
                attrs[name] = [memo.get(id(v), v) if isinstance(v, Element) else v for v in value]
