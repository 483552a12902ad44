"""How attached models are composed into one MJCF document: each keeps its own tree, and only
what is written is composed, every model as its `ModelContext` says.

    composition = composition_of(scene)        # the last one, while no model changed
    composition.context(arm).prefix            # 'arm/': arm's names, scoped in scene's

The document compiles each model's elements as that model alone would: names scoped, default
classes kept apart, the output model's settings but for those each model keeps, unnamed
elements named by `mjcf.compose.naming`, an asset that compiles like an earlier one written
once (`mjcf.compose.sharing`). Raises mjcf.AttachmentError for settings it cannot reconcile.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, cast

import mujoco
import numpy as np

from mjcf import errors
from mjcf.compose import attachment, defaults, keyframes, naming, settings, sharing
from mjcf.schema.values import format_number
from mjcf.tree.element import stored_attributes, tree_children, value_of
from mjcf.tree.element_list import attached_models
from mjcf.tree.namescope import NAMED_AFTER_FILE, PREFIX_SEPARATOR, WORLD
from mjcf.tree.namescope import unescape as _unescape
from mjcf.tree.root import compositions_of, own_version, section_of, set_compositions

if TYPE_CHECKING:
    from mjcf.io.file_names import FileNamer
    from mjcf.schema import AttributeSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

_ANGLE_JOINT_ATTRIBUTES = ("range", "ref", "springref")
_ANGLE_JOINT_TYPES = frozenset({"hinge", "ball"})
MAIN = "main"
_DEFAULT_DENSITY = 1000.0


class ModelContext:
    """How one model's elements are written in one output document:

    - names are scoped by the model's prefix relative to the output model ('arm/');
    - default classes stay isolated: an attached model's global defaults become a class
      named after its scope ('arm/'), set as `childclass` on its attachment frame and as
      `class` on its elements outside the world body; if the output model itself has
      global defaults and attachments, they move to a class '/' the same way, so that no
      model's defaults leak into another's;
    - global settings are the output model's, which the models attached into it share
      (merged when each was attached: see `mjcf.compose.global_settings`), but for the
      compiler settings each model keeps, as in MuJoCo's own attachment (see
      `mjcf.compose.settings`): `angle` (euler, axisangle, and the range/ref/springref of
      hinge and ball joints, attachment frames included) and `eulerseq` (euler becomes quat)
      are converted element by element to the output model's, and an attached model's
      `settotalmass` becomes its own densities, masses and inertias scaled (the models
      attached inside it keep theirs);
    - unnamed elements are written with the names `mjcf.compose.naming` gives them
      ('child//unnamed_geom_0'), in every output, so the compiled names are the written
      ones;
    - a mesh or texture that compiles exactly like one of a model written before is
      written once, references to it naming the first (see `mjcf.compose.sharing`)."""

    __slots__ = (
        "angle_scale",
        "composition",
        "euler_seq",
        "inject_class",
        "is_output",
        "main_class_written",
        "main_reference",
        "mass_scale",
        "model",
        "names_only",
        "plain",
        "prefix",
        "shared_names",
        "signature",
        "token",
    )

    def __init__(self, composition: Composition, model: RootElement, prefix: str) -> None:
        self.composition = composition
        self.model = model
        self.prefix = prefix
        self.is_output = model is composition.root
        self.main_class_written: str | None = None
        self.main_reference = MAIN
        self.inject_class = False
        self.angle_scale: float | None = None
        self.euler_seq: str | None = None
        self.mass_scale: float | None = None
        self.plain = True
        # (namespace, name) -> written name, for this model's assets written as another
        # model's (see mjcf.compose.sharing).
        self.shared_names: dict[tuple[str | None, str], str] = {}
        # Stands for everything above: equal in two outputs that write this model's
        # elements alike (see `seal`), so text written for one serves the other.
        self.token = object()
        self.signature: tuple = ()

    def finish(self) -> None:
        """Decide whether names and values can be written as stored."""
        self.plain = (
            not self.prefix
            and self.main_reference == MAIN
            and not self.model.namescope.has_escaped_names
        )
        # Whether stored values are written as they are, only names being added.
        self.names_only = (
            self.plain
            and not self.inject_class
            and self.angle_scale is None
            and self.euler_seq is None
            and self.mass_scale is None
        )

    def seal(
        self, shared: tuple[tuple[Element, str | None], ...], previous: ModelContext | None
    ) -> None:
        """Take the token of `previous` (this model's context in an earlier output) if
        it writes the model's elements as this one does; `shared`: (asset, written
        name) of the model's assets written as another model's."""
        self.signature = (
            self.prefix, self.main_class_written, self.main_reference, self.inject_class,
            self.angle_scale, self.euler_seq, self.mass_scale, self.plain, shared,
        )  # fmt: skip
        if previous is not None and previous.signature == self.signature:
            self.token = previous.token

    # -- names ---------------------------------------------------------------------------

    def class_text(self, name: str) -> str:
        if name == MAIN:
            return self.main_reference
        return self.prefix + _unescape(name)

    def identifier_text(self, element: Element, value: str) -> str:
        if element.spec.namespace == "default":
            return self.class_text(value)
        return self.prefix + _unescape(value)

    def reference_text(self, attribute: AttributeSpec, value: str) -> str:
        if attribute.namespace == "default":
            return self.class_text(value)
        if value == WORLD and attribute.namespace in ("body", None):
            return value  # the world body is shared, never scoped
        if self.shared_names:
            shared = self.shared_names.get((attribute.namespace, value))
            if shared is not None:
                return shared
        return self.prefix + _unescape(value)

    # -- per-element changes --------------------------------------------------------------

    def rewrite(self, element: Element) -> dict[str, str | None] | None:
        """Attributes this output writes differently from what the element stores
        (None values are left out), or None when it writes them as stored."""
        composition = self.composition
        override: dict[str, str | None] | None = None
        spec = element.spec
        if spec.identifier is not None and spec.identifier not in stored_attributes(element):
            name = composition.generated_name(element, self)
            if name is not None:
                override = {spec.identifier: name}
        if self.inject_class:
            parent = element.parent
            if parent is not None and parent.parent is self.model:
                attribute = self._class_attribute(element, parent.spec.tag)
                if attribute is not None:
                    override = override or {}
                    override[attribute] = self.main_reference
        if self.angle_scale is not None or self.euler_seq is not None:
            converted = self._convert_angles(element)
            if converted:
                override = override or {}
                override.update(converted)
        if self.mass_scale is not None:
            scaled = self._scale_mass(element)
            if scaled:
                override = override or {}
                override.update(scaled)
        return override

    def _class_attribute(self, element: Element, section: str) -> str | None:
        attributes = element.spec.attributes
        attrs = stored_attributes(element)
        if section == "default":
            return None
        if section == "worldbody":
            if not self.is_output:
                return None
            if (
                "childclass" in attributes
                and "childclass" not in attrs
                and "class" not in attributes
            ):
                return "childclass"
        if "class" in attributes and "class" not in attrs:
            return "class"
        return None

    def _convert_angles(self, element: Element) -> dict[str, str | None]:
        out: dict[str, str | None] = {}
        attrs = stored_attributes(element)
        scale = self.angle_scale or 1.0
        if "euler" in attrs:
            euler = _numbers(element, "euler")
            if self.euler_seq is not None:
                if "quat" not in element.spec.attributes:
                    raise errors.AttachmentError(
                        f"{element.path}: its euler angles are in sequence {self.euler_seq!r}, "
                        "unlike the model it is attached to, and a "
                        f"<{element.tag}> has no quat to convert them to; set the same "
                        "<compiler eulerseq> on both models"
                    )
                radians = (
                    math.pi / 180 if settings.setting(self.model, "angle") == "degree" else 1.0
                )
                out["euler"] = None
                out["quat"] = _text(euler_to_quat(euler * radians, self.euler_seq))
            else:
                out["euler"] = _text(euler * scale)
        if self.angle_scale is None:
            return out
        if "axisangle" in attrs:
            axisangle = _numbers(element, "axisangle").copy()
            axisangle[3] *= scale
            out["axisangle"] = _text(axisangle)
        if element.spec.tag == "joint" and element.spec.namespace == "joint":
            joint_type = defaults.effective_value(element, "type") or "hinge"
            if joint_type in _ANGLE_JOINT_TYPES:
                for name in _ANGLE_JOINT_ATTRIBUTES:
                    value = defaults.effective_value(element, name)
                    if value is not None:
                        out[name] = _text(np.atleast_1d(np.asarray(value, dtype=float)) * scale)
        return out

    def _scale_mass(self, element: Element) -> dict[str, str | None]:
        """Masses and inertias of `element` scaled as the model's settotalmass would."""
        spec = element.spec
        scale = self.mass_scale
        out: dict[str, str | None] = {}
        if spec.namespace == "geom" and _in_body(element):
            mass = defaults.effective_value(element, "mass")
            if mass is not None:
                out["mass"] = _text(np.atleast_1d(mass) * scale)
            else:
                density = defaults.effective_value(element, "density")
                density = _DEFAULT_DENSITY if density is None else density
                out["density"] = _text(np.atleast_1d(density) * scale)
        elif spec.tag == "inertial" and _in_body(element):
            for name in ("mass", "diaginertia", "fullinertia"):
                if name in stored_attributes(element):
                    out[name] = _text(_numbers(element, name) * scale)
        return out


def composition_of(
    root: RootElement, for_compile: bool = False, share_assets: bool = True
) -> Composition:
    """The composition of an output of `root` (with its attached models): the one made
    for the last output of the same kind while no model changed, else a new one. Copies'
    meshes and textures are written once unless not `share_assets` (`mjcf.compose.sharing`)."""
    models = [root, *attached_models(root)]
    versions = [(model, own_version(model)) for model in models]
    top = root.root_model
    if top is not root:  # an attached model written alone: it writes the settings it shares
        versions.append((top, own_version(top)))
    cached = compositions_of(root)
    kind = (for_compile, share_assets)
    found = cached.get(kind) if cached else None
    if found is not None and found.versions == versions:
        return found
    previous = found or (next(iter(cached.values())) if cached else None)
    composition = Composition(root, for_compile, models, previous, share_assets)
    composition.versions = versions
    set_compositions(root, {**(cached or {}), kind: composition})
    return composition


class Composition:
    """The models composed into one output document, and how each is written.

    Made by `composition_of`, which keeps the last one made for each kind of output of a
    model on it (`RootElement._composed`) and gives it again while no model changes:
    what a composition computes (settings checked and merged, shared assets, keys) is
    then computed once for all the outputs of an unchanged model."""

    def __init__(
        self,
        root: RootElement,
        for_compile: bool = False,
        models: list[RootElement] | None = None,
        previous: Composition | None = None,
        share_assets: bool = True,
    ) -> None:
        self.root = root
        # Compiling writes the file names of meshes and textures named after their file
        # with their names, as the assets are renamed.
        self.for_compile = for_compile
        self.versions: list[tuple[RootElement, int]] = []
        # {element: compiled index} of those written with generated names, which every
        # compile of this composition gives alike: set by mjcf.sim.compiler.
        self.compiled_ids: dict[Element, int] | None = None
        # (XML, assets, element of each line) of the output compiled, which is the same
        # for every compile of this composition: set by mjcf.io.serializer.
        self.compiled_text: tuple[str, dict[str, bytes], list] | None = None
        # The names of the files of this composition's output (to_xml_string,
        # get_assets), which every such output gives alike: set by mjcf.io.serializer.
        self.file_names: FileNamer | None = None
        self._inertia: str | None = None
        self._checked = False
        self._merged: dict[str, settings.MergedSettings] = {}
        self._keys: list | None = None
        self._written_assets: dict[ModelContext, list[Element]] = {}
        self._models = models if models is not None else [root, *attached_models(root)]
        self.has_attachments = len(self._models) > 1
        self._contexts: dict[RootElement, ModelContext] = {}
        moved = len(self._models) > 1 and _has_global_defaults(root)
        root_angle = settings.setting(root, "angle")
        root_seq = settings.setting(root, "eulerseq")
        for model in self._models:
            context = ModelContext(self, model, model.namescope.prefix(root.namescope))
            if model is root:
                if moved:
                    context.main_class_written = context.main_reference = PREFIX_SEPARATOR
                    context.inject_class = True
            else:
                context.main_class_written = context.main_reference = context.prefix
                context.inject_class = True
                angle = settings.setting(model, "angle")
                if angle != root_angle:
                    context.angle_scale = math.pi / 180 if angle == "degree" else 180 / math.pi
                seq = settings.setting(model, "eulerseq")
                if seq != root_seq:
                    context.euler_seq = seq
            late = defaults.late_sections(model)
            if late and context.main_class_written is not None:  # see mjcf.io.serializer
                context.main_reference = defaults.late_class_name(context.main_class_written, late)
            self._contexts[model] = context
        if self.has_attachments:
            self._scale_masses()
        for context in self._contexts.values():
            context.finish()
        # Assets of attached models written as an earlier model's (see mjcf.compose.sharing).
        self.shared = (
            sharing.shared_assets(self._models) if self.has_attachments and share_assets else {}
        )
        self._copies: dict[Element, list[Element]] | None = None
        shared: dict[RootElement, list[tuple[Element, str | None]]] = {}
        for element, first in self.shared.items():
            written = self._written_name(first)
            shared.setdefault(element.root, []).append((element, written))
            name = element.identifier
            if name is not None and written is not None:
                context = self._contexts[element.root]
                context.shared_names[(element.spec.namespace, name)] = written
        before = previous._contexts if previous is not None else {}
        for model, context in self._contexts.items():
            context.seal(tuple(shared.get(model, ())), before.get(model))

    def _scale_masses(self) -> None:
        """Give each attached model with a settotalmass the scale it applies to its own
        bodies alone; the models attached inside it keep their masses (`mjcf.settings`)."""
        for model in self._models[1:]:
            total = settings.setting(model, "settotalmass")
            if total is None or total <= 0:
                continue
            self._contexts[model].mass_scale = float(total) / settings.unscaled_mass(model)

    def check(self) -> None:
        """Raise mjcf.AttachmentError if the compiler settings each model keeps cannot be
        reconciled (see `mjcf.compose.settings`)."""
        if self._checked:
            return
        if self.has_attachments:
            problems = settings.compiler_problems(
                self.root, self._models[1], inertia=False, output=True
            )
            if problems:
                raise errors.AttachmentError(
                    f"model {self.root.model!r} cannot be written with the models attached "
                    f"to it: {problems[0]}"
                )
            self.inertia_setting()
        self._checked = True

    def inertia_setting(self) -> str:
        """The `inertiafromgeom` of the output (see `mjcf.compose.settings.inertia_setting`)."""
        if self._inertia is None:
            self._inertia = settings.inertia_setting(self._models)
        return self._inertia

    def context(self, model: RootElement) -> ModelContext:
        """The context of `model`; raises mjcf.InvalidReferenceError for a model that is not
        part of this output."""
        context = self._contexts.get(model)
        if context is None:
            raise errors.InvalidReferenceError(
                f"model {model.model!r} is not attached inside model {self.root.model!r}"
            )
        return context

    def attached_contexts(self) -> list[ModelContext]:
        """Contexts of the attached models, in the order they are written."""
        return [self._contexts[m] for m in self._models[1:]]

    def default_roots(self) -> list[tuple[ModelContext, Element]]:
        """(context, global default element) of each model, in writing order."""
        return [(self._contexts[m], m.default) for m in self._models]

    # -- settings -------------------------------------------------------------------------

    def merged_settings(self, tag: str) -> settings.MergedSettings:
        """One settings section as this output writes it (see
        `mjcf.compose.settings.merged`); raises mjcf.AttachmentError when the models'
        inertia settings cannot be reconciled."""
        merged = self._merged.get(tag)
        if merged is None:
            inertia = self.inertia_setting() if tag == "compiler" and self.has_attachments else None
            merged = self._merged[tag] = settings.merged(self._models, tag, inertia)
        return merged

    def keyframes(self) -> list[tuple[Element, ModelContext, dict | None]]:
        """The keys to write: the output model's, and those of attached models."""
        if self._keys is None:
            self._keys = keyframes.keys_to_write(self, self.for_compile)
        return self._keys

    # -- references and names --------------------------------------------------------------

    def element_reference_text(
        self, element: Element, attribute: AttributeSpec, target: Element
    ) -> str:
        """The written name of a referenced element object."""
        if target.is_removed:
            raise errors.InvalidReferenceError(
                f"{element.path}: {attribute.name!r} refers to a removed element: {target.path}"
            )
        context = self._contexts.get(target.root)
        if context is None:
            raise errors.InvalidReferenceError(
                f"{element.path}: {attribute.name!r} refers to {target.path} in model "
                f"{target.root.model!r}, which is not attached inside model {self.root.model!r}"
            )
        if isinstance(target, attachment.AttachmentFrame):
            return naming.frame_name(target, context.prefix)
        if target.spec.tag == "worldbody":
            return WORLD
        written = self._written_name(self.shared.get(target, target))
        if written is None:
            raise errors.InvalidReferenceError(
                f"{element.path}: {attribute.name!r} refers to {target.path}, which is "
                "inside a <replicate> and compiles to several unnamed objects; name it"
            )
        return written

    def _written_name(self, target: Element) -> str | None:
        """The name `target` (a named or unnamed element of a model of this output) is
        written with; None if it is written without one (inside a <replicate>)."""
        context = self._contexts[target.root]
        name = target.identifier
        if name is None:
            return self.generated_name(target, context)
        parent = target.parent
        if isinstance(parent, attachment.AttachmentFrame):
            return naming.frame_child_name(target, parent, context.prefix)
        if target.spec.namespace == "default":
            return context.class_text(name)
        return context.prefix + _unescape(name)

    def copies_of(self, first: Element) -> list[Element]:
        """The assets written as `first` (see `shared`), in writing order."""
        if self._copies is None:
            self._copies = {}
            for copy, written_as in self.shared.items():
                self._copies.setdefault(written_as, []).append(copy)
        return self._copies.get(first, [])

    def written_assets(self, context: ModelContext) -> Sequence[Element]:
        """The children of `context`'s model's `<asset>` that this output writes: all
        but those written as another model's (see mjcf.compose.sharing)."""
        children = tree_children(section_of(context.model, "asset"))
        if not self.shared or context.is_output:
            return children
        written = self._written_assets.get(context)
        if written is None:
            shared = self.shared
            written = self._written_assets[context] = [c for c in children if c not in shared]
        return written

    def generated_name(self, element: Element, context: ModelContext) -> str | None:
        """The name written for an element without a name attribute: its scoped file
        name for meshes and textures named after their file (when that could change),
        else its generated name (see `mjcf.compose.naming`), else None."""
        if (
            context.plain
            and not self.for_compile
            and element.spec.tag in NAMED_AFTER_FILE
            and stored_attributes(element).get("file") is not None
        ):
            return None  # MuJoCo names it after its file, as it is written
        implicit = element.identifier
        if implicit is not None:
            if context.plain and not self.for_compile:
                return None
            return context.prefix + implicit
        return naming.written_name(element, context.prefix)

    def frame_child_override(self, child: Element, context: ModelContext) -> dict | None:
        """What an attachment frame's own joint writes differently: its name, scoped to
        the frame ('arm/root_x/', see `mjcf.compose.naming`), and its class: the joints belong
        to the model that owns the frame, not to the attached model whose class the
        frame sets as childclass, so they take the class that applies where the frame is
        (a body's childclass, or main)."""
        override = context.rewrite(child) or {}
        if child.identifier is not None:  # named within the frame (see mjcf.compose.naming)
            override["name"] = naming.frame_child_name(
                child, cast(attachment.AttachmentFrame, child.parent), context.prefix
            )
        if "class" in child.spec.attributes and "class" not in stored_attributes(child):
            default = defaults.class_of(child)
            override["class"] = context.class_text(default.identifier or MAIN)
        return override or None


def frame_attributes(
    frame: attachment.AttachmentFrame, child_context: ModelContext
) -> dict[str, str | None]:
    """Attributes an attachment frame writes besides its own: its output name, the
    attached model's default class, and its orientation in the output's angle units
    (the frame's pose is in those of the model it belongs to)."""
    context = child_context.composition.context(frame.root)
    out: dict[str, str | None] = {}
    if context.angle_scale is not None or context.euler_seq is not None:
        out.update(context._convert_angles(frame))
    out["name"] = naming.frame_name(frame, context.prefix)
    out["childclass"] = child_context.main_reference
    return out


def _has_global_defaults(root: RootElement) -> bool:
    return any(
        child.spec.tag != "default" and (stored_attributes(child) or tree_children(child))
        for child in tree_children(root.default)
    )


def _numbers(element: Element, name: str) -> np.ndarray:
    return np.atleast_1d(np.asarray(value_of(element, element.spec.attributes[name]), dtype=float))


def _text(values: np.ndarray) -> str:
    return " ".join(format_number(v) for v in np.asarray(values, dtype=float).ravel().tolist())


def euler_to_quat(euler: np.ndarray, sequence: str) -> np.ndarray:
    """The quaternion (4,) of Euler angles `euler` (3,), in radians, in MuJoCo's
    `eulerseq` convention (lower-case axes rotate with the frame, upper-case stay
    fixed), by MuJoCo's own conversion."""
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, np.asarray(euler, dtype=float), sequence)
    return quat


def _in_body(element: Element) -> bool:
    """Whether `element` is inside a body (not static in the world body)."""
    parent = element.parent
    while parent is not None:
        tag = parent.spec.tag
        if tag == "body":
            return True
        if tag == "worldbody" or isinstance(parent, attachment.AttachmentFrame):
            return False
        parent = parent.parent
    return False
