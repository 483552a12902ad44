"""Property tests: random valid trees built through the Python API survive
parse(serialize(tree)) unchanged, for every element and attribute kind of the schema."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mjcf
from mjcf import schema

_FLOATS = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False, width=64)
_INTS = st.integers(min_value=-1000, max_value=1000)
_NAMES = itertools.count()
_TEXT = st.text(alphabet="abcxyz_-.<>&\"' 09", min_size=1, max_size=8)


def _accepted(attribute: schema.AttributeSpec, value: object) -> bool:
    try:
        attribute.converter.from_python(value)
    except ValueError:
        return False
    return True


def _counts(attribute: schema.AttributeSpec) -> list[int]:
    """Every count of numbers the schema accepts (up to 6 past the minimum when unbounded):
    inside the arity bounds, a multiple where one is asked, and none of the gaps MuJoCo
    refuses between the bounds (a frame's scale takes 1 or 3 numbers, not 2)."""
    low = max(attribute.min, 1)
    high = attribute.max if attribute.max is not None else low + 6
    step = attribute.multiple_of or 1
    counts = [n for n in range(low, high + 1) if n % step == 0 and n not in attribute.gaps]
    assert counts, f"no count accepted by {attribute!r}"
    return counts


def _value(attribute: schema.AttributeSpec) -> st.SearchStrategy:
    kind = attribute.kind
    if kind == "keyword":
        if attribute.is_list:
            words = [v for v in attribute.values if v not in attribute.alone]
            return st.lists(st.sampled_from(words), min_size=1, max_size=3, unique=True).map(
                lambda chosen: " ".join(sorted(chosen, key=attribute.values.index))
            )
        return st.sampled_from(attribute.values)
    if attribute.text_format is not None:
        samples = ["-1", "0", "10M", "1K", "xyz", "XYZ", "zyx"]
        return st.sampled_from([t for t in samples if _accepted(attribute, t)])
    if kind in ("int", "real"):
        numbers = _INTS if kind == "int" else _FLOATS
        if attribute.min_value is not None or attribute.max_value is not None:
            numbers = numbers.filter(lambda number: _accepted(attribute, number))
        if attribute.scalar:
            return numbers
        return st.sampled_from(_counts(attribute)).flatmap(
            lambda n: st.lists(numbers, min_size=n, max_size=n)
        )
    # Plain strings, with characters that need escaping; blank only where the schema takes it.
    return _TEXT.filter(lambda text: _accepted(attribute, text))


def _settable(spec: schema.ElementSpec) -> list[schema.AttributeSpec]:
    return [a for a in spec.attributes.values() if a.kind in ("keyword", "int", "real", "string")]


def _buildable(spec: schema.ElementSpec) -> bool:
    """Elements whose required attributes a random tree can fill in."""
    if spec.needs_rules:  # one of some references, say
        return False
    return all(spec.attributes[name].kind not in ("reference", "file") for name in spec.required)


def _compatible(spec: schema.ElementSpec, chosen: list) -> list:
    """`chosen` without the attributes MuJoCo allows only one group of at a time."""
    kept: list = []
    for attribute in chosen:
        names = {a.name for a in kept} | {attribute.name}
        if not any(
            rule.kind == "at_most_one" and rule.broken_by(dict.fromkeys(names))
            for rule in spec.rules
        ):
            kept.append(attribute)
    return kept


@st.composite
def _element(draw, parent: mjcf.Element, depth: int) -> None:
    specs = [s for s in parent.spec.children.values() if _buildable(s)]
    if not specs:
        return
    spec = draw(st.sampled_from(specs))
    if not spec.repeated and any(c.tag == spec.tag for c in parent.all_children()):
        return
    attributes = _settable(spec)
    chosen = (
        draw(st.lists(st.sampled_from(attributes), unique_by=lambda a: a.name, max_size=4))
        if attributes
        else []
    )
    values = {a.name: draw(_value(a)) for a in _compatible(spec, chosen)}
    for name in spec.required:
        attribute = spec.attributes[name]
        if attribute.kind == "identifier":
            values[name] = f"n{next(_NAMES)}"
        elif name not in values:
            values[name] = draw(_value(attribute))
    values = {("dclass" if k == "class" else k): v for k, v in values.items()}
    child = parent.add(spec.tag, **values)
    if depth < 3:
        for _ in range(draw(st.integers(0, 3))):
            draw(_element(child, depth + 1))


@st.composite
def models(draw) -> mjcf.RootElement:
    root = mjcf.RootElement(model="random")
    sections = draw(st.lists(st.sampled_from(list(schema.ROOT_SECTIONS)), min_size=1, max_size=4))
    for tag in sections:
        for _ in range(draw(st.integers(1, 3))):
            draw(_element(getattr(root, tag), 1))
    return root


def _written(element: mjcf.Element) -> bool:
    """Whether the element appears in XML: empty once-only elements are left out."""
    return (
        element.spec.repeated
        or bool(element.get_attributes())
        or any(_written(c) for c in element.all_children())
    )


def _same_tree(a: mjcf.Element, b: mjcf.Element) -> None:
    assert a.tag == b.tag
    left, right = a.get_attributes(), b.get_attributes()
    assert left.keys() == right.keys(), a.path
    for name, value in left.items():
        assert np.array_equal(np.asarray(value), np.asarray(right[name])), f"{a.path} {name}"
    children_a = [c for c in a.all_children() if _written(c)]
    children_b = [c for c in b.all_children() if _written(c)]
    assert len(children_a) == len(children_b), a.path
    for x, y in zip(children_a, children_b, strict=True):
        _same_tree(x, y)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(models())
def test_parse_of_serialize_is_identity(root: mjcf.RootElement) -> None:
    text = root.to_xml_string()
    parsed = mjcf.from_xml_string(text, resolve_references=False)
    _same_tree(root, parsed)
    assert parsed.to_xml_string() == text


@settings(max_examples=60, deadline=None)
@given(models(), st.integers(1, 16))
def test_lower_precision_stays_valid(root: mjcf.RootElement, precision: int) -> None:
    mjcf.from_xml_string(root.to_xml_string(precision=precision), resolve_references=False)
