"""Names have one owner, `NameScope`: every way of giving an element a name (add, set,
set_attributes, parse, include_copy, deepcopy, attach) obeys the same rules and fails
the same way, leaving the model as it was."""

import copy

import mujoco
import pytest

import mjcf

TAKEN = r"the name 'tip' is already used by another geom in model 'arm'"


def _arm() -> mjcf.RootElement:
    arm = mjcf.RootElement(model="arm")
    body = arm.worldbody.add("body", name="upper")
    body.add("geom", name="tip", size=[0.1])
    body.add("geom", name="pad", size=[0.1])
    return arm


def _refused(model: mjcf.RootElement, change, match: str = TAKEN) -> None:
    before = model.to_xml_string()
    with pytest.raises(mjcf.NameClashError, match=match):
        change()
    assert model.to_xml_string() == before


def test_every_way_of_taking_a_name_is_refused_alike() -> None:
    arm = _arm()
    body, pad = arm.find("body", "upper"), arm.find("geom", "pad")
    _refused(arm, lambda: body.add("geom", name="tip", size=[1]))
    _refused(arm, lambda: body.insert("geom", 0, name="tip", size=[1]))
    _refused(arm, lambda: setattr(pad, "name", "tip"))
    _refused(arm, lambda: pad.set_attributes(name="tip", rgba=[1, 0, 0, 1]))
    other = mjcf.RootElement(model="other")
    other.worldbody.add("geom", name="tip", size=[1])
    _refused(arm, lambda: arm.include_copy(other), r"'tip' is already used by another geom")
    xml = '<mujoco model="arm"><worldbody><geom name="tip" size="1"/><body><geom name="tip" '
    with pytest.raises(mjcf.NameClashError, match=r"<string>:1: .*" + TAKEN):
        mjcf.from_xml_string(xml + 'size="1"/></body></worldbody></mujoco>')


def test_renaming_to_its_own_name_and_back_is_free() -> None:
    arm = _arm()
    pad = arm.find("geom", "pad")
    pad.name = "pad"
    pad.set_attributes(name="pad2")
    assert arm.find("geom", "pad") is None and arm.find("geom", "pad2") is pad
    del pad.name
    assert arm.find("geom", "pad2") is None
    arm.find("body", "upper").add("geom", name="pad2", size=[1])  # free again


def test_a_body_cannot_be_called_world_however_it_is_named() -> None:
    xml = '<mujoco><worldbody><body name="world"><geom size="1"/></body></worldbody></mujoco>'
    with pytest.raises(ValueError, match="repeated name 'world'"):
        mujoco.MjModel.from_xml_string(xml)  # MuJoCo's verdict
    with pytest.raises(mjcf.NameClashError, match="'world' is already used by another body"):
        mjcf.from_xml_string(xml)
    model = mjcf.RootElement()
    _refused(model, lambda: model.worldbody.add("body", name="world"), "'world'")
    body = model.worldbody.add("body", name="b")
    _refused(model, lambda: setattr(body, "name", "world"), "'world'")


def test_include_copy_of_a_model_whose_attached_model_clashes_changes_nothing() -> None:
    scene = mjcf.RootElement(model="scene")
    scene.attach(_arm())
    source = mjcf.RootElement(model="source")
    source.worldbody.add("body", name="box")
    source.attach(_arm())  # an unnamed frame holding another 'arm'
    before = scene.to_xml_string()
    with pytest.raises(mjcf.NameClashError, match="a model named 'arm' is already attached"):
        scene.include_copy(source)
    assert scene.to_xml_string() == before and scene.find("body", "box") is None


def test_include_copy_into_an_unnamed_element_refuses_a_name_taken_and_changes_nothing() -> None:
    model = mjcf.from_xml_string('<mujoco><worldbody><body name="x"/></worldbody></mujoco>')
    other = mjcf.from_xml_string('<mujoco><worldbody><body name="x"/></worldbody></mujoco>')
    unnamed = model.worldbody.add("body")
    before = model.to_xml_string()
    _refused(model, lambda: unnamed.include_copy(other.find("body", "x")), "'x'")
    assert unnamed.name is None and model.to_xml_string() == before
    fresh = model.worldbody.add("body")
    fresh.include_copy(mjcf.from_xml_string(before.replace('"x"', '"y"')).find("body", "y"))
    assert model.find("body", "y") is fresh  # the merged name is the element's
    copy.deepcopy(model)  # a model copies, and reads back, as MuJoCo compiles it
    mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(model.to_xml_string()))


def test_the_same_model_attached_twice_gets_numbered_names() -> None:
    scene = mjcf.RootElement(model="scene")
    frames = [scene.attach(_arm()) for _ in range(3)]
    assert [f.attached_model.model for f in frames] == ["arm", "arm_1", "arm_2"]
    with pytest.raises(mjcf.NameClashError, match="'arm_1' is already attached"):
        frames[0].attached_model.model = "arm_1"
    assert frames[0].attached_model.model == "arm"
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_GEOM, "arm_2/tip") >= 0


@pytest.mark.parametrize("how", ["parsed", "set", "copied", "attached"])
def test_escaped_names_are_written_as_mujoco_sees_them(how: str) -> None:
    if how == "parsed":
        xml = '<mujoco model="m"><worldbody><geom name="a/b" size="1"/></worldbody></mujoco>'
        model = mjcf.from_xml_string(xml, escape_separators=True)
    else:
        model = mjcf.RootElement(model="m")
        model.worldbody.add("geom", name="a\\/b", size=[1])
    if how == "copied":
        model = copy.deepcopy(model)
    scene = model
    if how == "attached":
        scene = mjcf.RootElement(model="scene")
        scene.attach(model)
    prefix = "m/" if how == "attached" else ""
    assert f'name="{prefix}a/b"' in scene.to_xml_string()
    assert model.find("geom", "a\\/b").full_identifier == f"{prefix}a/b"
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_GEOM, f"{prefix}a/b") == 0
