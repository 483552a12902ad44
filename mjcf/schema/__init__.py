"""MuJoCo's MJCF schema as Python objects, loaded from data generated from the
installed mujoco's own XML reference (`python -m mjcf.schema.generate`).

    from mjcf import schema
    geom = schema.MUJOCO.child('worldbody').child('body').child('geom')
    geom.attributes['size']        # AttributeSpec(real, 1..3 numbers)
    geom.namespace                 # 'geom'

An `ElementSpec` says which attributes and children an element may have in one
place of the tree (a `<geom>` in a body differs from a `<geom>` in a default class);
an `AttributeSpec` says what values an attribute takes. Specs are immutable and
shared by every element of that kind.
"""

from __future__ import annotations

import copy
import json
import warnings
from collections.abc import Mapping
from pathlib import Path

import mujoco

from mjcf import values as _values

__all__ = ["MUJOCO", "NAMESPACES", "ROOT_SECTIONS", "AttributeSpec", "ElementSpec", "all_specs"]

_DATA_FILE = Path(__file__).with_name("mjcf_schema.json")


class AttributeSpec:
    """What one attribute of one element accepts: its `kind` ('identifier',
    'string', 'file', 'reference', 'keyword', 'int', 'real'), arity bounds for
    numbers, keywords, the namespace a reference points into, and MuJoCo's default."""

    __slots__ = (
        "converter",
        "default",
        "is_list",
        "kind",
        "max",
        "min",
        "multiple_of",
        "name",
        "namespace",
        "namespace_from",
        "namespace_map",
        "required",
        "scalar",
        "scoped",
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
        self.multiple_of: int | None = data.get("multiple_of")
        self.namespace: str | None = data.get("namespace")
        self.namespace_from: str | None = data.get("namespace_from")
        self.namespace_map: dict[str, str] = dict(data.get("namespace_map", {}))
        self.is_list: bool = bool(data.get("list", False))
        # Numbers with exactly one value read back as Python scalars, others as arrays.
        self.scalar: bool = self.kind in ("int", "real") and self.min == 1 and self.max == 1
        # Names that take the model's name-scope prefix when models are composed.
        self.scoped: bool = self.kind in ("identifier", "reference")
        self.converter = _values.converter_for(self)

    def arity_text(self) -> str:
        """Human-readable count of numbers this attribute takes ('1 to 3 numbers')."""
        if self.max is None:
            base = f"{self.min} or more numbers" if self.min else "any number of numbers"
            return base + (f", a multiple of {self.multiple_of}" if self.multiple_of else "")
        if self.min == self.max:
            return f"{self.min} number" + ("" if self.min == 1 else "s")
        return f"{self.min} to {self.max} numbers"

    def reference_namespace(self, element_attributes: Mapping[str, object]) -> str | None:
        """The namespace this reference points into, given the attributes of its element
        (for references whose namespace another attribute selects, e.g. objtype)."""
        if self.namespace_from is None:
            return self.namespace
        selector = element_attributes.get(self.namespace_from)
        if not isinstance(selector, str):
            return None
        return self.namespace_map.get(selector, selector)

    def __repr__(self) -> str:
        detail = self.kind
        if self.kind in ("int", "real"):
            detail += f", {self.arity_text()}"
        elif self.kind == "keyword":
            detail += f" {list(self.values)}"
        elif self.kind == "reference":
            detail += f" -> {self.namespace or 'namespace from ' + str(self.namespace_from)}"
        return f"AttributeSpec({self.name!r}: {detail})"


class ElementSpec:
    """What one element accepts in one place of the tree: attributes, child elements
    by tag, whether it may repeat under its parent, and the namespace of its name."""

    __slots__ = (
        "attributes",
        "children",
        "file_attributes",
        "identifier",
        "key",
        "namespace",
        "on_demand",
        "references",
        "repeated",
        "required",
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
        identifiers = [a.name for a in self.attributes.values() if a.kind == "identifier"]
        self.identifier: str | None = identifiers[0] if identifiers else None
        self.scoped_attributes = frozenset(a.name for a in self.attributes.values() if a.scoped)
        self.references = frozenset(
            a.name for a in self.attributes.values() if a.kind == "reference"
        )
        self.required = tuple(a.name for a in self.attributes.values() if a.required)
        self.file_attributes = frozenset(
            a.name for a in self.attributes.values() if a.kind == "file"
        )
        # A child that may appear once is created on first access (`option.flag`).
        self.on_demand = False

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
        identifiers = [a.name for a in spec.attributes.values() if a.kind == "identifier"]
        spec.identifier = identifiers[0] if identifiers else None
        spec.scoped_attributes = frozenset(a.name for a in spec.attributes.values() if a.scoped)
        spec.references = frozenset(
            a.name for a in spec.attributes.values() if a.kind == "reference"
        )
        spec.required = tuple(a.name for a in spec.attributes.values() if a.required)
        spec.file_attributes = frozenset(
            a.name for a in spec.attributes.values() if a.kind == "file"
        )
        return spec

    def child(self, tag: str) -> ElementSpec:
        """The spec of child `tag`; raises KeyError when MJCF has no such child here."""
        return self.children[tag]

    def __repr__(self) -> str:
        return f"ElementSpec(<{self.tag}> {self.key!r})"


def _load() -> tuple[ElementSpec, dict[str, ElementSpec]]:
    data = json.loads(_DATA_FILE.read_text())
    if data.get("mujoco_version") != mujoco.__version__:
        warnings.warn(
            f"mjcf's schema was generated from MuJoCo {data.get('mujoco_version')}, but "
            f"MuJoCo {mujoco.__version__} is installed; regenerate it with "
            "`python -m mjcf.schema.generate`.",
            stacklevel=3,
        )
    specs = {key: ElementSpec(key, value) for key, value in data["elements"].items()}
    for key, value in data["elements"].items():
        spec = specs[key]
        for child_key in value["children"]:
            child = specs[child_key]
            spec.children[child.tag] = child
    for spec in specs.values():
        for child in spec.children.values():
            child.on_demand = not child.repeated
    root = specs[data["root"]]
    # Repeated top-level sections are merged into one, as MuJoCo itself does. A section
    # spec may also be used deeper (a <default> in a <default>): that use stays repeated.
    for tag, section in list(root.children.items()):
        single = copy.copy(section)
        single.repeated = False
        single.on_demand = True
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
