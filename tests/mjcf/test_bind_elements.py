"""physics.bind(element): model elements bound to the compiled simulation."""

from __future__ import annotations

import copy
import pickle

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import ROBOTIQ, UR5E, gym_model

_WIDTHS = {0: (7, 6), 1: (4, 3), 2: (1, 1), 3: (1, 1)}  # free, ball, slide, hinge


def _check_joints(physics: mjcf.Physics, joints: list[mjcf.Element]) -> None:
    model, data = physics.model, physics.data
    for joint in joints:
        index = mujoco.mj_name2id(
            model, mujoco.mjtObj.mjOBJ_JOINT, physics._compiled.name_of(joint)
        )
        width_q, width_v = _WIDTHS[int(model.jnt_type[index])]
        qpos_start, dof_start = model.jnt_qposadr[index], model.jnt_dofadr[index]
        bound = physics.bind(joint)
        assert np.array_equal(bound.qpos, data.qpos[qpos_start : qpos_start + width_q])
        assert np.array_equal(bound.qvel, data.qvel[dof_start : dof_start + width_v])
        values = np.linspace(0.1, 0.2, width_q)
        bound.qpos = values
        assert np.array_equal(data.qpos[qpos_start : qpos_start + width_q], values)
    together = np.concatenate([np.atleast_1d(physics.bind(j).qpos) for j in joints])
    assert np.array_equal(np.ravel(physics.bind(joints).qpos), together)


def test_humanoid_joints_sensors_and_actuators() -> None:
    model = mjcf.from_path(gym_model("humanoid"))
    physics = mjcf.Physics.from_mjcf_model(model)
    joints = model.find_all("joint")
    _check_joints(physics, joints)
    physics.reset()
    motors = model.find_all("actuator")
    hip = model.find("joint", "right_hip_y")
    before = physics.bind(hip).qpos.copy()
    physics.bind(motors).ctrl = 0.0
    physics.bind(model.find("actuator", "right_hip_y")).ctrl = 0.4
    physics.step(50)
    assert not np.allclose(physics.bind(hip).qpos, before)
    torso = model.find("body", "torso")
    assert np.array_equal(physics.bind(torso).xpos, physics.named.data.xpos["torso"])
    assert physics.bind(torso).mass == physics.named.model.body_mass["torso"]


def _arm_with_gripper(name: str) -> mjcf.RootElement:
    arm = mjcf.from_path(UR5E)
    arm.model = name
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    return arm


def test_composed_robots_bind_through_scoped_names(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", type="plane", size=[2, 2, 0.1])
    arms = [_arm_with_gripper("left"), _arm_with_gripper("right")]
    for x, arm in zip((-0.5, 0.5), arms, strict=True):
        scene.worldbody.add("site", pos=[x, 0, 0]).attach(arm)
    physics = mjcf.Physics.from_mjcf_model(scene)
    _check_joints(physics, scene.find_all("joint"))
    physics.reset()
    for arm in arms:
        gripper = arm.find_all("actuator")[-1]
        assert gripper.full_identifier == f"{arm.model}/robotiq_2f85/fingers_actuator"
        physics.bind(gripper).ctrl = 255
        assert physics.named.data.ctrl[gripper.full_identifier] == 255
    elbow = arms[0].find("joint", "elbow_joint")
    physics.bind(arms[0].find("actuator", "elbow")).ctrl = 1.0
    physics.step(200)
    assert abs(physics.bind(elbow).qpos[0]) > 0.1
    sensors = scene.find_all("sensor")
    for sensor in sensors:
        index = mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_SENSOR, sensor.full_identifier)
        start, size = physics.model.sensor_adr[index], physics.model.sensor_dim[index]
        assert np.array_equal(
            physics.bind(sensor).sensordata, physics.data.sensordata[start : start + size]
        )


def test_free_attachment_frame_binds_as_a_body() -> None:
    scene = mjcf.RootElement()
    box = mjcf.RootElement(model="box")
    box.worldbody.add("geom", type="box", size=[0.1, 0.1, 0.1], mass=1)
    frame = scene.attach(box)
    free = frame.add("freejoint")
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(free).qpos = [0, 0, 1, 1, 0, 0, 0]
    physics.forward()
    assert np.allclose(physics.bind(frame).xpos, [0, 0, 1])
    assert physics.bind(scene.worldbody).xpos.tolist() == [0, 0, 0]
    still = mjcf.RootElement(model="still")
    still.worldbody.add("geom", size=[0.1])
    fixed = scene.attach(still)
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.bind(fixed).xpos.tolist() == [0, 0, 0]  # a frame's pose: see frame_binding
    physics.bind(fixed).pos = [0, 0, 1]  # moves the frame and the geom it holds
    np.testing.assert_allclose(physics.bind(still.find_all("geom")).xpos, [[0, 0, 1]])


def test_binding_errors() -> None:
    model = mjcf.from_path(gym_model("ant"))
    physics = mjcf.Physics.from_mjcf_model(model)
    other = mjcf.from_path(gym_model("ant"))
    stranger = other.find("body", "torso").add("site", name="stranger")
    with pytest.raises(mjcf.BindingError, match=r"stranger.*no site named 'stranger'"):
        physics.bind(stranger)
    with pytest.raises(mjcf.BindingError, match="different kinds"):
        physics.bind([model.find("joint", "hip_1"), model.find("body", "torso")])
    hip = model.find("joint", "hip_1")
    with pytest.raises(mjcf.BindingError, match="xpos"):
        physics.bind(hip).xpos  # noqa: B018
    site = model.find("body", "torso").add("site", name="probe")
    physics = mjcf.Physics.from_mjcf_model(model)
    assert physics.bind(site).xpos.shape == (3,)
    site.remove()  # the compiled physics still has it; a new compile does not
    assert physics.bind(site).xpos.shape == (3,)
    with pytest.raises(mjcf.BindingError, match="removed"):
        mjcf.Physics.from_mjcf_model(model).bind(site)
    new = model.worldbody.add("body", name="new")
    with pytest.raises(mjcf.BindingError, match="not in the compiled model"):
        physics.bind(new)
    with pytest.raises(mjcf.BindingError, match="cannot be bound"):
        physics.bind(model.default)


def test_bindings_survive_copy_pickle_and_reload() -> None:
    model = mjcf.from_path(gym_model("ant"))
    physics = mjcf.Physics.from_mjcf_model(model)
    hip = model.find("joint", "hip_1")
    physics.bind(hip).qpos = 0.3
    clone = physics.copy()
    assert clone.bind(hip).qpos[0] == 0.3
    restored = pickle.loads(pickle.dumps(physics))
    assert restored.data.qpos.tolist() == physics.data.qpos.tolist()
    physics.step(100)
    restored.step(100)
    assert np.array_equal(restored.data.qpos, physics.data.qpos)
    # A pickle of the model and physics together keeps the elements bindable.
    model_copy, physics_copy = pickle.loads(pickle.dumps((model, physics)))
    assert physics_copy.bind(model_copy.find("joint", "hip_1")).qpos[0] == physics.bind(hip).qpos[0]
    # Reloading after a change gives fresh data, as dm_control does; keep_state=True keeps
    # time and the state of what still exists.
    model.find("body", "torso").add("geom", type="sphere", size=[0.05], pos=[0, 0, 0.3])
    state = physics.bind(model.find_all("joint")).qpos.copy()
    time = physics.time()
    physics.reload_from_mjcf_model(model, keep_state=True)
    assert np.array_equal(physics.bind(model.find_all("joint")).qpos, state)
    assert physics.time() == time > 0
    physics.reload_from_mjcf_model(model)
    assert physics.time() == 0.0
    assert np.array_equal(physics.data.qpos, physics.model.qpos0)
    deep = copy.deepcopy(model)
    assert deep.find("joint", "hip_1") is not hip
