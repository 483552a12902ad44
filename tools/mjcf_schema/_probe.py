"""Ask MuJoCo's XML reader what it accepts, to check and complete the schema.

``mujoco.MjSpec.from_string`` runs only the reader (no compiler), so whether it
raises tells what MJCF the reader accepts; it runs in a child process
(``_reader``), replaced when a document leaves MuJoCo in a state that would
hang it on a later one. A probe is a one-line fragment of MJCF: an element
placed in a minimal context (the chain of ancestors where the documentation
puts it, each with its required attributes filled in) with one thing varied.
Fragments expected to be accepted are parsed together, one document per batch,
and a failing one is found from the line MuJoCo reports; fragments expected to
be rejected are parsed one by one, since a document reports only its first
error.

MuJoCo's reader checks the whole document against its own schema before it
reads any value, except inside ``frame`` and ``replicate`` (meta elements
read by separate code that ignores attributes it does not know); there an
attribute is known when a nonsense value is refused or a value changes the
model MuJoCo writes back.

A probe's error is judged by what it is about: an unknown attribute, a bad
keyword, a wrong count of numbers. A value the reader reads and then finds
meaningless in its context still shows that the reader knows the attribute.
"""

from __future__ import annotations

import itertools
import logging
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import mujoco

from tools.mjcf_schema._docs import Attribute, Element
from tools.mjcf_schema._reader import Reader

logger = logging.getLogger(__name__)

# A model file the probes may name: `<asset><model file=...>` loads it while reading.
_MODEL_FILE = "probe_model.xml"
FILES = {_MODEL_FILE: b"<mujoco/>"}
# Documents naming this model (`attach model=`) or class start by defining it.
_MODEL_NAME = "probe_model"
_CLASS_NAME = "probe_class"
PRELUDES = {
    _MODEL_NAME: f'<asset><model name="{_MODEL_NAME}" file="{_MODEL_FILE}"/></asset>',
    _CLASS_NAME: f'<default><default class="{_CLASS_NAME}"/></default>',
}
# One element named "p" in each namespace a reference can point into.
NAMED_PRELUDE = (
    '<extension><plugin plugin="mujoco.pid"><instance name="p">'
    '<config key="kp" value="1"/></instance></plugin></extension>'
    '<asset><texture name="p" builtin="flat" width="2" height="2"/><material name="p"/>'
    '<mesh name="p" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>'
    '<hfield name="p" nrow="2" ncol="2" size="1 1 1 1"/></asset>'
    '<worldbody><body name="p"><joint name="p"/><geom name="p" size="1"/><site name="p"/>'
    '<camera name="p"/><light name="p"/></body>'
    '<flexcomp name="p" type="grid" count="2 2 1" spacing="1 1 1" dim="2"/></worldbody>'
    '<tendon><fixed name="p"><joint joint="p" coef="1"/></fixed></tendon>'
    '<actuator><motor name="p" joint="p"/><plugin name="p_plugin" instance="p" joint="p"/>'
    "</actuator>"
    '<sensor><jointpos name="p" joint="p"/></sensor>'
    '<equality><joint name="p" joint1="p" active="false"/></equality>'
    '<contact><exclude name="p" body1="p" body2="world"/></contact>'
    '<keyframe><key name="p"/></keyframe><custom><numeric name="p" data="1"/></custom>'
    # The model probes name; the default class only where named, since a second
    # top-level <default> is read differently (see mjcf.io.default_sections).
    + PRELUDES[_MODEL_NAME]
)

# A count of numbers larger than any fixed arity; divisible by 1..8.
_MANY = 840
# Content for frame and replicate probes: a named geom shows replicated names.
_INNER = '<geom name="probe_geom" size="1"/>'
# The object types of MuJoCo's API (mjtObj), candidates for object type keywords.
OBJECT_TYPES = [
    name.removeprefix("mjOBJ_").lower()
    for name in mujoco.mjtObj.__members__
    if name.startswith("mjOBJ_")
]
# Values a minimal element needs beyond its required attributes: one of several
# attributes the reader requires together, or a default the reader rejects.
ALSO_FILL = {
    "body-attach": {"model": _MODEL_NAME},  # else body= or frame= (self-attachment)
    "sensor-plugin": {"plugin": "probe"},  # or instance=
    "body-flexcomp": {"count": "2 2 1"},  # the default 10x10x10 grid is not 2-D
    "actuator-dcmotor": {"motorconst": "1 1", "resistance": "1"},  # must be positive
    "default-dcmotor": {"motorconst": "1 1", "resistance": "1"},
    "custom-numeric": {"data": "1"},  # size or data
    # A flex that compiles: three points of the world body, two segments.
    "deformable-flex": {
        "dim": "1",
        "body": "world world world",
        "vertex": "0 0 0 1 0 0 2 0 0",
        "element": "0 1 1 2",
    },
    "custom-text": {"data": "probe"},  # text cannot be empty
    "extension-plugin": {"plugin": "mujoco.pid"},  # a plugin shipped with the wheel
}
# Numbers for a count that depends on the model: a multiple of 1, 2, 3, 4 and 6.
_MODEL_COUNT = 12
_ONE_OF = re.compile(r"(at most )?one of (.+?) (?:must|can) be specified")
# Fragments parsed on their own: replicate renames elements across the document.
_ALONE = re.compile(r"<replicate[ />]")
# Fragments per document: a rejected one costs a parse of the others again.
_BATCH = 50
_LINE = re.compile(r"line (\d+)")
# Errors that mean "this child is not allowed here", as opposed to a bad probe.
# (A flexcomp needs a named body as its parent; replicate never is one.)
_NOT_ALLOWED = re.compile(
    r"unrecognized element|unrecognized model element|cannot have|cannot be a direct child"
    r"|Parent body must have name"
)


def note(message: str) -> None:
    """Log what the probes found that the documentation does not say (shown by
    ``python -m tools.mjcf_schema.generate``)."""
    logger.info("note: %s", message)


class ProbeError(RuntimeError):
    """A probe that should be accepted was not: the probe, not MuJoCo, needs fixing."""


@dataclass
class Probe:
    """Element ``key`` in its context, with ``attributes`` set and ``omit`` left out."""

    key: str
    attributes: dict[str, str] = field(default_factory=dict)
    parent: str | None = None  # place under this element's context instead
    copies: int = 1
    omit: tuple[str, ...] = ()
    inner: str = ""  # content of the element


@dataclass
class Arity:
    """Numbers accepted for one attribute, as probed."""

    min: int
    max: int | None
    gaps: list[int] = field(default_factory=list)  # counts inside [min, max] rejected


class Prober:
    """Builds probe documents around schema elements and runs MuJoCo's reader on them.

    The prober learns the reader's "one of ... must be specified" and "at most
    one of ... can be specified" rules from its errors, and fills in an
    alternative that fits the attributes a probe sets.
    """

    def __init__(
        self,
        elements: dict[str, Element],
        root: str,
        prelude: str = "",
        fill: dict[str, dict[str, str]] | None = None,
    ) -> None:
        self.elements = elements
        self.root = root
        self.prelude = prelude  # MJCF placed at the start of every document
        # Values every element of a key gets besides ALSO_FILL's.
        self.fill = {key: {**ALSO_FILL.get(key, {}), **(fill or {}).get(key, {})}
                     for key in {*ALSO_FILL, *(fill or {})}}  # fmt: skip
        self.paths: dict[str, list[str]] = {}
        self.parses = 0
        self._reader = Reader(FILES)
        self._serial = itertools.count()
        self._one_of: dict[str, list[list[list[str]]]] = {}
        self._at_most_one: dict[str, list[list[list[str]]]] = {}

    def set_paths(self) -> None:
        """Place every element under its first parent in document order (depth first)."""
        self.paths = {self.root: [self.root]}
        stack = [self.root]
        while stack:
            key = stack.pop()
            for child in reversed(self.elements[key].children):
                if child not in self.paths:
                    self.paths[child] = [*self.paths[key], child]
                    stack.append(child)

    # -- documents ---------------------------------------------------------------

    def value(self, attribute: Attribute, count: int | None = None) -> str:
        """A valid-looking value for ``attribute`` (``count`` numbers if given)."""
        kind = attribute.kind
        if kind == "identifier":  # "_": replicate appends digits to names
            return f"probe{next(self._serial)}_"
        if kind == "reference":
            return {"default": _CLASS_NAME, "model": _MODEL_NAME}.get(
                attribute.namespace or "", "p"
            )
        if kind == "file":
            return _MODEL_FILE
        if kind == "keyword":  # no values yet: an object type keyword before probing
            return attribute.default or (attribute.values[0] if attribute.values else "body")
        if kind in ("int", "real"):
            return " ".join(["1"] * (count or attribute.count or _MODEL_COUNT))
        if attribute.default is not None:
            return attribute.default
        return f"probe{next(self._serial)}_" if attribute.required else ""

    def values(self, key: str, parent: str, chosen: dict[str, str]) -> dict[str, str]:
        """Attribute values for element ``key``: ``chosen`` plus what it needs besides."""
        attributes = self.elements[key].attributes
        values: dict[str, str] = {}
        for attribute in attributes.values():
            named = attribute.kind == "identifier" and parent != self.root
            if attribute.required or named:
                values[attribute.name] = self.value(attribute)
        values.update(self.fill.get(key, {}))
        for name in self._alternatives(key, chosen):
            values[name] = self.value(attributes[name])
        values.update(chosen)
        for attribute in attributes.values():  # objtype and objname go together
            selector = attribute.namespace_from
            if selector is not None and (selector in values) != (attribute.name in values):
                missing = attribute if selector in values else attributes[selector]
                values[missing.name] = self.value(missing)
        return values

    def fragment(self, probe: Probe) -> str:
        """One line of MJCF holding the probe (for the root: the document's start tag)."""
        parent = probe.parent
        chain = [*self.paths[parent], probe.key] if parent else list(self.paths[probe.key])
        heads = []
        for _ in range(probe.copies):
            values = self.values(probe.key, chain[-2] if len(chain) > 1 else "", probe.attributes)
            for name in probe.omit:
                values.pop(name, None)
            heads.append(_start_tag(self.elements[probe.key].tag, values))
        tag = self.elements[probe.key].tag
        if probe.key == self.root:
            return heads[0]
        xml = "".join(f"{h}{probe.inner}</{tag}>" if probe.inner else h[:-1] + "/>" for h in heads)
        for depth in range(len(chain) - 2, 0, -1):
            tag = self.elements[chain[depth]].tag
            head = _start_tag(tag, self.values(chain[depth], chain[depth - 1], {}))
            xml = f"{head}{xml}</{tag}>"
        return xml

    def _alternatives(self, key: str, chosen: dict[str, str]) -> list[str]:
        """For each learned "one of" rule not met by ``chosen``, a group that fits it."""
        names: list[str] = []
        for groups in self._one_of.get(key, []):
            if any(set(group) <= chosen.keys() for group in groups):
                continue
            ranked = sorted(groups, key=lambda group: not set(group) & chosen.keys())
            fitting = [group for group in ranked if self._compatible(key, group, chosen)]
            names.extend((fitting or ranked)[0])
        return names

    def _compatible(self, key: str, group: list[str], chosen: dict[str, str]) -> bool:
        for rule in self._at_most_one.get(key, []):
            wanted = {i for i, g in enumerate(rule) if set(g) & chosen.keys()}
            used = {i for i, g in enumerate(rule) if set(g) & set(group)}
            if wanted and not used <= wanted:
                return False
        return True

    def learned_one_of(self, key: str) -> list[list[list[str]]]:
        """The "one of ... must be specified" rules learned for element ``key``."""
        return list(self._one_of.get(key, []))

    def _learn(self, key: str, error: str) -> bool:
        """Remember a "one of" / "at most one of" rule from ``error``; True if new."""
        rule = _ONE_OF.search(error)
        if not rule:
            return False
        groups = _groups_in(rule.group(2))
        rules = (self._at_most_one if rule.group(1) else self._one_of).setdefault(key, [])
        if groups in rules:
            return False
        rules.append(groups)
        return True

    # -- running ---------------------------------------------------------------

    def error(self, probe: Probe) -> str | None:
        """MuJoCo's error for a document holding the probe, or None if accepted."""
        while True:
            error = self._parse([self.fragment(probe)])
            if error is None or not self._learn(probe.key, error):
                return error

    def quick_error(self, probe: Probe, seconds: float) -> str | None:
        """MuJoCo's error for a document holding the probe, None if it reads it;
        raises ReaderError if reading takes more than ``seconds``."""
        return self._parse([self.fragment(probe)], seconds)

    def errors(self, probes: Sequence[Probe], mostly_rejected: bool = False) -> list[str | None]:
        """The error (or None) of each probe, parsing the accepted ones together.

        A rejected probe costs a parse of its batch besides its own, so probes
        expected to be ``mostly_rejected`` are parsed one by one instead.
        """
        if mostly_rejected:
            return [self.error(probe) for probe in probes]
        results: list[str | None] = [None] * len(probes)
        fragments = [self.fragment(probe) for probe in probes]
        pending = []
        for index, fragment in enumerate(fragments):
            if probes[index].key == self.root or _ALONE.search(fragment):
                results[index] = self.error(probes[index])
            else:
                pending.append(index)
        for start in range(0, len(pending), _BATCH):
            batch = pending[start : start + _BATCH]
            while batch:
                failure = self._parse([fragments[i] for i in batch])
                if failure is None:
                    break
                line = _LINE.search(failure)
                position = int(line.group(1)) - 2 if line else -1
                if not 0 <= position < len(batch):
                    for index in batch:
                        results[index] = self.error(probes[index])
                    break
                index = batch.pop(position)
                results[index] = self.error(probes[index])
        return results

    def require_accepted(self, probes: Sequence[Probe]) -> None:
        """Raise ProbeError listing the probes MuJoCo rejects."""
        failures = [
            f"{self.fragment(probe)}\n    -> {error}"
            for probe, error in zip(probes, self.errors(probes), strict=True)
            if error is not None
        ]
        if failures:
            raise ProbeError("MuJoCo rejects probes:\n  " + "\n  ".join(failures))

    def written(self, probe: Probe, leave_out_empty: bool = False) -> str | None:
        """The MJCF MuJoCo writes back after reading the probe (the probe's own
        names made alike, so documents compare); None if it cannot. With
        ``leave_out_empty``, the document is the probe's without its element, which must
        be empty (the parents it needs stay)."""
        fragment = self.fragment(probe)
        if leave_out_empty:
            empty = f"<{self.elements[probe.key].tag}/>"
            at = fragment.rindex(empty)
            fragment = fragment[:at] + fragment[at + len(empty) :]
        self.parses += 1
        error, xml = self._reader.read(self.document([fragment]), write_back=True)
        return None if error is not None or xml is None else re.sub(r"probe\d+_", "probe_", xml)

    def _parse(self, fragments: list[str], seconds: float | None = None) -> str | None:
        self.parses += 1
        error, _ = self._reader.read(self.document(fragments), seconds=seconds)
        return None if error is None else " ".join(error.split())

    def document(self, fragments: list[str]) -> str:
        """A whole document holding ``fragments``, one per line after the first (a
        fragment of the root element's start tag replaces the plain one; an empty
        root element is a child)."""
        tag = self.elements[self.root].tag
        start = f"<{tag}>"
        first = fragments[0] if fragments else ""
        if first.startswith(start[:-1]) and not first.endswith("/>"):
            start, fragments = fragments[0], fragments[1:]
        start += self.prelude
        for name, prelude in PRELUDES.items():
            if prelude not in self.prelude and any(f'"{name}"' in f for f in fragments):
                start += prelude
        return "\n".join([start, *fragments, f"</{tag}>"])


def _groups_in(text: str) -> list[list[str]]:
    """Attribute groups of a rule: "('a', 'b'), 'c'" -> [['a', 'b'], ['c']]."""
    return [
        re.findall(r"'(\w+)'", group) if group else [name]
        for group, name in re.findall(r"\(([^)]*)\)|'(\w+)'", text)
    ]


def rule_groups(error: str) -> list[list[str]] | None:
    """The groups of an "at most one of ... can be specified" error, or None."""
    rule = _ONE_OF.search(error)
    return _groups_in(rule.group(2)) if rule and rule.group(1) else None


def _start_tag(tag: str, values: dict[str, str]) -> str:
    attributes = "".join(f' {name}="{value}"' for name, value in values.items())
    return f"<{tag}{attributes}>"


# -- what is probed ---------------------------------------------------------------


def unrecognized(error: str, name: str) -> bool:
    """Whether ``error`` says the reader does not take attribute ``name`` there."""
    return f"unrecognized attribute: '{name}'" in error or "cannot have attributes" in error


# How the reader of keyword lists (camera output="rgb depth") reports a bad one.
LIST_READER = "invalid keyword: '(null)'"


def bad_keyword(error: str, value: str, name: str | None = None) -> bool:
    """Whether ``error`` says the reader has no keyword ``value`` (for attribute ``name``).

    Keyword lists report "invalid keyword: '(null)'", a few keywords that also take
    numbers "problem reading attribute", and an object type that a name needs reads as
    not given ("objname is specified but objtype is not"); those count when ``name`` is
    given.
    """
    quoted = re.escape(f"'{value}'")
    pattern = rf"invalid keyword: {quoted}|unknown [\w ]+ {quoted}|unknown object type$"
    pattern += r"|no longer supported"  # a keyword MuJoCo keeps only to refuse it
    if name is not None:
        pattern += rf"|{re.escape(LIST_READER)}|problem reading attribute '{name}'"
        pattern += rf"|but {re.escape(name)} is not$"
    return re.search(pattern, error.split(" Element ")[0]) is not None


def bad_count(error: str, name: str) -> bool:
    """Whether ``error`` is about attribute ``name``'s text (its count of numbers)."""
    return f"attribute '{name}'" in error


def accepted_keywords(prober: Prober, key: str, name: str, candidates: list[str]) -> list[str]:
    """The candidate values MuJoCo's reader accepts for keyword ``name`` of ``key``."""
    errors = prober.errors([Probe(key, {name: value}) for value in candidates])
    return [
        value
        for value, error in zip(candidates, errors, strict=True)
        if not (error and bad_keyword(error, value))
    ]


def allowed_children(prober: Prober, container: str, candidates: list[str]) -> list[str]:
    """The candidate element keys MuJoCo's reader accepts as children of ``container``."""
    errors = prober.errors([Probe(key, parent=container) for key in candidates])
    allowed = []
    for key, error in zip(candidates, errors, strict=True):
        if error is None:
            allowed.append(key)
        elif not _NOT_ALLOWED.search(error):
            raise ProbeError(f"<{container}> child {key!r} failed for another reason: {error}")
    return allowed


def accepted_attributes(prober: Prober, key: str, candidates: list[Attribute]) -> list[str]:
    """The names of the candidate attributes MuJoCo's reader knows on element ``key``."""
    errors = prober.errors([Probe(key, {a.name: prober.value(a)}) for a in candidates])
    return [
        a.name
        for a, error in zip(candidates, errors, strict=True)
        if not (error and unrecognized(error, a.name))
    ]


def is_read(prober: Prober, key: str, attribute: Attribute) -> bool:
    """Whether MuJoCo reads ``attribute`` of an element that ignores unknown ones
    (frame, replicate): a nonsense value is refused, or a value changes the model
    MuJoCo writes back."""
    if prober.error(Probe(key, {attribute.name: "probe_nonsense"})) is not None:
        return True
    base = prober.written(Probe(key, omit=(attribute.name,), inner=_INNER))
    changed = prober.written(Probe(key, {attribute.name: "probe_text"}, inner=_INNER))
    return changed is not None and changed != base


def arity(prober: Prober, key: str, attribute: Attribute) -> Arity:
    """The numbers of values MuJoCo's reader accepts for a numeric attribute.

    The documented count must be known to be accepted (``attribute.count``;
    None when it depends on the model). Only errors about the attribute's text
    count as rejections: a count the reader reads and then finds meaningless
    (``maxhullvert="1"``) is accepted. Counts between 1 and the documented one
    are assumed to behave like their ends when both ends agree.
    """

    def rejected(count: int) -> bool:
        error = prober.error(Probe(key, {attribute.name: prober.value(attribute, count)}))
        return error is not None and bad_count(error, attribute.name)

    documented = attribute.count
    if documented is None:
        low = next((count for count in range(1, _MODEL_COUNT + 1) if not rejected(count)), None)
        if low is None:
            raise ProbeError(f"{key}/{attribute.name}: no count up to {_MODEL_COUNT} accepted")
        return Arity(low, _largest_accepted(rejected, low))
    maximum = documented if rejected(documented + 1) else _largest_accepted(rejected, documented)
    if documented == 1:
        return Arity(1, maximum)
    lowest, below = rejected(1), rejected(documented - 1)
    if lowest == below:
        return Arity(documented if lowest else 1, maximum)
    counts = range(1, documented)
    accepted = [count for count in counts if not rejected(count)]
    gaps = [count for count in counts if count > accepted[0] and count not in accepted]
    return Arity(accepted[0], maximum, gaps)


def _largest_accepted(rejected: Callable[[int], bool], low: int) -> int | None:
    """The largest count from ``low`` (accepted) up that is not rejected; None: unbounded."""
    high = _MANY
    if not rejected(high):
        return None
    while high - low > 1:
        middle = (low + high) // 2
        if rejected(middle):
            high = middle
        else:
            low = middle
    return low
