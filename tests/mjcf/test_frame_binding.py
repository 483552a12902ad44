"""Binding an element that compiles to a MuJoCo `<frame>` (an attached model's world body,
its attachment frame, a `<frame>`) gives the frame's pose, as dm_control gives the pose of
its attachment body: read-only, never the numbers of another object."""

from __future__ import annotations

import numpy as np
import pytest

import mjcf


def _scene(angle: str = "degree") -> tuple[mjcf.RootElement, mjcf.RootElement, mjcf.Element]:
    """A scene whose arm swings on a hinge; a child model attached at a turned site of
    the arm, with a body at the child's origin to compare the frame's pose with."""
    scene = mjcf.RootElement(model="scene")
    scene.compiler.angle = angle
    turn = 30 if angle == "degree" else np.pi / 6
    arm = scene.worldbody.add("body", name="arm", pos=[0, 0, 1], euler=[0, 0, turn])
    arm.add("joint", name="hinge", axis=[0, 1, 0])
    arm.add("geom", size=[0.1])
    site = arm.add("site", name="mount", pos=[1, 2, 3], euler=[turn, 0, 0])
    child = mjcf.RootElement(model="child")
    child.worldbody.add("body", name="origin").add("geom", size=[0.05])
    frame = site.attach(child)
    return scene, child, frame


@pytest.mark.parametrize("angle", ["degree", "radian"])
def test_an_attached_world_body_binds_to_the_pose_of_its_attachment(angle: str) -> None:
    scene, child, frame = _scene(angle)
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(scene.find("joint", "hinge")).qpos = 0.7
    origin = physics.bind(child.find("body", "origin"))
    for element in (child.worldbody, frame):
        bound = physics.bind(element)
        np.testing.assert_allclose(bound.xpos, origin.xpos, atol=1e-12)
        np.testing.assert_allclose(bound.xquat, origin.xquat, atol=1e-12)
        np.testing.assert_allclose(bound.xmat, origin.xmat, atol=1e-12)
        np.testing.assert_allclose(bound.pos, origin.pos, atol=1e-12)  # from the arm body
        np.testing.assert_allclose(bound.quat, origin.quat, atol=1e-12)
        assert not np.allclose(bound.xpos, physics.bind(scene.worldbody).xpos)


def test_frames_bind_as_a_list_and_read_only() -> None:
    scene, child, frame = _scene()
    inner = scene.find("body", "arm").add("frame", name="f", pos=[0, 0, 0.5], zaxis=[1, 0, 0])
    inner.add("body", name="in_frame").add("geom", size=[0.05])
    physics = mjcf.Physics.from_mjcf_model(scene)
    both = physics.bind([frame, inner])
    assert both.xpos.shape == (2, 3) and both.xmat.shape == (2, 9)
    in_frame = physics.bind(scene.find("body", "in_frame"))
    np.testing.assert_allclose(both.xquat[1], in_frame.xquat, atol=1e-12)
    np.testing.assert_allclose(both["xpos", 2], [physics.bind(child.worldbody).xpos[2],
                                                 in_frame.xpos[2]], atol=1e-12)  # fmt: skip
    with pytest.raises(mjcf.BindingError, match=r"cannot be written.*freejoint"):
        physics.bind(frame).pos = [0, 0, 0]
    with pytest.raises(mjcf.BindingError, match="cannot be written"):
        both["xpos"] = np.zeros((2, 3))
    with pytest.raises(ValueError, match="read-only"):
        physics.bind(frame).xpos[0] = 5
    with pytest.raises(mjcf.BindingError, match="has no 'mass'"):
        physics.bind(child.worldbody).mass  # noqa: B018
    with pytest.raises(mjcf.BindingError, match="apart from elements of other kinds"):
        physics.bind([frame, scene.find("body", "arm")])


def test_the_pose_is_the_compiled_one_whatever_the_tree_became() -> None:
    scene, child, frame = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    compiled = physics.bind(child.worldbody).xpos.copy()
    frame.pos = [9, 9, 9]
    np.testing.assert_allclose(physics.bind(frame).xpos, compiled, atol=1e-12)
    np.testing.assert_allclose(
        mjcf.Physics.from_mjcf_model(scene).bind(frame).xpos,
        mjcf.Physics.from_mjcf_model(scene).bind(child.find("body", "origin")).xpos,
        atol=1e-12,
    )


def test_a_frame_with_joints_is_a_body_and_binds_as_one() -> None:
    scene, child, frame = _scene()
    frame.add("joint", name="swivel")
    physics = mjcf.Physics.from_mjcf_model(scene)
    bound = physics.bind(child.worldbody)
    assert bound.mass.shape == ()  # a body binding
    bound.xfrc_applied = [0, 0, 1, 0, 0, 0]


def test_a_model_compiled_alone_binds_its_world_body_to_the_world() -> None:
    _, child, _ = _scene()
    physics = mjcf.Physics.from_mjcf_model(child)  # attached elsewhere, compiled alone
    assert physics.bind(child.worldbody).xpos.tolist() == [0, 0, 0]
    assert physics.bind(child.worldbody).mass.shape == ()  # the world body
