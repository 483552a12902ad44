"""Compiling a model tree into a `mujoco.MjModel`.

    compiled = compiler.compile_composition(model)
    compiled.model                      # mujoco.MjModel
    compiled.name_of(element)           # the name `element` has in compiled.model
    compiled.id_of(element, kind)       # its index there, named or not

The compiled model is the one stock MuJoCo compiles from `to_xml_string()` or an export,
names included. A model past `mjcf.budget` raises mjcf.BudgetError; a MuJoCo error becomes
an `mjcf.CompileError` naming its element (in debug mode, the Python line that made it).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, NamedTuple

import mujoco

from mjcf import errors
from mjcf.compose import attachment, keyframes, naming
from mjcf.io import serializer
from mjcf.sim import budget
from mjcf.tree.element import created_at
from mjcf.tree.namescope import unescape

if TYPE_CHECKING:
    from mjcf.compose.composition import Composition
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

_LINE = re.compile(r"line (\d+)")


class Compiled(NamedTuple):
    """A compiled model and how its elements are named in it."""

    model: mujoco.MjModel
    composition: Composition
    xml: str
    assets: dict[str, bytes]
    ids: dict[Element, int]  # the compiled index of each element with a generated name
    lines: list[Element | None]  # the element each line of `xml` writes (its start tag)

    def name_of(self, element: Element) -> str:
        """The name `element` has in the compiled model; raises mjcf.BindingError for
        an element that is not part of it."""
        composition = self.composition
        try:
            context = composition.context(element.root)
        except errors.InvalidReferenceError as error:
            raise errors.BindingError(f"{element.path}: {error}") from None
        if element.is_removed:
            raise errors.BindingError(f"{element.path}: the element was removed from its model")
        first = composition.shared.get(element)
        if first is not None:  # compiled as another model's asset (see mjcf.compose.sharing)
            return self.name_of(first)
        if isinstance(element, attachment.AttachmentFrame):
            return naming.frame_name(element, composition.context(element.root).prefix)
        if element.spec.tag == "worldbody":
            return naming.scoped_name(element, composition.root) or ""
        if isinstance(element.parent, attachment.AttachmentFrame) and element.identifier:
            return naming.scoped_name(element, composition.root) or ""
        name = element.identifier
        if name is None:
            index = self.ids.get(element)
            if index is None:
                if naming.is_replicated(element):
                    raise errors.BindingError(
                        f"{element.path}: is inside a <replicate>, so it compiles to several "
                        "objects; name it and bind them by their numbered names"
                    )
                raise errors.BindingError(f"{element.path}: was added after the model was compiled")
            return mujoco.mj_id2name(self.model, _KINDS[element.spec.namespace], index) or ""
        if element.spec.namespace == "default":
            return context.class_text(name)
        return context.prefix + unescape(name)

    def sharers(self, element: Element) -> list[Element]:
        """The elements compiled to the same mesh or texture as `element` (copies of one
        model share them, see `mjcf.compose.sharing`), itself first; [element] alone when it
        shares with none."""
        first = self.composition.shared.get(element, element)
        group = [first, *self.composition.copies_of(first)]
        return [element, *(e for e in group if e is not element)]

    def id_of(self, element: Element, kind: mujoco.mjtObj) -> int:
        """The index of `element` (an object of `kind`) in the compiled model, or -1;
        raises mjcf.BindingError like `name_of`."""
        name = self.name_of(element)
        element = self.composition.shared.get(element, element)
        index = self.ids.get(element)
        if index is not None:
            return index
        return mujoco.mj_name2id(self.model, kind, name)


def compile_composition(root: RootElement, share_assets: bool = True) -> Compiled:
    """Write `root` (with attached models) once and compile the text, with the assets
    passed in memory, the meshes and textures of copies once unless not `share_assets`
    (see `mjcf.compose.sharing`); the keyframes of attached models are then filled in.
    Raises mjcf.BudgetError past the budget, and mjcf.CompileError naming the offending
    element when MuJoCo rejects it."""
    xml, assets, composition, lines = serializer.serialize_for_compile(root, share_assets)
    name = f"model {root.model!r}" if root.model else "the model"
    budget.check(xml, assets, name, lambda line: _element_at(line, lines))
    try:
        model = mujoco.MjSpec.from_string(xml, assets=assets).compile()
    except ValueError as error:
        raise errors.CompileError(_explain(str(error), lines)) from None
    except RuntimeError as error:  # MuJoCo's "Caught an unknown exception!": out of memory
        raise errors.CompileError(unknown_failure(name, error)) from None
    ids = composition.compiled_ids  # the same for every compile of one composition
    if ids is None:
        ids = composition.compiled_ids = _generated_ids(model, composition)
    compiled = Compiled(model, composition, xml, assets, ids, lines)
    keyframes.fill(model, composition, compiled.id_of)
    return compiled


def _generated_ids(model: mujoco.MjModel, composition: Composition) -> dict[Element, int]:
    """{element: compiled index} of the objects written with generated names (found by
    element, as their names shift when elements are added before them)."""
    ids = {}
    for context in (composition.context(composition.root), *composition.attached_contexts()):
        for element in naming.unnamed_elements(context.model):
            if element in composition.shared:
                continue  # compiled as another model's (see mjcf.compose.sharing)
            kind = _KINDS.get(element.spec.namespace)
            name = naming.written_name(element, context.prefix)
            if kind is not None and name is not None:
                ids[element] = mujoco.mj_name2id(model, kind, name)
    return ids


def unnamed_pairs(old: Compiled | None, new: Compiled) -> dict[tuple[int, int], int]:
    """{(kind, index in `new`): index in `old`} of the joints, actuators and bodies with
    generated names compiled in both, so that state follows them from one to the other
    (their generated names can shift when elements are added before them)."""
    if old is None:
        return {}
    kinds: dict[str | None, int] = {  # by namespace, None for elements without one
        "joint": int(mujoco.mjtObj.mjOBJ_JOINT),
        "actuator": int(mujoco.mjtObj.mjOBJ_ACTUATOR),
        "body": int(mujoco.mjtObj.mjOBJ_BODY),
    }
    pairs = {}
    for element, index in new.ids.items():
        kind = kinds.get(element.spec.namespace)
        previous = old.ids.get(element)
        if kind is not None and previous is not None:
            pairs[(kind, index)] = previous
    return pairs


# Object kinds of the compiled model by namespace (a <frame> compiles to none).
# Looked up by an element's namespace, None for elements without one.
_KINDS: dict[str | None, mujoco.mjtObj] = {
    namespace: getattr(mujoco.mjtObj, f"mjOBJ_{namespace.upper()}")
    for namespace in (
        "body", "joint", "geom", "site", "camera", "light", "flex", "mesh", "skin", "hfield",
        "texture", "material", "pair", "exclude", "equality", "tendon", "actuator", "sensor",
        "numeric", "text", "tuple", "key", "plugin",
    )
}  # fmt: skip


def unknown_failure(name: str, error: RuntimeError) -> str:
    """The message of a CompileError for MuJoCo's RuntimeError `error` compiling `name`
    (what its bindings raise for an exception of no known kind, such as running out of
    memory)."""
    return (
        f"MuJoCo failed to compile {name}: {error} (most often memory ran out: see "
        "mjcf.budget for what a model may ask)"
    )


def _element_at(line: int, lines: list[Element | None]) -> str:
    """The element written on `line` of the compiled text, for a message."""
    element = lines[line - 1] if 0 < line <= len(lines) else None
    return f"line {line}" if element is None else element.path


def _explain(message: str, lines: list[Element | None]) -> str:
    """MuJoCo's message, plus the element its line number points at."""
    match = _LINE.search(message)
    if match is None:
        return message
    line = int(match.group(1))
    element = lines[line - 1] if 0 < line <= len(lines) else None
    if element is None:
        return message
    where = f"\n  in {element.path}"
    site = created_at(element)
    if site is not None:
        where += f" (created at {site})"
    return message.rstrip() + where
