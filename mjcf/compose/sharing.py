"""Meshes and textures written once for all the models composed into one scene.

    for i in range(100):
        scene.attach(copy.deepcopy(arm)).pos = [i, 0, 0]   # 'arm', 'arm_1', ...
    mjcf.Physics.from_mjcf_model(scene).model.nmesh        # the arm's meshes once, not 100x

An attached model's asset that compiles exactly like one written before is not written:
references to it name the first. The trees are untouched. A binding of a shared asset reads
as ever but refuses writes, which would change every copy (mjcf.BindingError); compile with
`share_assets=False` to write one copy's asset (`mjcf.sim.tree_binding.write_refusal`).
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
    first model's of that key, so copies map one to one.

    "Exactly like" means every attribute but the name equal, default classes applied (same
    file on disk, same `scale`, `refquat`, `maxhullvert` ...); a mesh that names a material
    of its own model is never shared. Within one model nothing is shared: a model compiles,
    alone or composed, to the assets its author wrote. The models' trees are untouched:
    each keeps its own elements, names and scopes; only the compiled model has one asset
    where the copies had several. Editing a copy's mesh in the tree (another scale) gives
    it its own asset again at the next compile."""
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
