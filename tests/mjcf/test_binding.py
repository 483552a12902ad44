"""Bindings on real models: the rows MuJoCo's own address arrays give, read and written live."""

from __future__ import annotations

import pickle
from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

from mjcf import errors
from mjcf.physics import Physics
from mjcf.sim import fields
from mjcf.sim.binding import Binding, WriteThrough
from tests.conftest import ROBOTIQ as GRIPPER
from tests.conftest import UR5E

Obj = mujoco.mjtObj
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata" / "model.xml"


def load(path: Path) -> Physics:
    physics = Physics.from_xml_path(path)
    # A state away from the initial one, so that rows are not all equal.
    rng = np.random.default_rng(0)
    physics.data.qvel[:] = rng.normal(scale=0.1, size=physics.model.nv)
    physics.data.ctrl[:] = rng.uniform(-0.3, 0.3, size=physics.model.nu)
    physics.step(10)
    return physics


MODELS = {
    "humanoid": lambda: load(GYM_ASSETS / "humanoid.xml"),
    "ant": lambda: load(GYM_ASSETS / "ant.xml"),
    "mujoco testdata": lambda: load(MUJOCO_TESTDATA),
    "ur5e": lambda: load(UR5E),
    "robotiq 2f85": lambda: load(GRIPPER),
}


@pytest.fixture(params=list(MODELS.values()), ids=list(MODELS))
def physics(request) -> Physics:
    return request.param()


def test_joint_qpos_and_qvel_are_mujocos_address_slices(physics):
    model, data = physics.model, physics.data
    widths = {
        mujoco.mjtJoint.mjJNT_FREE: (7, 6),
        mujoco.mjtJoint.mjJNT_BALL: (4, 3),
        mujoco.mjtJoint.mjJNT_SLIDE: (1, 1),
        mujoco.mjtJoint.mjJNT_HINGE: (1, 1),
    }
    for j in range(model.njnt):
        nq, nv = widths[mujoco.mjtJoint(model.jnt_type[j])]
        qadr, vadr = model.jnt_qposadr[j], model.jnt_dofadr[j]
        joint = physics._binding(Obj.mjOBJ_JOINT, j)
        assert joint.qpos.shape == (nq,) and joint.qvel.shape == (nv,)
        assert np.array_equal(joint.qpos, data.qpos[qadr : qadr + nq])
        assert np.array_equal(joint.qvel, data.qvel[vadr : vadr + nv])
        assert np.array_equal(joint.qfrc_applied, data.qfrc_applied[vadr : vadr + nv])
        assert np.array_equal(joint.damping, model.dof_damping[vadr : vadr + nv])
        assert np.array_equal(joint.range, model.jnt_range[j])
        assert np.array_equal(joint.qpos0, model.qpos0[qadr : qadr + nq])
    every = physics._binding(Obj.mjOBJ_JOINT, np.arange(model.njnt)[::-1])
    expected = np.concatenate(
        [
            data.qpos[model.jnt_qposadr[j] : model.jnt_qposadr[j] + widths[mujoco.mjtJoint(t)][0]]
            for j, t in reversed(list(enumerate(model.jnt_type)))
        ]
    )
    assert np.array_equal(every.qpos, expected)
    assert every.range.shape == (model.njnt, 2)


def test_free_and_ball_joints_write_through():
    physics = Physics.from_xml_path(MUJOCO_TESTDATA)
    model, data = physics.model, physics.data
    free = int(np.flatnonzero(model.jnt_type == mujoco.mjtJoint.mjJNT_FREE)[0])
    ball = int(np.flatnonzero(model.jnt_type == mujoco.mjtJoint.mjJNT_BALL)[0])
    root = physics._binding(Obj.mjOBJ_JOINT, free)
    root.qpos[:3] = [1.0, 2.0, 3.0]  # a single joint's rows are a view
    assert np.array_equal(data.qpos[model.jnt_qposadr[free] :][:3], [1, 2, 3])
    assert np.shares_memory(root.qpos, data.qpos)

    both = physics._binding(Obj.mjOBJ_JOINT, [ball, free])  # rows 7 apart: not a slice
    assert isinstance(both.qpos, WriteThrough) and both.qpos.shape == (11,)
    both.qpos[0] = 0.5  # item assignment on a copy writes back
    assert data.qpos[model.jnt_qposadr[ball]] == 0.5
    both.qpos[:] += 1.0
    assert data.qpos[model.jnt_qposadr[ball]] == 1.5
    assert data.qpos[model.jnt_qposadr[free]] == 2.0
    values = np.arange(11.0)
    both.qpos = values
    assert np.array_equal(both.qpos, values)
    assert np.array_equal(data.qvel[model.jnt_dofadr[free] :][:6], both.qvel[3:])


def test_sensors_read_their_sensordata_slices():
    physics = load(MUJOCO_TESTDATA)
    model, data = physics.model, physics.data
    assert model.nsensor > 5 and len(set(model.sensor_dim)) > 1
    for s in range(model.nsensor):
        adr, dim = model.sensor_adr[s], model.sensor_dim[s]
        sensor = physics._binding(Obj.mjOBJ_SENSOR, s)
        assert sensor.sensordata.shape == (dim,)
        assert np.array_equal(sensor.sensordata, data.sensordata[adr : adr + dim])
        assert np.array_equal(sensor.sensordata, data.sensor(s).data)
    every = physics._binding(Obj.mjOBJ_SENSOR, np.arange(model.nsensor))
    assert np.array_equal(every.sensordata, data.sensordata)
    physics.step(5)  # a binding keeps reading the live buffer
    assert np.array_equal(every.sensordata, data.sensordata)


def test_actuator_ctrl_writes_move_the_ur5e():
    physics = Physics.from_xml_path(UR5E)
    arm = physics.bind_names(Obj.mjOBJ_ACTUATOR, fields.names(physics.model, Obj.mjOBJ_ACTUATOR))
    joints = physics._binding(Obj.mjOBJ_JOINT, np.arange(physics.model.njnt))
    target = np.array([0.5, -1.0, 1.2, -0.6, 0.4, 0.3])
    arm.ctrl = target
    assert np.array_equal(physics.data.ctrl, target)
    assert arm.gear.shape == (6, 6) and arm.ctrlrange.shape == (6, 2)
    start_error = np.abs(joints.qpos - target).max()
    physics.step(1500)
    assert np.abs(joints.qpos - target).max() < 0.1 * start_error
    assert np.abs(arm.force).max() > 0


def test_gripper_tendon_and_equality_rows():
    physics = load(GRIPPER)
    model, data = physics.model, physics.data
    split = physics.bind_names(Obj.mjOBJ_TENDON, "split")
    assert split.length.shape == () and split.length == data.ten_length[0]
    assert np.array_equal(split.range, model.tendon_range[0])
    couplings = physics._binding(Obj.mjOBJ_EQUALITY, np.arange(model.neq))
    assert np.array_equal(couplings.data, model.eq_data)
    assert np.array_equal(couplings.active, data.eq_active)
    couplings.active = False  # a state field written through
    assert not data.eq_active.any()
    couplings.active = True
    fingers = physics._binding(Obj.mjOBJ_ACTUATOR, 0)
    closing = physics._binding(Obj.mjOBJ_JOINT, np.arange(model.njnt))
    fingers.ctrl = 255.0  # fully closed
    physics.step(500)
    assert np.abs(closing.qpos).max() > 0.1


def test_actuator_ctrl_writes_move_the_humanoid():
    physics = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    motors = physics._binding(Obj.mjOBJ_ACTUATOR, np.arange(physics.model.nu))
    joints = physics._binding(Obj.mjOBJ_JOINT, np.arange(1, physics.model.njnt))
    still = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    motors.ctrl = 0.4
    physics.step(20)
    still.step(20)
    moved = joints.qpos - still._binding(Obj.mjOBJ_JOINT, np.arange(1, still.model.njnt)).qpos
    assert np.abs(moved).max() > 1e-2
    assert motors.ctrl.shape == (physics.model.nu,)


def test_single_objects_drop_the_leading_axis():
    physics = load(GYM_ASSETS / "humanoid.xml")
    torso = physics.bind_names(Obj.mjOBJ_BODY, "torso")
    assert torso.xpos.shape == (3,) and torso.xquat.shape == (4,)
    assert torso.mass.shape == () and np.shares_memory(torso.mass, physics.model.body_mass)
    torso.mass[...] = 9.0  # a 0-d view writes through
    assert physics.model.body_mass[1] == 9.0
    torso.mass = 10.0
    assert physics.model.body_mass[1] == 10.0
    motor = physics._binding(Obj.mjOBJ_ACTUATOR, 0)
    assert motor.ctrl.shape == () and motor.gear.shape == (6,)
    hinge = physics.bind_names(Obj.mjOBJ_JOINT, "right_knee")
    assert hinge.qpos.shape == (1,) and hinge.range.shape == (2,)
    bodies = physics.bind_names(Obj.mjOBJ_BODY, ["torso"])
    assert bodies.xpos.shape == (1, 3) and bodies.mass.shape == (1,)


def test_reads_are_views_when_rows_are_evenly_spaced():
    physics = load(GYM_ASSETS / "humanoid.xml")
    data = physics.data
    run = physics._binding(Obj.mjOBJ_JOINT, np.arange(1, 6))
    assert np.shares_memory(run.qpos, data.qpos)
    strided = physics._binding(Obj.mjOBJ_BODY, [1, 3, 5])
    assert np.shares_memory(strided.xpos, data.xpos)
    assert np.array_equal(strided.xpos, data.xpos[[1, 3, 5]])
    scattered = physics._binding(Obj.mjOBJ_BODY, [5, 1, 2])
    assert not np.shares_memory(scattered.xpos, data.xpos)
    scattered.xfrc_applied[1, 2] = 7.0
    assert data.xfrc_applied[1, 2] == 7.0
    derived = scattered.xpos[1:]  # arrays derived from a copy are plain copies
    derived[0] = 0.0
    assert not np.array_equal(data.xpos[2], np.zeros(3))


def test_mujoco4_multi_control_actuator():
    physics = Physics.from_xml_string(
        """
        <mujoco>
          <worldbody><body><joint name="ball" type="ball"/><geom size="0.1"/>
          <body pos="0 0 -0.5"><joint name="hinge"/><geom size="0.1"/></body></body></worldbody>
          <actuator>
            <motor name="spin" joint="hinge"/>
            <orientation name="aim" joint="ball" kp="5"/>
          </actuator>
        </mujoco>"""
    )
    aim = physics.bind_names(Obj.mjOBJ_ACTUATOR, "aim")
    assert aim.ctrl.shape == (3,) and aim.force.shape == (3,) and aim.gear.shape == (3, 6)
    aim.ctrl = [0.1, 0.2, 0.3]
    assert np.array_equal(physics.data.ctrl[1:], [0.1, 0.2, 0.3])
    both = physics.bind_names(Obj.mjOBJ_ACTUATOR, ["aim", "spin"])
    assert np.array_equal(both.ctrl, [0.1, 0.2, 0.3, 0.0])
    spin = physics.bind_names(Obj.mjOBJ_ACTUATOR, "spin")
    assert spin.ctrl.shape == () and spin.act.shape == (0,)


def test_mocap_bodies():
    physics = Physics.from_xml_string(
        """
        <mujoco><worldbody>
          <body name="target" mocap="true" pos="1 2 3"><geom size="0.1"/></body>
          <body name="other" mocap="true"><geom size="0.1"/></body>
          <body name="free"><freejoint/><geom size="0.1"/></body>
        </worldbody></mujoco>"""
    )
    target = physics.bind_names(Obj.mjOBJ_BODY, "target")
    assert np.array_equal(target.mocap_pos, [1, 2, 3])
    target.mocap_pos = [0, 0, 1]
    assert np.array_equal(physics.data.mocap_pos[0], [0, 0, 1])
    both = physics.bind_names(Obj.mjOBJ_BODY, ["other", "target"])
    assert both.mocap_quat.shape == (2, 4)
    mixed = physics.bind_names(Obj.mjOBJ_BODY, ["target", "free"])
    assert mixed.xpos.shape == (2, 3)  # fields every body has: bound together
    for error in (ValueError, AttributeError):  # what dm_control code catches
        with pytest.raises(error, match=r"'free' own no rows of 'mocap_pos'.*not mocap"):
            mixed.mocap_pos  # noqa: B018
    with pytest.raises(errors.BindingError, match="not mocap"):
        mixed.mocap_pos = [[0, 0, 0], [1, 1, 1]]
    assert np.array_equal(physics.data.mocap_pos[0], [0, 0, 1])  # nothing written


def test_bindings_are_cached_and_follow_reset_and_copy():
    physics = load(GYM_ASSETS / "humanoid.xml")
    ids = np.array([1, 4, 7])
    joints = physics._binding(Obj.mjOBJ_JOINT, ids)
    assert physics._binding(Obj.mjOBJ_JOINT, ids.astype(np.int32)) is joints
    assert physics._binding(Obj.mjOBJ_JOINT, [1, 4, 7]) is joints
    assert physics._binding(Obj.mjOBJ_JOINT, 1) is not physics._binding(Obj.mjOBJ_JOINT, [1])
    joints.qpos = [0.1, 0.2, 0.3]
    physics.reset()
    assert np.array_equal(joints.qpos, physics.data.qpos[physics.model.jnt_qposadr[ids]])
    joints.qpos = [0.4, 0.5, 0.6]
    clone = physics.copy()
    on_clone = clone._binding(Obj.mjOBJ_JOINT, ids)
    on_clone.qpos = [1.0, 1.0, 1.0]
    assert np.array_equal(joints.qpos, [0.4, 0.5, 0.6])  # the original's data is untouched
    assert np.array_equal(on_clone.qpos, [1.0, 1.0, 1.0])
    restored = pickle.loads(pickle.dumps(physics))
    assert np.array_equal(restored._binding(Obj.mjOBJ_JOINT, ids).qpos, [0.4, 0.5, 0.6])


class ObservedPhysics(Physics):
    """A physics holding bindings, as composer's observables will."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        super().__init__(model, data)
        self.legs = self._binding(Obj.mjOBJ_JOINT, np.array([1, 2, 3]))


def test_bindings_pickle_and_copy_with_their_physics():
    physics = ObservedPhysics.from_xml_path(GYM_ASSETS / "ant.xml")
    physics.legs.qpos = [0.1, 0.2, 0.3]
    for clone in (pickle.loads(pickle.dumps(physics)), physics.copy()):
        assert clone.legs is not physics.legs and clone.legs._physics is clone
        assert np.array_equal(clone.legs.qpos, [0.1, 0.2, 0.3])
        clone.legs.qpos = [1.0, 1.0, 1.0]  # writes the clone's MjData only
        assert np.array_equal(clone.data.qpos[7:10], [1, 1, 1])
        assert np.array_equal(physics.legs.qpos, [0.1, 0.2, 0.3])
        clone.reset()
        assert np.array_equal(clone.legs.qpos, clone.data.qpos[7:10])


def test_binding_made_before_a_model_change_refuses_to_read():
    physics = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    joints = physics._binding(Obj.mjOBJ_JOINT, [1, 2])
    joints.qpos  # noqa: B018 - cache the arrays of the first model
    other = Physics.from_xml_path(GYM_ASSETS / "ant.xml")
    physics._attach(other.model, other.data)
    with pytest.raises(errors.BindingError, match="bind again"):
        joints.qpos  # noqa: B018
    assert physics._binding(Obj.mjOBJ_JOINT, [1, 2]).qpos.shape == (2,)


def test_bad_input_raises_binding_errors():
    physics = Physics.from_xml_path(GYM_ASSETS / "ant.xml")
    joint = Obj.mjOBJ_JOINT
    with pytest.raises(errors.BindingError, match="empty list of joints"):
        physics._binding(joint, [])
    with pytest.raises(errors.BindingError, match="joint id 99 is out of range"):
        physics._binding(joint, [0, 99])
    with pytest.raises(errors.BindingError, match="out of range"):
        physics._binding(joint, -1)
    with pytest.raises(errors.BindingError, match="must not repeat"):
        physics._binding(joint, [1, 1])
    with pytest.raises(errors.BindingError, match="1-D list of ints"):
        physics._binding(joint, [0.5])
    with pytest.raises(errors.BindingError, match="no MjModel/MjData field is indexed by"):
        physics._binding(Obj.mjOBJ_FRAME, 0)
    legs = physics._binding(joint, [1, 2, 3])
    with pytest.raises(errors.BindingError, match=r"no field 'qpso' \(did you mean 'qpos'"):
        legs.qpso  # noqa: B018
    with pytest.raises(errors.BindingError, match=r"valid fields: .*range.*xanchor"):
        legs.qpso = 1  # assignment to an unknown field is refused, not stored
    assert not hasattr(legs, "qpso") and hasattr(legs, "qpos")
    with pytest.raises(errors.BindingError, match=r"cannot write \(2,\)-shaped values to 'qpos'"):
        legs.qpos = [1.0, 2.0]
    with pytest.raises(errors.BindingError, match=r"bound rows have shape \(3, 2\)"):
        legs.range = np.zeros((2, 3))
    legs.qpos = 0.25  # broadcasting a scalar is fine
    assert np.all(legs.qpos == 0.25)
    with pytest.raises(errors.NotFoundError, match="no joint named 'hipp_1'"):
        physics.bind_names(joint, ["hip_1", "hipp_1"])


def test_binding_repr_and_dir():
    physics = Physics.from_xml_path(GYM_ASSETS / "ant.xml")
    legs = physics.bind_names(Obj.mjOBJ_JOINT, ["hip_1", "ankle_1"])
    assert repr(legs) == "<JointBinding 2 joints ['hip_1', 'ankle_1']>"
    assert {"qpos", "qvel", "range", "jnt_range", "dof_damping"} <= set(dir(legs))
    assert isinstance(legs, Binding) and legs.kind == Obj.mjOBJ_JOINT
    assert legs.ids.tolist() == [
        mujoco.mj_name2id(physics.model, Obj.mjOBJ_JOINT, n) for n in ("hip_1", "ankle_1")
    ]
