"""Building and editing models: what a user does with elements."""

from __future__ import annotations

import copy
import gc
import pickle

import numpy as np
import pytest

import mjcf
from mjcf import schema
from tests.conftest import GYM_ASSETS


@pytest.fixture
def arm() -> mjcf.RootElement:
    model = mjcf.RootElement(model="arm")
    upper = model.worldbody.add("body", name="upper", pos=[0, 0, 1])
    upper.add("joint", name="shoulder", type="hinge", axis=[0, 1, 0])
    upper.add("geom", name="upper", type="capsule", size=[0.05, 0.2])
    return model


def test_every_section_exists_even_empty() -> None:
    model = mjcf.RootElement()
    for tag in ("worldbody", "asset", "default", "option", "compiler", "size", "visual",
                "statistic", "actuator", "sensor", "tendon", "equality", "contact",
                "keyframe", "custom", "extension", "deformable"):  # fmt: skip
        section = getattr(model, tag)
        assert section.tag == tag and section.parent is model
    assert model.to_xml_string() == "<mujoco>\n</mujoco>\n"


def test_attributes_read_back_as_python_values(arm: mjcf.RootElement) -> None:
    body = arm.find("body", "upper")
    assert isinstance(body.pos, np.ndarray) and body.pos.tolist() == [0, 0, 1]
    geom = arm.find("geom", "upper")
    geom.density = 500
    assert geom.density == 500.0 and isinstance(geom.density, float)
    geom.condim = 3
    assert geom.condim == 3 and isinstance(geom.condim, int)
    assert geom.rgba is None
    geom.rgba = (1, 0, 0, 1)
    del geom.rgba
    assert geom.rgba is None and "rgba" not in geom.get_attributes()
    geom.friction = [1, 0.1, 0.01]
    geom.friction = None
    assert "friction" not in geom.to_xml_string()


def test_in_place_array_edits_change_the_model(arm: mjcf.RootElement) -> None:
    body = arm.find("body", "upper")
    version = arm.version
    body.pos[2] = 2.5
    assert 'pos="0 0 2.5"' in body.to_xml_string()
    assert arm.version > version


def _models_named(name: str) -> int:
    gc.collect()
    return sum(1 for o in gc.get_objects() if type(o) is mjcf.RootElement and o.model == name)


def test_a_model_nothing_holds_is_freed_however_its_arrays_were_given() -> None:
    """Elements and their arrays refer to each other, a cycle Python's collector frees
    only if it sees every reference; numpy's arrays hide their base from it, so an array
    kept as a view of another element's array would keep the model, and all it holds,
    alive for good (every environment made and closed in a training loop)."""

    def build() -> None:
        model = mjcf.from_xml_string(
            '<mujoco model="dropped"><default><joint damping="2"/></default>'
            '<default><joint axis="0 1 0"/></default><worldbody>'  # merged into the first
            '<body name="b" pos="0 0 1"><joint name="j"/>'
            '<geom name="g" type="capsule" size="0.1"/></body>'
            "</worldbody></mujoco>"
        )
        body = model.find("body", "b")
        body.pos[2] = 2.0  # read from text, edited in place
        body.add("site", name="s", pos=[0, 0, 1], quat=np.array([1.0, 0, 0, 0]))
        model.find("joint", "j").set_attributes(axis=[0, 1, 0], range=[-1, 1])
        model.find("geom", "g").fromto = [0, 0, 0, *body.pos]
        model.find("site", "s").set_attributes(pos=model.find("joint", "j").axis)
        mjcf.commit_defaults(model)
        model.compile_model()
        child = mjcf.RootElement(model="child")
        child.visual.headlight.set_attributes(ambient=[0.4, 0.4, 0.4], diffuse=[0.8, 0.8, 0.8])
        child.worldbody.add("geom", size=[0.1])
        model.find("site", "s").attach(child).detach()  # the child's settings shared, then its own
        model.compile_model()

    before = _models_named("dropped")
    for _ in range(3):
        build()
    assert _models_named("dropped") == before


def test_class_is_dclass(arm: mjcf.RootElement) -> None:
    arm.default.add("default", dclass="thick").geom.size = [0.1]
    geom = arm.find("geom", "upper")
    geom.dclass = "thick"
    assert geom.dclass is arm.find("default", "thick")
    assert getattr(geom, "class") is geom.dclass
    assert 'class="thick"' in geom.to_xml_string()
    physics = mjcf.Physics.from_mjcf_model(arm)
    assert physics.bind(geom).size[0] == 0.05  # own size wins over the class's


def test_children_by_tag_and_name(arm: mjcf.RootElement) -> None:
    upper = arm.find("body", "upper")
    lower = upper.add("body", name="lower")
    assert arm.worldbody.body["upper"].body["lower"] is lower
    assert upper.geom[0] is arm.find("geom", "upper")
    assert upper.get_children("joint")[0].name == "shoulder"
    assert upper.all_children()[-1] is lower
    assert upper.inertial is None and upper.freejoint is None  # absent until added
    inertial = upper.add("inertial", pos=[0, 0, 0], mass=2)
    assert upper.inertial is inertial and "<inertial" in arm.to_xml_string()
    with pytest.raises(mjcf.SchemaError, match="only one <inertial>"):
        upper.add("inertial", pos=[0, 0, 0], mass=3)
    del upper.inertial  # as dm_control: removes it
    assert upper.inertial is None and inertial.is_removed
    flag = arm.option.flag  # other once-only children are there when first read
    assert flag.tag == "flag" and "<flag" not in arm.to_xml_string()


def test_find_and_find_all_in_declaration_order() -> None:
    model = mjcf.from_path(GYM_ASSETS / "humanoid.xml")
    joints = model.find_all("joint")
    assert joints[0].tag == "freejoint" or joints[0].type == "free"
    assert [j.name for j in joints[1:4]] == ["abdomen_z", "abdomen_y", "abdomen_x"]
    assert model.find("joint", "abdomen_y") is joints[2]
    assert model.find("body", "nonexistent") is None
    thigh = model.find("body", "right_thigh")
    assert {g.name for g in thigh.find_all("geom")} >= {"right_thigh1", "right_shin1"}
    assert len(thigh.find_all("body", immediate_children_only=True)) == 1
    assert model.find_all("motor") == model.find_all("actuator")
    with pytest.raises(mjcf.NotFoundError, match="did you mean 'joint'"):
        model.find_all("jiont")


def test_references_accept_elements_and_follow_renames(arm: mjcf.RootElement) -> None:
    shoulder = arm.find("joint", "shoulder")
    motor = arm.actuator.add("motor", joint=shoulder, gear=[10])
    assert motor.joint is shoulder
    shoulder.name = "hip"
    assert 'joint="hip"' in motor.to_xml_string()
    sensor = arm.sensor.add("jointpos", joint="hip")
    assert sensor.joint is shoulder  # a name resolves to the element on reading
    with pytest.raises(mjcf.InvalidReferenceError, match="refers to a joint"):
        motor.joint = arm.find("geom", "upper")


def test_reference_to_unnamed_element_gets_a_name(arm: mjcf.RootElement) -> None:
    hinge = arm.find("body", "upper").add("joint", axis=[1, 0, 0])
    arm.actuator.add("motor", joint=hinge)
    physics = mjcf.Physics.from_mjcf_model(arm)
    physics.bind(arm.actuator.motor[0]).ctrl = 1.0
    physics.step(10)
    assert physics.bind(hinge).qvel[0] != 0
    reloaded = mjcf.from_xml_string(arm.to_xml_string())
    assert reloaded.actuator.motor[0].joint.tag == "joint"


def test_rename_and_remove_update_names(arm: mjcf.RootElement) -> None:
    geom = arm.find("geom", "upper")
    geom.name = "bone"
    assert arm.find("geom", "bone") is geom and arm.find("geom", "upper") is None
    geom.remove()
    assert arm.find("geom", "bone") is None and geom.parent is None
    arm.find("body", "upper").add("geom", name="bone", size=[0.1])  # the name is free again


def test_set_attributes_is_all_or_nothing(arm: mjcf.RootElement) -> None:
    geom = arm.find("geom", "upper")
    before = arm.to_xml_string()
    with pytest.raises(mjcf.AttributeValueError):
        geom.set_attributes(rgba=[1, 0, 0, 1], size=[1, 2, 3, 4])
    assert arm.to_xml_string() == before
    geom.set_attributes(rgba=[1, 0, 0, 1], size=[0.1, 0.2])
    assert geom.rgba.tolist() == [1, 0, 0, 1]


def test_copy_and_pickle_whole_models(arm: mjcf.RootElement) -> None:
    duplicate = copy.deepcopy(arm)
    duplicate.find("body", "upper").pos = [1, 1, 1]
    assert arm.find("body", "upper").pos.tolist() == [0, 0, 1]
    restored = pickle.loads(pickle.dumps(arm))
    assert restored.to_xml_string() == arm.to_xml_string()
    assert restored.find("joint", "shoulder").parent is restored.find("body", "upper")


def test_compile_model_and_bind(arm: mjcf.RootElement) -> None:
    physics = arm.compile_model()
    shoulder = arm.find("joint", "shoulder")
    physics.bind(shoulder).qpos = 0.5
    assert physics.data.qpos[0] == 0.5
    assert physics.named.data.qpos["shoulder"] == 0.5


def test_escaped_separators_keep_slashes_in_names() -> None:
    text = (
        '<mujoco><worldbody><body name="a/b"><geom name="g/1" size=".1"/></body>'
        "</worldbody></mujoco>"
    )
    with pytest.raises(mjcf.NameClashError, match="escape_separators"):
        mjcf.from_xml_string(text)
    root = mjcf.from_xml_string(text, escape_separators=True)
    assert root.find("body", "a\\/b") is not None
    physics = mjcf.Physics.from_mjcf_model(root)
    assert physics.named.model.body_pos["a/b"].shape == (3,)


def test_element_api_names_do_not_shadow_mjcf() -> None:
    """No MJCF attribute or child tag collides with a public Element/RootElement name."""
    api = {n for cls in (mjcf.Element, mjcf.RootElement) for n in dir(cls) if not n.startswith("_")}
    api -= {"model"}  # the <mujoco model> attribute is the RootElement.model property
    api -= {"attach"}  # Element.attach composes models; MuJoCo's <attach> is get_children
    for spec in schema.all_specs():
        clashes = api & (set(spec.attributes) | set(spec.children))
        assert not clashes, f"<{spec.tag}> {clashes}"


def test_written_text_follows_every_change(arm: mjcf.RootElement) -> None:
    """Writing twice reuses unchanged elements' text; every kind of change shows."""
    body = arm.find("body", "upper")
    geom = arm.find("geom", "upper")
    assert 'pos="0 0 1"' in arm.to_xml_string()
    body.pos[0] = 7
    assert 'pos="7 0 1"' in arm.to_xml_string()
    geom.rgba = [0, 1, 0, 1]
    assert 'rgba="0 1 0 1"' in arm.to_xml_string()
    del geom.rgba
    assert "rgba" not in arm.to_xml_string()
    body.pos = [1 / 3, 0, 0]
    assert 'pos="0.33 0 0"' in arm.to_xml_string(precision=2)
    assert 'pos="0.3333333333333333 0 0"' in arm.to_xml_string()
