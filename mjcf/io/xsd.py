"""An XML Schema of MJCF, generated from `mjcf.schema`, that libxml2 checks whole
documents against in C: the fast reader's first check. Built once per thread, when used.

    if xsd.accepts(xml_root):    # every element and attribute known, every value well formed
        ...                      # read fast (mjcf.io.fast_reader)
    else:
        ...                      # read element by element, which says what is wrong

It is conservative: it accepts a document only if the element-by-element checks accept it
too; what it cannot say simply it refuses or leaves to `unchecked` and the indexer.
"""

from __future__ import annotations

import functools
import threading
from xml.sax.saxutils import quoteattr

from lxml import etree

from mjcf import schema
from mjcf.schema import AttributeSpec, ElementSpec

_XS = "http://www.w3.org/2001/XMLSchema"


def accepts(xml_root: etree._Element, exact: bool = False) -> bool:
    """Whether the document under `xml_root` (a `<mujoco>`) passes the schema: the one
    that counts the digits of decimals if `exact` (see `needs_exact`)."""
    return _schema(_EXACT if exact else _FAST).validate(xml_root)


def is_made(exact: bool = False) -> bool:
    """Whether this thread has made the schema `accepts` checks with (the exact one if
    `exact`): the first check makes it, which takes about 8 ms."""
    return getattr(_per_thread, _EXACT if exact else _FAST, None) is not None


def needs_exact(data: bytes, encoding: str | None) -> bool:
    """Whether MJCF text `data` (a file's bytes, in `encoding` as lxml read it) must be
    checked against the schema that counts the digits of decimals: whether it could
    hold a decimal too large for a C float (39 digits in a row, or a reference, which
    could spell them: any '&'), or is in an encoding that spells digits otherwise than
    ASCII does (UTF-16 ...)."""
    if (encoding or "").upper() not in _ASCII_DIGITS or b"\0" in data:  # UTF-16, UTF-32
        return True
    digits = data.translate(_DIGITS_AND_AMPERSANDS)
    return b"&" in digits or _LONG_RUN in digits


def unchecked(spec: ElementSpec) -> tuple[AttributeSpec, ...]:
    """The attributes of `spec` whose values the schema takes as any text, but the
    element-by-element checks do not: to be checked with their converters. They are what
    the schema cannot say simply (numbers counted in multiples or bounded, blank values,
    keyword lists, text with a grammar ...); rules between attributes it leaves to the
    indexer."""
    return _unchecked(spec)


@functools.cache
def _unchecked(spec: ElementSpec) -> tuple[AttributeSpec, ...]:
    return tuple(
        attribute
        for attribute in spec.attributes.values()
        if attribute.checks_text and _simple_type(attribute) is None
    )


def _simple_type(attribute: AttributeSpec) -> tuple | None:
    """What the schema checks an attribute's value with: ('keywords', words) or
    ('numbers', item type, least, most); None for any text."""
    converter = attribute.converter
    if converter.keywords:
        if attribute.is_list:  # distinct words, some in order or alone: left to converters
            return None
        words = attribute.values
        if attribute.integers is not None:
            low, high = attribute.integers
            words += tuple(str(number) for number in range(low, high + 1))
        return ("keywords", words)
    if (
        converter.numbers
        and attribute.min >= 1
        and not attribute.multiple_of
        and not attribute.gaps
        and attribute.min_value is None
        and attribute.max_value is None
    ):
        # Integers in 32 bits, as MuJoCo reads them; reals within a C double or float,
        # and without INF and NaN where mjcf wants them finite (see schema._refusals).
        item = "float" if attribute.float32 else "double"
        if attribute.finite is not None:
            item = "finite-" + item
        return ("numbers", item if converter.reals else "xs:int", attribute.min, attribute.max)
    return None


_per_thread = threading.local()  # lxml's validators are not for concurrent use


def _schema(kind: str) -> etree.XMLSchema:
    found = getattr(_per_thread, kind, None)
    if found is None:
        found = etree.XMLSchema(etree.fromstring(_text(kind).encode()))
        setattr(_per_thread, kind, found)
    return found


@functools.cache
def _text(kind: str) -> str:
    return schema_text(exact=kind == _EXACT)


def schema_text(exact: bool = False) -> str:
    """The XML Schema, as text: the one that counts the digits of decimals if `exact`
    (see `needs_exact`)."""
    complex_names: dict[int, str] = {}
    pending: list[ElementSpec] = []
    simple_names: dict[tuple, str] = {}

    def complex_name(spec: ElementSpec) -> str:
        name = complex_names.get(id(spec))
        if name is None:
            name = complex_names[id(spec)] = f"element{len(complex_names)}"
            pending.append(spec)
        return name

    def simple_name(attribute: AttributeSpec) -> str:
        kind = _simple_type(attribute)
        if kind is None:
            return "xs:string"
        name = simple_names.get(kind)
        if name is None:
            name = simple_names[kind] = f"value{len(simple_names)}"
        return name

    out = [f'<xs:schema xmlns:xs="{_XS}">',
           f'<xs:element name="mujoco" type="{complex_name(schema.MUJOCO)}"/>']  # fmt: skip
    while pending:
        spec = pending.pop()
        out.append(f'<xs:complexType name="{complex_names[id(spec)]}" mixed="true">')
        if spec.children:
            out.append('<xs:choice minOccurs="0" maxOccurs="unbounded">')
            out.extend(
                f'<xs:element name="{tag}" type="{complex_name(child)}"/>'
                for tag, child in spec.children.items()
            )
            out.append("</xs:choice>")
        out.extend(
            f'<xs:attribute name="{name}" type="{simple_name(attribute)}"'
            + (' use="required"/>' if attribute.required else "/>")
            for name, attribute in spec.attributes.items()
        )
        out.append("</xs:complexType>")
    for kind, name in simple_names.items():
        out.append(_simple_type_text(name, kind))
    out.append(_reals(_EXACT if exact else _FAST))
    out.append("</xs:schema>")
    return "".join(out)


# A real number: libxml2 takes '1e' and '1e+' for doubles, which Python's float()
# refuses, so a double must end as only well-formed ones do. Decimals (most values) are
# tried first: that costs no pattern, which would double the time of the whole check.
# Reals stay within what MuJoCo holds (a C double; a C float for some), with a margin:
# others by their value, decimals by their count of digits. A count of digits is a facet
# that makes libxml2 compute every decimal's value, which doubled the time of the whole
# check; so the schema documents are checked against (`_FAST`) takes any decimal, and a
# document whose text could hold a decimal too large for a C float (39 digits in a row,
# or a character reference, which could spell them) is checked against the schema that
# counts them (`_EXACT`).
_FAST, _EXACT = "fast", "exact"
_DIGITS = {_FAST: None, _EXACT: {"double": 300, "float": 38}}
_LONG_RUN = b"0" * 39  # digits in a row, after _DIGITS_AND_AMPERSANDS
# Each digit as '0', '&' (which begins a character reference) as itself, the rest as ' '.
_DIGITS_AND_AMPERSANDS = bytes(
    48 if 48 <= byte <= 57 else byte if byte == 38 else 32 for byte in range(256)
)
# Encodings (as lxml names them) whose bytes for digits, '&' and '#' are ASCII's and mean
# only those characters.
_ASCII_DIGITS = frozenset({"UTF-8", "ASCII", "US-ASCII", "ISO-8859-1", "LATIN1", "WINDOWS-1252"})


def _reals(kind: str) -> str:
    digits = _DIGITS[kind]
    out = []
    for name, size, largest, last in (
        ("double", "double", "1.7e308", "NF"),
        ("float", "float", "3.4e38", "NF"),
        ("finite-double", "double", "1.7e308", ""),  # no INF, no NaN
        ("finite-float", "float", "3.4e38", ""),
    ):
        facet = f'<xs:totalDigits value="{digits[size]}"/>' if digits else ""
        out.append(
            f'<xs:simpleType name="{name}"><xs:union memberTypes="{name}-decimal '
            f'{name}-exponent"/></xs:simpleType><xs:simpleType name="{name}-decimal">'
            f'<xs:restriction base="xs:decimal">{facet}</xs:restriction></xs:simpleType>'
            f'<xs:simpleType name="{name}-exponent"><xs:restriction base="xs:double">'
            f'<xs:minExclusive value="-{largest}"/><xs:maxExclusive value="{largest}"/>'
            f'<xs:pattern value=".*[0-9{last}]"/></xs:restriction></xs:simpleType>'
        )
    return "".join(out)


def _simple_type_text(name: str, kind: tuple) -> str:
    if kind[0] == "keywords":
        enumeration = "".join(f"<xs:enumeration value={quoteattr(v)}/>" for v in kind[1])
        return (
            f'<xs:simpleType name="{name}"><xs:restriction base="xs:string">{enumeration}'
            "</xs:restriction></xs:simpleType>"
        )
    _, item, least, most = kind
    if least == most == 1:
        return f'<xs:simpleType name="{name}"><xs:restriction base="{item}"/></xs:simpleType>'
    facets = f'<xs:minLength value="{least}"/>'
    if most is not None:
        facets += f'<xs:maxLength value="{most}"/>'
    return (
        f'<xs:simpleType name="{name}"><xs:restriction><xs:simpleType>'
        f'<xs:list itemType="{item}"/></xs:simpleType>{facets}</xs:restriction>'
        "</xs:simpleType>"
    )
