"""Composing models: attach, detach, scoped names, isolated defaults, converted compiler
settings, helpers and bad input, on the real UR5e, Robotiq 2F-85 and gymnasium models."""

from __future__ import annotations

import copy
import re
import warnings

import mujoco
import numpy as np
import pytest

import mjcf
from mjcf.sim import fields
from tests.conftest import ROBOTIQ, UR5E, gym_model

Obj = mujoco.mjtObj
_KINDS = (Obj.mjOBJ_BODY, Obj.mjOBJ_JOINT, Obj.mjOBJ_GEOM, Obj.mjOBJ_SITE, Obj.mjOBJ_ACTUATOR)
# Where a model is put: its top-level bodies, and its world body's geoms and sites.
_PLACEMENT = frozenset({"body_pos", "body_quat", "geom_pos", "geom_quat", "site_pos", "site_quat"})


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


def element_values(model: mujoco.MjModel, kind: Obj, name: str) -> dict[str, np.ndarray]:
    """The float MjModel rows of one named object."""
    index = mujoco.mj_name2id(model, kind, name)
    assert index >= 0, f"{name!r} is not in the model"
    rows = {}
    for field in set(fields.kind_fields(kind).values()):
        if field.struct == "model" and field.address is None:
            values = getattr(model, field.name)
            if values.dtype.kind == "f":
                rows[field.name] = values[index]
    return rows


def differences_from_alone(
    alone: mujoco.MjModel, composed: mujoco.MjModel, prefix: str, placed: set[str] = frozenset()
) -> list[str]:
    """Every compiled value of a named body, joint, geom, site or actuator of `alone`
    that differs in `composed`, where its names start with `prefix` (the placement of
    the bodies in `placed` and of the world body's geoms and sites is left out)."""
    found = []
    static = {Obj.mjOBJ_GEOM: alone.geom_bodyid, Obj.mjOBJ_SITE: alone.site_bodyid}
    for kind in _KINDS:
        for index in range(fields.count(alone, kind)):
            name = mujoco.mj_id2name(alone, kind, index)
            if not name or name == "world":
                continue
            mine = element_values(alone, kind, name)
            # A generated '//unnamed_geom_0' is 'prefix//unnamed_geom_0' when attached.
            scoped = prefix + name[1:] if name.startswith("//") else prefix + name
            theirs = element_values(composed, kind, scoped)
            is_placed = name in placed or (kind in static and static[kind][index] == 0)
            for field, value in mine.items():
                if is_placed and field in _PLACEMENT:
                    continue
                if not np.allclose(value, theirs[field], rtol=1e-9, atol=1e-12):
                    found.append(f"{prefix}{name} {field}: {value} != {theirs[field]}")
    return found


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
    assert differences_from_alone(alone, model, last, placed=_top_bodies(alone)) == []
    physics.step(5)
    assert np.all(np.isfinite(physics.data.qpos))


def _top_bodies(model: mujoco.MjModel) -> set[str]:
    return {
        mujoco.mj_id2name(model, Obj.mjOBJ_BODY, b)
        for b in range(1, model.nbody)
        if model.body_parentid[b] == 0
    }


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


# -- default classes, angles and settings ----------------------------------------------------


def _parent(angle: str) -> mjcf.RootElement:
    degrees = angle == "degree"
    parent = mjcf.RootElement(model="parent")
    parent.compiler.angle = angle
    parent.default.geom.rgba = [1, 0, 0, 1]
    parent.default.joint.damping = 3
    body = parent.worldbody.add("body", name="pb", euler=[0, 90 if degrees else np.pi / 2, 0])
    body.add("joint", name="pj", type="hinge", range=[-45, 45] if degrees else [-0.7, 0.7])
    body.add("geom", name="pg", size=[0.1])
    parent.worldbody.add("site", name="mount", pos=[0.5, 0, 0])
    return parent


def _child(angle: str, eulerseq: str | None = None) -> mjcf.RootElement:
    degrees = angle == "degree"
    child = mjcf.RootElement(model="child")
    child.compiler.angle = angle
    if eulerseq is not None:
        child.compiler.eulerseq = eulerseq
    child.default.geom.set_attributes(rgba=[0, 1, 0, 1], friction=[0.5, 0.1, 0.1])
    child.default.joint.armature = 0.2
    child.default.add("default", dclass="thin").geom.size = [0.02]
    body = child.worldbody.add(
        "body", name="cb", pos=[1, 0, 0], euler=[30, 20, 10] if degrees else [0.5, 0.3, 0.2]
    )
    body.add("joint", name="hinge", type="hinge", range=[-30, 60] if degrees else [-0.5, 1],
             ref=10 if degrees else 0.2)  # fmt: skip
    body.add("joint", name="ball", type="ball", range=[0, 40] if degrees else [0, 0.7])
    body.add("geom", name="cg", size=[0.1], dclass="thin",
             axisangle=[0, 0, 1, 30] if degrees else [0, 0, 1, 0.5])  # fmt: skip
    body.add("site", name="cs", euler=[10, 20, 30] if degrees else [0.1, 0.2, 0.3])
    child.actuator.add("position", name="servo", joint="hinge", ctrlrange=[-1, 1], kp=10)
    return child


@pytest.mark.parametrize(
    ("parent_angle", "child_angle", "eulerseq"),
    [
        ("radian", "degree", None),
        ("degree", "radian", None),
        ("radian", "radian", "zyx"),
        ("degree", "degree", "XYZ"),
        ("radian", "degree", "ZYX"),
    ],
)
def test_defaults_angles_and_eulerseq_compile_as_alone(
    parent_angle: str, child_angle: str, eulerseq: str | None
) -> None:
    parent, child = _parent(parent_angle), _child(child_angle, eulerseq)
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    child_alone = mjcf.Physics.from_mjcf_model(child).model
    parent.find("site", "mount").attach(child)
    composed = mjcf.Physics.from_mjcf_model(parent).model
    assert differences_from_alone(child_alone, composed, "child/", placed={"cb"}) == []
    assert differences_from_alone(parent_alone, composed, "") == []
    green = composed.geom_rgba[mujoco.mj_name2id(composed, Obj.mjOBJ_GEOM, "child/cg")]
    assert np.array_equal(green, [0, 1, 0, 1])  # the child's defaults, not the parent's


@pytest.mark.parametrize("name", ["humanoid", "ant", "half_cheetah", "hopper", "walker2d"])
def test_gymnasium_settings_convert_into_a_radian_model(name: str) -> None:
    """Degrees, inertiafromgeom="true" and settotalmass (half_cheetah) of gymnasium's
    models, inside a radian model whose bodies have explicit inertias."""
    alone = mujoco.MjModel.from_xml_path(str(gym_model(name)))
    parent = _parent("radian")
    parent.find("body", "pb").add("inertial", pos=[0, 0, 0], mass=2, diaginertia=[0.1, 0.2, 0.3])
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    parent.find("site", "mount").attach(mjcf.from_path(gym_model(name)))
    composed = mjcf.Physics.from_mjcf_model(parent).model
    model_name = mjcf.from_path(gym_model(name)).model
    placed = _top_bodies(alone)
    assert differences_from_alone(alone, composed, f"{model_name}/", placed) == []
    assert differences_from_alone(parent_alone, composed, "") == []


def test_a_radian_robot_inside_a_degree_model(menagerie) -> None:
    arm_alone = mjcf.Physics.from_mjcf_model(mjcf.from_path(UR5E)).model
    parent = _parent("degree")
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    parent.find("site", "mount").attach(mjcf.from_path(UR5E))
    composed = mjcf.Physics.from_mjcf_model(parent).model
    assert differences_from_alone(arm_alone, composed, "ur5e/", placed={"base"}) == []
    assert differences_from_alone(parent_alone, composed, "") == []


@pytest.mark.parametrize(("angle", "quarter"), [("degree", 90.0), ("radian", np.pi / 2)])
def test_attachment_frames_inside_an_attached_model_keep_its_angle_units(
    angle: str, quarter: float
) -> None:
    """A frame belongs to the model it is in: its pose (set, or taken from the site it
    is attached at) is in that model's units, also when that model is attached."""
    base = mjcf.RootElement(model="base")
    base.compiler.angle = angle
    body = base.worldbody.add("body", name="bb")
    body.add("geom", size=[0.1])
    site = body.add("site", name="mount", euler=[0, 0, quarter])
    for name, place in (("at_site", site), ("at_body", body)):
        child = mjcf.RootElement(model=name)
        child.worldbody.add("body", name="cb").add("geom", size=[0.1])
        frame = place.attach(child)
        if place is body:
            frame.euler = [quarter, 0, 0]
    alone = mjcf.Physics.from_mjcf_model(base)
    root = mjcf.RootElement(model="root")
    root.compiler.angle = "radian" if angle == "degree" else "degree"
    root.attach(base)
    composed = mjcf.Physics.from_mjcf_model(root)
    for name in ("at_site", "at_body"):
        expected = alone.named.data.xquat[f"{name}/cb"]
        assert np.allclose(composed.named.data.xquat[f"base/{name}/cb"], expected)


def test_conflicting_options_are_refused_and_change_nothing() -> None:
    parent, child = _parent("radian"), _child("degree")
    parent.option.integrator = "RK4"
    child.option.integrator = "implicitfast"
    child.option.timestep = 0.005  # merges: the smaller step
    before, child_before = parent.to_xml_string(), child.to_xml_string()
    with pytest.raises(mjcf.AttachmentError, match=r"<option> integrator: 'RK4' in model"):
        parent.attach(child)
    assert parent.to_xml_string() == before and child.to_xml_string() == child_before
    assert child.parent_model is None
    child.option.integrator = "RK4"  # the same value on both is fine
    parent.attach(child)
    assert parent.option.timestep == 0.005
    child.option.integrator = "Euler"  # written later: the composed model's, as in dm_control
    assert mjcf.Physics.from_mjcf_model(parent).model.opt.integrator == 0  # Euler


def test_gymnasium_models_with_different_timesteps_compose_at_the_smaller_step() -> None:
    ant = mjcf.from_path(gym_model("ant"))  # timestep 0.01
    ant.attach(mjcf.from_path(gym_model("humanoid")))  # timestep 0.003, 50 PGS iterations
    model = mjcf.Physics.from_mjcf_model(ant).model
    assert model.opt.timestep == 0.003 and model.opt.iterations == 50
    assert model.opt.solver == mujoco.mjtSolver.mjSOL_PGS
    arena = mjcf.RootElement(model="arena")
    arena.attach(mjcf.from_path(gym_model("ant")))
    arena.attach(mjcf.from_path(gym_model("humanoid")))
    assert mjcf.Physics.from_mjcf_model(arena).model.opt.timestep == 0.003


def test_irreconcilable_inertia_settings_are_refused() -> None:
    parent = mjcf.RootElement(model="parent")
    parent.compiler.inertiafromgeom = "true"  # ignores the inertial below
    body = parent.worldbody.add("body", name="b")
    body.add("inertial", pos=[0, 0, 0], mass=5, diaginertia=[1, 1, 1])
    body.add("geom", size=[0.1])
    child = mjcf.RootElement(model="child")  # "auto": uses its inertial
    child_body = child.worldbody.add("body", name="c")
    child_body.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[1, 1, 1])
    child_body.add("geom", size=[0.1])
    before = parent.to_xml_string()
    with pytest.raises(mjcf.AttachmentError, match="inertiafromgeom"):
        parent.attach(child)
    assert parent.to_xml_string() == before


def _masses(model: mujoco.MjModel, prefix: str) -> dict[str, float]:
    """{body name without `prefix`: mass} of the bodies named `prefix` + a plain name (the
    world body left out)."""
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, i) or "" for i in range(model.nbody)
    ]
    return {
        name.removeprefix(prefix): float(model.body_mass[i])
        for i, name in enumerate(names)
        if i > 0
        and name.startswith(prefix)
        and name != prefix
        and "/" not in name.removeprefix(prefix)
    }


def _spec_attached(scene: mujoco.MjSpec, body: str, child: mujoco.MjSpec, prefix: str) -> None:
    """MuJoCo's own attachment: `child`'s top body on a frame of `scene`'s `body`."""
    frame = (scene.worldbody if not body else scene.body(body)).add_frame()
    frame.attach_body(child.worldbody.first_body(), prefix, "")


@pytest.mark.parametrize("order", ["cheetah first", "hopper first"])
def test_a_model_attached_inside_a_settotalmass_model_keeps_its_own_masses(order: str) -> None:
    """half_cheetah sets <compiler settotalmass="14">: attached into a scene its bodies weigh
    what they weigh alone (14 kg), and a hopper attached on its torso weighs what it weighs
    alone, in either order of attaching; the hopper was scaled with the cheetah (its 15.8 kg
    to 6.0). MuJoCo's own attach leaves the hopper's masses too (its compile here, with the
    same files, is the reference); dm_control scales every model of the scene to 14 kg."""
    hopper_alone = mujoco.MjModel.from_xml_path(str(gym_model("hopper")))
    cheetah_alone = mujoco.MjModel.from_xml_path(str(gym_model("half_cheetah")))
    scene = mjcf.RootElement(model="scene")
    cheetah, hopper = mjcf.from_path(gym_model("half_cheetah")), mjcf.from_path(gym_model("hopper"))
    hopper.option.timestep = cheetah.option.timestep  # one timestep for the composed model
    hopper.find("geom", "floor").remove()  # a plane is static: not on the cheetah's torso
    mount = cheetah.find("body", "torso").add("site", name="mount", pos=[0, 0, 0.5])
    if order == "cheetah first":
        scene.worldbody.attach(cheetah)
        mount.attach(hopper)
    else:
        mount.attach(hopper)
        scene.worldbody.attach(cheetah)
    composed = mjcf.Physics.from_mjcf_model(scene).model
    hopper_masses = _masses(composed, "cheetah/hopper/")
    assert hopper_masses == pytest.approx(_masses(hopper_alone, ""), rel=1e-12)
    assert _masses(composed, "cheetah/") == pytest.approx(_masses(cheetah_alone, ""), rel=1e-12)
    spec = mujoco.MjSpec.from_string("<mujoco/>")
    with warnings.catch_warnings():  # MuJoCo's "Attach conflict" of options, when compiling
        warnings.simplefilter("ignore", UserWarning)
        _spec_attached(spec, "", mujoco.MjSpec.from_file(str(gym_model("half_cheetah"))),
                       "cheetah/")  # fmt: skip
        _spec_attached(spec, "cheetah/torso", mujoco.MjSpec.from_file(str(gym_model("hopper"))),
                       "hopper/")  # fmt: skip
        theirs = spec.compile()
    assert hopper_masses == pytest.approx(_masses(theirs, "hopper/"), rel=1e-12)


def test_settotalmass_of_the_output_model_with_attachments_is_refused() -> None:
    """Written as the output model, half_cheetah's settotalmass would scale the hopper
    attached to it too (MuJoCo's and dm_control's do): refused when written or compiled,
    whenever the hopper was attached; attached into a scene, it is written."""
    cheetah, hopper = mjcf.from_path(gym_model("half_cheetah")), mjcf.from_path(gym_model("hopper"))
    hopper.option.timestep = cheetah.option.timestep
    cheetah.attach(hopper)
    for write in (cheetah.to_xml_string, lambda: mjcf.Physics.from_mjcf_model(cheetah)):
        with pytest.raises(
            mjcf.AttachmentError, match=r"settotalmass=14\.0> of model 'cheetah' would scale"
        ):
            write()
    scene = mjcf.RootElement(model="scene")
    scene.attach(cheetah)
    assert mjcf.Physics.from_mjcf_model(scene).model.nbody > 1


def test_sizes_merge_to_the_largest() -> None:
    parent, child = _parent("radian"), _child("radian")
    parent.size.nkey = 2
    child.size.nkey = 4
    parent.attach(child)
    assert mjcf.Physics.from_mjcf_model(parent).model.nkey == 4


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
