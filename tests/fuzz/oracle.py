"""The oracle of the editing fuzz (test_editing.py): the same edits applied to the MJCF
text itself (an lxml tree), as a user would make them by hand, for MuJoCo to compile.

It knows MJCF only through the schema's facts (which attribute names an element, which
one refers to another, and into which namespace), and keeps mjcf's documented semantics
in the plainest way there is:

- a reference names an element: renaming an element renames every reference to it,
  removing (or detaching) it makes them name nothing MuJoCo can find, so that the text
  fails to compile, as writing such a model raises;
- attaching a model puts its world body's contents in a `<frame>` named after it where
  it is attached, with a default class of its own (so that no class of the scene reaches
  it), and its other sections after the scene's own, every name and reference of it
  prefixed with its name ('pod/swing'); detaching takes all of that out again;
- an unnamed element that is referenced is given a name of the oracle's own
  ('__unnamed_3'), which compares equal to the name mjcf generates for it.

The fuzz uses models without global default classes and compiler settings, whose
isolation and conversion mjcf does when composing (tested elsewhere).
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Iterator

from lxml import etree

from mjcf import schema

REMOVED = "__removed__"  # what a reference to an element that is gone names
UNNAMED = "__unnamed_"  # the oracle's own names of referenced unnamed elements
ISOLATED = "__isolated"  # the default class of attached models


class Oracle:
    """An MJCF document edited as text; `text()` is what MuJoCo compiles."""

    def __init__(self, xml: str) -> None:
        self.root = etree.fromstring(xml)
        # The elements each attached model contributed, by its prefix ('pod/').
        self.units: dict[str, list[etree._Element]] = {}
        self._numbers = itertools.count()

    def copy(self) -> Oracle:
        """An independent oracle of the same document."""
        twin = Oracle.__new__(Oracle)
        twin.root = copy.deepcopy(self.root)
        mapping = dict(zip(self.root.iter(), twin.root.iter(), strict=True))
        twin.units = {p: [mapping[e] for e in elements] for p, elements in self.units.items()}
        twin._numbers = self._numbers
        return twin

    def text(self) -> str:
        """The document, its sections ordered as mjcf writes them (the scene's own elements
        first, then each attached model's, in the order they were attached, each followed
        by those attached inside it)."""
        root = copy.deepcopy(self.root)
        rank = {}
        for index, prefix in enumerate(self._attach_order(), start=1):
            for element in self.units[prefix]:
                rank[element] = index
        originals = dict(zip(root.iter(), self.root.iter(), strict=True))
        for section in root:
            if section.tag == "worldbody":  # attached models are where they were attached
                continue
            children = list(section)
            ordered = sorted(children, key=lambda child: rank.get(originals[child], 0))
            for child in children:
                section.remove(child)
            section.extend(ordered)
        return etree.tostring(root, encoding="unicode")

    # -- what the schema says of an element -------------------------------------------

    def specs(self) -> Iterator[tuple[etree._Element, schema.ElementSpec]]:
        """Every element of the document with its spec."""
        stack = [(child, schema.MUJOCO.children[child.tag]) for child in self.root]
        while stack:
            element, spec = stack.pop()
            yield element, spec
            stack.extend((child, spec.children[child.tag]) for child in element)

    def spec_of(self, target: etree._Element) -> schema.ElementSpec:
        for element, spec in self.specs():
            if element is target:
                return spec
        raise LookupError(target)

    def named(self, namespace: str) -> list[str]:
        """The names of the document's elements of `namespace`."""
        return [
            element.get(spec.identifier)
            for element, spec in self.specs()
            if spec.namespace == namespace and spec.identifier and element.get(spec.identifier)
        ]

    # -- edits --------------------------------------------------------------------------

    def rename(self, element: etree._Element, new: str | None) -> None:
        """Give `element` name `new` (None: no name), and every reference to it too."""
        spec = self.spec_of(element)
        old = element.get(spec.identifier)
        if new is None:
            element.attrib.pop(spec.identifier, None)
            if old is not None and self._refer_to(spec.namespace, old):
                new = f"{UNNAMED}{next(self._numbers)}"  # referenced: it needs a name
                element.set(spec.identifier, new)
        else:
            element.set(spec.identifier, new)
        if old is not None:
            self._retarget(spec.namespace, old, new or REMOVED)

    def remove(self, element: etree._Element) -> None:
        """Remove `element` and its subtree; references to them name nothing now."""
        gone = [
            (spec.namespace, e.get(spec.identifier))
            for e, spec in self._subtree(element)
            if spec.identifier is not None
        ]
        element.getparent().remove(element)
        for elements in self.units.values():
            for inside in list(elements):
                if inside is element:
                    elements.remove(inside)
        for namespace, name in gone:
            if namespace is not None and name:
                self._retarget(namespace, name, REMOVED)

    def attach(self, parent: etree._Element, child: str, prefix: str, pose: dict) -> None:
        """Attach model `child` (its text) into `parent` (a body or the world body) with
        `pose` (the frame's pos and orientation, as text), names prefixed `prefix`."""
        model = etree.fromstring(child)
        prefixed = Oracle(etree.tostring(model, encoding="unicode"))
        for element, spec in prefixed.specs():
            if spec.identifier and spec.namespace and element.get(spec.identifier):
                element.set(spec.identifier, prefix + element.get(spec.identifier))
            for name in spec.references & set(element.keys()):
                attribute = spec.attributes[name]
                if attribute.reference_namespace(element.attrib) not in (None, "default"):
                    words = element.get(name).split() if attribute.is_list else [element.get(name)]
                    element.set(name, " ".join(w if w == "world" else prefix + w for w in words))
        # Default classes stay isolated: an empty class (the scene has no global defaults)
        # keeps a childclass of the place from reaching the attached model.
        defaults = self.root.find("default")
        if defaults is None:
            defaults = etree.SubElement(self.root, "default")
        if defaults.find(f"default[@class='{ISOLATED}']") is None:
            etree.SubElement(defaults, "default", {"class": ISOLATED})
        frame = etree.SubElement(parent, "frame", {"name": prefix, "childclass": ISOLATED, **pose})
        contributed = [frame]
        for section in prefixed.root:
            if section.tag == "worldbody":
                frame.extend(list(section))
                continue
            target = self.root.find(section.tag)
            if target is None:
                target = etree.SubElement(self.root, section.tag)
            for element in list(section):
                target.append(element)
                contributed.append(element)
        self.units[prefix] = contributed

    def detach(self, prefix: str) -> None:
        """Take out everything the model attached as `prefix` contributed, and the models
        attached inside it."""
        for inner in [p for p in self.units if p.startswith(prefix)]:
            for element in self.units.pop(inner):
                if element.getparent() is not None:
                    self.remove(element)

    def _attach_order(self) -> list[str]:
        """The prefixes of the attached models in mjcf's order: each model attached to
        the scene, in the order it was, followed by those attached inside it."""
        order: list[str] = []

        def visit(outer: str) -> None:
            for prefix in self.units:
                rest = prefix[len(outer) :]
                if prefix.startswith(outer) and rest.count("/") == 1:
                    order.append(prefix)
                    visit(prefix)

        visit("")
        return order

    def include(self, other: str) -> None:
        """Merge the sections of document `other` into this one, names as they are."""
        for section in etree.fromstring(other):
            target = self.root.find(section.tag)
            if target is None:
                target = etree.SubElement(self.root, section.tag)
            target.extend(list(section))

    # -- references ---------------------------------------------------------------------

    def _subtree(self, top: etree._Element) -> Iterator[tuple[etree._Element, schema.ElementSpec]]:
        inside = set(top.iter())
        for element, spec in self.specs():
            if element in inside:
                yield element, spec

    def _references(self) -> Iterator[tuple[etree._Element, str, str, bool]]:
        """(element, attribute, namespace, is a list) of every reference of the document."""
        for element, spec in self.specs():
            for name in spec.references & set(element.keys()):
                attribute = spec.attributes[name]
                namespace = attribute.reference_namespace(element.attrib)
                if namespace is not None:
                    yield element, name, namespace, attribute.is_list

    def _refer_to(self, namespace: str, name: str) -> bool:
        return any(
            name in (element.get(attribute).split() if is_list else [element.get(attribute)])
            for element, attribute, space, is_list in self._references()
            if space == namespace
        )

    def _retarget(self, namespace: str, old: str, new: str) -> None:
        for element, attribute, space, is_list in list(self._references()):
            if space != namespace:
                continue
            words = element.get(attribute).split() if is_list else [element.get(attribute)]
            if old in words:
                element.set(attribute, " ".join(new if w == old else w for w in words))
