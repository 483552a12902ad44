"""Binding an element that compiles to a MuJoCo `<frame>` (an attached model's world body,
its attachment frame, a `<frame>`) gives the frame's pose, as dm_control gives the pose of
its attachment body: `pos` and `quat` move the frame (tests/mjcf/test_frame_moves.py
compares that with compiling it there), never the numbers of another object."""

from __future__ import annotations

import pickle

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


def test_frames_bind_as_a_list() -> None:
    scene, child, frame = _scene()
    inner = scene.find("body", "arm").add("frame", name="f", pos=[0, 0, 0.5], zaxis=[1, 0, 0])
    inner.add("body", name="in_frame").add("geom", size=[0.05])
    physics = mjcf.Physics.from_mjcf_model(scene)
    both = physics.bind([frame, inner])
    assert both.xpos.shape == (2, 3) and both.xmat.shape == (2, 9)
    in_frame = physics.bind(scene.find("body", "in_frame"))
    np.testing.assert_allclose(both.xquat[1], in_frame.xquat, atol=1e-12)
    np.testing.assert_allclose(both["xpos", "z"], [physics.bind(child.worldbody).xpos[2],
                                                   in_frame.xpos[2]], atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(both["quat", ["qw", "qz"]], both.quat[:, [0, 3]])
    with pytest.raises(mjcf.BindingError, match="has no 'mass'"):
        physics.bind(child.worldbody).mass  # noqa: B018
    with pytest.raises(mjcf.BindingError, match="apart from elements of other kinds"):
        physics.bind([frame, scene.find("body", "arm")])
    with pytest.raises(mjcf.BindingError, match="no column named 'w'"):
        both["quat", "w"]


def test_writing_pos_or_quat_moves_the_frame_for_every_binding_of_it() -> None:
    scene, child, frame = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    origin = child.find("body", "origin")
    world, bound = physics.bind(child.worldbody), physics.bind(frame)
    bound.pos = [0.5, 0, 0]
    world.quat = [0, 0, 0, 2]  # normalized
    np.testing.assert_allclose(bound.quat, [0, 0, 0, 1])
    np.testing.assert_allclose(world.pos, [0.5, 0, 0])
    for field in ("xpos", "xquat", "xmat"):  # the body at the origin of the attached model
        np.testing.assert_allclose(getattr(bound, field), getattr(physics.bind(origin), field),
                                   atol=1e-12)  # fmt: skip
    bound.pos[2] = 1.5  # an item of a read writes the field back
    assert bound.pos.tolist() == [0.5, 0, 1.5] and world.pos.tolist() == [0.5, 0, 1.5]
    bound["pos", "x"] = 0.25
    assert world.pos.tolist() == [0.25, 0, 1.5]
    np.testing.assert_allclose(physics.bind(origin).pos, [0.25, 0, 1.5], atol=1e-12)


def test_xpos_xquat_and_xmat_are_derived_and_read_only() -> None:
    scene, _, frame = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    bound = physics.bind(frame)
    with pytest.raises(mjcf.BindingError, match=r"'xpos' is derived.*write 'pos' or 'quat'"):
        bound.xpos = [0, 0, 0]
    with pytest.raises(ValueError, match="read-only"):
        bound.xquat[0] = 1
    with pytest.raises(mjcf.BindingError, match="no 'mass' to write"):
        bound.mass = 1


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("pos", [1, 2], r"expected \(3,\) numbers"),
        ("pos", "up", r"expected \(3,\) numbers"),
        ("pos", [0, np.nan, 0], "not finite"),
        ("quat", [0, 0, 0, 0], "a zero quaternion"),
    ],
)
def test_a_bad_pose_raises_and_changes_nothing(field: str, value: object, message: str) -> None:
    scene, _, frame = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    before = physics.model.body_pos.copy()
    with pytest.raises(mjcf.BindingError, match=message):
        setattr(physics.bind(frame), field, value)
    assert physics.bind(frame).pos.tolist() == [1, 2, 3]
    np.testing.assert_array_equal(physics.model.body_pos, before)


def test_nested_frames_follow_the_frame_around_them_and_keep_their_offset_meaning() -> None:
    """`pos` of a frame in frames is its offset from the body they are in; written together,
    the outer frame moves first, so both end where they are asked."""
    scene = mjcf.RootElement(model="scene")
    outer = scene.worldbody.add("frame", name="outer", pos=[1, 0, 0])
    inner = outer.add("frame", name="inner", pos=[0, 1, 0])
    inner.add("site", name="mark")
    physics = mjcf.Physics.from_mjcf_model(scene)
    mark = physics.bind(scene.find("site", "mark"))
    np.testing.assert_allclose(physics.bind(inner).pos, [1, 1, 0])
    physics.bind(outer).pos = [2, 0, 0]
    np.testing.assert_allclose(physics.bind(inner).pos, [2, 1, 0])
    np.testing.assert_allclose(mark.xpos, [2, 1, 0])
    physics.bind([inner, outer]).pos = [[0, 0, 5], [3, 0, 0]]
    np.testing.assert_allclose(physics.bind([outer, inner]).pos, [[3, 0, 0], [0, 0, 5]])
    np.testing.assert_allclose(mark.xpos, [0, 0, 5])


def test_frames_whose_move_a_recompile_would_do_otherwise_refuse_it() -> None:
    scene = mjcf.RootElement(model="scene")
    arm = scene.worldbody.add("body", name="arm")
    arm.add("joint", name="hinge")
    arm.add("geom", size=[0.1])
    held = arm.add("frame", name="held", pos=[0, 0, 1])
    held.add("geom", name="weight", size=[0.1], mass=5)
    copies = scene.worldbody.add("frame", name="copies")
    copies.add("replicate", count=3, offset=[0.2, 0, 0]).add("geom", size=[0.05])
    physics = mjcf.Physics.from_mjcf_model(scene)
    before = physics.model.geom_pos.copy()
    with pytest.raises(mjcf.BindingError, match=r'held.*mass makes part of the inertia of.*"arm"'):
        physics.bind(held).pos = [0, 0, 2]
    with pytest.raises(mjcf.BindingError, match=r"copies.*holds a <replicate>"):
        physics.bind(copies).pos = [0, 0, 2]
    np.testing.assert_array_equal(physics.model.geom_pos, before)
    assert physics.bind(held).pos.tolist() == [0, 0, 1]
    arm.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[1, 1, 1])  # geoms' mass: unused
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(held).pos = [0, 0, 2]
    np.testing.assert_allclose(physics.bind(scene.find("geom", "weight")).xpos, [0, 0, 2])


def test_a_frame_pose_belongs_to_a_physics_and_its_compiled_model() -> None:
    scene, _, frame = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    other = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(frame).pos = [0, 0, 9]
    assert other.bind(frame).pos.tolist() == [1, 2, 3]
    shared = physics.copy(share_model=True)
    copied = physics.copy(share_model=False)
    restored_frame, restored = pickle.loads(pickle.dumps((frame, physics)))
    assert restored.bind(restored_frame).pos.tolist() == [0, 0, 9]
    for each in (shared, copied):
        assert each.bind(frame).pos.tolist() == [0, 0, 9]
    physics.bind(frame).pos = [0, 0, 7]  # the shared model moved with it
    assert shared.bind(frame).pos.tolist() == [0, 0, 7]
    assert copied.bind(frame).pos.tolist() == [0, 0, 9]
    np.testing.assert_allclose(copied.bind(frame).xpos, restored.bind(restored_frame).xpos,
                               atol=1e-12)  # fmt: skip
    old = physics.bind(frame)
    physics.reload_from_mjcf_model(scene)  # a recompile starts again from the text
    assert physics.bind(frame).pos.tolist() == [1, 2, 3]
    with pytest.raises(mjcf.BindingError, match="no longer holds; bind again"):
        old.pos  # noqa: B018


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
