"""An element's attributes: reading them (converting text as read when first used) and
setting them, each value checked against the schema and the element's rules before
anything changes. A part of `Element` (see `mjcf.tree.element`).

    geom.size                        # array([0.05, 0.2]): read, converted once
    geom.rgba = [1, 0, 0, 1]         # checked now: mjcf.AttributeValueError if it fits not
    geom.set_attributes(size=[0.1], rgba=None)   # all checked, then all set (None: unset)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

from mjcf import errors
from mjcf.schema import values as _values
from mjcf.schema.suggestions import suggest
from mjcf.schema.tracked_array import track
from mjcf.schema.values import ElementBase
from mjcf.tree import assets, references
from mjcf.tree.element_checks import ElementChecks
from mjcf.tree.namescope import NAMED_AFTER_FILE

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec, ElementSpec
    from mjcf.tree.element import Element

# Python spellings of MJCF attribute names that are Python keywords.
ALIASES = {"dclass": "class", "class_": "class"}


def _element(values: ElementValues) -> Element:
    """`values` as the `Element` it is (ElementValues is only a base of Element)."""
    return cast("Element", values)


class ElementValues(ElementChecks):
    """The attributes of an element; a base of `Element`, not used alone."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element the attributes use on `self`
        _spec: ElementSpec
        _attrs: dict[str, Any]

        @property
        def path(self) -> str: ...
        @property
        def tag(self) -> str: ...
        def _modified(self) -> None: ...

    def _attribute_spec(self, name: str, action: str = "set") -> AttributeSpec:
        """The schema of attribute `name`; raises mjcf.UnknownAttributeError (an
        AttributeError) saying what failed, in dm_control's words inside ours: `action`
        is 'set', 'read' (or delete) or 'give' (an attribute given to `add` or
        `set_attributes`)."""
        spec = self._spec
        attribute = spec.attributes.get(ALIASES.get(name, name))
        if attribute is None:
            known = [*spec.attributes, "dclass" if "class" in spec.attributes else ""]
            suggestion = suggest(name, [k for k in known if k])
            if action == "give":
                problem = f"{name!r} is not a valid attribute of <{spec.tag}>{suggestion}"
            elif action == "read":
                problem = f"<{spec.tag}> object has no attribute {name!r}{suggestion}"
            elif name in spec.children:
                problem = (
                    f"can't set attribute {name!r}: <{name}> is a child element of "
                    f"<{spec.tag}>; set its attributes instead"
                )
            else:
                problem = f"can't set attribute {name!r}: <{spec.tag}> has no such attribute"
                problem += suggestion
            raise errors.UnknownAttributeError(f"{self.path}: {problem}")
        return attribute

    def _get_value(self, attribute: AttributeSpec) -> Any:
        value = self._attrs.get(attribute.name)
        if value is None or type(value) is not str:
            return value
        converter = attribute.converter
        if converter.lazy:
            converted = self._convert(attribute, value, from_text=True)
            if converted is None:  # blank text, which MuJoCo reads as not set
                return None
            value = track(converted, self)
            self._attrs[attribute.name] = value
        elif converter.refers:
            value = references.read(_element(self), attribute, value, self._attrs)
        elif converter.files and value:  # an empty one names no file, for MuJoCo
            self._attrs[attribute.name] = value = assets.resolve(
                _element(self), attribute.name, value
            )
        return value

    def _convert(self, attribute: AttributeSpec, value: Any, from_text: bool = False) -> Any:
        try:
            if from_text:
                return attribute.converter.from_text(value)
            return attribute.converter.from_python(value)
        except _values.InvalidValue as error:
            raise errors.AttributeValueError(f"{self.path}: {attribute.name!r} {error}") from None

    def _set_attribute(self, attribute: AttributeSpec, value: Any) -> None:
        """Set one attribute from a Python value; None (or a text MuJoCo reads as not
        set, such as an empty name) removes it."""
        if value is not None:
            value = self._convert(attribute, value)
            if value is not None and attribute.name in self._spec.rule_names:
                self._check_rules({attribute.name}, ())
            if value is not None:
                self._check_crash([attribute.name])
        self._store(attribute, value)

    def _store(self, attribute: AttributeSpec, value: Any) -> None:
        """Store one converted value (None removes the attribute)."""
        name = attribute.name
        if value is None:
            if attribute.required and name in self._attrs:
                raise errors.AttributeValueError(
                    f"{self.path}: {name!r} is required by <{self.tag}> and cannot be removed"
                )
            if attribute.converter.names:
                self._rename(None)
            if self._attrs.pop(name, None) is not None:
                self._modified()
            return
        stored = track(value, self)
        converter = attribute.converter
        if converter.names:
            self._check_name(stored)
            self._rename(stored)
        elif converter.refers:
            self._check_reference(attribute, stored)
            stored = references.stored(_element(self), attribute, stored, self._attrs)
        elif converter.files:
            if isinstance(stored, assets.Asset):
                assets.claim(stored, _element(self))
            if self._spec.tag in NAMED_AFTER_FILE:
                self._rename_after_file(stored)
        self._attrs[name] = stored
        self._modified()

    def get_attributes(self) -> dict[str, Any]:
        """The attributes that are set, as Python values (`class` under 'dclass')."""
        return {
            ("dclass" if name == "class" else name): self._get_value(self._spec.attributes[name])
            for name in self._attrs
        }

    def set_attributes(self, **attributes: Any) -> None:
        """Set several attributes at once; if any is invalid, none is set."""
        converted = self._prepare(attributes)
        self._apply(converted)

    def _prepare(self, attributes: dict[str, Any]) -> list[tuple[AttributeSpec, Any]]:
        """Convert and check every attribute without changing anything."""
        converted = []
        for name, value in attributes.items():
            attribute = self._attribute_spec(name, "give")
            if value is None:
                converted.append((attribute, None))
                continue
            stored = track(self._convert(attribute, value), self)
            if stored is None:
                converted.append((attribute, None))
                continue
            if attribute.converter.names:
                self._check_name(stored)
                self._check_free(stored)
            elif attribute.converter.refers:
                self._check_reference(attribute, stored)
            converted.append((attribute, stored))
        if self._spec.rule_names:
            setting = {a.name for a, value in converted if value is not None}
            if not self._spec.rule_names.isdisjoint(setting):
                self._check_rules(setting, [a.name for a, value in converted if value is None])
        self._check_crash([a.name for a, value in converted if value is not None])
        return converted

    def _apply(self, converted: list[tuple[AttributeSpec, Any]]) -> None:
        # References last: a name is resolved in the namespace the new values select.
        for attribute, stored in sorted(converted, key=lambda item: item[0].converter.refers):
            self._store(attribute, stored)

    def _check_reference(self, attribute: AttributeSpec, value: Any) -> None:
        items = value if isinstance(value, list) else [value]
        namespace = attribute.reference_namespace(self._attrs)
        for item in items:
            if (
                isinstance(item, ElementBase)
                and namespace is not None
                and cast("Element", item).spec.namespace != namespace
            ):
                raise errors.InvalidReferenceError(
                    f"{self.path}: {attribute.name!r} refers to a {namespace}, got "
                    f"{cast('Element', item).path} "
                    f"(a {cast('Element', item).spec.namespace or cast('Element', item).tag})"
                )

    def _apply_unregistered(self, converted: list[tuple[AttributeSpec, Any]]) -> None:
        for attribute, stored in converted:
            if stored is not None:
                if isinstance(stored, assets.Asset):
                    assets.claim(stored, _element(self))
                self._attrs[attribute.name] = stored
        for attribute, stored in converted:
            if stored is not None and attribute.converter.refers:
                self._attrs[attribute.name] = references.stored(
                    _element(self), attribute, stored, self._attrs
                )


def fill_new(element: Element, attributes: dict[str, Any]) -> None:
    """Check `attributes` (Python values, as `add` takes them) for `element`, new and not
    yet in its parent's children, and store them: nothing is stored if one is invalid."""
    converted = element._prepare(attributes)
    element._apply_unregistered(converted)


def value_of(element: Element, attribute: AttributeSpec) -> Any:
    """The value of `element`'s attribute `attribute` as `getattr(element, name)` returns
    it (None if unset), converting and resolving text as read once (see
    `mjcf.schema.values`)."""
    return element._get_value(attribute)
