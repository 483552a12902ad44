"""MuJoCo's MJCF schema as Python objects, loaded from `DATA_FILE`, which
`python -m tools.mjcf_schema.generate` makes from the installed mujoco's XML reference.

    from mjcf import schema
    geom = schema.MUJOCO.child('worldbody').child('body').child('geom')
    geom.attributes['size']        # AttributeSpec(real, 1..3 numbers)
    geom.namespace                 # 'geom'

Specs are immutable, shared by every element of their kind; importing warns if the data
was made from another MuJoCo than the installed one. `_refusals` adds what mjcf refuses.
"""

from __future__ import annotations

import copy
import json
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path

import mujoco

from mjcf.schema import _refusals
from mjcf.schema import values as _values

__all__ = [
    "DATA_FILE",
    "MUJOCO",
    "NAMESPACES",
    "ROOT_SECTIONS",
    "AttributeSpec",
    "ElementSpec",
    "Rule",
    "all_specs",
]

# The generated schema this module loads (the generator writes it, its checker reads it).
DATA_FILE = Path(__file__).with_name("mjcf_schema.json")


class AttributeSpec:
    """What one attribute of one element accepts: its `kind` ('identifier',
    'string', 'file', 'reference', 'keyword', 'int', 'real'), arity bounds for
    numbers (and bounds on their values, and whether MuJoCo holds them as 32-bit
    floats), keywords (whether case counts, which integers stand for them), the
    namespace a reference points into, a grammar for text, MuJoCo's default, and how two
    models' values merge when one is attached to the other (`merge`)."""

    __slots__ = (
        "alone",
        "blank",
        "case_insensitive",
        "checks_text",
        "converter",
        "default",
        "finite",
        "float32",
        "gaps",
        "integers",
        "is_list",
        "kind",
        "max",
        "max_exclusive",
        "max_value",
        "merge",
        "min",
        "min_exclusive",
        "min_value",
        "multiple_of",
        "name",
        "namespace",
        "namespace_from",
        "namespace_map",
        "ordered",
        "refused",
        "required",
        "scalar",
        "scoped",
        "text_format",
        "trims",
        "values",
    )

    def __init__(self, name: str, data: Mapping) -> None:
        self.name = name
        self.kind: str = data["type"]
        self.required: bool = bool(data.get("required", False))
        self.default: str | None = data.get("default")
        self.values: tuple[str, ...] = tuple(data.get("values", ()))
        self.min: int = data.get("min", 1)
        self.max: int | None = data.get("max", 1)
        # Counts between min and max MuJoCo refuses (a frame's scale: 1 or 3 numbers).
        self.gaps: frozenset[int] = frozenset(data.get("gaps", ()))
        self.multiple_of: int | None = data.get("multiple_of")
        self.namespace: str | None = data.get("namespace")
        self.namespace_from: str | None = data.get("namespace_from")
        self.namespace_map: dict[str, str] = dict(data.get("namespace_map", {}))
        self.is_list: bool = bool(data.get("list", False))
        self.float32: bool = bool(data.get("float32", False))
        self.min_value: float | None = data.get("min_value")
        self.min_exclusive: bool = bool(data.get("min_exclusive", False))
        self.max_value: float | None = data.get("max_value")
        self.max_exclusive: bool = bool(data.get("max_exclusive", False))
        self.case_insensitive: bool = bool(data.get("case_insensitive", False))
        integers = data.get("integers")
        self.integers: tuple[int, int] | None = tuple(integers) if integers else None
        self.ordered: bool = bool(data.get("ordered", False))
        self.alone: frozenset[str] = frozenset(data.get("alone", ()))
        self.text_format: str | None = data.get("format")
        kind = _values.converter_class(self.kind, self.text_format)
        # Blank text: numbers and text take it (MuJoCo reads it as not set), keywords not.
        self.blank: bool = bool(data.get("blank", kind.takes_blank))
        self.trims: bool = bool(data.get("trims", False))
        # How two models' values merge when one is attached to the other ('min', 'max',
        # 'or'), where MuJoCo's documentation says (see mjcf.compose.global_settings).
        self.merge: str | None = data.get("merge")
        # Text mjcf refuses though MuJoCo's reader takes it, and why (see _refusals);
        # why it refuses infinite or NaN numbers here, if it does.
        self.refused: dict[str, str] = {}
        self.finite: str | None = None
        # Numbers with exactly one value read back as Python scalars, others as arrays.
        self.scalar: bool = kind.numbers and self.min == 1 and self.max == 1
        # Names that take the model's name-scope prefix when models are composed.
        self.scoped: bool = kind.scoped()
        self.converter = kind(self)
        # Whether reading text must check it (names are checked by the element).
        self.checks_text: bool = self.converter.checks_text()

    def arity_text(self) -> str:
        """Human-readable count of numbers this attribute takes ('1 to 3 numbers')."""
        if self.max is None:
            base = f"{self.min} or more numbers" if self.min else "any number of numbers"
            return base + (f", a multiple of {self.multiple_of}" if self.multiple_of else "")
        if self.min == self.max:
            return f"{self.min} number" + ("" if self.min == 1 else "s")
        if self.gaps and self.max is not None:
            *counts, last = (c for c in range(self.min, self.max + 1) if c not in self.gaps)
            return f"{', '.join(map(str, counts))} or {last} numbers"
        return f"{self.min} to {self.max} numbers"

    def reference_namespace(self, element_attributes: Mapping[str, object]) -> str | None:
        """The namespace this reference points into, given the attributes of its element
        (for references whose namespace another attribute selects, e.g. objtype)."""
        if self.namespace_from is None:
            return self.namespace
        selector = element_attributes.get(self.namespace_from)
        if not isinstance(selector, str):
            return None
        # Only the exact word selects: MuJoCo reads ' Body' or a number, where it takes
        # them, as an unknown object type, and ignores the name then.
        return self.namespace_map.get(selector)

    def __repr__(self) -> str:
        return f"AttributeSpec({self.name!r}: {self.converter.describe()})"


class Rule:
    """A rule MuJoCo's reader keeps between the attributes of one element: at most
    one of some groups of attributes may be set (`at_most_one`), at least one group
    must be set entirely (`one_of`), the first attribute needs the second
    (`requires`), or all of some attributes or none (`together`). A group counts as
    set when any attribute of it is; with `blank_is_none`, when MuJoCo does not read
    its text as none (blank numbers, empty text)."""

    __slots__ = ("blank_is_none", "groups", "kind", "message", "names", "numbers", "reason")

    def __init__(self, data: Mapping, attributes: Mapping[str, AttributeSpec]) -> None:
        self.kind = next(k for k in ("at_most_one", "one_of", "requires", "together") if k in data)
        groups = data[self.kind]
        if self.kind in ("requires", "together"):
            groups = [[name] for name in groups]
        self.groups: tuple[tuple[str, ...], ...] = tuple(tuple(g) for g in groups)
        self.names = frozenset(name for group in self.groups for name in group)
        self.message: str = data.get("message", "")
        # Why mjcf keeps a rule MuJoCo's reader does not (see _refusals), for messages.
        self.reason: str = data.get("reason", "")
        # Whether an attribute MuJoCo reads as none counts as not given (its reader's
        # own checks), or any text does (its schema's): blank numbers, empty text.
        self.blank_is_none = bool(data.get("blank_is_none", False))
        self.numbers = frozenset(name for name in self.names if attributes[name].converter.numbers)

    def broken_by(self, attributes: Mapping[str, object]) -> bool:
        """Whether element attributes `attributes` (name -> value) break this rule."""
        if self.kind == "at_most_one":
            return sum(1 for group in self.groups if any(n in attributes for n in group)) > 1
        if self.kind == "one_of":
            return not any(all(self._given(n, attributes) for n in group) for group in self.groups)
        if self.kind == "together":
            return 0 < sum(1 for name in self.names if name in attributes) < len(self.names)
        first, needed = self.groups
        return first[0] in attributes and not self._given(needed[0], attributes)

    def _given(self, name: str, attributes: Mapping[str, object]) -> bool:
        """Whether attribute `name` counts as given for this rule (see `blank_is_none`)."""
        value = attributes.get(name)
        if isinstance(value, str) and self.blank_is_none:
            return (value.strip() if name in self.numbers else value) != ""
        return value is not None

    def describe(self) -> str:
        """The rule in words, for error messages."""
        shown = " / ".join("+".join(group) for group in self.groups)
        if self.kind == "at_most_one":
            return f"at most one of {shown} may be set"
        if self.kind == "one_of":
            return f"one of {shown} must be set" + (f": {self.reason}" if self.reason else "")
        if self.kind == "together":
            return f"{' and '.join(sorted(self.names))} must be set together"
        return f"{self.groups[0][0]!r} needs {self.groups[1][0]!r}"


class ElementSpec:
    """What one element accepts in one place of the tree (a `<geom>` in a body differs from
    a `<geom>` in a default class): attributes, child elements by tag, whether it may repeat
    under its parent, and the namespace of its name."""

    __slots__ = (
        "attributes",
        "checked_on_write",
        "children",
        "crashing_children",
        "file_attributes",
        "identifier",
        "key",
        "matters_empty",
        "namespace",
        "needs_rules",
        "on_demand",
        "references",
        "repeated",
        "required",
        "rule_names",
        "rules",
        "scoped_attributes",
        "tag",
    )

    def __init__(self, key: str, data: Mapping) -> None:
        self.key = key
        self.tag: str = data["tag"]
        self.namespace: str | None = data.get("namespace")
        self.repeated: bool = bool(data.get("repeated", True))
        self.attributes: dict[str, AttributeSpec] = {
            name: AttributeSpec(name, spec) for name, spec in data["attributes"].items()
        }
        self.children: dict[str, ElementSpec] = {}
        self._sort_attributes()
        # A child that may appear once and is absent (None) until added, as dm_control's
        # "on demand" children (a body's inertial and free joint); other children that
        # may appear once are created empty on first access (`option.flag`).
        self.on_demand = False
        # Once-only, and its mere presence changes the model (an actuator shortcut in a
        # default class sets the actuator type): written even when empty, unless it was
        # only created by access (see `Element.get_children`).
        self.matters_empty: bool = bool(data.get("matters_empty", False))
        self.rules: tuple[Rule, ...] = tuple(
            Rule(rule, self.attributes) for rule in data.get("rules", ())
        )
        self.rule_names = frozenset(name for rule in self.rules for name in rule.names)
        # Rules that an element being built may break for a while (checked on writing).
        self.needs_rules = tuple(rule for rule in self.rules if rule.kind != "at_most_one")
        self.checked_on_write = bool(self.required or self.needs_rules)
        # (own attribute or None, child tag, the child's attribute or None, why): an
        # element with that attribute and such a child crashes MuJoCo (_refusals).
        self.crashing_children: tuple[tuple[str | None, str, str | None, str], ...] = ()

    def _sort_attributes(self) -> None:
        """Which attributes name the element, refer, name files, are scoped, required."""
        attributes = self.attributes.values()
        identifiers = [a.name for a in attributes if a.converter.names]
        self.identifier: str | None = identifiers[0] if identifiers else None
        self.scoped_attributes = frozenset(a.name for a in attributes if a.scoped)
        self.references = frozenset(a.name for a in attributes if a.converter.refers)
        self.required = tuple(a.name for a in attributes if a.required)
        self.file_attributes = frozenset(a.name for a in attributes if a.converter.files)

    def add_rule(self, rule: Rule) -> None:
        """Keep `rule` too (see _refusals)."""
        self.rules = (*self.rules, rule)
        self.rule_names = frozenset(name for rule in self.rules for name in rule.names)
        self.needs_rules = tuple(rule for rule in self.rules if rule.kind != "at_most_one")
        self.checked_on_write = bool(self.required or self.needs_rules)

    def crash(
        self, attributes: Iterable[str], children: Iterable[tuple[str, Iterable[str]]]
    ) -> str | None:
        """Why an element of this spec with `attributes` set and `children` ((tag, the
        attributes set), ...) would crash MuJoCo, or None (see _refusals)."""
        if not self.crashing_children:
            return None
        names = set(attributes)
        found = [(tag, set(child)) for tag, child in children]
        for name, tag, child_name, why in self.crashing_children:
            if name is not None and name not in names:
                continue
            for child_tag, child_names in found:
                if child_tag == tag and (child_name is None or child_name in child_names):
                    return why
        return None

    @property
    def name(self) -> str:
        """The tag (dm_control's name for it)."""
        return self.tag

    @classmethod
    def synthesize(
        cls,
        key: str,
        tag: str,
        namespace: str | None,
        attributes: dict[str, AttributeSpec],
        children: dict[str, ElementSpec],
    ) -> ElementSpec:
        """A spec made of existing attribute and child specs (for elements MuJoCo does
        not have, such as attachment frames)."""
        spec = cls(key, {"tag": tag, "namespace": namespace, "attributes": {}})
        spec.attributes = dict(attributes)
        spec.children = dict(children)
        spec._sort_attributes()
        spec.rules = spec.needs_rules = ()
        spec.rule_names = frozenset()
        spec.checked_on_write = bool(spec.required)
        return spec

    def unmet(self, attributes: Mapping[str, object]) -> str | None:
        """What an element holding `attributes` (name -> value) lacks or breaks, in
        words: a required attribute, or a rule between attributes; None if nothing."""
        for name in self.required:
            if name not in attributes:
                return f"<{self.tag}> requires the attribute {name!r}"
        for rule in self.rules:
            if rule.broken_by(attributes):
                return rule.describe()
        return None

    def conflict(self, names: Iterable[str]) -> Rule | None:
        """The rule that allows only one of some of `names` to be set together (two
        orientations of a body, say), if they break one."""
        present = dict.fromkeys(names)
        for rule in self.rules:
            if rule.kind == "at_most_one" and rule.broken_by(present):
                return rule
        return None

    def child(self, tag: str) -> ElementSpec:
        """The spec of child `tag`; raises KeyError when MJCF has no such child here."""
        return self.children[tag]

    def __repr__(self) -> str:
        return f"ElementSpec(<{self.tag}> {self.key!r})"


def _load() -> tuple[ElementSpec, dict[str, ElementSpec]]:
    data = json.loads(DATA_FILE.read_text())
    if data.get("mujoco_version") != mujoco.__version__:
        warnings.warn(
            f"mjcf's schema was generated from MuJoCo {data.get('mujoco_version')}, but "
            f"MuJoCo {mujoco.__version__} is installed; regenerate it in a checkout of the "
            "repository with `python -m tools.mjcf_schema.generate`.",
            stacklevel=3,
        )
    specs = {key: ElementSpec(key, value) for key, value in data["elements"].items()}
    _refusals.apply(specs, Rule)
    for key, value in data["elements"].items():
        spec = specs[key]
        for child_key in value["children"]:
            child = specs[child_key]
            spec.children[child.tag] = child
    # A body's inertial and free joint are absent until added, as in dm_control (MuJoCo
    # refuses a second free joint of a body, as it refuses any other joint beside it).
    body = specs["body"]
    for tag in ("inertial", "freejoint"):
        absent = body.children[tag] = copy.copy(body.children[tag])
        absent.repeated, absent.on_demand = False, True
    # An element that appears once elsewhere may repeat under some parents.
    for key, value in data["elements"].items():
        for parent_key in value.get("repeated_in", ()):
            several = copy.copy(specs[key])
            several.repeated, several.on_demand = True, False
            specs[parent_key].children[several.tag] = several
    root = specs[data["root"]]
    # Repeated top-level sections are merged into one, as MuJoCo itself does. A section
    # spec may also be used deeper (a <default> in a <default>): that use stays repeated.
    for tag, section in list(root.children.items()):
        single = copy.copy(section)
        single.repeated = False
        root.children[tag] = single
    return root, specs


MUJOCO, _BY_KEY = _load()


def all_specs() -> list[ElementSpec]:
    """Every element spec of the schema."""
    return list(_BY_KEY.values())


ROOT_SECTIONS: tuple[str, ...] = tuple(MUJOCO.children)
NAMESPACES: frozenset[str] = frozenset(
    spec.namespace for spec in _BY_KEY.values() if spec.namespace is not None
)
