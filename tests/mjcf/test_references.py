"""References follow the elements they name: a model read from a file behaves as if every
reference had been resolved when it was read (dm_control's `resolve_references=True`),
however lazily it was built; `resolve_references=False` keeps them as text until
`resolve_references()`."""

from __future__ import annotations

import copy
from pathlib import Path

import mujoco
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mjcf
from mjcf.io import fast_reader
from tests.conftest import GYM_ASSETS, MENAGERIE, MUJOCO_TESTDATA

TWO_JOINTS = """<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" type="hinge"/>
      <joint name="k" type="slide"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator><motor name="m" joint="j"/></actuator>
</mujoco>"""


def _driven_joint_type(model: mjcf.RootElement) -> int:
    compiled = mjcf.Physics.from_mjcf_model(model).model
    return int(compiled.jnt_type[compiled.actuator_trnid[0, 0]])


@pytest.mark.parametrize("read_first", [False, True])
def test_swapping_two_names_keeps_the_motor_on_its_joint(read_first: bool) -> None:
    model = mjcf.from_xml_string(TWO_JOINTS)
    if read_first:
        assert model.find("actuator", "m").joint is model.find("joint", "j")
    hinge, slide = model.find("joint", "j"), model.find("joint", "k")
    hinge.name = "tmp"
    slide.name = "j"
    hinge.name = "k"
    assert model.find("actuator", "m").joint is hinge
    assert 'joint="k"' in model.actuator.to_xml_string()
    assert _driven_joint_type(model) == mujoco.mjtJoint.mjJNT_HINGE


def test_writing_a_reference_to_a_removed_element_raises() -> None:
    model = mjcf.from_xml_string(TWO_JOINTS)
    model.find("joint", "j").remove()
    with pytest.raises(mjcf.InvalidReferenceError, match=r"refers to a removed element.*joint"):
        model.to_xml_string()
    with pytest.raises(mjcf.InvalidReferenceError):
        mjcf.Physics.from_mjcf_model(model)
    # A new joint of the old name is another joint: the motor still names the removed one.
    model.find("body", "b").add("joint", name="j")
    with pytest.raises(mjcf.InvalidReferenceError):
        model.to_xml_string()


def test_a_name_set_in_python_resolves_when_set_and_follows_the_element() -> None:
    model = mjcf.from_xml_string(TWO_JOINTS)
    motor = model.find("actuator", "m")
    motor.joint = "k"
    assert motor.joint is model.find("joint", "k")
    model.find("joint", "k").name = "slider"
    assert 'joint="slider"' in model.actuator.to_xml_string()


def test_a_name_set_before_its_element_exists_follows_it_once_it_does() -> None:
    model = mjcf.from_xml_string(TWO_JOINTS)
    motor = model.actuator.add("motor", name="later", joint="wrist")
    assert motor.joint == "wrist"  # names no element yet: text
    wrist = model.find("body", "b").add("joint", name="wrist")
    wrist.name = "wrist_x"
    assert motor.joint is wrist
    assert 'joint="wrist_x"' in motor.to_xml_string()


def test_a_scoped_name_follows_the_element_of_the_attached_model() -> None:
    scene = mjcf.RootElement(model="scene")
    arm = mjcf.from_xml_string(TWO_JOINTS)
    arm.model = "arm"
    scene.attach(arm)
    scene.sensor.add("jointpos", joint="arm/k")
    arm.find("joint", "k").name = "slider"
    assert 'joint="arm/slider"' in scene.sensor.to_xml_string()
    arm.model = "left"
    assert 'joint="left/slider"' in scene.sensor.to_xml_string()


def test_unresolved_references_stay_text_until_resolved() -> None:
    path = MUJOCO_TESTDATA / "model.xml"
    resolved = mjcf.from_path(path)
    unresolved = mjcf.from_path(path, resolve_references=False)
    index, geom = next((i, e) for i, e in enumerate(resolved.find_all("geom")) if e.material)
    name = geom.material.name
    twin = unresolved.find_all("geom")[index]
    assert twin.material == name
    assert unresolved.find("material", name) is not None
    unresolved.resolve_references()
    assert twin.material is unresolved.find("material", name)
    unresolved.find("material", name).name = "renamed"
    assert twin.get_attribute_xml_string("material") == "renamed"


def test_dm_control_model_material_is_text_without_resolving() -> None:
    model = mjcf.from_xml_string(
        '<mujoco><asset><material name="mat_texture"/></asset>'
        '<worldbody><geom name="g" size="1" material="mat_texture"/></worldbody></mujoco>',
        resolve_references=False,
    )
    geom = model.find("geom", "g")
    assert geom.material == "mat_texture"
    model.find("material", "mat_texture").name = "other"  # by name, as dm_control
    assert geom.material == "mat_texture"
    model.resolve_references()
    assert geom.material == "mat_texture"  # names nothing now: stays text


def test_copies_of_a_model_just_read_follow_renames_as_the_original() -> None:
    model = mjcf.from_xml_string(TWO_JOINTS)
    twin = copy.deepcopy(model)
    twin.find("joint", "j").name = "hinge"
    assert 'joint="hinge"' in twin.actuator.to_xml_string()
    assert 'joint="j"' in model.actuator.to_xml_string()


def test_include_copy_names_what_it_does_not_copy_as_the_included_text_would() -> None:
    source = mjcf.from_xml_string(
        '<mujoco><asset><material name="red"/></asset>'
        '<worldbody><body name="part"><geom size="1" material="red"/></body></worldbody>'
        "</mujoco>"
    )
    target = mjcf.RootElement()
    red = target.asset.add("material", name="red", rgba=[1, 0, 0, 1])
    target.worldbody.add("body").include_copy(source.find("body", "part"))
    geom = target.find("body", "part").geom[0]
    assert geom.material is red
    red.name = "crimson"
    assert 'material="crimson"' in target.worldbody.to_xml_string()


# -- the lazy reader against the eager read-and-resolve ------------------------------

MODELS = [
    GYM_ASSETS / "ant.xml",
    GYM_ASSETS / "humanoid.xml",
    MUJOCO_TESTDATA / "model.xml",
    MENAGERIE / "robotiq_2f85" / "2f85.xml",
    MENAGERIE / "universal_robots_ur5e" / "ur5e.xml",
]
_NAMESPACES = ("body", "joint", "geom", "site", "tendon", "material", "mesh", "default",
               "actuator", "texture")  # fmt: skip


def _read_eagerly(path: Path) -> mjcf.RootElement:
    """Read element by element, every reference resolved at once, as dm_control reads."""
    fast = fast_reader.read
    fast_reader.read = lambda *args: False  # type: ignore[assignment]
    try:
        model = mjcf.from_path(path)
    finally:
        fast_reader.read = fast  # type: ignore[assignment]
    model.resolve_references()
    return model


def _targets(model: mjcf.RootElement, namespace: str) -> list[mjcf.Element]:
    return [e for e in model.find_all(namespace) if e.tag != "worldbody"]


def _apply(model: mjcf.RootElement, step: tuple) -> str:
    """Carry out one edit; returns what happened (the error's type and text, if any)."""
    kind, namespace, index, *rest = step
    elements = _targets(model, namespace)
    if not elements:
        return "none"
    element = elements[index % len(elements)]
    try:
        if kind == "rename":
            if namespace == "default" and element.parent is element.root:
                return "none"
            element.set_attributes(**{"dclass" if namespace == "default" else "name": rest[0]})
        elif kind == "unname":
            if namespace == "default":
                return "none"
            element.name = None
        elif kind == "remove":
            element.remove()
        return "ok"
    except mjcf.Error as error:
        return f"{type(error).__name__}: {error}"


def _written(model: mjcf.RootElement) -> str:
    try:
        return model.to_xml_string()
    except mjcf.Error as error:
        return f"{type(error).__name__}: {error}"


_STEP = st.tuples(
    st.sampled_from(["rename", "rename", "unname", "remove"]),
    st.sampled_from(_NAMESPACES),
    st.integers(0, 200),
    st.sampled_from(["a", "b", "torso", "hip", "left_knee", "main", "x_1"]),
)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(MODELS), st.lists(_STEP, min_size=1, max_size=8))
def test_the_lazy_reader_edits_as_the_eager_read_and_resolve(path: Path, steps: list) -> None:
    """Whatever the fast reader defers (building elements, resolving references), renames
    and removals give the model reading element by element and resolving every reference
    at once gives: the same outcome of each step, the same written model."""
    lazy, eager = mjcf.from_path(path), _read_eagerly(path)
    for step in steps:
        assert _apply(lazy, step) == _apply(eager, step)
    assert _written(lazy) == _written(eager)
