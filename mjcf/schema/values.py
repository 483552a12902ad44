"""Attribute values: from XML text or Python values to what an element stores, and back.

Each `AttributeSpec` gets a converter from `converter_for`. A converter never sees the
element: it raises `InvalidValue` saying what was expected, and the element adds its path
and attribute name to make the user-facing `mjcf.AttributeValueError`. Stored values:
single numbers are `int`/`float`, other numbers 1-D numpy arrays (the same array is
returned to the user, so in-place edits change the model, as in dm_control), keywords and
strings `str`, references `str` names or `Element`s, files `str` paths or `mjcf.Asset`s.
Text read from a file stays `str` until first read or changed, so parsing and writing a
model never converts numbers it does not need to.
"""

from __future__ import annotations

import copy
import math
import numbers
import re
import struct
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any, Protocol, TypeVar, cast, overload

import numpy as np

from mjcf import errors

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec


class InvalidValue(ValueError):
    """A value that does not fit the attribute; the message says what was expected."""


class ElementBase:
    """The base class of every element (`mjcf.Element`): what a reference attribute holds
    when it holds no name. Defined here, below the tree that builds on these values."""

    __slots__ = ()


class AssetBase:
    """The base class of `mjcf.Asset`: what a file attribute holds when it holds no name."""

    __slots__ = ()


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

    def __reduce__(self) -> tuple[Any, ...]:
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
    """`value`, as a `TrackedArray` owned by `owner` if it is an array (the same memory).

    An array `owner` tracks already is returned as it is, and another tracked array is
    viewed through a plain view of the memory beneath it: numpy does not show an array's
    base to the garbage collector, so a tracked view of a tracked array would hold that
    array, and through its owner the whole model, unseen, and the model (a cycle of
    references) would never be freed. (An unpickled tracked array owns its memory, so a
    view of it holds it still.)"""
    if isinstance(value, np.ndarray):
        if type(value) is TrackedArray and value._owner is owner:
            return value  # tracked by `owner` already
        value = np.asarray(value).view(TrackedArray)  # asarray: a plain view of its memory
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
    return errors.did_you_mean(word, choices, n=1)


# Elements older MuJoCo had (dm_control's schema still has them), with what replaces them.
_REMOVED_ELEMENTS = {
    "composite": "MuJoCo 4 has no <composite>: build the object with <flexcomp> (cables, "
    "cloth, soft bodies), or with bodies (nested for a chain, <replicate> for copies)",
}


def suggest_child(tag: str, allowed: Iterable[str]) -> str:
    """What to say of child `tag` an element cannot have: what replaces an element
    MuJoCo removed, else the closest allowed tag (see `suggest`)."""
    removed = _REMOVED_ELEMENTS.get(tag)
    return f" ({removed})" if removed else suggest(tag, allowed)


# MuJoCo reads numbers as C's strtod and strtol do: decimal or hexadecimal reals,
# inf/infinity/nan in any case, integers in decimal only; Python's float() and int()
# also take underscores and non-ASCII digits, which MuJoCo refuses.
_C_REAL = re.compile(
    r"[+-]?(?:0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
    r"|(?i:nan\([0-9a-zA-Z_]*\)))"
)
_INT32 = (-(2**31), 2**31 - 1)
_FLOAT32_TOO_LARGE = 3.4028235677973366e38  # rounds to infinity as a C float
_BLANK = frozenset(" \t\n\r")


def _is_blank(text: str) -> bool:
    return not text or _BLANK.issuperset(text)


class _TooLarge(ValueError):
    pass


class _Converter:
    """Base of the converters, one class for each kind of attribute, holding that kind's
    rules: how its text and Python values are read and checked, and what it means to the
    rest of mjcf (the flags below, which other modules ask instead of the kind's name)."""

    lazy = False  # True: text from files is converted on first read
    names = False  # holds the element's name ('identifier'): setting it renames the element
    refers = False  # holds references to elements by name ('reference')
    files = False  # names a file ('file'), read into an `mjcf.Asset`
    keywords = False  # holds one of a list of words, or several ('keyword')
    numbers = False  # holds numbers ('int', 'real'): compared and defaulted as numbers
    reals = False  # holds real numbers, rewritten to an output's precision ('real')
    takes_blank = True  # reads blank text as not set, unless the schema says otherwise
    unset_is_empty = True  # MuJoCo's built-in value is empty text (not names, keywords, numbers)

    def __init__(self, spec: AttributeSpec) -> None:
        self.spec = spec

    @classmethod
    def scoped(cls) -> bool:
        """Whether values take the model's name-scope prefix when models are composed."""
        return cls.names or cls.refers

    def checks_text(self) -> bool:
        """Whether text read from a file must be checked (names are checked by the
        element)."""
        return False

    def same(self, a: Any, b: Any) -> bool:
        """Whether two stored values (neither None) are the same value."""
        return bool(a == b)  # files (mjcf.Asset) compare by path, else by contents

    def describe(self) -> str:
        """The kind, for an AttributeSpec's repr ('real, 1 to 3 numbers')."""
        return self.spec.kind

    def from_text(self, text: str) -> object:
        if not self.spec.blank and _is_blank(text):
            raise InvalidValue(f"takes text that is not blank, got {text!r}")
        return text

    def check_text(self, text: str) -> None:
        self.from_text(text)

    def from_python(self, value: object) -> object:
        if not isinstance(value, str):
            raise InvalidValue(f"takes a string, got {type(value).__name__}: {value!r}")
        return value

    def to_text(self, value: Any, precision: int = 17) -> str:  # a value it stores
        return str(value)


class _String(_Converter):
    """Strings stay strings (not blank ones, where MuJoCo refuses them)."""

    def from_python(self, value: object) -> object:
        return self.from_text(cast(str, super().from_python(value)))

    def checks_text(self) -> bool:
        return not self.spec.blank


def round_float32(value: float) -> float:
    """`value` as the nearest C float holds it."""
    return struct.unpack("<f", struct.pack("<f", value))[0] if abs(value) < 3.4e38 else value


_MEMORY = re.compile(r"[ \t\n\r]*(?:-1|\+?([0-9]+)([KMGTPEkmgtpe]?))[ \t\n\r]*")


def _memory_size(text: str) -> bool:
    """A byte count as MuJoCo reads `size memory`: -1, or digits with a K..E suffix."""
    match = _MEMORY.fullmatch(text)
    if match is None or not text.isascii():
        return False
    if match.group(1) is None:
        return True
    power = "KMGTPE".find(match.group(2).upper()) + 1 if match.group(2) else 0
    return int(match.group(1)) * 1024**power < 2**64


def _three_characters(text: str) -> bool:
    """`compiler eulerseq`: MuJoCo's reader takes any three bytes (its compiler then
    wants x, y, z, X, Y or Z, where an Euler angle is used)."""
    return len(text.encode()) == 3


# Grammars of text attributes, by the name `_annotations.TEXT_FORMATS` gives them.
TEXT_FORMATS = {"memory size": _memory_size, "three characters": _three_characters}


class _Format(_Converter):
    """Text MuJoCo reads by a grammar of its own (`size memory="10M"`)."""

    def checks_text(self) -> bool:
        return True

    def __init__(self, spec: AttributeSpec) -> None:
        super().__init__(spec)
        self.check = TEXT_FORMATS[cast(str, spec.text_format)]  # only made for one

    def from_text(self, text: str) -> object:
        if not self.check(text):
            raise InvalidValue(f"takes {self.spec.text_format}, got {text!r}")
        return text

    def from_python(self, value: object) -> object:
        return self.from_text(str(super().from_python(value)))


def _bound(value: float) -> str:
    """A bound as an error shows it: integers whole ('10000000'), reals short ('1e-15')."""
    return str(value) if isinstance(value, int) else f"{value:g}"


class _Numbers(_Converter):
    """Numbers as MuJoCo reads them. Blank text is accepted (MuJoCo reads it as
    if the attribute were not set); it reads back as None and is written as it was."""

    lazy = True
    numbers = True
    reals = True
    unset_is_empty = False
    dtype: type = float
    noun = "numbers"

    def __init__(self, spec: AttributeSpec) -> None:
        super().__init__(spec)
        self.limit = _FLOAT32_TOO_LARGE if spec.float32 else float("inf")
        self.bounded = (
            spec.min_value is not None or spec.max_value is not None or spec.finite is not None
        )

    def _check_count(self, count: int, shown: object) -> None:
        spec = self.spec
        if (
            count < spec.min
            or (spec.max is not None and count > spec.max)
            or count in spec.gaps
            or (spec.multiple_of and count % spec.multiple_of)
        ):
            too_many = spec.max is not None and count > spec.max
            limit = f" (no more than {spec.max} entries)" if too_many else ""
            raise InvalidValue(f"takes {spec.arity_text()}, got {count}{limit}: {shown!r}")

    def _words(self, text: str) -> list:
        words = text.split()
        self._check_count(len(words), text)
        if "_" in text or not text.isascii():
            raise InvalidValue(f"takes {self.noun}, got {text!r}")
        try:
            values = [self._parse_word(w) for w in words]
        except _TooLarge:
            raise InvalidValue(
                f"takes {self.noun} MuJoCo can hold, got one too large: {text!r}"
            ) from None
        except ValueError:
            raise InvalidValue(f"takes {self.noun}, got {text!r}") from None
        if self.bounded:
            self._check_bounds(values, text)
        return values

    def _check_bounds(self, values: Iterable, shown: object) -> None:
        spec = self.spec
        low, high = spec.min_value, spec.max_value
        for value in values:
            if spec.finite is not None and not math.isfinite(value):
                raise InvalidValue(f"takes finite {self.noun}, got {shown!r}: {spec.finite}")
            if value != value:  # NaN passes MuJoCo's comparisons
                continue
            if spec.float32:
                value = round_float32(value)
            if low is not None and (value < low or (spec.min_exclusive and value == low)):
                relation = "greater than" if spec.min_exclusive else "at least"
                raise InvalidValue(f"takes {self.noun} {relation} {_bound(low)}, got {shown!r}")
            if high is not None and (value > high or (spec.max_exclusive and value == high)):
                relation = "less than" if spec.max_exclusive else "at most"
                raise InvalidValue(f"takes {self.noun} {relation} {_bound(high)}, got {shown!r}")

    def from_text(self, text: str) -> object:
        if _is_blank(text):
            if not self.spec.blank:
                raise InvalidValue(f"takes {self.noun}, got {text!r}")
            return None
        values = self._words(text)
        if self.spec.scalar:
            return values[0]
        return np.array(values, dtype=self.dtype)

    def check_text(self, text: str) -> None:
        if not _is_blank(text):
            self._words(text)
        elif not self.spec.blank:
            raise InvalidValue(f"takes {self.noun}, got {text!r}")

    def _parse_word(self, word: str) -> object:
        try:
            value = float(word)
        except ValueError:
            if _C_REAL.fullmatch(word) is None:
                raise
            value = float("nan") if "(" in word else _from_hex(word)
        if -self.limit < value < self.limit or value != value:
            return value
        if "n" in word or "N" in word:  # inf, infinity: MuJoCo takes them
            return value
        raise _TooLarge(word)

    def from_python(self, value: object) -> object:
        if isinstance(value, str):
            return value if _is_blank(value) and self.spec.blank else self.from_text(value)
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
        if self.bounded:
            self._check_bounds(converted.tolist(), value)
        return converted[0].item() if self.spec.scalar else converted

    def _convert_array(self, array: np.ndarray, shown: object) -> np.ndarray:
        if array.dtype.kind not in "biuf":
            raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        converted = array.astype(float)
        if self.spec.float32:
            finite = converted[np.isfinite(converted)]
            if finite.size and np.abs(finite).max() >= self.limit:
                raise InvalidValue(
                    f"takes {self.noun} MuJoCo can hold, got one too large: {shown!r}"
                )
        return converted

    def checks_text(self) -> bool:
        return True

    def same(self, a: Any, b: Any) -> bool:
        first, second = np.asarray(a), np.asarray(b)
        return first.shape == second.shape and bool(np.array_equal(first, second))

    def describe(self) -> str:
        return f"{self.spec.kind}, {self.spec.arity_text()}"

    def to_text(self, value: float | np.ndarray, precision: int = 17) -> str:
        if isinstance(value, np.ndarray):
            return " ".join([format_number(v, precision) for v in value.tolist()])
        return format_number(value, precision)


def _from_hex(word: str) -> float:
    try:
        return float.fromhex(word)
    except OverflowError:
        raise _TooLarge(word) from None


class _Integers(_Numbers):
    reals = False
    dtype = int
    noun = "integers"

    def _parse_word(self, word: str) -> object:
        value = int(word)
        if not _INT32[0] <= value <= _INT32[1]:
            raise _TooLarge(word)
        return value

    def _convert_array(self, array: np.ndarray, shown: object) -> np.ndarray:
        if array.dtype.kind == "f":
            if not np.all(np.isfinite(array)) or not np.all(array == np.round(array)):
                raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        elif array.dtype.kind not in "biu":
            raise InvalidValue(f"takes {self.noun}, got {shown!r}")
        if array.size and (array.min() < _INT32[0] or array.max() > _INT32[1]):
            raise InvalidValue(f"takes 32-bit {self.noun}, got {shown!r}")
        return array.astype(np.int64)

    def to_text(self, value: object, precision: int = 17) -> str:
        if isinstance(value, np.ndarray):
            return " ".join(map(str, value.tolist()))
        return str(value)


class _Keyword(_Converter):
    """One keyword (or a list of distinct keywords), compared as MuJoCo compares
    them (some attributes ignore case; a few also take the keyword's number)."""

    keywords = True
    takes_blank = False
    unset_is_empty = False

    def __init__(self, spec: AttributeSpec) -> None:
        super().__init__(spec)
        self.folded = frozenset(v.lower() for v in spec.values) if spec.case_insensitive else None
        self.lenient = spec.case_insensitive or spec.trims

    def checks_text(self) -> bool:
        return True

    def describe(self) -> str:
        return f"{self.spec.kind} {list(self.spec.values)}"

    def from_text(self, text: str) -> object:
        if self.spec.is_list:
            words = text.split()
            for word in words:
                self._check_word(word)
            if len(set(words)) != len(words):
                raise InvalidValue(f"takes distinct keywords, got {text!r}")
            if len(words) > 1 and (self.spec.ordered or self.spec.alone):
                self._check_order(words, text)
            elif words and words[0] in self.spec.alone and words[0] != text:
                raise InvalidValue(f"takes {words[0]!r} only alone, without spaces: {text!r}")
            return text
        self._check_word(text)
        return text

    def _check_order(self, words: list[str], text: str) -> None:
        spec = self.spec
        alone = spec.alone.intersection(words)
        if alone:
            raise InvalidValue(f"takes {sorted(alone)[0]!r} only alone, got {text!r}")
        if spec.ordered:
            places = [spec.values.index(word) for word in words]
            if places != sorted(places):
                raise InvalidValue(f"takes keywords in the order {list(spec.values)}, got {text!r}")

    def _check_word(self, text: str) -> None:
        spec = self.spec
        if text in spec.values or (spec.blank and _is_blank(text)):
            return
        if spec.refused:
            refused = spec.refused.get(text.strip(" \t\n\r").lower())
            if refused is not None:
                raise InvalidValue(refused)
        if self.lenient:
            word = text.strip(" \t\n\r") if spec.trims else text
            if word in spec.values or (self.folded is not None and word.lower() in self.folded):
                return
        if spec.integers is not None and _integer_text(text, spec.integers):
            return
        numbers = (
            f", or an integer from {spec.integers[0]} to {spec.integers[1]}"
            if spec.integers
            else ""
        )
        raise InvalidValue(
            f"takes one of {list(spec.values)}{numbers}, got {text!r}" + suggest(text, spec.values)
        )

    def from_python(self, value: object) -> object:
        if self.spec.is_list and isinstance(value, list | tuple):
            value = " ".join(str(word) for word in value)
        if isinstance(value, bool | np.bool_) and "true" in self.spec.values:
            return "true" if value else "false"
        if self.spec.integers is not None and isinstance(value, int | np.integer):
            value = str(int(value))
        if not isinstance(value, str):
            raise InvalidValue(
                f"takes one of {list(self.spec.values)}, got {type(value).__name__}: {value!r}"
            )
        return self.from_text(value)


def _integer_text(text: str, bounds: tuple[int, int]) -> bool:
    word = text.strip(" \t\n\r")
    if not word.isascii() or "_" in word or " " in word:
        return False
    try:
        return bounds[0] <= int(word) <= bounds[1]
    except ValueError:
        return False


class _Identifier(_Converter):
    """Names; an empty one is no name, as MuJoCo reads it (returns None)."""

    names = True
    unset_is_empty = False

    def from_python(self, value: object) -> object:
        value = super().from_python(value)
        return value or None


class _Reference(_Converter):
    """References keep names as `str` and element objects as given; the element
    checks namespaces, since only it knows the model. An empty name is kept: MuJoCo
    reads it as no reference, except for a default class, which must be named, and
    where MuJoCo takes it for the first unnamed element (`AttributeSpec.refused`)."""

    refers = True

    def describe(self) -> str:
        spec = self.spec
        return f"{spec.kind} -> {spec.namespace or 'namespace from ' + str(spec.namespace_from)}"

    def from_text(self, text: str) -> object:
        refused = self.spec.refused.get(text)
        if refused is not None:
            raise InvalidValue(refused)
        return super().from_text(text)

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
            if not value and self.spec.namespace == "default":
                raise InvalidValue("takes the name of a default class, got ''")
            return self.from_text(value)
        if _is_element(value):
            return value
        raise InvalidValue(f"takes a name or an element, got {type(value).__name__}: {value!r}")


class _File(_Converter):
    """File attributes hold a path string or an `mjcf.Asset`."""

    files = True

    def from_python(self, value: object) -> object:
        if isinstance(value, str | AssetBase):
            return value
        raise InvalidValue(f"takes a file name or an mjcf.Asset, got {value!r}")


def _is_element(value: object) -> bool:
    return isinstance(value, ElementBase)


_CONVERTERS: dict[str, type[_Converter]] = {
    "string": _String,
    "identifier": _Identifier,
    "reference": _Reference,
    "file": _File,
    "keyword": _Keyword,
    "int": _Integers,
    "real": _Numbers,
}


def converter_class(kind: str, text_format: str | None = None) -> type[_Converter]:
    """The converter class of attributes of `kind` ('real', 'reference' ...), or of text
    read by the grammar `text_format` (see `TEXT_FORMATS`)."""
    return _Format if text_format is not None else _CONVERTERS[kind]


def converter_for(spec: AttributeSpec) -> _Converter:
    """The converter for an `AttributeSpec`."""
    return converter_class(spec.kind, spec.text_format)(spec)
