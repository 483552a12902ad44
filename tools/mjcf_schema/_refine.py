"""What MuJoCo's reader accepts beyond what its documentation says, found by probing.

After ``generate.py`` has checked the documented schema against the reader, these
steps ask the reader about values, one question at a time:

* which reals it holds as C floats (it refuses ``3.5e38`` there);
* the bounds it puts on numbers ("kv cannot be negative", "nstack must be >= -1"),
  found exactly by bisection between a refused and an accepted value;
* whether a keyword ignores case, which integers stand for keywords
  (``<headlight active="1">``), and in what order and combination a keyword list
  takes its words (``input="pos vel"``, never ``"vel pos"``);
* which references take a list of names where one is documented;
* which string attributes hold keyword lists (the reader's "invalid keyword:
  '(null)'"), with the candidates their documentation quotes;
* that the grammars of ``values.TEXT_FORMATS`` named in ``_annotations.TEXT_FORMATS``
  accept exactly what the reader accepts, on sample texts.

The rules between the attributes of one element are ``_rules``'s.

A probe's error counts only for what it is about (see ``_probe``); a behaviour none
of these shapes describes is logged as a note and left to the differential check
(``check.py``), which reports it.
"""

from __future__ import annotations

import itertools
import re
import struct

from mjcf.schema import values as _values
from tools.mjcf_schema import _annotations, _probe, _reader
from tools.mjcf_schema._docs import Attribute, Element, SchemaError
from tools.mjcf_schema._probe import Probe, note

_TOO_LARGE = "number is too large"
# Values tried for bounds: moderate ones, since some numbers are sizes the reader acts
# on (a flexcomp of count="100 100 1" takes seconds to read), and within C floats.
_INT_CANDIDATES = [-1000, -2, -1, 0, 1, 2, 10, 1000]
# The largest 32-bit integer, tried where an attribute holds one number, for a size
# the reader caps (a <numeric>'s size, at most 10,000,000); within a few seconds, since
# the reader acts on some sizes first (a <replicate count="2147483647"> takes hours).
_INT_LARGEST = 2**31 - 1
_LARGEST_SECONDS = 5.0
_REAL_CANDIDATES = [-1e30, -1.0, -1e-30, 0.0, 1e-30, 1.0, 1e30]
# Texts for string attributes that may be keyword lists or follow a grammar.
_FORMAT_SAMPLES = (
    "", "0", "-1", "-2", "-0", "+5", "010", "10", "10M", "1k", "10m", "1.5M", "1X", "M",
    "10 M", " 10M", "10M ", "1KB", "abc", "xyz", "XYZ", "xYz", "xy", "xyzx", "x y", "123",
    "18446744073709551615", "18446744073709551616", "17179869183G", "17179869184G", "8191P",
    "16E", "\u00e9..",
)  # fmt: skip


# -- the tree and blank values ---------------------------------------------------------


def repetition(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Which children the reader takes twice, under each parent: repeated under all,
    under none, or only under some (`repeated_in`: an <inertial> appears once in a
    body, any number of times in a <replicate>)."""
    edges = [(parent, child) for parent, e in elements.items() for child in e.children]
    errors = prober.errors([Probe(child, parent=parent, copies=2) for parent, child in edges])
    twice: dict[str, list[str]] = {}
    for (parent, child), error in zip(edges, errors, strict=True):
        twice.setdefault(child, [])
        if error is None:
            twice[child].append(parent)
    for child, parents in twice.items():
        element = elements[child]
        every = [p for p, c in edges if c == child]
        repeated = len(parents) == len(every)
        if repeated != element.repeated:
            documented = "repeated" if element.repeated else "once"
            note(f"{child}: documented {documented}, the reader disagrees")
        element.repeated = repeated
        element.repeated_in = [] if repeated else parents


def empty_presence(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Which once-only elements change what the reader reads by being there, empty: an
    actuator shortcut in a default class sets the class's actuator type and gains
    (`matters_empty`). The reader's model, written back, differs with one and without."""
    for key, element in elements.items():
        if element.repeated or key == prober.root:
            continue
        probe = Probe(key)
        if not prober.fragment(probe).endswith(f"<{element.tag}/>" + _closing(prober, key)):
            continue  # it cannot be empty: it needs attributes
        with_it = prober.written(probe)
        element.matters_empty = with_it is not None and with_it != prober.written(
            probe, leave_out_empty=True
        )


def _closing(prober: _probe.Prober, key: str) -> str:
    """The end tags after element ``key``'s place in its probe fragment."""
    chain = prober.paths[key][1:-1]
    return "".join(f"</{prober.elements[k].tag}>" for k in reversed(chain))


_BLANK_BY_KIND = {"int": True, "real": True, "keyword": False, "string": True}


def blanks(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Whether the reader takes blank text for each attribute: numbers and text take
    it (as not set) and keywords do not, with exceptions the probes find."""
    found = [
        (key, a)
        for key, element in elements.items()
        for a in element.attributes.values()
        if a.kind in _BLANK_BY_KIND
    ]
    errors = prober.errors([Probe(key, {a.name: ""}) for key, a in found])
    for (_, attribute), error in zip(found, errors, strict=True):
        accepted = error is None or not (
            _probe.bad_count(error, attribute.name)
            or _probe.bad_keyword(error, "", attribute.name)
            or "empty" in error
            or f"required attribute missing: '{attribute.name}'" in error  # blank: missing
            # MuJoCo 4.0.0 fails in its bindings on some blanks (<connect anchor="">),
            # and a later warning then hangs the process: never pass one on.
            or "unknown exception" in error
        )
        if accepted != _BLANK_BY_KIND[attribute.kind]:
            attribute.blank = accepted


def reference_lists(elements: dict[str, Element], root: str) -> None:
    """References the reader takes as lists of names where the documentation has one
    name (a flexcomp's material in MuJoCo 4: one material per element, or one for
    all): with an element named "p" in every namespace, MuJoCo compiles ``" p  p "``
    and writes it back as ``"p p"``, where a single name ``" p  p "`` is not found."""
    prober = _probe.Prober(elements, root, prelude=_probe.NAMED_PRELUDE)
    prober.set_paths()
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "reference" or attribute.is_list or not attribute.namespace:
                continue
            written = prober.written(Probe(key, {attribute.name: " p  p "}))
            if written is not None and f'{attribute.name}="p p"' in written:
                note(f"{key}/{attribute.name}: documented one name, the reader takes a list")
                attribute.is_list = True


# -- numbers ---------------------------------------------------------------------------


def _numbers(elements: dict[str, Element]) -> list[tuple[str, Attribute]]:
    return [
        (key, attribute)
        for key, element in elements.items()
        for attribute in element.attributes.values()
        if attribute.kind in ("int", "real")
    ]


def _count(attribute: Attribute) -> int:
    """How many numbers to probe with: all an attribute takes, when bounded."""
    if attribute.max is not None:
        return attribute.max
    return max(attribute.min, attribute.multiple_of or 1)


def _text(attribute: Attribute, word: str, position: int | None = None) -> str:
    """``word`` in every place (position None) or one place of the attribute, "1" elsewhere."""
    count = _count(attribute)
    if position is None:
        return " ".join([word] * count)
    words = ["1"] * count
    words[position] = word
    return " ".join(words)


def _semantic(error: str | None, name: str) -> bool:
    """Whether ``error`` refuses a value for what it means, not for its text."""
    return error is not None and not _probe.bad_count(error, name)


def float_precision(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Reals held as C floats: the reader refuses 3.5e38 as too large."""
    reals = [(key, a) for key, a in _numbers(elements) if a.kind == "real"]
    errors = prober.errors([Probe(key, {a.name: _text(a, "3.5e38", 0)}) for key, a in reals])
    for (_, attribute), error in zip(reals, errors, strict=True):
        attribute.float32 = error is not None and _TOO_LARGE in error


def bounds(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Bounds the reader puts on every number of an attribute, found exactly."""
    numbers = _numbers(elements)
    probes = []
    for key, attribute in numbers:
        for value in _candidates(attribute):
            probes.append(Probe(key, {attribute.name: _text(attribute, _word(attribute, value))}))
    errors = iter(prober.errors(probes))
    for key, attribute in numbers:
        values = _candidates(attribute)
        found = [next(errors) for _ in values]
        largest = _largest_refused(prober, key, attribute)
        if largest is not None:
            values, found = [*values, _INT_LARGEST], [*found, largest]
        accepted = [not _semantic(error, attribute.name) for error in found]
        if all(accepted):
            continue
        first, last = accepted.index(True) if any(accepted) else -1, len(accepted) - 1
        if first < 0:
            note(f"{key}/{attribute.name}: the reader refuses every probed value")
            continue
        last = len(accepted) - 1 - accepted[::-1].index(True)
        if not all(accepted[first : last + 1]):
            note(f"{key}/{attribute.name}: the values the reader accepts are not one range")
            continue
        # A value refused for what it means in the probe's context (a flexcomp of
        # dim 3 needs more points) hides the reader's own check (dim at most 3) beyond
        # it: then the bound is where the far candidate's refusal starts.
        places = (values, found, first, last)
        if not any(
            _bounds_found(prober, key, attribute, places, elements[key], alike)
            for alike in (False, True)
        ):
            attribute.min_value = attribute.max_value = None
            attribute.min_exclusive = attribute.max_exclusive = False


def _largest_refused(prober: _probe.Prober, key: str, attribute: Attribute) -> str | None:
    """The reader's error for the largest 32-bit integer in a one-number integer
    attribute; None if it takes it, or takes more than a few seconds to answer."""
    if attribute.kind != "int" or _count(attribute) != 1:
        return None
    try:
        error = prober.quick_error(
            Probe(key, {attribute.name: str(_INT_LARGEST)}), _LARGEST_SECONDS
        )
    except _reader.ReaderError:
        return None
    return error if _semantic(error, attribute.name) else None


def _bounds_found(
    prober: _probe.Prober,
    key: str,
    attribute: Attribute,
    places: tuple[list, list[str | None], int, int],
    element: Element,
    alike: bool,
) -> bool:
    """Set the attribute's bounds between the accepted candidates values[first..last]
    and their refused neighbours; True if they hold whatever else the element has.
    With ``alike``, a value counts as refused only with the neighbour's refusal."""
    values, found, first, last = places
    outside = []
    if first > 0:
        refusal = _refusal(found[first - 1]) if alike else None
        refused, taken = _threshold(
            prober, key, attribute, values[first - 1], values[first], refusal
        )
        attribute.min_value, attribute.min_exclusive = _bound(attribute, refused, taken)
        outside.append(refused)
    if last < len(values) - 1:
        refusal = _refusal(found[last + 1]) if alike else None
        refused, taken = _threshold(prober, key, attribute, values[last + 1], values[last], refusal)
        attribute.max_value, attribute.max_exclusive = _bound(attribute, refused, taken)
        outside.append(refused)
    return _intrinsic(prober, key, attribute, outside, element)


def _refusal(error: str | None) -> str:
    """The reader's error without what changes from probe to probe: names, numbers."""
    return re.sub(r"probe\d+_|-?\d[\d.e+-]*", "#", error or "")


def _candidates(attribute: Attribute) -> list:
    return _INT_CANDIDATES if attribute.kind == "int" else _REAL_CANDIDATES


def _word(attribute: Attribute, value: float) -> str:
    return str(value) if attribute.kind == "int" else repr(float(value))


def _threshold(
    prober: _probe.Prober,
    key: str,
    attribute: Attribute,
    refused: float,
    accepted: float,
    refusal: str | None = None,
) -> tuple[float, float]:
    """The neighbouring (refused, accepted) values between the two given, by bisection
    whose first two probes are the neighbours of the two ends: most bounds are at one
    of the candidates ("at least 0", "greater than 0"), found so in a probe or two
    instead of the sixty or so that halving the doubles between takes. With
    ``refusal``, only an error that reads so (see `_refusal`) refuses."""
    to_index, from_index = (int, int) if attribute.kind == "int" else (_ordinal, _from_ordinal)
    bad, good = to_index(refused), to_index(accepted)
    step = 1 if bad < good else -1
    neighbours = [good - step, bad + step]
    while abs(good - bad) > 1:
        middle = neighbours.pop(0) if neighbours else (bad + good) // 2
        text = _text(attribute, _word(attribute, from_index(middle)))
        error = prober.error(Probe(key, {attribute.name: text}))
        if _semantic(error, attribute.name) and (refusal is None or _refusal(error) == refusal):
            bad = middle
        else:
            good = middle
    return from_index(bad), from_index(good)


def _ordinal(value: float) -> int:
    """Doubles in order as integers (neighbouring doubles differ by one)."""
    bits = struct.unpack("<q", struct.pack("<d", value))[0]
    return bits if bits >= 0 else -(bits & 0x7FFFFFFFFFFFFFFF)


def _from_ordinal(ordinal: int) -> float:
    bits = ordinal if ordinal >= 0 else (-ordinal) | -0x8000000000000000
    return struct.unpack("<d", struct.pack("<q", bits))[0]


def _bound(attribute: Attribute, refused: float, accepted: float) -> tuple:
    """(bound, exclusive) spelled the short way: 'at least 0', 'greater than 1e-15'."""
    if attribute.kind == "int":
        return int(accepted), False
    if attribute.float32:  # compared after rounding to a C float
        refused, accepted = _values.round_float32(refused), _values.round_float32(accepted)
    if len(repr(refused)) < len(repr(accepted)):
        return refused, True
    return accepted, False


def _intrinsic(
    prober: _probe.Prober, key: str, attribute: Attribute, outside: list, element: Element
) -> bool:
    """Whether the values just outside the bounds are refused whatever the other
    numbers of the element are (a flexcomp's spacing must exceed its radius: that is
    no bound of spacing), and in the first and last place alone too."""
    name = attribute.name
    places, others = [], []
    for value in outside:
        word = _word(attribute, value)
        places += [
            Probe(key, {name: _text(attribute, word, p)}) for p in {0, _count(attribute) - 1}
        ]
        for other in element.attributes.values():
            if other is attribute or other.kind not in ("int", "real"):
                continue
            for scale in ("1", "2") if other.kind == "int" else ("0.001", "1000"):
                chosen = {name: _text(attribute, word), other.name: _text(other, scale)}
                others.append(Probe(key, chosen))
    if any(error is None for error in prober.errors(places, mostly_rejected=True)):
        note(f"{key}/{name}: bounded in some places only; no bound kept")
        return False
    if any(error is None for error in prober.errors(others, mostly_rejected=True)):
        note(f"{key}/{name}: its bound depends on other attributes; no bound kept")
        return False
    return True


# -- keywords ----------------------------------------------------------------------------


def keyword_forms(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Case, integers standing for keywords, and the order of keyword lists."""
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "keyword" or not attribute.values:
                continue
            _case(prober, key, attribute)
            _integers(prober, key, attribute)
            if attribute.is_list:
                _list_order(prober, key, attribute)


def _accepts(
    prober: _probe.Prober, key: str, name: str, texts: list[str], mostly_rejected: bool = False
) -> list[bool]:
    errors = prober.errors([Probe(key, {name: text}) for text in texts], mostly_rejected)
    return [
        error is None or not _probe.bad_keyword(error, text, name)
        for text, error in zip(texts, errors, strict=True)
    ]


def _case(prober: _probe.Prober, key: str, attribute: Attribute) -> None:
    first = attribute.values[0]
    spaced = [f" {first}", f"{first} "]
    attribute.trims = all(_accepts(prober, key, attribute.name, spaced, mostly_rejected=True))
    variants = [v.upper() for v in attribute.values if v.upper() != v]
    variants += [v.capitalize() for v in attribute.values if v.capitalize() not in (v, v.upper())]
    if not variants:
        return
    accepted = _accepts(prober, key, attribute.name, variants, mostly_rejected=True)
    if all(accepted):
        attribute.case_insensitive = True
    elif any(accepted):
        note(f"{key}/{attribute.name}: the reader ignores case for some keywords only")


def _integers(prober: _probe.Prober, key: str, attribute: Attribute) -> None:
    numbers = list(range(-1, len(attribute.values) + 2))
    texts = [str(n) for n in numbers]
    accepted = _accepts(prober, key, attribute.name, texts, mostly_rejected=True)
    taken = [n for n, ok in zip(numbers, accepted, strict=True) if ok]
    if not taken:
        return
    if taken != list(range(taken[0], taken[-1] + 1)):
        note(f"{key}/{attribute.name}: the reader takes the integers {taken}")
        return
    attribute.integers = (taken[0], taken[-1])


def _list_order(prober: _probe.Prober, key: str, attribute: Attribute) -> None:
    """Keyword lists: words in any order, or in the order of `values` (some alone)."""
    values = attribute.values
    pairs = list(itertools.permutations(values, 2))
    probes = [Probe(key, {attribute.name: f"{a} {b}"}) for a, b in pairs]
    errors = prober.errors(probes, mostly_rejected=True)
    accepted = {pair: error is None for pair, error in zip(pairs, errors, strict=True)}
    if all(accepted.values()):
        return
    alone = [
        v for v in values if not any(accepted[v, w] or accepted[w, v] for w in values if w != v)
    ]
    words = [v for v in values if v not in alone]
    rest = sorted(words, key=lambda a: -sum(accepted[a, b] for b in words if b != a))
    ordered = all(accepted[a, b] and not accepted[b, a] for a, b in itertools.combinations(rest, 2))
    if not ordered:
        raise SchemaError(f"{key}/{attribute.name}: keyword pairs the reader takes: {accepted}")
    attribute.values = rest + alone
    attribute.ordered, attribute.alone = True, alone
    # A word taken alone is the whole text: the reader reads ' none' as a list, and
    # refuses it. mjcf's converter relies on that; stop if it changes.
    spaced = [f" {word}" for word in alone] + [f"{word} " for word in alone]
    if any(_accepts(prober, key, attribute.name, spaced)):
        raise SchemaError(f"{key}/{attribute.name}: the reader takes {alone} with spaces")


def keyword_lists(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """String attributes the reader reads as keyword lists, with the words it takes
    among those quoted in the documentation of attributes of that name."""
    quoted: dict[str, set[str]] = {}
    for element in elements.values():
        for attribute in element.attributes.values():
            words = re.findall(r'"(\w+)"', attribute.description)
            quoted.setdefault(attribute.name, set()).update(words)
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "string" or attribute.name in _annotations.TEXT_FORMATS:
                continue
            error = prober.error(Probe(key, {attribute.name: "probe_text"}))
            if error is None or _probe.LIST_READER not in error:
                continue
            candidates = sorted(quoted[attribute.name])
            accepted = _accepts(prober, key, attribute.name, candidates)
            values = [word for word, ok in zip(candidates, accepted, strict=True) if ok]
            if not values:
                raise SchemaError(f"{key}/{attribute.name}: a keyword list, but no keyword found")
            note(f"{key}/{attribute.name}: documented string, the reader takes keywords {values}")
            attribute.kind, attribute.values, attribute.is_list = "keyword", values, True


def text_formats(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """String attributes read by a grammar: the one annotated must match the reader's."""
    for key, element in elements.items():
        for attribute in element.attributes.values():
            name = _annotations.TEXT_FORMATS.get(attribute.name)
            if attribute.kind != "string" or name is None:
                continue
            check = _values.TEXT_FORMATS[name]
            errors = prober.errors([Probe(key, {attribute.name: t}) for t in _FORMAT_SAMPLES])
            wrong = [
                text
                for text, error in zip(_FORMAT_SAMPLES, errors, strict=True)
                if check(text) != (error is None)
            ]
            if wrong:
                raise SchemaError(f"{key}/{attribute.name}: format {name!r} is wrong for {wrong}")
            attribute.text_format = name
