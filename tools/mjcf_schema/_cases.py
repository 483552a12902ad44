"""The documents of the differential check (``check.py``), made from mjcf's schema.

Every case is one small MJCF document that differs from an accepted one in a
single thing: one attribute's text (every keyword and its case variants,
booleans as words and digits, numbers where keywords are expected and the
reverse, arities from none to one too many, negative, huge, hexadecimal and
non-finite numbers, empty and blank text), a required attribute left out, a
child element placed under a parent, an element repeated, or a section given
twice with different values. The element sits in the context ``_probe.Prober``
builds (its ancestors, required attributes and the alternatives MuJoCo wants),
after a prelude that defines an element named ``p`` in every namespace
(``_probe.NAMED_PRELUDE``), so that
references resolve and most documents compile.

A case also says how to make the same change through the Python API (``Edit``):
the document without the change is parsed, and the change is made with
``set_attributes`` or ``add`` on the element at ``path``.
"""

from __future__ import annotations

import re
import struct
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field

from tools.mjcf_schema import _probe
from tools.mjcf_schema._docs import Attribute, Element
from tools.mjcf_schema._probe import Probe

# Words tried in the first place of a numeric attribute (the rest are "1").
NUMBER_WORDS = (
    "-1",
    "0",
    "2",
    "-0.5",
    "1.5",
    "1.0",
    "1e3",
    "+1",
    "010",
    "0x10",
    "0x1p3",
    "1e-400",
    "3e38",
    "1e39",
    "1e308",
    "1e309",
    "-1e309",
    "inf",
    "-inf",
    "nan",
    "INF",
    "infinity",
    "2147483647",
    "2147483648",
    "-2147483648",
    "-2147483649",
    "4294967296",
    "1d",
    "1,",
    ".",
    "e3",
    "abc",
    "true",
)
# Text tried for every keyword attribute besides its own keywords.
KEYWORD_EXTRAS = ("", "0", "1", "2", "3", "-1", "true", "false", "probe_keyword")
# Text tried for free-text attributes.
STRING_TEXTS = ("", "abc", "xyz", "XYZ", "xy", "xyzx", "a b", "10M", "1K", "-1", "1.5M", "1X")
IDENTIFIER_TEXTS = ("probe_name", "", "a b", "p", "a/b", "main", "world")
REFERENCE_TEXTS = ("p", "", "missing", "p p", "main", "world")
# What mjcf's own refusals (mjcf/schema/_refusals.py) want of a minimal element, so that
# the cases around it test what they test: a pair's geoms, the plugin a plugin names (a
# plugin, not an instance: MuJoCo reads the <config> of a plugin, not an instance's).
REFUSAL_FILL = {
    "contact-pair": {"geom1": "p", "geom2": "p"},
    **{
        f"{parent}-plugin": {"plugin": "mujoco.pid"}
        for parent in ("body", "geom", "mesh", "flexcomp", "actuator")
    },
}


def _png() -> bytes:
    """A 2x2 grey PNG image."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", 2, 2, 8, 0, 0, 0, 0)
    pixels = zlib.compress(b"\x00\x80\x80" * 2)
    return (
        b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", pixels) + chunk(b"IEND", b"")
    )


def _stl() -> bytes:
    """A tetrahedron as binary STL."""
    corners = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    data = bytearray(b"\0" * 80 + struct.pack("<I", len(faces)))
    for face in faces:
        data += struct.pack("<3f", 0, 0, 0)
        for index in face:
            data += struct.pack("<3f", *corners[index])
        data += b"\0\0"
    return bytes(data)


FILES: dict[str, bytes] = {**_probe.FILES, "probe.png": _png(), "probe.stl": _stl()}
FILE_TEXTS = ("", "probe.stl", "probe.png", "missing.stl")


@dataclass(frozen=True)
class Edit:
    """The change of a case made through the API, on the element at ``path`` (tags
    from the root; the last child of each tag) of the document without it."""

    path: tuple[str, ...]
    attribute: str | None = None  # set this attribute to `text`
    text: str | None = None
    child: str | None = None  # or add this child with `child_attributes`
    child_attributes: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class Case:
    """One document of the check. ``kind`` is 'value', 'omit', 'child', 'repeat' or
    'sections'; ``subject`` names what is varied, e.g. 'body-geom/size="1 1 1 1"'."""

    kind: str
    key: str
    subject: str
    document: str
    baseline: str | None = None  # the document without the change, for `edit`
    edit: Edit | None = None
    coverage: tuple[str, ...] = field(default=(), compare=False)  # "key/attribute" covered


def drafts_from_schema(data: dict) -> dict[str, Element]:
    """The schema's elements as the generator's drafts, so that ``_probe.Prober``
    places them in documents."""
    elements = {}
    for key, entry in data["elements"].items():
        attributes = {}
        for name, spec in entry["attributes"].items():
            attribute = Attribute(
                name,
                spec["type"],
                required=spec["required"],
                default=spec.get("default"),
                values=list(spec.get("values", ())),
                namespace=spec.get("namespace"),
                namespace_from=spec.get("namespace_from"),
                is_list=bool(spec.get("list", False)),
            )
            if attribute.kind in ("int", "real"):
                attribute.min, attribute.max = spec["min"], spec["max"]
                attribute.multiple_of = spec.get("multiple_of")
                attribute.count = spec["max"] or max(spec["min"], spec.get("multiple_of") or 1)
            attributes[name] = attribute
        elements[key] = Element(
            key, entry["tag"], entry["repeated"], attributes, list(entry["children"])
        )
        elements[key].namespace = entry["namespace"]
    return elements


def candidates(attribute: Attribute) -> list[str]:
    """The texts tried for one attribute."""
    kind = attribute.kind
    if kind in ("int", "real"):
        return _number_texts(attribute)
    if kind == "keyword":
        return _keyword_texts(attribute)
    if kind == "identifier":
        return list(IDENTIFIER_TEXTS)
    if kind == "reference":
        return list(REFERENCE_TEXTS)
    if kind == "file":
        return list(FILE_TEXTS)
    return list(STRING_TEXTS)


def _number_texts(attribute: Attribute) -> list[str]:
    low, high, step = attribute.min, attribute.max, attribute.multiple_of or 1
    top = high + 1 if high is not None else low + 3 * step
    counts = sorted({*range(1, min(top, 24) + 1), top, low, low + step, low + step + 1})
    texts = ["", "  "] + [" ".join(["1"] * count) for count in counts]
    usual = max(low, step)
    texts += [" ".join([word] + ["1"] * (usual - 1)) for word in NUMBER_WORDS]
    texts += [" " + texts[2] + " ", " ".join(["1"] * usual).replace(" ", "  ")]
    return list(dict.fromkeys(texts))


def _keyword_texts(attribute: Attribute) -> list[str]:
    texts = list(attribute.values)
    for value in attribute.values:
        texts += [value.upper(), value.capitalize(), value.lower(), f" {value}", f"{value} "]
    texts += KEYWORD_EXTRAS
    if attribute.is_list and len(attribute.values) > 1:
        first, second = attribute.values[:2]
        texts += [f"{first} {second}", f"{first}  {second}", f"{first} {first}", " "]
    return list(dict.fromkeys(texts))


class CaseMaker:
    """Makes the cases of a schema (the JSON data mjcf loads)."""

    def __init__(self, data: dict) -> None:
        self.elements = drafts_from_schema(data)
        self.root = data["root"]
        self.prober = _probe.Prober(
            self.elements, self.root, prelude=_probe.NAMED_PRELUDE, fill=REFUSAL_FILL
        )
        self.prober.set_paths()
        self.tags = sorted({e.tag for e in self.elements.values()} | {"probe_tag"})
        self.by_tag: dict[str, str] = {}
        for key, element in self.elements.items():
            self.by_tag.setdefault(element.tag, key)
        self.failures: list[str] = []  # elements whose minimal document MuJoCo refuses

    def learn(self) -> None:
        """Run each element's minimal document once, so that the prober learns the
        attribute alternatives MuJoCo wants; remember the ones still refused."""
        for key in self.elements:
            error = self.prober.error(Probe(key))
            if error is not None:
                self.failures.append(f"{key}: {error}")

    def path(self, key: str, parent: str | None = None) -> tuple[str, ...]:
        chain = [*self.prober.paths[parent], key] if parent else self.prober.paths[key]
        return tuple(self.elements[k].tag for k in chain[1:])

    def _document(self, *probes: Probe) -> str:
        return self.prober.document([self.prober.fragment(p) for p in probes])

    # -- cases ------------------------------------------------------------------------

    def value_cases(self) -> Iterator[Case]:
        """Each attribute of each element with each of its candidate texts."""
        for key, element in self.elements.items():
            for name, attribute in element.attributes.items():
                for text in candidates(attribute):
                    yield self.value_case(key, name, text)

    def value_case(self, key: str, name: str, text: str) -> Case:
        """Element ``key`` with attribute ``name`` set to ``text``."""
        chosen = {name: text}
        baseline = None
        if key != self.root:
            baseline = self._document(Probe(key, chosen, omit=(name,)))
        edit = Edit(self.path(key), attribute=name, text=text)
        document = self._document(Probe(key, chosen))
        return Case(
            "value",
            key,
            f"{key}/{name}={text!r}",
            document,
            None if baseline is None else _same_names(baseline, document),
            edit if baseline is not None else None,
            coverage=(f"{key}/{name}",),
        )

    def omit_cases(self) -> Iterator[Case]:
        """Each required attribute left out."""
        for key, element in self.elements.items():
            for name, attribute in element.attributes.items():
                if attribute.required:
                    yield Case(
                        "omit",
                        key,
                        f"{key} without {name}",
                        self._document(Probe(key, omit=(name,))),
                    )

    def child_cases(self, sample: bool = False) -> Iterator[Case]:
        """Under each element, every tag of the schema (and one it does not have)
        with the attributes it needs; ``sample``: its own children and two others."""
        for parent, element in self.elements.items():
            own = {self.elements[c].tag for c in element.children}
            tags = self.tags
            if sample:
                others = [t for t in self.tags if t not in own]
                pick = zlib.crc32(parent.encode()) % len(others)
                tags = sorted(own) + sorted({others[pick], "probe_tag"})
            for tag in tags:
                yield self.child_case(parent, tag)

    def child_case(self, parent: str, tag: str) -> Case:
        """Element ``tag`` placed under ``parent``."""
        own = {self.elements[c].tag: c for c in self.elements[parent].children}
        child_key = own.get(tag) or self.by_tag.get(tag)
        values = self.prober.values(child_key, parent, {}) if child_key else {}
        inner = _probe._start_tag(tag, values)[:-1] + "/>"
        if parent == self.root:
            document, baseline = self.prober.document([inner]), self.prober.document([])
        else:
            document = self._document(Probe(parent, inner=inner))
            baseline = _same_names(self._document(Probe(parent)), document)
        edit = Edit(self.path(parent), child=tag, child_attributes=tuple(values.items()))
        return Case("child", parent, f"<{tag}> in {parent}", document, baseline, edit)

    def repeat_cases(self) -> Iterator[Case]:
        """Each child twice under each parent that may have it."""
        for parent, element in self.elements.items():
            for child in element.children:
                probe = Probe(child, parent=parent, copies=2)
                yield Case("repeat", child, f"two {child} in {parent}", self._document(probe))

    def section_cases(self) -> Iterator[Case]:
        """Each top-level section twice, with one child in each: a child that may
        appear once gets different values for the same attributes the second time
        (MuJoCo applies them in order), a repeated one a second copy."""
        for section in self.elements[self.root].children:
            for child in self.elements[section].children:
                first, second = self._two_settings(child)
                probes = (Probe(child, first, parent=section), Probe(child, second, parent=section))
                covered = tuple(f"{child}/{name}" for name in first)
                subject = f"{section} twice, {child} with {first} then {second}"
                yield Case("sections", child, subject, self._document(*probes), coverage=covered)

    def _two_settings(self, key: str) -> tuple[dict[str, str], dict[str, str]]:
        """Two settings of up to two attributes of ``key``: the first sets both, the
        second changes the first attribute only."""
        first: dict[str, str] = {}
        second: dict[str, str] = {}
        for name, attribute in self.elements[key].attributes.items():
            pair = _two_values(attribute)
            if pair is None or attribute.required:
                continue
            first[name] = pair[0]
            if not second:
                second[name] = pair[1]
            if len(first) == 2:
                break
        return first, second

    def all_cases(self, sample: bool = False) -> Iterator[Case]:
        """Every case (``sample``: a deterministic subset that still covers every
        attribute and every parent-child pair of the schema)."""
        values = self.value_cases()
        if sample:
            values = self._sampled_values()
        yield from values
        yield from self.omit_cases()
        yield from self.child_cases(sample)
        yield from self.repeat_cases()
        yield from self.section_cases()

    def _sampled_values(self) -> Iterator[Case]:
        """Per attribute one candidate chosen by a hash of its name, so that every
        attribute is tried and every kind of candidate is tried somewhere."""
        for key, element in self.elements.items():
            for name, attribute in element.attributes.items():
                texts = candidates(attribute)
                seed = zlib.crc32(f"{key}/{name}".encode())
                yield self.value_case(key, name, texts[seed % len(texts)])


_PROBE_NAME = re.compile(r"probe\d+_")


def _same_names(baseline: str, document: str) -> str:
    """``baseline`` with the probes' names of ``document`` (each document the prober
    makes numbers its names anew), so that the models both compile to compare; the
    document may name one more probe (a child placed), after those they share."""
    ours = list(dict.fromkeys(_PROBE_NAME.findall(baseline)))
    theirs = list(dict.fromkeys(_PROBE_NAME.findall(document)))
    if len(theirs) - len(ours) not in (0, 1):
        return baseline
    renamed = dict(zip(ours, theirs[: len(ours)], strict=True))
    return _PROBE_NAME.sub(lambda match: renamed[match.group()], baseline)


def _two_values(attribute: Attribute) -> tuple[str, str] | None:
    """Two different valid texts for an attribute, or None."""
    if attribute.kind in ("int", "real"):
        count = attribute.max or attribute.min
        if attribute.multiple_of:
            count = max(count, attribute.multiple_of)
        low, high = ("1", "2") if attribute.kind == "int" else ("0.25", "0.75")
        return " ".join([low] * count), " ".join([high] * count)
    if attribute.kind == "keyword" and len(attribute.values) > 1:
        return attribute.values[0], attribute.values[-1]
    return None
