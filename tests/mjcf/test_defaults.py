"""commit_defaults and include_copy on real models: the compiled model is unchanged by
committing, and including copies elements without a name scope or fails cleanly."""

from __future__ import annotations

import copy
import pickle
import warnings
from collections.abc import Callable

import mujoco
import pytest

import mjcf
from tests.conftest import ROBOTIQ, UR5E, gym_model
from tests.mjcf.compare import model_differences


def _commit_keeps_the_compiled_model(model: mjcf.RootElement) -> None:
    before = mjcf.Physics.from_mjcf_model(model).model
    mjcf.commit_defaults(model)
    for each in (model, *[f.attached_model for f in model.find_all("attachment_frame")]):
        assert each.default.all_children() == []
        assert not any("class" in e.get_attributes() or "childclass" in e.get_attributes()
                       for e in each.iter())  # fmt: skip
    after = mjcf.Physics.from_mjcf_model(model).model
    assert model_differences(before, after) == []
    stock = mujoco.MjModel.from_xml_string(model.to_xml_string(), model.get_assets())
    assert model_differences(before, stock) == []


def test_commit_defaults_ur5e(menagerie) -> None:
    _commit_keeps_the_compiled_model(mjcf.from_path(UR5E))


def test_commit_defaults_gripper_with_actuator_classes(menagerie) -> None:
    gripper = mjcf.from_path(ROBOTIQ)
    actuator = gripper.find("actuator", "fingers_actuator")
    assert actuator.get_attribute_xml_string("class") == "2f85"
    assert actuator.biastype is None  # affine, from its class
    _commit_keeps_the_compiled_model(gripper)
    assert actuator.biastype == "affine"


@pytest.mark.parametrize("name", ["humanoid", "walker2d", "ant", "half_cheetah"])
def test_commit_defaults_gymnasium(name: str) -> None:
    """walker2d's feet set friction="0.9" over a default of three numbers: the other two
    stay the default's. MuJoCo's compile warnings reach Python's warnings: half_cheetah
    still sets the deprecated `settotalmass`, the others compile without a word."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _commit_keeps_the_compiled_model(mjcf.from_path(gym_model(name)))
    messages = {str(w.message).split(":")[0] for w in caught}
    if name == "half_cheetah":
        assert messages == {"compiler attribute 'settotalmass' is deprecated and will be "
                            "removed in a future release"}  # fmt: skip
    else:
        assert messages == set()


def test_commit_defaults_of_a_composed_scene(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    scene.default.geom.rgba = [1, 0, 0, 1]
    scene.default.joint.damping = 2
    scene.worldbody.add("geom", type="plane", size=[2, 2, 0.1])
    arm = mjcf.from_path(UR5E)
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    scene.attach(arm)
    spare = mjcf.from_path(ROBOTIQ)
    spare.model = "spare"
    scene.attach(spare).pos = [1, 0, 0]
    _commit_keeps_the_compiled_model(scene)


def _compiled(model: mjcf.RootElement) -> mujoco.MjModel:
    return mjcf.Physics.from_mjcf_model(model).model


def test_commit_defaults_of_one_element_as_dm_control(menagerie) -> None:
    """Given one element, only that element gets its values; classes and the rest of
    the model stay as they are."""
    arm = mjcf.from_path(UR5E)
    before = _compiled(arm)
    elbow = arm.find("joint", "elbow_joint")  # class size3_limited, inside childclass ur5e
    shoulder = arm.find("joint", "shoulder_lift_joint")
    defaults_before = arm.default.to_xml_string()
    mjcf.commit_defaults(elbow)
    assert elbow.range.tolist() == [-3.1415, 3.1415]  # its own class
    assert elbow.armature == 0.1 and elbow.axis.tolist() == [0, 1, 0]  # inherited
    assert elbow.get_attribute_xml_string("class") == "size3_limited"  # its class stays
    assert shoulder.armature is None  # the other joints are left alone
    assert arm.default.to_xml_string() == defaults_before
    assert model_differences(before, _compiled(arm)) == []


def test_commit_defaults_limited_to_attributes(menagerie) -> None:
    arm = mjcf.from_path(UR5E)
    before = _compiled(arm)
    visual = arm.find("body", "base").geom[0]  # class visual: type, contype, conaffinity, group
    mjcf.commit_defaults(visual, attributes=["group", "contype"])
    assert (visual.group, visual.contype) == (2, 0)
    assert visual.type is None and visual.conaffinity is None  # not asked for
    collision = arm.find("body", "shoulder_link").geom[3]
    mjcf.commit_defaults(collision, "type")  # one name as a string, as dm_control code does
    assert collision.type == "capsule" and collision.group is None
    site = arm.find("site", "attachment_site")  # a name the element lacks is left alone
    mjcf.commit_defaults(site, ["rgba", "friction"])
    assert site.rgba.tolist() == [0.5, 0.5, 0.5, 0.3]
    assert model_differences(before, _compiled(arm)) == []


def test_commit_defaults_of_a_model_limited_to_attributes(menagerie) -> None:
    """Every element of the model and of the models attached to it gets those
    attributes; the classes stay for the others, and the compiled model is the same
    (stock MuJoCo agrees)."""
    arm = mjcf.from_path(UR5E)
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    before = _compiled(arm)
    classes_before = [d.dclass for d in arm.find_all("default")]
    mjcf.commit_defaults(arm, attributes=["group", "ctrlrange"])
    geoms = arm.find_all("geom")
    assert all(g.group is not None for g in geoms)  # UR5e and gripper geoms all have one
    assert all(a.ctrlrange is not None for a in arm.find_all("actuator"))
    assert [d.dclass for d in arm.find_all("default")] == classes_before
    assert any(g.contype is None and g.dclass is not None for g in geoms)
    assert model_differences(before, _compiled(arm)) == []
    stock = mujoco.MjModel.from_xml_string(arm.to_xml_string(), arm.get_assets())
    assert model_differences(before, stock) == []


def test_commit_defaults_refuses_an_attribute_no_class_can_set(menagerie) -> None:
    arm = mjcf.from_path(UR5E)
    before = arm.to_xml_string()
    joint = arm.find("joint", "elbow_joint")
    with pytest.raises(mjcf.UnknownAttributeError, match=r"elbow_joint.*'armatur'.*'armature'"):
        mjcf.commit_defaults(joint, attributes=["range", "armatur"])
    with pytest.raises(AttributeError, match="no default class sets an attribute 'nonsense'"):
        mjcf.commit_defaults(arm, attributes=["nonsense"])
    assert arm.to_xml_string() == before


# -- include_copy -------------------------------------------------------------------------------


def _base() -> mjcf.RootElement:
    base = mjcf.RootElement(model="base")
    base.compiler.angle = "radian"
    base.worldbody.add("body", name="b1").add("geom", name="g1", size=[0.1])
    return base


def _extra(angle: str = "radian") -> mjcf.RootElement:
    extra = mjcf.RootElement(model="extra")
    extra.compiler.angle = angle
    body = extra.worldbody.add("body", name="b2", pos=[1, 0, 0])
    hinge = body.add("joint", name="hinge")
    body.add("geom", name="g2", size=[0.1])
    extra.actuator.add("motor", name="m2", joint=hinge)
    extra.default.geom.rgba = [0, 0, 1, 1]
    return extra


def test_include_copy_merges_without_a_scope() -> None:
    base, extra = _base(), _extra()
    extra_before = extra.to_xml_string()
    base.include_copy(extra)
    assert base.find("geom", "g2") is not None and base.find("geom", "extra/g2") is None
    motor = base.find("actuator", "m2")
    assert motor.joint is base.find("joint", "hinge")  # references point at the copies
    assert extra.to_xml_string() == extra_before  # the source is untouched
    physics = mjcf.Physics.from_mjcf_model(base)
    assert physics.model.nbody == 3 and physics.model.nu == 1
    parts = mjcf.RootElement(model="parts")
    parts.worldbody.add("body", pos=[0, 0, 1]).add("site", name="tip")
    base.find("body", "b1").include_copy(parts.worldbody.body[0])  # same tag: merged in
    assert base.find("site", "tip").parent is base.find("body", "b1")
    assert base.find("body", "b1").pos.tolist() == [0, 0, 1]


def test_include_copy_conflicts_and_override() -> None:
    base = _base()
    before = base.to_xml_string()
    with pytest.raises(mjcf.AttachmentError, match=r"`angle`: 'radian' here and 'degree'"):
        base.include_copy(_extra("degree"))
    assert base.to_xml_string() == before
    base.include_copy(_extra("degree"), override_attributes=True)
    assert base.compiler.angle == "degree" and base.find("body", "b2") is not None
    moved = mjcf.RootElement(model="moved")  # overriding: a named element takes the values
    moved.worldbody.add("body", name="b2", pos=[0, 1, 2]).add("site", name="mark")
    base.include_copy(moved, override_attributes=True)
    assert base.find("body", "b2").pos.tolist() == [0, 1, 2]
    assert base.find("site", "mark").parent is base.find("body", "b2")
    assert mjcf.Physics.from_mjcf_model(base).model.nbody == 3  # merged, not added


def test_include_copy_name_collisions_change_nothing() -> None:
    base = _base()
    base.include_copy(_extra())
    before = base.to_xml_string()
    with pytest.raises(mjcf.NameClashError, match=r"the name 'b2' is already used by another body"):
        base.include_copy(_extra())
    assert base.to_xml_string() == before
    clash = mjcf.RootElement(model="clash")
    clash.worldbody.add("body", name="fresh")
    clash.actuator.add("motor", name="m2", joint="j")
    clash.find("body", "fresh").add("joint", name="j")
    with pytest.raises(mjcf.NameClashError, match=r"'m2' is already used by another actuator"):
        base.include_copy(clash)
    assert base.to_xml_string() == before
    with pytest.raises(mjcf.SchemaError, match="same kind"):
        base.include_copy(clash.worldbody)


# -- a default that changes the model by being there, empty ---------------------------------

_SHORTCUT_TAGS = sorted(
    spec.tag for spec in mjcf.schema.all_specs() if spec.matters_empty
)  # fmt: skip


def _arm_with_default(default: str) -> str:
    return f"""<mujoco><default>{default}<default class="c"/></default>
      <worldbody><body><joint name="j"/><geom size=".1" mass="1"/></body></worldbody>
      <actuator><general joint="j"/><general joint="j" class="c"/></actuator></mujoco>"""


def test_the_schema_knows_which_defaults_matter_empty() -> None:
    assert {"position", "velocity", "muscle"} <= set(_SHORTCUT_TAGS)
    assert "general" not in _SHORTCUT_TAGS and "geom" not in _SHORTCUT_TAGS


def _outcome(compile_: Callable[[], mujoco.MjModel]) -> mujoco.MjModel | str:
    try:
        return compile_()
    except (ValueError, mjcf.CompileError) as error:
        return "refused: " + str(error).split(" in actuator")[0].splitlines()[0]


def _same_outcome(stock: mujoco.MjModel | str, ours: mujoco.MjModel | str) -> bool:
    if isinstance(stock, str) or isinstance(ours, str):
        return stock == ours
    return model_differences(stock, ours) == []


@pytest.mark.parametrize("tag", _SHORTCUT_TAGS)
def test_an_empty_actuator_shortcut_in_a_default_compiles_as_in_mujoco(tag: str) -> None:
    """MuJoCo compiles the model, or refuses it (an adhesion or damper default limits
    controls, and the actuators set no range), and so does mjcf."""
    xml = _arm_with_default(f"<{tag}/>")
    stock = _outcome(lambda: mujoco.MjModel.from_xml_string(xml))
    without = _outcome(lambda: mujoco.MjModel.from_xml_string(_arm_with_default("")))
    assert not _same_outcome(stock, without), f"<{tag}/> changes nothing: why is it listed?"
    model = mjcf.from_xml_string(xml)
    for each in (model, copy.deepcopy(model), pickle.loads(pickle.dumps(model))):
        assert _same_outcome(stock, _outcome(lambda m=each: mjcf.Physics.from_mjcf_model(m).model))
    # A <general> takes its type from the shortcut: no attribute of its own says so.
    with pytest.raises(mjcf.AttributeValueError, match=f"has a <{tag}>.* cannot express"):
        mjcf.commit_defaults(model)
    assert model.default.get_children(tag).get_attributes() == {}


def test_reading_a_default_on_demand_changes_nothing_and_adding_it_does() -> None:
    model = mjcf.from_xml_string(_arm_with_default(""))
    plain = mjcf.Physics.from_mjcf_model(model).model
    assert model.default.position.kp is None
    assert model.default.position.get_attributes() == {}
    assert "<position" not in model.to_xml_string()
    assert model_differences(plain, mjcf.Physics.from_mjcf_model(model).model) == []
    assert model.is_same_as(mjcf.from_xml_string(_arm_with_default("")))

    model.default.add("position")
    stock = mujoco.MjModel.from_xml_string(_arm_with_default("<position/>"))
    assert model_differences(stock, mjcf.Physics.from_mjcf_model(model).model) == []
    assert model.is_same_as(mjcf.from_xml_string(_arm_with_default("<position/>")))
    assert not model.is_same_as(mjcf.from_xml_string(_arm_with_default("")))


def test_an_empty_default_shortcut_survives_include_copy() -> None:
    source = mjcf.from_xml_string("<mujoco><default><velocity/></default></mujoco>")
    model = mjcf.from_xml_string(_arm_with_default(""))
    assert model.default.velocity.kv is None  # made on demand in the target first
    model.include_copy(source)
    stock = mujoco.MjModel.from_xml_string(_arm_with_default("<velocity/>"))
    assert model_differences(stock, mjcf.Physics.from_mjcf_model(model).model) == []


def test_commit_defaults_of_actuators_whose_class_sets_other_shortcuts() -> None:
    """dm_control's case: a class sets <general>, <motor>, <position kp> and <velocity
    kv>. A motor's own shortcut sets its gain and bias, so it takes only what every
    actuator takes (forcelimited, forcerange); a position, for which MuJoCo reads the
    velocity's gain in a way no attribute says, is refused rather than committed wrong.
    Each committed model compiles as MuJoCo compiles the classes."""

    def model(actuator: str) -> mjcf.RootElement:
        root = mjcf.RootElement()
        root.default.general.forcelimited = "true"
        root.default.motor.forcerange = [-2, 3]
        root.default.position.kp = 0.1
        root.default.velocity.kv = 0.2
        joint = root.worldbody.add("body").add("joint", name="j")
        joint.parent.add("geom", size=[0.1])
        root.actuator.add(actuator, joint=joint)
        return root

    root = model("motor")
    expected = mujoco.MjModel.from_xml_string(root.to_xml_string())
    motor = root.actuator.motor[0]
    mjcf.commit_defaults(motor)
    assert motor.forcelimited == "true" and motor.forcerange.tolist() == [-2, 3]
    assert set(motor.get_attributes()) == {"joint", "forcelimited", "forcerange"}
    assert model_differences(expected, mjcf.Physics.from_mjcf_model(root).model) == []
    root = model("position")
    before = root.to_xml_string()
    with pytest.raises(mjcf.AttributeValueError, match=r"<velocity kv>.*cannot commit"):
        mjcf.commit_defaults(root.actuator.position[0])
    assert root.to_xml_string() == before
    reading = mjcf.from_xml_string(
        """<mujoco><default><position kp="5"/><general ctrlrange="-1 1"/></default>
        <worldbody><body><joint name="j"/><geom size=".1"/></body></worldbody>
        <actuator><position joint="j"/></actuator></mujoco>"""
    )
    expected = mjcf.Physics.from_mjcf_model(reading).model
    mjcf.commit_defaults(reading)  # a <general> of settings only: committed
    assert reading.actuator.position[0].kp == 5
    assert model_differences(expected, mjcf.Physics.from_mjcf_model(reading).model) == []


def test_the_top_level_default_class_cannot_be_renamed_through_the_api() -> None:
    """As the reader refuses it (MuJoCo: "top-level default class 'main' cannot be
    renamed"), and the model stays as it was."""
    model = mjcf.RootElement()
    model.default.geom.rgba = [1, 0, 0, 1]
    before = model.to_xml_string()
    with pytest.raises(mjcf.AttributeValueError, match="top-level default class is 'main'"):
        model.default.dclass = "mine"
    assert model.to_xml_string() == before
    model.default.dclass = "main"  # its own name, as MuJoCo takes it
    mjcf.Physics.from_mjcf_model(model)
