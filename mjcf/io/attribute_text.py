"""Attribute values as one output writes them: numbers with its precision (and those
below its zero threshold as 0, text as read too when it asks for either), names and
references as the composed model names them, files under the names the output gives
them, all escaped for XML. A base of `mjcf.io.serializer`'s writer, which adds the tags.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from mjcf.schema.values import escape
from mjcf.tree.element import stored_attributes, value_of

if TYPE_CHECKING:
    from mjcf.compose import composition
    from mjcf.io.file_names import FileNamer
    from mjcf.schema import AttributeSpec
    from mjcf.tree.element import Element


class AttributeWriter:
    """The text of attribute values in one output: `precision` significant digits (17:
    exactly), `zero_threshold`, the output's `files` and its composition (`composed`)."""

    def __init__(
        self,
        precision: int,
        zero_threshold: float,
        files: FileNamer,
        composed: composition.Composition,
    ) -> None:
        self.precision = precision
        self.zero_threshold = zero_threshold
        # Numbers are rewritten from their values, text read from files too, only when
        # the output asks for fewer digits or for small numbers written as 0.
        self.reformat = precision < 17 or zero_threshold > 0
        self.files = files
        self.composed = composed

    def attributes(
        self, element: Element, context: composition.ModelContext, override: dict | None = None
    ) -> str:
        """' name="value" ...' for the element's attributes as written in this output
        (`override` replaces some; None values in it are left out)."""
        return self._escaped_attributes(element, context, override)

    def _escaped_attributes(
        self, element: Element, context: composition.ModelContext, override: dict | None
    ) -> str:
        attrs = stored_attributes(element)
        spec = element.spec
        plain = context.plain
        scoped = spec.scoped_attributes
        special = spec.file_attributes
        reformat = self.reformat
        out = []
        for name, value in attrs.items():
            if override and name in override:
                continue
            if (
                type(value) is str
                and (plain or name not in scoped)
                and name not in special
                and not (reformat and spec.attributes[name].converter.reals)
            ):
                out.append(f' {name}="{escape(value)}"')
            else:
                text = self.value_text(element, spec.attributes[name], value, context)
                out.append(f' {name}="{escape(text)}"')
        if override:
            identifier = spec.identifier
            for name, value in override.items():
                if value is None:
                    continue
                if name == identifier and name not in attrs:  # a generated name goes first
                    out.insert(0, f' {name}="{escape(value)}"')
                else:
                    attribute = spec.attributes.get(name)
                    if reformat and attribute is not None and attribute.converter.reals:
                        value = self._number_text(attribute, value)
                    out.append(f' {name}="{escape(value)}"')
        return "".join(out)

    def _escaped_value(
        self, element: Element, name: str, value: object, context: composition.ModelContext
    ) -> str:
        return escape(self.value_text(element, element.spec.attributes[name], value, context))

    def value_text(
        self,
        element: Element,
        attribute: AttributeSpec,
        value: Any,
        context: composition.ModelContext,
    ) -> str:
        """The text of one attribute value in this output."""
        converter = attribute.converter
        if converter.scoped() and value == "":
            return ""  # an empty name is no name: never scoped
        if converter.refers:
            return self._reference_text(element, attribute, value, context)
        if converter.names:
            return context.identifier_text(element, value)
        if converter.files:
            if value == "":  # no file, as MuJoCo reads it
                return ""
            if type(value) is str:  # resolve once, as reading the attribute would
                value = value_of(element, attribute)
            return self.files.name_for(element, attribute.name, value)
        if self.reformat and converter.reals:
            return self._number_text(attribute, value)
        if type(value) is str:
            return value
        return attribute.converter.to_text(value, self.precision)

    def _number_text(self, attribute: AttributeSpec, value: Any) -> str:
        """Real numbers (a value, or text as read) written with `precision` digits,
        those smaller in magnitude than `zero_threshold` as 0."""
        if type(value) is str:
            value = attribute.converter.from_text(value)
        threshold = self.zero_threshold
        if threshold > 0:
            if isinstance(value, np.ndarray):
                value = np.where(np.abs(value) < threshold, 0.0, value)
            elif abs(value) < threshold:
                value = 0.0
        return attribute.converter.to_text(value, self.precision)

    def _reference_text(
        self,
        element: Element,
        attribute: AttributeSpec,
        value: Any,
        context: composition.ModelContext,
    ) -> str:
        if isinstance(value, list):
            return " ".join(self._reference_text(element, attribute, v, context) for v in value)
        if isinstance(value, str):
            if attribute.is_list:
                return " ".join(context.reference_text(attribute, v) for v in value.split())
            return context.reference_text(attribute, value)
        return self.composed.element_reference_text(element, attribute, value)

    def _own_name(self, element: Element, context: composition.ModelContext) -> str:
        """' name="..."' for an element that MuJoCo names after its file, when its file
        is written under another name; '' when it has a name of its own."""
        identifier = element.spec.identifier
        if identifier is None or identifier in stored_attributes(element):
            return ""
        name = element.identifier
        if name is None:
            return ""
        return f' {identifier}="{escape(context.identifier_text(element, name))}"'
