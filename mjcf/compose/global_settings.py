"""Global settings of composed models: how the `<option>`, `<size>`, `<visual>`,
`<statistic>` and `<compiler>` of an attached model join those of the model it goes into.

    arena.option.timestep = 0.002; robot.option.timestep = 0.005
    arena.attach(robot)             # arena.option.timestep: 0.002, the smaller step
    robot.option.timestep           # 0.002 too: the composed model's, shared
    robot.compiler.boundmass = 0    # after the attach: the composed model's boundmass

Merged when attached (`SettingsMerge`: every conflict named in one mjcf.AttachmentError,
nothing changed), then shared with the outermost model, as in dm_control (`share`).
"""

from __future__ import annotations

from collections.abc import Iterator, MutableMapping
from typing import TYPE_CHECKING, Any

import numpy as np

from mjcf import errors, schema
from mjcf.compose.settings import OWN_COMPILER_SETTINGS, capacity, same
from mjcf.schema.tracked_array import track
from mjcf.tree import builder
from mjcf.tree.element import (
    Element,
    count_change,
    stored_attributes,
    tree_children,
    value_of,
)
from mjcf.tree.element_list import attached_models
from mjcf.tree.root import section_of

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec, ElementSpec
    from mjcf.tree.root import RootElement

SECTIONS = ("compiler", "option", "size", "statistic", "visual")
MIN, MAX, OR = "min", "max", "or"

# How two models' values of a setting merge where MuJoCo's documentation gives no rule:
# dm_control's (its schema marks `njmax` and `nconmax` "max"), and `nstack`, a capacity
# too, whose largest value serves both models (dm_control requires it to agree).
UNDOCUMENTED_RULES: dict[tuple[str, str], str] = {
    ("size", "njmax"): MAX,
    ("size", "nconmax"): MAX,
    ("size", "nstack"): MAX,
}


def rule_of(path: str, attribute: AttributeSpec) -> str | None:
    """How two models' values of `attribute` of the settings element at `path`
    ('visual.map') merge: 'min', 'max' (`<size memory>` in bytes) or 'or' (flags, and
    groups of actuators disabled); None if they must agree. MuJoCo's documentation gives
    it (its merging table, `compiler conflict="merge"`: see `mjcf.schema`), which agrees
    with dm_control's schema wherever both have a rule; `UNDOCUMENTED_RULES` the others."""
    return attribute.merge or UNDOCUMENTED_RULES.get((path, attribute.name))


class CompilerAttributes(MutableMapping[str, Any]):
    """The attribute storage of an attached model's `<compiler>`: the settings the model
    keeps for itself (`OWN_COMPILER_SETTINGS`: its angle units, euler sequence, inertia
    and limit rules, total mass, file folders, and settings of the output only) in `own`,
    the others in `shared`, the outermost model's storage. `mjcf.compose.settings` and
    `mjcf.compose.composition` reconcile the own settings per model when writing.
    dm_control lets `meshdir`, `texturedir` and `assetdir` differ and keeps the parent's;
    here each model keeps its own, since its files are found from it."""

    __slots__ = ("own", "shared")

    def __init__(self, own: dict[str, Any], shared: dict[str, Any]) -> None:
        self.own = own
        self.shared = shared

    def _holder(self, name: str) -> dict[str, Any]:
        return self.own if name in OWN_COMPILER_SETTINGS else self.shared

    def __getitem__(self, name: str) -> Any:
        return self._holder(name)[name]

    def get(self, name: str, default: Any = None) -> Any:
        return self._holder(name).get(name, default)

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and name in self._holder(name)

    def __setitem__(self, name: str, value: Any) -> None:
        self._holder(name)[name] = value

    def __delitem__(self, name: str) -> None:
        del self._holder(name)[name]

    def __iter__(self) -> Iterator[str]:
        yield from self.own
        for name in self.shared:
            if name not in OWN_COMPILER_SETTINGS:
                yield name

    def __len__(self) -> int:
        return len(self.own) + sum(1 for name in self.shared if name not in OWN_COMPILER_SETTINGS)


class SharedSettings(Element):
    """A settings element of an attached model, holding the storage of the outermost
    model's element at its place.

    Each settings element of an attached model (the five sections and their once-only
    children, all made when the model is attached) is one, and counts a change as one of
    the outermost model too and keeps no written text (see `mjcf.io.serializer`); its
    `<compiler>` storage is a `CompilerAttributes`, which keeps the model's own settings
    apart. Attaching, detaching, copying and emptying a section keep this true for every
    model of a composed tree."""

    __slots__ = ()

    # Its written text is never kept: the storage changes with the outermost model, whose
    # changes do not count as this model's (the writer's cache is per model).
    @property
    def _text(self) -> None:
        return None

    @_text.setter
    def _text(self, value: object) -> None:
        pass

    def _modified(self) -> None:
        """Count a change of this model and of the outermost model, which share it."""
        super()._modified()
        top = self._root.root_model
        if top is not self._root:
            count_change(top)


# (path, tag) of the once-only children of each settings section: ('visual.map', 'map').
_ONCE_ONLY = {
    tag: tuple(
        (f"{tag}.{child}", child)
        for child, spec in schema.MUJOCO.child(tag).children.items()
        if not spec.repeated
    )
    for tag in SECTIONS
}


def settings_elements(model: RootElement, make: bool = True) -> Iterator[tuple[str, Element]]:
    """(path, element) of each settings element of `model`: its five sections and their
    once-only children ('visual.map'), those absent made if `make`, else left out."""
    sections = {section.spec.tag: section for section in tree_children(model)}
    for tag in SECTIONS:
        section = sections[tag]
        yield tag, section
        once_only = _ONCE_ONLY[tag]
        if not once_only:
            continue
        present = {child.spec.tag: child for child in tree_children(section)}
        for path, child_tag in once_only:
            child = present.get(child_tag)
            if child is None and make:
                child = section.get_children(child_tag)
            if child is not None:
                yield path, child


class SettingsMerge:
    """What attaching models changes in the settings of the outermost model `top`:
    planned and checked by `add` before anything changes, made by `apply`.

    Each setting an attached model gives is merged into the outermost model it goes into
    (`RootElement.root_model`) by `rule_of`: dm_control's rules, which MuJoCo's documented
    merging table agrees with and extends (a timestep and tolerances take the smaller
    value, iteration counts and capacities the larger, `<size memory>` the larger in bytes;
    where only MuJoCo has a rule, a flag takes the value that is not its default); a
    setting only one model gives is the composed model's; any other setting the two give
    differently is a conflict, and every conflict (with a `<size>` that would set two of
    memory / njmax / nstack, an `<compiler inertiafromgeom>` that cannot be reconciled
    ...) is named in one mjcf.AttachmentError (`raise_problems`), nothing changed."""

    def __init__(self, top: RootElement) -> None:
        self.top = top
        self.problems: list[str] = []
        self.conflicting: list[str] = []  # names of the conflicting attributes
        # path -> {attribute: (stored value, model it comes from)}
        self._changes: dict[str, dict[str, tuple[Any, RootElement]]] = {}
        self._tops = {path: element for path, element in settings_elements(top, make=False)}

    def add(self, model: RootElement) -> None:
        """Plan merging the shared settings of `model` (attached models' included: they
        share its) into `top`'s, recording each conflict in `problems`."""
        for path, theirs in settings_elements(model, make=False):
            mine = self._tops.get(path)
            changes = self._changes.setdefault(path, {})
            for name in list(stored_attributes(theirs)):
                if path == "compiler" and name in OWN_COMPILER_SETTINGS:
                    continue
                attribute = theirs.spec.attributes[name]
                their_value = value_of(theirs, attribute)
                if their_value is None:  # blank text: not set, for MuJoCo
                    continue
                planned = changes.get(name)
                source = planned[1] if planned else self.top
                my_value = self._value(mine, attribute, planned)
                stored = stored_attributes(theirs)[name]
                if my_value is None:
                    changes[name] = (stored, model)
                    continue
                rule = rule_of(path, attribute)
                if rule is None:
                    if not same(attribute, my_value, their_value):
                        self._conflict(path, attribute, my_value, source, their_value, model)
                    continue
                merged = _merge(rule, attribute, my_value, their_value)
                if merged is their_value:
                    changes[name] = (stored, model)
                elif merged is not my_value:  # memory in bytes, or groups of both models
                    changes[name] = (merged, model)
            if not changes:
                del self._changes[path]
                continue
            self._check_rules(path, mine, changes)

    def _value(self, mine: Element | None, attribute: AttributeSpec, planned: tuple | None) -> Any:
        """The value `top` has for `attribute` once the changes planned so far are made."""
        if planned is not None:
            stored = planned[0]
            if type(stored) is str:
                return attribute.converter.from_text(stored)
            return stored
        return None if mine is None else value_of(mine, attribute)

    def _conflict(
        self,
        path: str,
        attribute: AttributeSpec,
        mine: Any,
        mine_from: RootElement,
        theirs: Any,
        theirs_from: RootElement,
    ) -> None:
        to_text = attribute.converter.to_text
        self.conflicting.append(attribute.name)
        self.problems.append(
            f"{_path_text(path)} {attribute.name}: {to_text(mine)!r} in model "
            f"{mine_from.model!r}, {to_text(theirs)!r} in model {theirs_from.model!r}"
        )

    def _check_rules(self, path: str, mine: Element | None, changes: dict) -> None:
        """Record a problem if the merged element would set two attributes MuJoCo allows
        one of (`<size memory>` with `njmax` or `nstack`)."""
        names = set(changes) | (set(stored_attributes(mine)) if mine is not None else set())
        spec = mine.spec if mine is not None else _spec_at(self.top, path)
        rule = spec.conflict(names)
        if rule is not None:
            given = ", ".join(
                f"{name} (model {changes[name][1].model!r})" if name in changes
                else f"{name} (model {self.top.model!r})"
                for name in sorted(rule.names & names)
            )  # fmt: skip
            self.problems.append(f"{_path_text(path)}: {given}: {rule.describe()}")

    def raise_problems(self, child: RootElement, parent: RootElement) -> None:
        """Raise the mjcf.AttachmentError naming every problem found, if any."""
        problems = list(dict.fromkeys(self.problems))
        if not problems:
            return
        head = ""
        if self.conflicting:
            conflicting = list(dict.fromkeys(self.conflicting))
            names = ", ".join(f"`{name}`" for name in conflicting)
            head = f"Conflicting values for attribute{'s' * (len(conflicting) > 1)} {names}: "
        if len(problems) == 1:
            detail = problems[0]
        else:
            detail = "".join(f"\n  {problem}" for problem in problems)
        raise errors.AttachmentError(
            f"{head}model {child.model!r} cannot be attached to model {parent.model!r}: a "
            "composed model has one value of each global setting (set the same value on "
            "both models, or on one of them only): " + detail
        )

    def apply(self) -> None:
        """Write the planned values into `top`'s settings."""
        if not self._changes:
            return
        elements = dict(settings_elements(self.top))
        for path, changes in self._changes.items():
            element = elements[path]
            for name, (stored, _) in changes.items():
                builder.attributes_to_fill(element)[name] = copied(stored, element)
            count_change(element)


def _merge(rule: str, attribute: AttributeSpec, mine: Any, theirs: Any) -> Any:
    """The composed value of two given values under `rule`: one of them, or a new value
    for `<size memory>` (the larger in bytes, as text in bytes, as dm_control writes it)
    and for groups of actuators disabled (those of both models)."""
    if rule == OR:
        if attribute.kind == "keyword":  # a flag: MuJoCo ORs the flag bits
            return theirs if mine == attribute.default != theirs else mine
        groups = sorted(set(np.atleast_1d(mine).tolist()) | set(np.atleast_1d(theirs).tolist()))
        if groups == sorted(np.atleast_1d(mine).tolist()):
            return mine
        return attribute.converter.from_python(groups)
    if attribute.name == "memory":
        mine_bytes, their_bytes = capacity("memory", mine), capacity("memory", theirs)
        if mine_bytes is None or their_bytes is None:  # never, once validated
            return mine
        larger = str(max(mine_bytes, their_bytes))
        return mine if larger == mine else theirs if larger == theirs else larger
    if rule == MIN:
        return theirs if theirs < mine else mine
    return theirs if theirs > mine else mine


def _path_text(path: str) -> str:
    return "/".join(f"<{tag}>" for tag in path.split("."))


def _spec_at(model: RootElement, path: str) -> ElementSpec:
    """The schema of the settings element at `path` ('visual.map') of `model`."""
    spec = section_of(model, path.split(".")[0]).spec
    for tag in path.split(".")[1:]:
        spec = spec.children[tag]
    return spec


def copied(value: Any, owner: Element) -> Any:
    """A stored value for `owner` to hold: text as it is, arrays and lists copied."""
    if type(value) is str:
        return value
    if isinstance(value, np.ndarray):
        return track(np.array(value), owner)
    if isinstance(value, list):
        return list(value)
    return value


# -- sharing ------------------------------------------------------------------------------


def share(model: RootElement) -> None:
    """Make `model` (attached) and the models attached inside it share the settings of
    the outermost model (merged into it already: see `SettingsMerge`), as dm_control's
    attached elements alias their parent's attributes: reading `robot.option.timestep`
    gives the composed value, and a value written on either model afterwards
    (`robot.compiler.boundmass = 0`, `robot.visual.headlight.ambient = ...` every episode)
    is the composed model's, replacing what the merge gave."""
    top = model.root_model
    targets = dict(settings_elements(top))
    for each in (model, *attached_models(model)):
        for path, element in settings_elements(each):
            _alias(path, element, targets[path])


def unshare(model: RootElement, top: RootElement | None = None) -> None:
    """Give `model`, attached nowhere now (detached from the outermost model `top`, or a
    copy of an attached model), settings of its own: a copy of the values it shared, as
    in dm_control (the model it leaves keeps them too); the models attached inside it
    share its settings from then on."""
    targets = dict(settings_elements(top, make=False)) if top is not None else {}
    for path, element in settings_elements(model, make=False):
        if path in targets and type(element) is SharedSettings:
            _reown(targets[path])
        _own(element)
    for attached in attached_models(model):
        if attached.parent_model is model:
            share(attached)


def _reown(target: Element) -> None:
    """Arrays in `target`'s storage, which models leaving it may have put there, edited
    in place count as changes of `target`'s model (see `mjcf.schema.tracked_array.track`)."""
    attrs = builder.attributes_to_fill(target)
    for name, value in attrs.items():
        if isinstance(value, np.ndarray):
            attrs[name] = track(value, target)


def _alias(path: str, element: Element, target: Element) -> None:
    attrs = builder.attributes_to_fill(element)
    storage = builder.attributes_to_fill(target)
    if path == "compiler":
        own = attrs.own if isinstance(attrs, CompilerAttributes) else {
            name: value for name, value in attrs.items() if name in OWN_COMPILER_SETTINGS
        }  # fmt: skip
        builder.replace_attributes(element, CompilerAttributes(own, storage))
    else:
        builder.replace_attributes(element, storage)
    builder.change_class(element, SharedSettings)


def _own(element: Element) -> None:
    """Give `element` storage of its own: a copy of what it holds."""
    if type(element) is not SharedSettings:
        return
    attrs = {
        name: copied(value, element) for name, value in builder.attributes_to_fill(element).items()
    }
    builder.change_class(element, Element)
    builder.replace_attributes(element, attrs)
