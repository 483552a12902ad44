"""Settings sections of composed models: the `<compiler>` settings each model keeps for
itself (`OWN_COMPILER_SETTINGS`, as in MuJoCo's own attachment), and the sections a
composed document writes (the output model's, which the others share since attached).

    settings.compiler_problems(scene, arm)    # at attach: what cannot be reconciled
    settings.merged([scene, arm], 'option')   # the section written, when writing

A composed model compiles every model's elements as that model alone would; settings that
cannot be reconciled so raise mjcf.AttachmentError (see `mjcf.compose.global_settings`).
"""

from __future__ import annotations

import hashlib
import os
import re
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.tree import above
from mjcf.tree.element import stored_attributes, tree_children, value_of
from mjcf.tree.root import section_of

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# Compiler settings that locate files: assets are resolved per model and written with
# final names, so these never reach the output.
FILE_SETTINGS = frozenset({"meshdir", "texturedir", "assetdir", "strippath"})
# Compiler settings converted per model instead of required to agree:
# - `angle` and `eulerseq` are converted element by element (see `mjcf.compose.composition`);
# - `autolimits` is written "true" when models differ (a model with "false" states every
#   limit, so "true" reads it the same);
# - `inertiafromgeom` takes a value under which every body of every model gets its inertia
#   the same way as alone ("true" and "auto" agree for a model without `<inertial>`), else
#   it is an AttachmentError (`inertia_setting`);
# - an attached model's `settotalmass` becomes its own densities, masses and inertias scaled
#   by what it would scale them by alone (`unscaled_mass` compiles it once to know); the
#   models attached inside it keep their own masses (MuJoCo's attach leaves them, and a
#   robot's mass never changes with where it is attached); the written model's own
#   `settotalmass` with models attached is an AttachmentError, since it would scale them.
CONVERTED_SETTINGS = frozenset(
    {"angle", "eulerseq", "autolimits", "inertiafromgeom", "settotalmass"}
)
# Compiler settings of the output model that apply to the models attached to it too,
# and never change their compiled values (or do so as MuJoCo's own attachment does).
OUTPUT_SETTINGS = frozenset(
    {"usethread", "saveinertial", "savecompiled", "savecanonical", "conflict", "passthrough"}
)
# Compiler settings each model keeps for itself, never shared with the models it is
# attached into (see mjcf.compose.global_settings).
OWN_COMPILER_SETTINGS = FILE_SETTINGS | CONVERTED_SETTINGS | OUTPUT_SETTINGS
_INERTIA_SETTINGS = ("true", "auto", "false")
# Elements whose mass `settotalmass` scaling cannot be expressed by their attributes.
_UNSCALABLE = frozenset({"flexcomp", "composite", "flex", "attach"})


class MergedSettings:
    """The attributes (as text) and once-only children of a settings section as a
    composed document writes it."""

    __slots__ = ("attributes", "children")

    def __init__(self) -> None:
        self.attributes: dict[str, str] = {}
        self.children: dict[str, MergedSettings] = {}


def merged(models: list[RootElement], tag: str, inertia: str | None = None) -> MergedSettings:
    """Section `tag` as the output of `models` (the output model first, whose settings
    the others share; `inertia` is their `inertia_setting` if known) writes it: the
    output model's, without file folders, and for `compiler` with the `autolimits` and
    `inertiafromgeom` every model compiles with as alone; raises mjcf.AttachmentError if
    there is no such `inertiafromgeom`."""
    root = models[0]
    result = MergedSettings()
    _copy_into(result, section_of(root, tag), FILE_SETTINGS if tag == "compiler" else frozenset())
    if tag == "compiler" and len(models) > 1:
        limits = {setting(model, "autolimits") for model in models}
        if len(limits) > 1:
            result.attributes["autolimits"] = "true"
        if inertia is None:
            inertia = inertia_setting(models)
        if inertia != setting(root, "inertiafromgeom"):
            result.attributes["inertiafromgeom"] = inertia
    return result


def compiler_problems(
    parent: RootElement, child: RootElement, inertia: bool = True, output: bool = False
) -> list[str]:
    """What keeps `child` from being composed into `parent` among the compiler settings
    each model keeps (see `OWN_COMPILER_SETTINGS`): inertia settings that cannot be
    reconciled (checked unless `inertia` is false), and (`output`: `parent` is the model
    written, attached to none) a `settotalmass` of `parent`, which would scale the
    attached models' masses too; empty if nothing does. The settotalmass is refused when
    written, not at attach, so that the order of attaching does not decide."""
    problems = []
    total = setting(parent, "settotalmass")
    # A model attached elsewhere is written alone only to know its own masses.
    if output and parent.parent_model is None and total is not None and total > 0:
        problems.append(
            f"<compiler settotalmass={total!r}> of model {parent.model!r} would scale the "
            "masses of attached models too (MuJoCo's would); attach it into another model, "
            "which keeps each model's masses as alone, or remove it (MuJoCo deprecates it) "
            "and scale the masses of its own bodies"
        )
    if inertia:
        try:
            inertia_setting([parent, child])
        except errors.AttachmentError as error:
            problems.append(str(error))
    return problems


def _copy_into(merged: MergedSettings, section: Element, skip: frozenset) -> None:
    for name, value in stored_attributes(section).items():
        if name in skip:
            continue
        converter = section.spec.attributes[name].converter
        merged.attributes[name] = value if type(value) is str else converter.to_text(value)
    for child in tree_children(section):
        if not child.spec.repeated:
            target = merged.children[child.spec.tag] = MergedSettings()
            _copy_into(target, child, frozenset())


_BYTE_SUFFIXES = {"k": 10, "m": 20, "g": 30, "t": 40, "p": 50, "e": 60}


def capacity(name: str, value: object) -> int | None:
    """A `<size>` value as a number to compare (bytes for `memory`, '2M' or '-1'), or
    None if it is not one."""
    if isinstance(value, int | np.integer) and not isinstance(value, bool):
        return int(value)
    if name != "memory" or not isinstance(value, str):
        return None
    text = value.strip().lower()
    shift = _BYTE_SUFFIXES.get(text[-1:], 0)
    digits = text[:-1] if shift else text
    try:
        return int(digits) << shift if int(digits) >= 0 else int(digits)
    except ValueError:
        return None


def same(attribute: AttributeSpec, a: object, b: object) -> bool:
    """Whether two values of `attribute` are equal (arrays by shape and value)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a_array, b_array = np.asarray(a), np.asarray(b)
        return a_array.shape == b_array.shape and bool(np.all(a_array == b_array))
    return a == b


def setting(model: RootElement, name: str) -> Any:
    """A compiler setting of `model`: its explicit value, or MuJoCo's default (of the
    setting's own type)."""
    compiler = section_of(model, "compiler")
    attribute = compiler.spec.attributes[name]
    value = value_of(compiler, attribute)
    if value is None and attribute.default is not None:
        try:
            value = attribute.converter.from_text(attribute.default)
        except ValueError:
            value = attribute.default
    return value


def _inertia_sources(model: RootElement) -> list[tuple[bool, bool]]:
    """(has an <inertial>, has geoms) of every body of `model` (its own bodies)."""
    found = []
    for element in model.worldbody.iter():
        if element.spec.tag != "body":
            continue
        inertial = geoms = False
        stack = list(tree_children(element))
        while stack:
            child = stack.pop()
            tag = child.spec.tag
            if tag == "inertial":
                inertial = True
            elif tag == "geom":
                geoms = True
            elif tag in ("frame", "replicate"):  # not attachment frames: another model
                stack.extend(tree_children(child))
        found.append((inertial, geoms))
    return found


def _inertia_outcome(value: str, inertial: bool, geoms: bool) -> str:
    """Where a body's inertia comes from under `<compiler inertiafromgeom=value>`."""
    if value == "true" or (value == "auto" and not inertial):
        return "geoms" if geoms else "none"
    return "inertial" if inertial else "none"


def inertia_setting(models: list[RootElement]) -> str:
    """An `inertiafromgeom` under which every body of `models` gets its inertia as in
    its own model (the first model's setting if it can be); raises
    mjcf.AttachmentError if there is none."""
    own_settings = [setting(model, "inertiafromgeom") for model in models]
    if len(set(own_settings)) == 1:
        return own_settings[0]
    allowed = set(_INERTIA_SETTINGS)
    for model, own in zip(models, own_settings, strict=True):
        bodies = set(_inertia_sources(model))
        allowed &= {
            candidate
            for candidate in _INERTIA_SETTINGS
            if all(
                _inertia_outcome(candidate, *body) == _inertia_outcome(own, *body)
                for body in bodies
            )
        }
    if not allowed:
        described = ", ".join(
            f"{model.model!r}: {value!r}" for model, value in zip(models, own_settings, strict=True)
        )
        raise errors.AttachmentError(
            f"models with different <compiler inertiafromgeom> ({described}) cannot be "
            "composed: some bodies have an <inertial> that one setting uses and another "
            "ignores; set the same value on the models, or give their bodies the same kind "
            "of inertia"
        )
    for preferred in (own_settings[0], "auto", "true", "false"):
        if preferred in allowed:
            return preferred
    raise AssertionError("unreachable")


_unscaled_masses: dict[bytes, float] = {}


def unscaled_mass(model: RootElement) -> float:
    """The total mass of `model`'s own bodies (not those of the models attached to it,
    which keep their own masses) compiled without its settotalmass; raises
    mjcf.AttachmentError if that cannot be scaled by element attributes."""
    for element in model.iter():
        if element.spec.tag in _UNSCALABLE:
            raise errors.AttachmentError(
                f"{element.path}: model {model.model!r} has <compiler settotalmass>, and "
                f"the mass of a <{element.tag}> cannot be scaled to match it when the "
                "model is attached; scale its masses instead of using settotalmass"
            )
    xml, assets, composition, _ = above.serialize_for_compile(model)
    prefixes = tuple(context.prefix for context in composition.attached_contexts())
    key = _compile_key(xml, assets)
    total = _unscaled_masses.get(key)
    if total is None:
        try:
            spec = mujoco.MjSpec.from_string(xml, assets=assets)
            spec.compiler.settotalmass = -1
            compiled = spec.compile()
        except ValueError as error:
            raise errors.CompileError(
                f"model {model.model!r} (compiled alone to apply its settotalmass): {error}"
            ) from None
        total = float(sum(
            compiled.body_mass[i]
            for i in range(1, compiled.nbody)
            if not _attached_body(mujoco.mj_id2name(compiled, mujoco.mjtObj.mjOBJ_BODY, i),
                                  prefixes)
        ))  # fmt: skip
        if len(_unscaled_masses) > 256:
            _unscaled_masses.clear()
        _unscaled_masses[key] = total
    if total <= 0:
        raise errors.AttachmentError(
            f"model {model.model!r} sets <compiler settotalmass> but its own bodies have no "
            "mass to scale (the models attached to it keep their own masses)"
        )
    return total


def _attached_body(name: str | None, prefixes: tuple[str, ...]) -> bool:
    """Whether the body `name` is an attached model's ('arm/upper'), not its attachment
    frame ('arm/', its parent model's)."""
    return name is not None and any(name.startswith(p) and name != p for p in prefixes)


def _compile_key(xml: str, assets: dict[str, bytes]) -> bytes:
    """A digest of what compiling `xml` with `assets` reads: the text, the assets, and
    the size and time of the files on disk it names."""
    digest = hashlib.sha1(xml.encode())
    for name in sorted(assets):
        digest.update(name.encode() + hashlib.sha1(assets[name]).digest())
    for path in sorted(set(re.findall(r' file\w*="([^"]+)"', xml))):
        try:
            stat = os.stat(path)
        except OSError:
            continue
        digest.update(f"{path}:{stat.st_mtime_ns}:{stat.st_size}".encode())
    return digest.digest()
