"""Meshes and textures written once for all the models composed into one scene.

    scene = mjcf.RootElement(model='scene')
    for i in range(100):
        scene.attach(copy.deepcopy(arm)).pos = [i, 0, 0]   # 'arm', 'arm_1', ...
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.model.nmesh                   # the arm's meshes once, not 100 times
    arm_7.find('mesh', 'base').full_identifier             # 'arm_7/base', as ever

When models are composed (written or compiled together), a `<mesh>` or `<texture>` of
an attached model that MuJoCo would compile exactly like one of a model written before
it is not written: the elements that refer to it name that first one instead, so the
scene holds each asset once however many copies of a robot it has. "Exactly like"
means every attribute but the name equal, default classes applied (same file on disk,
same `scale`, `refquat`, `maxhullvert` ...); a mesh that names a material of its own
model is never shared. Within one model nothing is shared: a model compiles, alone or
composed, to the assets its author wrote.

The models' trees are untouched: each keeps its own elements, names and scopes; only
the compiled model has one asset where the copies had several. Editing a copy's mesh in
the tree (another scale) gives it its own asset again at the next compile. Binding a
copy's mesh or texture (`physics.bind(arm_7_mesh)`) reaches the one asset all the copies
compile to: it reads as ever, but a write through it would change every copy, so it is
refused (mjcf.BindingError, naming the copies that share it), through any copy, the first
too. To write one copy's asset at run time, compile without sharing:
`mjcf.Physics.from_mjcf_model(scene, share_assets=False)` (or
`physics.reload_from_mjcf_model(scene, share_assets=False)`), which compiles every copy's
meshes and textures apart, at the cost of the memory sharing saves. Named access
(`physics.named.model.mesh_scale['arm/base']`) and `physics.model` address the compiled
asset itself, by the first copy's name, as MuJoCo's own API does: what they write is what
every copy compiled to.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mjcf import errors
from mjcf.compose import defaults
from mjcf.tree import assets
from mjcf.tree.element import stored_attributes, tree_children
from mjcf.tree.root import section_of

if TYPE_CHECKING:
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

SHARED_TAGS = frozenset({"mesh", "texture"})
_NOT_COMPARED = frozenset({"name", "class"})


def shared_assets(models: list[RootElement]) -> dict[Element, Element]:
    """{asset element: the element of an earlier model it is written as} for the meshes
    and textures of `models` (in writing order) that compile exactly like an earlier
    model's. The n-th of a model's assets with one key shares with the n-th of the
    first model's of that key, so copies map one to one."""
    first: dict[tuple, Element] = {}
    shared: dict[Element, Element] = {}
    for model in models:
        seen: dict[tuple, int] = {}
        for element in tree_children(section_of(model, "asset")):
            if element.spec.tag not in SHARED_TAGS:
                continue
            key = _compiled_key(element)
            if key is None:
                continue
            count = seen.get(key, 0)
            seen[key] = count + 1
            earlier = first.setdefault((key, count), element)
            if earlier is not element:
                shared[element] = earlier
    return shared


def _compiled_key(element: Element) -> tuple | None:
    """What MuJoCo compiles `element` from: its attributes over its default class's, by
    value, files by where they are; None for an element that cannot be shared."""
    try:
        attributes = _effective_attributes(element)
    except errors.Error:
        return None  # a class that does not exist: the writer reports it
    key = []
    for name in sorted(attributes):
        owner, value = attributes[name]
        attribute = owner.spec.attributes[name]
        converter = attribute.converter
        if converter.refers:
            return None  # names an element of its own model
        if converter.files and value != "":  # "": no file
            asset = assets.resolve(owner, name, value)
            value = asset.path if asset.path is not None else (asset.extension, asset.contents)
        elif type(value) is str and converter.lazy:
            value = converter.from_text(value)
        if isinstance(value, np.ndarray):
            value = (value.dtype.str, value.shape, value.tobytes())
        key.append((name, value))
    return (element.spec.tag, *key)


def _effective_attributes(element: Element) -> dict[str, tuple[Element, object]]:
    """{attribute: (the element that sets it, stored value)}: `element`'s own over those
    of its default classes, inner classes over outer ones."""
    found: dict[str, tuple[Element, object]] = {}
    tag = defaults.default_tag(element)
    if tag is not None:
        for default in defaults.class_chain(defaults.class_of(element)):
            for child in tree_children(default):
                if child.spec.tag == tag:
                    for name, value in stored_attributes(child).items():
                        found[name] = (child, value)
    for name, value in stored_attributes(element).items():
        if name not in _NOT_COMPARED:
            found[name] = (element, value)
    return found
