"""Default classes: which class an element uses, the value it gets from it, and
`commit_defaults`, which writes those values onto the elements.

    mjcf.commit_defaults(model)      # every element now carries its default values;
                                     # the <default> section is emptied; the compiled
                                     # model is unchanged
    mjcf.commit_defaults(geom, attributes=['rgba'])   # one element, one attribute

A class inherits from the classes it is nested in. What commit_defaults cannot express on
the element raises mjcf.AttributeValueError (an actuator class setting another's gains).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from mjcf import errors, schema
from mjcf.compose import traversal
from mjcf.schema.suggestions import suggest
from mjcf.schema.tracked_array import track
from mjcf.tree import builder
from mjcf.tree.element import (
    Element,
    count_change,
    stored_attributes,
    tree_children,
    value_of,
    written_empty,
)
from mjcf.tree.element_list import attached_models

if TYPE_CHECKING:
    from mjcf.tree.root import RootElement

MAIN = "main"
# Elements whose defaults come from a default child of another tag.
_DEFAULT_TAG = {"spatial": "tendon", "fixed": "tendon"}
_EQUALITY_TAGS = frozenset({"connect", "weld", "joint", "tendon", "flex", "flexstrain"})
# Attributes a default class can set: those `commit_defaults` can commit.
_DEFAULTABLE = frozenset(
    name
    for spec in schema.MUJOCO.child("default").children.values()
    if spec.tag != "default"
    for name in spec.attributes
    if name != "class"
)


class LateDefault(Element):
    """An actuator default of the global defaults set by a later top-level `<default>`
    section: the classes before it among the global defaults' children copied the
    actuator defaults without it, those after it with it.

    A file may set the global actuator defaults in a later top-level `<default>` section,
    after classes were defined that copied them as they were then (Gymnasium-Robotics'
    Adroit hand does): such a setting is a `LateDefault` child of the global defaults,
    placed after the classes that do not see it, and written as a new top-level section
    (see `mjcf.io.serializer`), so that MuJoCo reads it as the file had it."""

    __slots__ = ()


def late_class_name(main_class: str, number: int) -> str:
    """The class that holds the `number`-th late section of a model whose global
    defaults are written as class `main_class` (an attached model's 'arm/'): a class
    nested in it, named so that no scoped class name can be the same ('arm//defaults_1')."""
    return f"{main_class}/defaults_{number}"


def late_sections(model: RootElement) -> int:
    """How many late top-level `<default>` sections `model` has (see `LateDefault`)."""
    return sum(type(child) is LateDefault for child in tree_children(model.default))


def settings_of(default: Element, inner: Element | None = None) -> Sequence[Element]:
    """The children of default class `default` that give their values to its class
    `inner` (one of its children), or, with `inner` None, to the elements that use
    `default` itself: every child, but the late settings of the global defaults made
    after `inner` was defined."""
    children = tree_children(default)
    if inner is None or default.parent is not default.root:
        return children
    position = children.index(inner)
    return [c for i, c in enumerate(children) if i < position or type(c) is not LateDefault]


def default_tag(element: Element) -> str | None:
    """The tag of the default-class child that gives `element` its defaults, or None if
    this kind of element takes no defaults."""
    spec = element.spec
    if "class" not in spec.attributes:
        return None
    parent = element.parent
    if parent is not None and parent.spec.tag == "equality" and spec.tag in _EQUALITY_TAGS:
        return "equality"
    return _DEFAULT_TAG.get(spec.tag, spec.tag)


def class_of(element: Element) -> Element:
    """The default class element (a `<default>`) that `element` uses: its `class`, else
    the `childclass` of its nearest enclosing body or frame, else the model's global
    defaults ('main'). Raises mjcf.InvalidReferenceError for a class that does not exist."""
    model = element.root
    name = stored_attributes(element).get("class")
    if name is None:
        ancestor = element.parent
        while ancestor is not None and ancestor.parent is not None:
            childclass = stored_attributes(ancestor).get("childclass")
            if childclass is not None:
                name = childclass
                break
            ancestor = ancestor.parent
    if name is None:
        return model.default
    if not isinstance(name, str):
        return name
    found = model.find("default", name)
    if found is None:
        raise errors.InvalidReferenceError(f"{element.path}: default class {name!r} does not exist")
    return found


def class_chain(default: Element) -> list[Element]:
    """`default` and the classes it inherits from, outermost (main) first."""
    chain = []
    current: Element | None = default
    while current is not None and current.spec.tag == "default":
        chain.append(current)
        current = current.parent
    return chain[::-1]


def effective_value(element: Element, name: str) -> Any:
    """The value of attribute `name` that MuJoCo uses for `element`: its own, else its
    default class's, else None (MuJoCo's built-in default)."""
    attribute = element.spec.attributes[name]
    if name in stored_attributes(element):
        return value_of(element, attribute)
    tag = default_tag(element)
    if tag is None:
        return None
    chain = class_chain(class_of(element))
    for index in range(len(chain) - 1, -1, -1):
        inner = chain[index + 1] if index + 1 < len(chain) else None
        for child in reversed(settings_of(chain[index], inner)):  # a later setting wins
            if child.spec.tag == tag and name in stored_attributes(child):
                return value_of(child, child.spec.attributes[name])
    return None


def commit_defaults(element: Element, attributes: Iterable[str] | None = None) -> None:
    """Write the values that elements get from default classes onto the elements
    themselves; the compiled model is unchanged.

    Given a model (a `RootElement`), every element of it and of the models attached to
    it gets its values, then the default classes and `class`/`childclass` attributes are
    removed, so the model no longer needs them. Given another element, as dm_control
    does, only that element gets its values, and the classes stay. `attributes` limits
    the commit to those attribute names; the classes then stay too, for the others.

    Raises mjcf.InvalidReferenceError for a class that does not exist,
    mjcf.UnknownAttributeError for a name in `attributes` that no default class can set;
    the model is unchanged then."""
    names = None if attributes is None else _checked_names(element, attributes)
    root = element.root
    whole_model = element is root
    models = [root, *attached_models(root)] if whole_model else []
    targets = [e for model in models for e in model.iter()] if whole_model else [element]
    plans = []
    for target in targets:
        tag = default_tag(target)
        if tag is None or target.parent is None or traversal.has_ancestor(target, "default"):
            continue
        values = _defaults_for(target, tag, names)
        if values:
            plans.append((target, values))
    for target, values in plans:
        attrs = builder.attributes_to_fill(target)
        for name, value in values.items():
            if name not in attrs:
                attrs[name] = track(value, target)
            else:
                own = value_of(target, target.spec.attributes[name])
                attrs[name] = track(overlay(name, value, own), target)
        count_change(target)
    if whole_model and names is None:
        for model in models:
            _remove_classes(model)


def _remove_classes(model: RootElement) -> None:
    """Remove the default classes of `model` and the attributes that name them."""
    for element in model.iter():
        if traversal.has_ancestor(element, "default"):
            continue
        attrs = builder.attributes_to_fill(element)
        attrs.pop("class", None)
        attrs.pop("childclass", None)
    for child in list(tree_children(model.default)):
        builder.unregister_subtree(child)
    builder.children_to_fill(model.default).clear()
    builder.attributes_to_fill(model.default).clear()
    count_change(model)


def _checked_names(element: Element, attributes: Iterable[str]) -> frozenset[str]:
    """`attributes` as a set; raises mjcf.UnknownAttributeError for a name that no default
    class can give (a name that only this element lacks is left alone, as dm_control
    does, so that one list serves elements of several kinds)."""
    names = frozenset([attributes] if isinstance(attributes, str) else attributes)
    for name in sorted(names, key=str):
        if name not in _DEFAULTABLE:
            raise errors.UnknownAttributeError(
                f"{element.path}: commit_defaults: no default class sets an attribute "
                f"{name!r}" + suggest(str(name), _DEFAULTABLE)
            )
    return names


def _defaults_for(element: Element, tag: str, names: frozenset[str] | None) -> dict[str, Any]:
    values: dict[str, Any] = {}
    attributes = element.spec.attributes
    chain = class_chain(class_of(element))
    for index, default in enumerate(chain):
        inner = chain[index + 1] if index + 1 < len(chain) else None
        for child in settings_of(default, inner):
            child_tag = child.spec.tag
            if child_tag == tag:
                source = child
            elif tag in _ACTUATOR_TAGS and child_tag in _ACTUATOR_TAGS:
                # Actuators share one default per class, set by every actuator element of
                # the class in order (MuJoCo's "actuator shortcuts").
                source = child
                _reset_shortcut(values, child_tag, tag)
                if tag == "general" and child.spec.matters_empty and written_empty(child):
                    raise errors.AttributeValueError(
                        f"{element.path}: its default class has a <{child_tag}>, which "
                        f"sets the actuator type a <{element.tag}> takes; commit_defaults "
                        "cannot express it"
                    )
            else:
                continue
            for name in stored_attributes(source):
                if names is not None and name not in names:
                    continue
                if child_tag != tag and name not in _ACTUATOR_SETTINGS:
                    # Gain, bias or dynamics set by another shortcut: a motor's own shortcut
                    # sets them all anyway; how MuJoCo reads them for another shortcut's
                    # parameters (kp, kv ...) no attribute of the element can say.
                    if tag in _SETS_GAIN_AND_BIAS:
                        continue
                    raise errors.AttributeValueError(
                        f"{element.path}: its default class sets <{child_tag} {name}>, which "
                        f"changes the gains of a <{element.tag}> in a way its attributes "
                        "cannot express; commit_defaults cannot commit it"
                    )
                if name in attributes and name != "class":
                    value = value_of(source, source.spec.attributes[name])
                    values[name] = overlay(name, values.get(name), value)
                elif child_tag != tag:
                    raise errors.AttributeValueError(
                        f"{element.path}: its default class sets <{child_tag} {name}>, which "
                        f"<{element.tag}> does not have; commit_defaults cannot express it"
                    )
    return values


def _reset_shortcut(values: dict[str, Any], default_tag_: str, tag: str) -> None:
    """A default actuator of another shortcut resets the gain, bias and dynamics that
    the element's own shortcut sets anyway."""
    if default_tag_ != tag:
        for name in ("gainprm", "biasprm", "dynprm", "gaintype", "biastype", "dyntype"):
            values.pop(name, None)


def overlay(name: str, below: Any, value: Any) -> Any:
    """A copy of `value` over the default `below`: MuJoCo reads fewer numbers than an
    array holds over the default's, so the rest of the default stays."""
    if isinstance(value, np.ndarray):
        value = np.array(value)
        if (
            isinstance(below, np.ndarray)
            and name != "user"
            and value.ndim == below.ndim == 1
            and value.size < below.size
        ):
            merged = np.array(below)
            merged[: value.size] = value
            return merged
    return value


# Attributes of `<general>` that every actuator shortcut has and none of them sets: what
# a default of one shortcut gives an actuator of another as it is.
_ACTUATOR_SETTINGS = frozenset(schema.MUJOCO.child("default").child("general").attributes) - {
    "gainprm",
    "biasprm",
    "dynprm",
    "gaintype",
    "biastype",
    "dyntype",
    "class",
}
# Shortcuts that set all of gain, bias and dynamics themselves.
_SETS_GAIN_AND_BIAS = frozenset({"motor"})
_ACTUATOR_TAGS = frozenset({
    "general", "motor", "position", "velocity", "intvelocity", "damper", "cylinder",
    "muscle", "adhesion", "dcmotor", "pid", "orientation", "plugin",
})  # fmt: skip
