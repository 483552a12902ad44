"""The rules MuJoCo's reader keeps between the attributes of one element, found by
probing: at most one of some groups (orientation specifiers), one of some groups (a
<numeric>'s size or data), one attribute requiring another (a plugin sensor's reftype
its refname), or some together; and whether text the reader reads as none counts as
given for them. Each rule is kept with the reader's message (see
``mjcf.schema.Rule``)."""

from __future__ import annotations

import itertools
import re

from tools.mjcf_schema import _probe
from tools.mjcf_schema._docs import Element
from tools.mjcf_schema._probe import Probe, note


def rules(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """At most one of, one of, and requires: each from the reader's errors."""
    for key, element in elements.items():
        element.rules = _rules_of(prober, key, element)


def _rules_of(prober: _probe.Prober, key: str, element: Element) -> list[dict]:
    names = [a.name for a in element.attributes.values() if a.kind != "identifier"]
    values = {name: prober.value(element.attributes[name]) for name in names}
    alone = dict(
        zip(names, prober.errors([Probe(key, {n: values[n]}) for n in names]), strict=True)
    )
    # An objtype and its objname are always given together in probes (see
    # `Prober.values`): whether the reader needs the other is asked leaving it out.
    pairs = [
        (a.name, a.namespace_from)
        for a in element.attributes.values()
        if a.namespace_from is not None
    ]
    pairs += [(second, first) for first, second in pairs]
    left_out = [Probe(key, {n: values[n]}, omit=(other,)) for n, other in pairs]
    without_partner = zip([n for n, _ in pairs], prober.errors(left_out), strict=True)
    found: list[dict] = []
    for name, error in [*alone.items(), *without_partner]:
        missing = re.search(r"required attribute missing: '(\w+)'", error or "") or re.search(
            rf"^(?:XML Error: )?{name} is specified but (\w+) is not", error or ""
        )
        together = re.search(r"attributes (.*) must be specified together", error or "")
        needed = element.attributes.get(missing.group(1)) if missing else None
        if missing and needed and not needed.required:  # a required one is needed anyway
            found.append({"requires": [name, missing.group(1)], "message": _message(error or "")})
        elif together:
            group = re.findall(r"'(\w+)'", together.group(1))
            rule = {"together": group, "message": _message(error or "")}
            if rule not in found:
                found.append(rule)
    usable = [n for n in names if alone[n] is None]
    pairs = list(itertools.combinations(usable, 2))
    errors = prober.errors([Probe(key, {a: values[a], b: values[b]}) for a, b in pairs])
    conflicts: dict[str, set[tuple[str, str]]] = {}
    for pair, error in zip(pairs, errors, strict=True):
        if error is not None:
            conflicts.setdefault(_message(error), set()).add(pair)
    for message, refused in conflicts.items():
        groups = _groups(message, refused) if _RULE_MESSAGE.search(message) else None
        if groups is None:
            note(f"{key}: the reader refuses {sorted(refused)} together: {message}")
        else:
            found.append({"at_most_one": groups, "message": message})
    for groups in prober.learned_one_of(key) or _needs_one(prober, key, element):
        found.append({"one_of": groups, "message": f"one of {groups} must be specified"})
    for kept in found:
        if _blank_is_none(prober, key, kept, values):
            kept["blank_is_none"] = True
    return found


def _blank_is_none(prober: _probe.Prober, key: str, rule: dict, values: dict[str, str]) -> bool:
    """Whether the reader takes an attribute a `requires` or `one_of` rule needs as not
    given when its text is empty (a <numeric>'s data="": "custom field size must be
    positive"), rather than given at all (a <connect>'s site1="")."""
    if "requires" in rule:
        first, needed = rule["requires"]
        return prober.error(Probe(key, {first: values[first], needed: ""})) is not None
    if "one_of" not in rule:
        return False
    group, *others = rule["one_of"]
    chosen = {name: values[name] for name in group} | {group[0]: ""}
    left_out = tuple(name for other in others for name in other if name not in group)
    return prober.error(Probe(key, chosen, omit=left_out)) is not None


def _needs_one(prober: _probe.Prober, key: str, element: Element) -> list[list[list[str]]]:
    """A "one of" rule the reader keeps without saying so: the element refused with
    none of its optional attributes and taken with any one of several (a <numeric>
    with its size or its data: "custom field size must be positive")."""
    filled = tuple(_probe.ALSO_FILL.get(key, ()))
    bare = prober.error(Probe(key, omit=filled)) if filled else None
    if bare is None:
        return []
    optional = [
        a.name
        for a in element.attributes.values()
        if not a.required and a.kind not in ("identifier", "keyword")
    ]
    probes = [
        Probe(
            key,
            {name: prober.value(element.attributes[name])},
            omit=tuple(other for other in filled if other != name),
        )
        for name in optional
    ]
    errors = prober.errors(probes)
    taken = [name for name, error in zip(optional, errors, strict=True) if error is None]
    # Each attribute the probes fill in must be one of the alternatives, and each other
    # attribute must leave the element refused as it is bare (not refused otherwise,
    # as an <attach> whose self-attached body the probe does not name).
    others_alike = all(error in (None, bare) for error in errors)
    if len(taken) < 2 or not set(filled) <= set(taken) or not others_alike:
        return []
    return [[[name] for name in taken]]


# Errors of the reader that state a rule between attributes rather than a meaning.
_RULE_MESSAGE = re.compile(
    r"at most one of|cannot both be|can only be used|multiple \w+ specifiers"
)


def _message(error: str) -> str:
    """A reader's error without its prefix and the place it names."""
    return error.split(" Element ")[0].removeprefix("XML Error: ")


def _groups(message: str, refused: set[tuple[str, str]]) -> list[list[str]] | None:
    """The groups of an "at most one of" rule that refusing exactly these pairs
    shows: named in the message; single attributes refused pairwise; or two groups,
    each of whose attributes is refused with each of the other's."""
    listed = _probe.rule_groups(message)
    if listed is not None:
        return listed
    edges = {frozenset(pair) for pair in refused}
    members = sorted({name for pair in refused for name in pair})
    if edges == {frozenset(p) for p in itertools.combinations(members, 2)}:
        return [[name] for name in members]
    first = [m for m in members if frozenset((members[0], m)) not in edges]
    second = [m for m in members if m not in first]
    if edges == {frozenset((a, b)) for a in first for b in second}:
        return [first, second]
    return None
