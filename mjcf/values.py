"""Attribute values: from XML text or Python values to what an element stores, and back.

Each `AttributeSpec` gets a converter from `converter_for`. A converter never sees the
element; it raises `InvalidValue` with what was expected, and the element adds its
path and the attribute name to make the user-facing `mjcf.AttributeValueError`.

Stored values: numbers with one value are Python `int`/`float`; other numbers are
1-D numpy arrays (the same array object is returned to the user, so in-place edits
change the model, as in dm_control); keywords and strings are `str`; references are
`str` names or `Element` objects; files are `str` paths or `mjcf.Asset` objects.
Text read from a file is kept as `str` until it is first read or changed, so parsing
and writing a model never converts numbers it does not need to.
"""

from __future__ import annotations

import copy
import difflib
import numbers
from collections.abc import Iterable
from typing import Any, Protocol, TypeVar, cast, overload

import numpy as np

from mjcf.assets import Asset


class InvalidValue(ValueError):
    """A value that does not fit the attribute; the message says what was expected."""


class _Owner(Protocol):
    """What owns a tracked array: an element, told of every change."""

    def _modified(self) -> None: ...


_T = TypeVar("_T")


class TrackedArray(np.ndarray):
    """The array an element returns for a numeric attribute: editing it in place edits
    the model, and counts as a change of the model (see `RootElement.version`)."""

    _owner: _Owner | None = None

    def __array_finalize__(self, obj: object) -> None:
        # A view of the stored array edits the model too; other derived arrays do not.
        self._owner = getattr(obj, "_owner", None) if self.base is obj else None

    def __setitem__(self, key: Any, value: Any) -> None:
        super().__setitem__(key, value)
        owner = self._owner
        if owner is not None:
            owner._modified()

    def __reduce__(self):
        constructor, arguments, state = cast(tuple, super().__reduce__())  # an ndarray's: 3 items
        return constructor, arguments, (state, self._owner)

    def __setstate__(self, state: tuple) -> None:
        array_state, owner = state
        super().__setstate__(array_state)
        self._owner = owner

    def __deepcopy__(self, memo: dict[int, Any] | None) -> TrackedArray:
        new = np.array(self).view(TrackedArray)
        new._owner = copy.deepcopy(self._owner, memo)
        return new


@overload
def track(value: np.ndarray, owner: _Owner) -> TrackedArray: ...
@overload
def track(value: _T, owner: _Owner) -> _T: ...
def track(value: object, owner: _Owner) -> object:
    """`value`, as a `TrackedArray` owned by `owner` if it is an array."""
    if isinstance(value, np.ndarray):
        value = value.view(TrackedArray)
        value._owner = owner
    return value


def format_number(value: float, precision: int = 17) -> str:
    """Shortest text that reads back as exactly `value` (precision 17), or `precision`
    significant digits; integral values without a trailing '.0'."""
    if precision >= 17:
        text = repr(float(value))
        return text[:-2] if text.endswith(".0") else text
    return f"{float(value):.{precision}g}"


def escape(text: str) -> str:
    """Escape text for a double-quoted XML attribute value."""
    if "&" in text:
        text = text.replace("&", "&amp;")
    if "<" in text:
        text = text.replace("<", "&lt;")
    if ">" in text:
        text = text.replace(">", "&gt;")
    if '"' in text:
        text = text.replace('"', "&quot;")
    return text


def suggest(word: str, choices: Iterable[str]) -> str:
    """' (did you mean 'x'?)' for the closest choice, or ''."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


class _Converter:
    """Base: strings stay strings."""

    lazy = False  # True: text from files is converted on first read

    def __init__(self, spec) -> None:
        self.spec = spec

    def from_text(self, text: str) -> object:
        return text

    def check_text(self, text: str) -> None:
        self.from_text(text)

    def from_python(self, value: object) -> object:
        if not isinstance(value, str):
            raise InvalidValue(f"takes a string, got {type(value).__name__}: {value!r}")
        return value

    def to_text(self, value: Any, precision: int = 17) -> str:  # a value it stores
        return str(value)


class _Numbers(_Converter):
    lazy = True
    dtype: type = float
    noun = "numbers"

    def _check_count(self, count: int, shown: object) -> None:
        spec = self.spec
        if (
            count < spec.min
            or (spec.max is not None and count > spec.max)
            or (spec.multiple_of and count % spec.multiple_of)
        ):
            raise InvalidValue(f"takes {spec.arity_text()}, got {count}: {shown!r}")

    def from_text(self, text: str) -> object:
        words = text.split()
        self._check_count(len(words), text)
        try:
            values = [self._parse_word(w) for w in words]
        except ValueError:
            raise InvalidValue(f"takes {self.noun}, got {text!r}") from None
        if self.spec.scalar:
            return values[0]
        return np.array(values, dtype=self.dtype)

    def check_text(self, text: str) -> None:
        words = text.split()
        self._check_count(len(words), text)
        try:
            for w in words:
                self._parse_word(w)
        except ValueError:
            raise InvalidValue(f"takes {self.noun}, got {text!r}") from None

    def _parse_word(self, word: str) -> object:
        return float(word)

    def from_python(self, value: object) -> object:
        if isinstance(value, str):
            return self.from_text(value)
        if isinstance(value, np.ndarray | list | tuple):
            array = np.asarray(value)
            if array.ndim > 1:
                raise InvalidValue(f"takes a flat list of {self.noun}, got shape {array.shape}")
            array = array.ravel()
        elif isinstance(value, numbers.Number | np.generic):
            array = np.asarray([value])
        else:
            raise InvalidValue(f"takes {self.noun}, got {type(value).__name__}: {value!r}")
        self._check_count(array.size, value)
        converted = self._convert_array(array, value)
        return converted[0].item() if self.spec.scalar else converted

    def _convert_array(self, array: np.ndarray, shown: object) -> np.ndarray:
        if array.dtype.kind not in "biuf":
            raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        return array.astype(float)

    def to_text(self, value: float | np.ndarray, precision: int = 17) -> str:
        if isinstance(value, np.ndarray):
            return " ".join([format_number(v, precision) for v in value.tolist()])
        return format_number(value, precision)


class _Integers(_Numbers):
    dtype = int
    noun = "integers"

    def _parse_word(self, word: str) -> object:
        try:
            return int(word)
        except ValueError:
            number = float(word)
            if not number.is_integer():
                raise
            return int(number)

    def _convert_array(self, array: np.ndarray, shown: object) -> np.ndarray:
        if array.dtype.kind == "f":
            if not np.all(np.isfinite(array)) or not np.all(array == np.round(array)):
                raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        elif array.dtype.kind not in "biu":
            raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        return array.astype(np.int64)

    def to_text(self, value: object, precision: int = 17) -> str:
        if isinstance(value, np.ndarray):
            return " ".join(map(str, value.tolist()))
        return str(value)


class _Keyword(_Converter):
    def from_text(self, text: str) -> object:
        if self.spec.is_list:
            for word in text.split():
                self._check_word(word)
            return text
        self._check_word(text)
        return text

    def _check_word(self, text: str) -> None:
        if text not in self.spec.values:
            raise InvalidValue(
                f"takes one of {list(self.spec.values)}, got {text!r}"
                + suggest(text, self.spec.values)
            )

    def from_python(self, value: object) -> object:
        if self.spec.is_list and isinstance(value, list | tuple):
            value = " ".join(str(word) for word in value)
        if isinstance(value, bool | np.bool_) and "true" in self.spec.values:
            return "true" if value else "false"
        if not isinstance(value, str):
            raise InvalidValue(
                f"takes one of {list(self.spec.values)}, got {type(value).__name__}: {value!r}"
            )
        return self.from_text(value)


class _Identifier(_Converter):
    def from_python(self, value: object) -> object:
        value = super().from_python(value)
        if not value:
            raise InvalidValue("takes a non-empty name, got ''")
        return value


class _Reference(_Converter):
    """References keep names as `str` and element objects as given; the element
    checks namespaces, since only it knows the model."""

    def from_python(self, value: object) -> object:
        if self.spec.is_list:
            if isinstance(value, str):
                return value
            if isinstance(value, Iterable):
                items = list(value)
                for item in items:
                    if not isinstance(item, str) and not _is_element(item):
                        raise InvalidValue(f"takes names or elements, got {item!r}")
                return items
            raise InvalidValue(f"takes a list of names or elements, got {value!r}")
        if isinstance(value, str):
            if not value:
                raise InvalidValue("takes a non-empty name, got ''")
            return value
        if _is_element(value):
            return value
        raise InvalidValue(f"takes a name or an element, got {type(value).__name__}: {value!r}")


class _File(_Converter):
    """File attributes hold a path string or an `mjcf.Asset`."""

    def from_python(self, value: object) -> object:
        if isinstance(value, str | Asset):
            return value
        raise InvalidValue(f"takes a file name or an mjcf.Asset, got {value!r}")


def _is_element(value: object) -> bool:
    from mjcf.element import Element  # cycle: element -> values

    return isinstance(value, Element)


_CONVERTERS = {
    "string": _Converter,
    "identifier": _Identifier,
    "reference": _Reference,
    "file": _File,
    "keyword": _Keyword,
    "int": _Integers,
    "real": _Numbers,
}


def converter_for(spec) -> _Converter:
    """The converter for an `AttributeSpec`."""
    return _CONVERTERS[spec.kind](spec)
