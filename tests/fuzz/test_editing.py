"""Editing fuzz: random sequences of edits through mjcf's Python API (add, remove, rename,
set an attribute, attach, detach, copy, include_copy) on a model read from a file, each
also made to the MJCF text by hand (`oracle.Oracle`). After each sequence the model
compiles exactly as MuJoCo compiles that text (every MjModel field compared), or both
fail; every edit either is made, or raises an mjcf.Error and changes nothing (the calls
are right, values wrong at times: anything but an mjcf.Error fails the test).

CI runs a fixed sample (the "ci" hypothesis profile is derandomized) that takes well
under a minute on one core. A longer search by hand, with fresh random sequences:

    MJCF_EDIT_FUZZ_EXAMPLES=3000 HYPOTHESIS_PROFILE=explore \\
        python -m pytest -q -p no:cacheprovider tests/fuzz/test_editing.py

Its last result is in docs/edit_fuzz.md.
"""

from __future__ import annotations

import copy
import os
import re
from typing import Any

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, event, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, rule
from lxml import etree

import mjcf
from mjcf.compose.naming import GENERATED
from tests.fuzz.oracle import ISOLATED, UNNAMED, Oracle
from tests.mjcf.compare import model_differences

SCENE = """<mujoco model="scene">
  <default>
    <default class="leg"><joint damping="0.5" range="-1 1" limited="true"/>
      <geom rgba="0 0 1 1" material="red"/></default>
  </default>
  <asset>
    <texture name="grid" type="2d" builtin="checker" width="8" height="8"/>
    <material name="floor_mat" texture="grid"/>
    <material name="red" rgba="1 0 0 1"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" material="floor_mat"/>
    <site name="mount" pos="0 1 1" euler="0 30 0"/>
    <body name="torso" pos="0 0 1">
      <freejoint name="root"/>
      <geom name="core" size="0.2" material="red"/>
      <site name="imu"/>
      <body name="thigh" childclass="leg" pos="0.2 0 0">
        <joint name="hip" axis="0 1 0"/>
        <geom name="thigh_geom" type="capsule" fromto="0 0 0 0.3 0 0" size="0.05"/>
        <body name="shin" pos="0.3 0 0">
          <joint name="knee"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
          <site name="foot"/>
        </body>
      </body>
      <body name="arm" pos="-0.2 0 0">
        <joint name="shoulder" class="leg"/>
        <geom name="arm_geom" size="0.05"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="coupling"><joint joint="hip" coef="1"/><joint joint="knee" coef="-1"/></fixed>
  </tendon>
  <equality>
    <joint name="lock" joint1="shoulder" joint2="hip" active="false"/>
    <connect body1="arm" body2="torso" anchor="0 0 0" active="false"/>
  </equality>
  <contact>
    <pair name="touch" geom1="core" geom2="floor"/>
    <exclude body1="thigh" body2="shin"/>
  </contact>
  <actuator>
    <motor name="hip_motor" joint="hip" gear="10"/>
    <motor joint="knee"/>
    <position name="arm_servo" joint="shoulder" kp="5"/>
  </actuator>
  <sensor>
    <jointpos name="hip_angle" joint="hip"/>
    <framepos objtype="site" objname="foot"/>
    <touch site="foot"/>
  </sensor>
</mujoco>"""
# Models to attach (each attach reads a fresh one) and to include_copy. The second
# includes refer to the scene's names, and one of them takes a name the scene has.
ATTACHED = (
    '<mujoco model="pod"><worldbody><body name="base"><joint name="swing"/>'
    '<geom name="shell" size="0.1"/><site name="tip" pos="0 0 0.1"/>'
    '<body><geom size="0.05"/></body></body></worldbody>'
    '<actuator><motor name="drive" joint="swing"/></actuator>'
    '<sensor><jointpos name="angle" joint="swing"/></sensor></mujoco>',
    '<mujoco model="box"><asset><material name="paint" rgba="0 1 0 1"/></asset>'
    '<worldbody><geom name="lid" type="box" size="0.1 0.1 0.1" material="paint"/>'
    '<site name="corner"/></worldbody></mujoco>',
)
INCLUDED = (
    '<mujoco><worldbody><body name="post" pos="2 0 0"><geom name="pole" type="capsule" '
    'size="0.05 0.5" material="red"/></body></worldbody>'
    '<tendon><fixed name="tie"><joint joint="knee" coef="1"/></fixed></tendon></mujoco>',
    '<mujoco><worldbody><body name="torso"><geom size="0.1"/></body></worldbody></mujoco>',
)
NAMES = ("hip", "knee", "torso", "red", "foot", "pole", "a", "b", "leg", "pod/swing")
# Attribute values to set, by tag: valid ones and some MuJoCo refuses.
VALUES: dict[str, dict[str, tuple]] = {
    "geom": {"size": ([0.1], [0.2, 0.3], [1, 2, 3, 4], [[1, 2]], {"x": 1}, "1 2 x", None),
             "rgba": ([1, 0, 1, 1], [1, 2], object()),
             "pos": ([0, 0, 0.1],), "material": ("red", "floor_mat", "nothing"),
             "type": ("sphere", "box", "bogus")},
    "body": {"pos": ([0, 0, 0.5], [1, 2]), "euler": ([0, 0, 45],)},
    "joint": {"range": ([-0.5, 0.5],), "axis": ([1, 0, 0], [0, 0]), "damping": (0.1, "x")},
    "site": {"pos": ([0.1, 0, 0],), "size": ([0.02],)},
    "motor": {"joint": NAMES, "gear": ([5], [1, 0, 0, 0, 0, 0]), "ctrlrange": ([-1, 1],)},
    "position": {"joint": NAMES, "kp": (10,)},
    "jointpos": {"joint": NAMES},
    "material": {"rgba": ([0, 0, 0, 1],)},
    "pair": {"geom1": NAMES, "geom2": NAMES, "condim": (1, 3, 7)},
    "exclude": {"body1": NAMES},
    "fixed": {"limited": ("true",)},
}  # fmt: skip
ADDED = ("geom", "site", "body", "joint", "motor", "jointpos")
EXAMPLES = int(os.environ.get("MJCF_EDIT_FUZZ_EXAMPLES", "200"))
STEPS = int(os.environ.get("MJCF_EDIT_FUZZ_STEPS", "20"))


def _prefix(model: mjcf.RootElement) -> str:
    """The scope of `model`'s names in the outermost model ('pod/box/'; '' for it)."""
    parts = []
    while model.parent_model is not None:
        parts.insert(0, model.model + "/")
        model = model.parent_model
    return "".join(parts)


def _written(model: mjcf.RootElement) -> str:
    try:
        return model.to_xml_string()
    except mjcf.Error as error:
        return f"{type(error).__name__}: {error}"


def _own_children(element: mjcf.Element) -> list[mjcf.Element]:
    """Children as they are written (once-only elements made empty by reading left out)."""
    return [c for c in element._children if c._attrs or c._children or c._written_empty()] + []


def _pairs(model: mjcf.RootElement, oracle: Oracle) -> list[tuple[mjcf.Element, Any]]:
    """(mjcf element, its oracle element) for every element of the model and of the models
    attached to it."""
    found: list[tuple[mjcf.Element, Any]] = []

    def match(element: mjcf.Element, xml: Any) -> None:
        found.append((element, xml))
        children = _own_children(element)
        xml_children = list(xml)
        if isinstance(element, mjcf.AttachmentFrame):
            children = children + _own_children(element.attached_model.worldbody)
        assert [c.tag if not isinstance(c, mjcf.AttachmentFrame) else "frame" for c in children] \
            == [x.tag for x in xml_children], element.path  # fmt: skip
        for child, xml_child in zip(children, xml_children, strict=True):
            match(child, xml_child)

    models = {_prefix(f.attached_model): f.attached_model
              for f in model.find_all("attachment_frame")}  # fmt: skip
    for section in model._children:
        xml_section = oracle.root.find(section.tag)
        if xml_section is None:
            continue
        if section.tag == "worldbody":
            match(section, xml_section)
            continue
        found.append((section, xml_section))
        attached = {e for elements in oracle.units.values() for e in elements}
        own = [x for x in xml_section if x not in attached and x.get("class") != ISOLATED]
        for child, xml_child in zip(_own_children(section), own, strict=True):
            match(child, xml_child)
        for prefix, elements in oracle.units.items():
            theirs = [x for x in xml_section if x in elements]
            mine = _own_children(models[prefix]._section(section.tag))
            for child, xml_child in zip(mine, theirs, strict=True):
                match(child, xml_child)
    return found


def _compiled(text_or_model: str | mjcf.RootElement) -> mujoco.MjModel | str:
    try:
        if isinstance(text_or_model, str):
            return mujoco.MjModel.from_xml_string(text_or_model)
        return mjcf.Physics.from_mjcf_model(text_or_model).model
    except (ValueError, mjcf.Error) as error:
        return f"fails: {error}"


def _differences(expected: mujoco.MjModel, ours: mujoco.MjModel) -> list[str]:
    """model_differences, an oracle name of a referenced unnamed element equal to the
    name mjcf generates for it."""
    unnamed = re.compile(rf"name '(?:{UNNAMED}\d+)?' != '(.*)'")
    return [
        d for d in model_differences(expected, ours)
        if not ((m := unnamed.search(d)) and GENERATED.search(m.group(1)))
    ]  # fmt: skip


class Editing(RuleBasedStateMachine):
    """One sequence of edits, made to an mjcf model and to its oracle."""

    @initialize()
    def read(self) -> None:
        self.model = mjcf.from_xml_string(SCENE)
        self.oracle = Oracle(SCENE)
        self.pairs = _pairs(self.model, self.oracle)
        self.edits: list[str] = []

    def _pick(self, data: st.DataObject, accept: Any) -> tuple[mjcf.Element, Any] | None:
        candidates = [(e, x) for e, x in self.pairs if accept(e)]
        if not candidates:
            return None
        return data.draw(st.sampled_from(candidates))

    def _edit(self, kind: str, description: str, change: Any, mirror: Any) -> None:
        """Make `change` to the model and, if it does not raise, `mirror` to the oracle; a
        change that raises must raise an mjcf.Error (or TypeError) and change nothing."""
        self.edits.append(description)
        before = _written(self.model)
        try:
            change()
        except mjcf.Error:  # anything else (a TypeError, a KeyError ...) fails the test
            assert _written(self.model) == before, f"a failed edit changed the model: {description}"
            self.edits[-1] += " (refused)"
            event(f"{kind} refused")
            return
        event(f"{kind} made")
        mirror()
        self.pairs = _pairs(self.model, self.oracle)

    @rule(data=st.data(), name=st.sampled_from((*NAMES, None)))
    def rename(self, data: st.DataObject, name: str | None) -> None:
        picked = self._pick(data, lambda e: e.spec.identifier and e.spec.namespace
                            and e.parent is not None and e.tag != "worldbody")  # fmt: skip
        if picked is None or (name is None and picked[0].tag == "default"):
            return
        element, xml = picked
        attribute = "dclass" if element.tag == "default" else element.spec.identifier
        written = None if name is None else _prefix(element.root) + name  # scoped
        self._edit(
            "rename",
            f"{element.path}.{attribute} = {name!r}",
            lambda: setattr(element, attribute, name),
            lambda: self.oracle.rename(xml, written),
        )

    @rule(data=st.data())
    def remove(self, data: st.DataObject) -> None:
        picked = self._pick(data, lambda e: e.parent is not None and e.parent.parent is not None)
        if picked is not None:
            element, xml = picked
            prefix = (
                _prefix(element.attached_model)
                if isinstance(element, mjcf.AttachmentFrame) else None
            )  # fmt: skip
            mirror = (
                (lambda: self.oracle.detach(prefix))
                if prefix
                else (lambda: self.oracle.remove(xml))
            )
            self._edit("remove", f"{element.path}.remove()", element.remove, mirror)

    @rule(data=st.data())
    def set_attribute(self, data: st.DataObject) -> None:
        picked = self._pick(data, lambda e: e.tag in VALUES and e.parent is not None)
        if picked is None:
            return
        element, xml = picked
        name = data.draw(st.sampled_from(sorted(VALUES[element.tag])))
        if name not in element.spec.attributes:
            return
        value = data.draw(st.sampled_from(VALUES[element.tag][name]))
        text = " ".join(map(repr, value)) if isinstance(value, list) else str(value)
        if element.spec.attributes[name].kind == "reference":
            text = _prefix(element.root) + text  # a name of the element's own model
        self._edit(
            "set",
            f"{element.path}.{name} = {value!r}",
            lambda: setattr(element, name, value),
            lambda: xml.set(name, text) if value is not None else xml.attrib.pop(name, None),
        )

    @rule(data=st.data(), kind=st.sampled_from(ADDED), name=st.sampled_from((None, "a", "x1")),
          reference=st.sampled_from(NAMES))  # fmt: skip
    def add(self, data: st.DataObject, kind: str, name: str | None, reference: str) -> None:
        places = {"motor": ("actuator",), "jointpos": ("sensor",), "joint": ("body",)}
        picked = self._pick(data, lambda e: e.tag in places.get(kind, ("body", "worldbody"))
                            and not isinstance(e, mjcf.AttachmentFrame))  # fmt: skip
        if picked is None:
            return
        parent, xml = picked
        attributes: dict[str, Any] = {"name": name}
        if kind == "geom":
            attributes["size"] = [0.05]
        elif kind == "body":
            attributes["pos"] = [0.1, 0, 0]
        elif kind in ("motor", "jointpos"):
            attributes["joint"] = reference
        text = {k: " ".join(map(repr, v)) if isinstance(v, list) else v
                for k, v in attributes.items() if v is not None}  # fmt: skip
        prefix = _prefix(parent.root)  # names of the parent's own model
        text = {k: prefix + v if k in ("name", "joint") else v for k, v in text.items()}
        self._edit(
            "add",
            f"{parent.path}.add({kind!r}, **{attributes!r})",
            lambda: parent.add(kind, **attributes),
            lambda: etree.SubElement(xml, kind, text),
        )

    @rule(data=st.data(), which=st.sampled_from(range(len(ATTACHED))))
    def attach(self, data: st.DataObject, which: int) -> None:
        picked = self._pick(data, lambda e: e.tag in ("site", "body", "worldbody"))
        if picked is None:
            return
        place, xml = picked
        child = mjcf.from_xml_string(ATTACHED[which])
        body = xml if place.tag != "site" else xml.getparent()
        pose = {k: xml.get(k) for k in ("pos", "euler") if place.tag == "site" and xml.get(k)}

        def mirror() -> None:
            self.oracle.attach(body, ATTACHED[which], _prefix(child), pose)

        self._edit(
            "attach", f"{place.path}.attach({child.model!r})", lambda: place.attach(child), mirror
        )

    @rule(data=st.data())
    def detach(self, data: st.DataObject) -> None:
        picked = self._pick(data, lambda e: isinstance(e, mjcf.AttachmentFrame))
        if picked is not None:
            frame = picked[0]
            prefix = _prefix(frame.attached_model)
            self._edit(
                "detach", f"{frame.path}.detach()", frame.detach, lambda: self.oracle.detach(prefix)
            )

    @rule(data=st.data())
    def read_attributes(self, data: st.DataObject) -> None:
        """Read an element's attributes (references then hold their elements): reading
        never changes what a model is."""
        picked = self._pick(data, lambda e: bool(e.spec.references))
        if picked is not None:
            self.edits.append(f"{picked[0].path}.get_attributes()")
            picked[0].get_attributes()

    @rule()
    def resolve_references(self) -> None:
        self.edits.append("model.resolve_references()")
        self.model.resolve_references()

    @rule()
    def copy_model(self) -> None:
        """Go on editing a deep copy (which compiles as the original)."""
        self.edits.append("model = copy.deepcopy(model)")
        self.model = copy.deepcopy(self.model)
        self.pairs = _pairs(self.model, self.oracle)

    @rule(which=st.sampled_from(range(len(INCLUDED))))
    def include_copy(self, which: int) -> None:
        other = mjcf.from_xml_string(INCLUDED[which], resolve_references=False)
        self._edit(
            "include_copy",
            f"model.include_copy(INCLUDED[{which}])",
            lambda: self.model.include_copy(other),
            lambda: self.oracle.include(INCLUDED[which]),
        )

    def teardown(self) -> None:
        if not hasattr(self, "model"):
            return
        expected, ours = _compiled(self.oracle.text()), _compiled(self.model)
        story = "\n  ".join(self.edits)
        if isinstance(expected, str):
            event("both fail to compile: " + re.sub(r"'[^']*'|\d+", "_", expected[:60]))
        else:
            event("compiled and compared")
        if isinstance(expected, str) or isinstance(ours, str):
            assert isinstance(expected, str) == isinstance(ours, str), (
                f"after\n  {story}\nMuJoCo on the edited text: {str(expected)[:300]}\n"
                f"mjcf: {str(ours)[:300]}\ntext:\n{self.oracle.text()}"
            )
            return
        differences = _differences(expected, ours)
        assert differences == [], f"after\n  {story}\n{differences[:10]}"
        assert np.array_equal(expected.body_pos, ours.body_pos)


Editing.TestCase.settings = settings(
    max_examples=EXAMPLES,
    stateful_step_count=STEPS,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
TestEditing = Editing.TestCase
# Random edits make odd but valid models at times (a near-singular inertia): MuJoCo warns,
# compiles, and the fuzz compares the result with MuJoCo's own as it does any other.
pytestmark = pytest.mark.filterwarnings("ignore:Inertia matrix is too close to singular")
