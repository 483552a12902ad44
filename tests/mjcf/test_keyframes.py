"""Keyframes of composed models: each key keeps its scoped name and sets its own model's
entries; every other entry keeps the composed model's defaults."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import ROBOTIQ, UR5E

HOME = np.array([-1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0])


def _arm(name: str) -> mjcf.RootElement:
    arm = mjcf.from_path(UR5E)
    arm.model = name
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    return arm


def _scene() -> tuple[mjcf.RootElement, mjcf.RootElement, mjcf.RootElement]:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", type="plane", size=[2, 2, 0.1])
    left, right = _arm("left"), _arm("right")
    scene.attach(left).pos = [0, -0.5, 0]
    scene.attach(right).pos = [0, 0.5, 0]
    return scene, left, right


def _entries(physics: mjcf.Physics, arm: mjcf.RootElement) -> tuple[np.ndarray, np.ndarray]:
    """qpos and ctrl indices of the arm's own joints and actuators (not the gripper's)."""
    model = physics.model
    joints = arm.find_all("joint", exclude_attachments=True)
    actuators = arm.find_all("actuator", exclude_attachments=True)
    qpos = [model.joint(j.full_identifier).qposadr[0] for j in joints]
    ctrl = [model.actuator(a.full_identifier).id for a in actuators]
    return np.array(qpos), np.array(ctrl)


def _check_home(model: mujoco.MjModel, data: mujoco.MjData, qpos: np.ndarray, ctrl: np.ndarray):
    expected_qpos = model.qpos0.copy()
    expected_qpos[qpos] = HOME
    expected_ctrl = np.zeros(model.nu)
    expected_ctrl[ctrl] = HOME
    assert np.array_equal(data.qpos, expected_qpos)
    assert np.array_equal(data.ctrl, expected_ctrl)
    assert not data.qvel.any()


def test_home_key_of_one_arm_sets_exactly_that_arm(menagerie) -> None:
    scene, left, right = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    names = [physics.model.key(i).name for i in range(physics.model.nkey)]
    assert names == ["left/home", "right/home"]
    physics.data.qpos[:] = 0.3  # a state the reset must overwrite everywhere
    physics.reset(keyframe="left/home")
    qpos, ctrl = _entries(physics, left)
    assert len(qpos) == 6
    _check_home(physics.model, physics.data, qpos, ctrl)
    physics.reset(keyframe="right/home")
    _check_home(physics.model, physics.data, *_entries(physics, right))


def test_written_model_keeps_the_keys_for_stock_mujoco(menagerie) -> None:
    scene, left, _ = _scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    stock = mujoco.MjModel.from_xml_string(scene.to_xml_string(), scene.get_assets())
    data = mujoco.MjData(stock)
    mujoco.mj_resetDataKeyframe(
        stock, data, mujoco.mj_name2id(stock, mujoco.mjtObj.mjOBJ_KEY, "left/home")
    )
    _check_home(stock, data, *_entries(physics, left))
    for name in ("qpos", "qvel", "act", "ctrl", "mpos", "mquat"):
        assert np.array_equal(getattr(stock, f"key_{name}"), getattr(physics.model, f"key_{name}"))


def test_keys_of_a_floating_arm_and_of_the_scene(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    arm = mjcf.from_path(UR5E)
    frame = scene.attach(arm)
    frame.pos = [1, 2, 0.5]
    frame.add("freejoint")
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.model.nq == 7 + 6
    full = np.arange(13, dtype=float) / 10
    scene.keyframe.add("key", name="everything", qpos=full)  # laid out for the whole scene
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.reset(keyframe="ur5e/home")
    assert np.array_equal(physics.data.qpos[:7], [1, 2, 0.5, 1, 0, 0, 0])  # the frame's pose
    assert np.array_equal(physics.data.qpos[7:], HOME)
    physics.reset(keyframe="everything")
    assert np.array_equal(physics.data.qpos, full)
    scene.keyframe.add("key", name="wrong", qpos=[0.1] * 5)
    with pytest.raises(mjcf.AttributeValueError, match=r'<key name="wrong">: .qpos. has 5 numbers'):
        mjcf.Physics.from_mjcf_model(scene)


def test_keys_leave_with_their_model(menagerie) -> None:
    scene, left, right = _scene()
    right.detach()
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert [physics.model.key(i).name for i in range(physics.model.nkey)] == ["left/home"]
    physics.reset(keyframe="left/home")
    _check_home(physics.model, physics.data, *_entries(physics, left))
