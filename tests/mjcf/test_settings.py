"""Compiler angle units of composed models: attached models are converted into the
units of the model they are attached to, and that model's own `compiler.angle` reads
back the units its own elements compile with (dm_control instead copies a child's
`angle` into a parent that has none, turning the parent's degrees into radians)."""

from __future__ import annotations

import re

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import UR5E, gym_model
from tests.mjcf.attaching import differences_from_alone

Obj = mujoco.mjtObj


def _written_angle(model: mjcf.RootElement) -> str | None:
    compiler = re.search(r"<compiler[^>]*>", model.to_xml_string())
    found = compiler and re.search(r' angle="(\w+)"', compiler.group(0))
    return found.group(1) if found else None


def _parent(angle: str | None) -> mjcf.RootElement:
    """A scene with a body turned a quarter about z and a hinge of +-45 degrees, both
    given in `angle` units (None: MuJoCo's default, degrees)."""
    quarter, eighth = (np.pi / 2, np.pi / 4) if angle == "radian" else (90, 45)
    scene = mjcf.RootElement(model="scene")
    if angle is not None:
        scene.compiler.angle = angle
    body = scene.worldbody.add("body", name="turned", euler=[0, 0, quarter])
    body.add("joint", name="hinge", range=[-eighth, eighth])
    body.add("geom", size=[0.1])
    return scene


def _assert_own_units(scene: mjcf.RootElement, angle: str | None) -> None:
    """The scene's elements compile as its own `angle` says, and it says so in Python
    and in the XML it writes."""
    assert scene.compiler.angle == angle
    assert _written_angle(scene) == angle
    reread = mjcf.from_xml_string(scene.to_xml_string(), escape_separators=True)
    assert reread.compiler.angle == angle
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert np.allclose(physics.named.model.jnt_range["hinge"], [-np.pi / 4, np.pi / 4])
    quarter_turn = [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)]
    assert np.allclose(physics.named.model.body_quat["turned"], quarter_turn)


@pytest.mark.parametrize("angle", [None, "degree"])
def test_a_radian_robot_leaves_the_scene_in_degrees(menagerie, angle: str | None) -> None:
    arm_alone = mjcf.Physics.from_mjcf_model(mjcf.from_path(UR5E)).model
    scene = _parent(angle)
    arm = mjcf.from_path(UR5E)
    scene.attach(arm)
    _assert_own_units(scene, angle)
    assert arm.compiler.angle == "radian"  # the robot's own setting is untouched too
    composed = mjcf.Physics.from_mjcf_model(scene).model
    assert differences_from_alone(arm_alone, composed, "ur5e/", placed={"base"}) == []


def test_a_degree_model_inside_a_radian_scene() -> None:
    ant_alone = mujoco.MjModel.from_xml_path(str(gym_model("ant")))
    scene = _parent("radian")
    scene.attach(mjcf.from_path(gym_model("ant")))  # angle="degree"
    _assert_own_units(scene, "radian")
    composed = mjcf.Physics.from_mjcf_model(scene).model
    hip = mujoco.mj_name2id(composed, Obj.mjOBJ_JOINT, "ant/hip_1")
    assert np.allclose(composed.jnt_range[hip], ant_alone.jnt_range[1])  # +-30 degrees


def test_changing_the_scene_angle_after_attaching_converts_again(menagerie) -> None:
    scene = _parent("degree")
    scene.attach(mjcf.from_path(UR5E))
    scene.compiler.angle = "radian"
    turned = scene.find("body", "turned")
    turned.euler = [0, 0, np.pi / 2]
    scene.find("joint", "hinge").range = [-np.pi / 4, np.pi / 4]
    _assert_own_units(scene, "radian")


# -- compiler settings one model leaves unset (issue 25) -----------------------------------


def _bounded_scene() -> mjcf.RootElement:
    """A scene that bounds masses and inertias, as dm_control's arenas and many scenes do."""
    scene = mjcf.RootElement(model="scene")
    scene.compiler.boundmass = 1e-5
    scene.compiler.boundinertia = 1e-11
    scene.worldbody.add("geom", type="plane", size=[5, 5, 0.1])
    return scene


def test_a_compiler_setting_the_child_leaves_unset_never_conflicts() -> None:
    ant_alone = mujoco.MjModel.from_xml_path(str(gym_model("ant")))
    scene = _bounded_scene()
    scene.attach(mjcf.from_path(gym_model("ant")))  # sets no boundmass, no boundinertia
    written = re.search(r"<compiler[^>]*>", scene.to_xml_string())
    assert written and 'boundmass="1e-05"' in written.group(0)
    composed = mjcf.Physics.from_mjcf_model(scene).model
    torso = mujoco.mj_name2id(composed, Obj.mjOBJ_BODY, "ant/torso")
    assert np.allclose(composed.body_mass[torso:], ant_alone.body_mass[1:])


def test_a_compiler_setting_of_the_child_alone_is_the_composed_models() -> None:
    scene = mjcf.RootElement(model="scene")
    child = mjcf.RootElement(model="light")
    child.compiler.boundmass = 1e-5
    body = child.worldbody.add("body", name="feather")
    body.add("inertial", pos=[0, 0, 0], mass=1e-7, diaginertia=[1e-3] * 3)
    body.add("joint", type="slide")
    scene.attach(child)
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.named.model.body_mass["light/feather"] == pytest.approx(1e-5)


def test_two_explicit_different_compiler_settings_still_conflict() -> None:
    scene = _bounded_scene()
    child = mjcf.from_path(gym_model("ant"))
    child.compiler.boundmass = 1e-3
    with pytest.raises(mjcf.AttachmentError, match="boundmass"):
        scene.attach(child)
    assert not scene.find_all("attachment_frame")  # a failed attach changes nothing
    child.compiler.boundmass = 1e-5  # the same value twice is no conflict
    scene.attach(child)
