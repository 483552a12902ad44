"""Composing models: attach, detach, scoped names, isolated defaults, converted compiler
settings, helpers and bad input, on the real UR5e, Robotiq 2F-85 and gymnasium models."""

from __future__ import annotations

import copy
import re

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import ROBOTIQ, UR5E, gym_model
from tests.mjcf.attaching import differences_from_alone, top_bodies

Obj = mujoco.mjtObj


def arm_with_gripper(name: str) -> mjcf.RootElement:
    arm = mjcf.from_path(UR5E)
    arm.model = name
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    return arm


def two_arm_scene() -> tuple[mjcf.RootElement, list[mjcf.RootElement]]:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", name="floor", type="plane", size=[2, 2, 0.1])
    arms = [arm_with_gripper("left"), arm_with_gripper("right")]
    for y, arm in zip((-0.5, 0.5), arms, strict=True):
        scene.attach(arm).pos = [0, y, 0]
    return scene, arms


# -- the UR5e with the 2F-85, twice ---------------------------------------------------------


def test_two_arms_with_grippers_compile_and_move(menagerie) -> None:
    scene, arms = two_arm_scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    named = physics.named.data.ctrl
    for side in ("left", "right"):
        for actuator in ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2"):
            assert mujoco.mj_name2id(physics.model, Obj.mjOBJ_ACTUATOR, f"{side}/{actuator}") >= 0
        named[f"{side}/robotiq_2f85/fingers_actuator"] = 255.0
    assert physics.model.nu == 2 * 7
    left, right = arms
    assert left.find("actuator", "robotiq_2f85/fingers_actuator").full_identifier == (
        "left/robotiq_2f85/fingers_actuator"
    )
    physics.bind(left.find("actuator", "shoulder_lift")).ctrl = -1.0
    physics.bind(right.find("actuator", "elbow")).ctrl = 1.0
    joints = {
        arm.model: [arm.find("joint", name) for name in ("shoulder_lift_joint", "elbow_joint")]
        for arm in arms
    }
    drivers = [arm.find("joint", "robotiq_2f85/right_driver_joint") for arm in arms]
    physics.step(200)
    assert physics.bind(joints["left"][0]).qpos[0] < -0.2
    assert physics.bind(joints["right"][1]).qpos[0] > 0.2
    assert (
        abs(physics.bind(joints["left"][1]).qpos[0] - physics.bind(joints["right"][1]).qpos[0])
        > 0.1
    )
    assert np.all(physics.bind(drivers).qpos > 0.1)  # both grippers close
    assert np.all(np.isfinite(physics.data.qpos))


def test_names_are_scoped_and_found_from_the_parent(menagerie) -> None:
    scene, (left, _) = two_arm_scene()
    pad = scene.find("geom", "left/robotiq_2f85/right_pad1")
    assert pad is not None and pad.root.model == "robotiq_2f85"
    assert pad is left.find("geom", "robotiq_2f85/right_pad1")
    assert pad.full_identifier == "left/robotiq_2f85/right_pad1"
    assert pad.prefixed_identifier(left) == "robotiq_2f85/right_pad1"
    assert scene.find("joint", "right/elbow_joint").full_identifier == "right/elbow_joint"
    assert scene.find("attachment_frame", "left/robotiq_2f85") is mjcf.get_attachment_frame(
        pad.root
    )
    assert len(scene.find_all("actuator")) == 14
    assert len(scene.find_all("actuator", exclude_attachments=True)) == 0


# -- gymnasium's models, many times ---------------------------------------------------------


@pytest.mark.parametrize("count", [1, 10, 50])
@pytest.mark.parametrize("name", ["ant", "humanoid", "half_cheetah"])
def test_gymnasium_models_attached_many_times(name: str, count: int) -> None:
    alone = mujoco.MjModel.from_xml_path(str(gym_model(name)))
    arena = mjcf.RootElement(model="arena")
    arena.worldbody.add("geom", name="ground", type="plane", size=[100, 100, 0.1])
    arena.worldbody.add("light", pos=[0, 0, 10])
    original = mjcf.from_path(gym_model(name))
    for i in range(count):
        robot = copy.deepcopy(original) if i % 2 else mjcf.from_path(gym_model(name))
        robot.model = f"{name}_{i}"
        arena.attach(robot).pos = [3 * i, 0, 0]
    physics = mjcf.Physics.from_mjcf_model(arena)
    model = physics.model
    assert model.nbody == 1 + count * (alone.nbody - 1)
    assert model.njnt == count * alone.njnt
    assert model.nu == count * alone.nu
    assert model.ngeom == 1 + count * alone.ngeom
    assert model.nq == count * alone.nq
    free = [j for j in range(alone.njnt) if alone.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    for i in range(count):
        for j in free:
            scoped = f"{name}_{i}/{mujoco.mj_id2name(alone, Obj.mjOBJ_JOINT, j)}"
            index = mujoco.mj_name2id(model, Obj.mjOBJ_JOINT, scoped)
            assert model.jnt_type[index] == mujoco.mjtJoint.mjJNT_FREE
    last = f"{name}_{count - 1}/"
    assert differences_from_alone(alone, model, last, placed=top_bodies(alone)) == []
    physics.step(5)
    assert np.all(np.isfinite(physics.data.qpos))


# -- detach -----------------------------------------------------------------------------------


_SETTINGS = ("compiler", "option", "size", "statistic", "visual")


def _without_settings(xml: str) -> str:
    sections = "|".join(_SETTINGS)
    return re.sub(rf"\n  <({sections})\b.*?(/>|</\1>)", "", xml, flags=re.S)


def _detach_restores(parent: mjcf.RootElement, attach, detach_frame: bool) -> mjcf.Element:
    """Detaching takes out all the child brought, but the global settings merged into
    the parent, which stay as the attach left them, as in dm_control."""
    before = parent.to_xml_string()
    frame = attach()
    child = frame.attached_model
    merged = {tag: getattr(parent, tag).to_xml_string() for tag in _SETTINGS}
    assert parent.to_xml_string() != before
    if detach_frame:
        frame.detach()
    else:
        child.detach()
    assert _without_settings(parent.to_xml_string()) == _without_settings(before)
    assert {tag: getattr(parent, tag).to_xml_string() for tag in _SETTINGS} == merged
    assert mjcf.get_attachment_frame(child) is None and child.parent_model is None
    return child


@pytest.mark.parametrize("detach_frame", [True, False], ids=["frame.detach", "child.detach"])
def test_detach_restores_the_parent_byte_for_byte(menagerie, detach_frame: bool) -> None:
    arm = mjcf.from_path(UR5E)
    gripper = mjcf.from_path(ROBOTIQ)
    site = arm.find("site", "attachment_site")
    wrist = arm.find("body", "wrist_3_link")
    _detach_restores(arm, lambda: site.attach(gripper), detach_frame)
    _detach_restores(arm, lambda: wrist.attach(gripper), detach_frame)
    _detach_restores(arm, lambda: arm.attach(gripper), detach_frame)

    def free() -> mjcf.Element:
        frame = arm.attach(gripper)
        frame.add("freejoint", name="float")
        frame.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[0.1, 0.1, 0.1])
        mjcf.Physics.from_mjcf_model(arm)  # keys of both layouts are filled in
        return frame

    _detach_restores(arm, free, detach_frame)
    assert arm.find("joint", "float") is None
    alone = mjcf.from_path(ROBOTIQ)
    # The gripper keeps a copy of the settings it shared with the arm, as in dm_control.
    assert _without_settings(gripper.to_xml_string()) == _without_settings(alone.to_xml_string())
    assert (gripper.option.integrator, gripper.option.impratio) == ("implicitfast", 10)


def test_detach_nested_attachments_and_keyframes(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    scene.keyframe.add("key", name="start", time=1.0)
    base = mjcf.RootElement(model="base")
    chassis = base.worldbody.add("body", name="chassis", pos=[0, 0, 0.2])
    chassis.add("joint", name="drive", type="slide", axis=[1, 0, 0])
    chassis.add("geom", type="box", size=[0.3, 0.3, 0.1])
    mount = chassis.add("site", name="mount", pos=[0, 0, 0.1])
    arm = mjcf.from_path(UR5E)
    arm.model = "arm"
    gripper = mjcf.from_path(ROBOTIQ)
    gripper.model = "gripper"
    arm.find("site", "attachment_site").attach(gripper)
    scene.attach(base)
    scene_before = scene.to_xml_string()
    base_before = base.to_xml_string()
    mount.attach(arm)
    pad = scene.find("geom", "base/arm/gripper/right_pad1")
    assert pad is not None and pad.full_identifier == "base/arm/gripper/right_pad1"
    physics = mjcf.Physics.from_mjcf_model(scene)
    names = [physics.model.key(i).name for i in range(physics.model.nkey)]
    assert names == ["start", "base/arm/home"]
    assert "base/arm/gripper/fingers_actuator" in physics.named.data.ctrl.axes.row.names
    arm.detach()
    assert _without_settings(base.to_xml_string()) == _without_settings(base_before)
    assert _without_settings(scene.to_xml_string()) == _without_settings(scene_before)
    assert scene.option.integrator == "implicitfast"  # the arm's, merged: it stays
    assert scene.find("geom", "base/arm/gripper/right_pad1") is None


def test_detach_leaves_no_compiler_setting_the_child_keeps_for_itself() -> None:
    parent = mjcf.RootElement(model="parent")
    parent.worldbody.add("geom", type="plane", size=[1, 1, 1])
    before = parent.to_xml_string()
    ant = mjcf.from_path(gym_model("ant"))  # angle="degree" inertiafromgeom="true"
    parent.attach(ant)
    assert 'angle="degree"' not in parent.to_xml_string()
    ant.detach()
    assert _without_settings(parent.to_xml_string()) == _without_settings(before)
    # What the ant shares stays merged, as in dm_control; what it keeps for itself goes.
    assert parent.compiler.get_attributes() == {"coordinate": "local"}
    assert parent.option.get_attributes() == {"integrator": "RK4", "timestep": 0.01}
    assert ant.compiler.angle == "degree" and ant.compiler.inertiafromgeom == "true"


def test_remove_of_a_frame_detaches() -> None:
    parent = mjcf.RootElement(model="parent")
    child = mjcf.RootElement(model="child")
    child.worldbody.add("geom", size=[0.1])
    before = parent.to_xml_string()
    parent.attach(child).remove()
    assert parent.to_xml_string() == before and child.parent_model is None


def test_joints_of_an_attachment_frame_use_the_classes_where_the_frame_is() -> None:
    parent = mjcf.RootElement(model="parent")
    parent.default.joint.damping = 2
    parent.default.add("default", dclass="heavy").joint.damping = 7
    carrier = parent.worldbody.add("body", name="carrier", childclass="heavy")
    carrier.add("geom", size=[0.1])
    child = mjcf.RootElement(model="child")
    child.default.joint.damping = 100  # the child's, for the child's joints only
    child.worldbody.add("body", name="cb").add("geom", size=[0.1])
    slide = carrier.attach(child).add("joint", name="slide", type="slide")
    other = mjcf.RootElement(model="other")
    other.worldbody.add("geom", size=[0.1])
    free = parent.attach(other).add("joint", name="lift", type="slide")
    physics = mjcf.Physics.from_mjcf_model(parent)
    assert physics.bind(slide).damping == 7  # the carrier's childclass
    assert physics.bind(free).damping == 2  # the parent's main class


# -- compiled names -----------------------------------------------------------------------------


def test_compiled_names_are_those_stock_mujoco_reads_from_the_written_model() -> None:
    """Unnamed elements compile with the names the written XML gives them, as in
    dm_control ('child//unnamed_joint_0'), and bind; replicated ones keep MuJoCo's."""
    child = mjcf.RootElement(model="child")
    body = child.worldbody.add("body", pos=[0, 0, 1])
    hinge = body.add("joint", axis=[0, 1, 0])
    geom = body.add("geom", size=[0.1])
    child.actuator.add("motor", joint=hinge)  # an unnamed joint, referenced
    row = child.worldbody.add("replicate", count=3, offset=[0.5, 0, 0])
    row.add("body").add("geom", size=[0.05])
    row.find_all("body")[0].add("site", name="tip")
    scene = mjcf.RootElement(model="scene")
    scene.attach(child)
    physics = mjcf.Physics.from_mjcf_model(scene)
    stock = mujoco.MjModel.from_xml_string(scene.to_xml_string())
    assert physics.model.names == stock.names
    assert physics.model.joint(0).name == "child//unnamed_joint_0" == hinge.full_identifier
    assert physics.model.geom(0).name == "child//unnamed_geom_0" == geom.full_identifier
    assert row.find_all("geom")[0].full_identifier is None
    assert [physics.model.site(i).name for i in range(3)] == [
        "child/tip0",
        "child/tip1",
        "child/tip2",
    ]
    physics.bind(geom).rgba = [1, 0, 0, 1]
    assert physics.model.geom_rgba[0].tolist() == [1, 0, 0, 1]
    physics.bind(child.actuator.motor[0]).ctrl = 1.0
    physics.step(20)
    assert physics.bind(hinge).qpos[0] != 0
    with pytest.raises(mjcf.BindingError, match="inside a <replicate>"):
        physics.bind(row.find_all("geom")[0])


def test_reload_keeps_the_state_of_unnamed_joints_and_actuators() -> None:
    """Unnamed joints (a free attachment frame's, say) have no name to match on
    reload with keep_state: they keep their state by element."""
    prop = mjcf.RootElement(model="prop")
    prop.worldbody.add("geom", type="box", size=[0.1, 0.1, 0.1])  # the frame body's mass
    body = prop.worldbody.add("body")
    hinge = body.add("joint", axis=[0, 1, 0])
    body.add("geom", size=[0.1], pos=[0.2, 0, 0])
    prop.actuator.add("motor", joint=hinge)
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", type="plane", size=[5, 5, 0.1])
    free = scene.attach(prop).add("freejoint")
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(free).qpos = [1, 2, 3, 1, 0, 0, 0]
    physics.bind(hinge).qpos = 0.4
    physics.bind(prop.actuator.motor[0]).ctrl = 0.7
    scene.worldbody.add("geom", pos=[3, 3, 0.5], size=[0.2])  # a change elsewhere
    physics.reload_from_mjcf_model(scene, keep_state=True)
    assert physics.bind(free).qpos.tolist() == [1, 2, 3, 1, 0, 0, 0]
    assert physics.bind(hinge).qpos[0] == 0.4
    assert physics.bind(prop.actuator.motor[0]).ctrl == 0.7


# -- copies -----------------------------------------------------------------------------------


def test_deepcopy_of_an_attached_model_is_detached_and_attachable(menagerie) -> None:
    scene, (left, _) = two_arm_scene()
    twin = copy.deepcopy(left)
    assert twin.parent_model is None and left.parent_model is scene
    assert twin.to_xml_string() == left.to_xml_string()
    assert (
        twin.find("body", "robotiq_2f85/base").root
        is not left.find("body", "robotiq_2f85/base").root
    )
    twin.model = "third"
    scene.attach(twin)
    actuator = twin.find("actuator", "elbow")
    assert actuator.joint is twin.find("joint", "elbow_joint")  # references follow the copy
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.model.nu == 21
    copied_scene = copy.deepcopy(scene)
    assert copied_scene.to_xml_string() == scene.to_xml_string()
    frames = copied_scene.find_all("attachment_frame")
    assert [type(f) for f in frames] == [mjcf.AttachmentFrame] * 6


def test_deepcopy_keeps_elements_copied_together(menagerie) -> None:
    arm = mjcf.from_path(UR5E)
    elbow = arm.find("joint", "elbow_joint")
    copied_arm, copied_elbow = copy.deepcopy((arm, elbow))
    assert copied_elbow is copied_arm.find("joint", "elbow_joint")
    assert copy.deepcopy(elbow).root is not arm


# -- helpers ----------------------------------------------------------------------------------


def test_frame_helpers() -> None:
    arena = mjcf.RootElement(model="arena")
    ant = mjcf.from_path(gym_model("ant"))
    frame = arena.attach(ant)
    assert mjcf.get_attachment_frame(ant) is frame
    assert mjcf.get_attachment_frame(arena) is None
    assert mjcf.get_frame_joints(arena) is None  # not attached: None, as in dm_control
    assert mjcf.get_frame_freejoint(frame) is None and mjcf.get_frame_joints(frame) == []
    torso_free = mjcf.get_freejoint(ant.find("body", "torso"))
    assert torso_free is ant.find("joint", "root")  # <joint type="free">
    assert mjcf.get_freejoint(ant.find("body", "front_left_leg")) is None
    slide = frame.add("joint", name="lift", type="slide", axis=[0, 0, 1])
    free = frame.add("freejoint", name="float")
    assert mjcf.get_frame_freejoint(frame) is free
    assert mjcf.get_frame_freejoint(ant) is free  # dm_control passes the model too
    assert mjcf.get_frame_joints(frame) == [slide, free]
    assert mjcf.get_freejoint(frame) is free
    assert slide.full_identifier == "ant/lift/"  # named within the frame, as dm_control
    frame.name = "mount"
    assert slide.full_identifier == "mount/lift/"
    assert arena.find("joint", "lift") is None  # not one of the arena's names
    assert arena.find("attachment_frame", "ant") is frame


# -- bad input --------------------------------------------------------------------------------


def _refused(model: mjcf.RootElement, action, error: type[mjcf.Error], match: str) -> None:
    before = model.to_xml_string()
    with pytest.raises(error, match=match):
        action()
    assert model.to_xml_string() == before


def test_bad_attachments_are_refused_and_change_nothing(menagerie) -> None:
    arm = mjcf.from_path(UR5E)
    gripper = mjcf.from_path(ROBOTIQ)
    site = arm.find("site", "attachment_site")
    _refused(arm, lambda: arm.attach(arm), mjcf.AttachmentError, "inside itself")
    site.attach(gripper)
    _refused(gripper, lambda: gripper.attach(arm), mjcf.AttachmentError, "inside itself")
    _refused(arm, lambda: arm.attach(gripper), mjcf.AttachmentError, "already attached")
    other = mjcf.RootElement(model="other")
    _refused(other, lambda: other.attach(gripper), mjcf.AttachmentError, "already attached")
    _refused(arm, lambda: site.attach(arm.worldbody), mjcf.AttachmentError, "only a model")
    _refused(arm, lambda: site.attach("2f85.xml"), mjcf.AttachmentError, "only a model")
    geom = arm.find("body", "base").geom[0]
    _refused(arm, lambda: geom.attach(mjcf.RootElement(model="x")), mjcf.AttachmentError,
             "models attach to a site, body, frame or worldbody")  # fmt: skip
    renamed = mjcf.from_path(ROBOTIQ)
    renamed.model = "second"
    arm.attach(renamed)
    _refused(arm, lambda: setattr(renamed, "model", "robotiq_2f85"), mjcf.NameClashError,
             "already attached")  # fmt: skip
    with pytest.raises(mjcf.NameClashError, match="separates"):
        mjcf.RootElement(model="a/b")
