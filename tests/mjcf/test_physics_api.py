"""The Physics and binding API dm_control code calls: bind's forms, binding by name on a
physics made from XML or an MjModel, element_id, columns, .ptr, name2id/id2name, state
vectors, controls, after_reset, free, check_invalid_state as a context manager.
MuJoCo's mj_name2id and address arrays are the oracle."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import gym_model

Obj = mujoco.mjtObj


def arm_scene() -> tuple[mjcf.RootElement, mjcf.RootElement]:
    """A scene with an attached two-joint arm ('arm/...'), a free box and a motor."""
    arm = mjcf.RootElement(model="arm")
    upper = arm.worldbody.add("body", name="upper", pos=[0, 0, 1])
    upper.add("joint", name="shoulder", axis=[0, 1, 0])
    upper.add("geom", name="upper", type="capsule", fromto=[0, 0, 0, 0, 0, -0.3], size=[0.03])
    lower = upper.add("body", name="lower", pos=[0, 0, -0.3])
    lower.add("joint", name="elbow", axis=[0, 1, 0])
    lower.add("geom", name="lower", type="capsule", fromto=[0, 0, 0, 0, 0, -0.3], size=[0.03])
    lower.add("site", name="tip", pos=[0, 0, -0.3])
    arm.actuator.add("motor", name="elbow", joint="elbow", gear=[2])
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", name="floor", type="plane", size=[2, 2, 0.1])
    box = scene.worldbody.add("body", name="box", pos=[1, 0, 0.2])
    box.add("freejoint", name="box")
    box.add("geom", type="box", size=[0.1, 0.1, 0.1])
    scene.worldbody.add("site", name="anchor").attach(arm)
    return scene, arm


def physics_of(how: str, scene: mjcf.RootElement, tmp_path) -> mjcf.Physics:
    compiled = mjcf.Physics.from_mjcf_model(scene)
    if how == "from_mjcf_model":
        return compiled
    if how == "from_xml_string":
        return mjcf.Physics.from_xml_string(scene.to_xml_string(), assets=scene.get_assets())
    if how == "from_xml_path":
        path = tmp_path / "scene.xml"
        path.write_text(scene.to_xml_string())
        return mjcf.Physics.from_xml_path(path)
    if how == "from_binary_path":
        path = tmp_path / "scene.mjb"
        mujoco.mj_saveModel(compiled.model, str(path), None)
        return mjcf.Physics.from_binary_path(path)
    return mjcf.Physics.from_model(compiled.model)


CONSTRUCTORS = ["from_mjcf_model", "from_xml_string", "from_xml_path", "from_binary_path",
                "from_model"]  # fmt: skip


@pytest.mark.parametrize("how", CONSTRUCTORS)
def test_elements_bind_by_full_identifier_on_any_physics(how, tmp_path) -> None:
    scene, arm = arm_scene()
    physics = physics_of(how, scene, tmp_path)
    model = physics.model
    joints = arm.find_all("joint")
    bound = physics.bind(joints)
    ids = [mujoco.mj_name2id(model, Obj.mjOBJ_JOINT, j.full_identifier) for j in joints]
    names = ("arm/shoulder", "arm/elbow")
    assert ids == [mujoco.mj_name2id(model, Obj.mjOBJ_JOINT, n) for n in names]
    assert bound.element_id.tolist() == ids
    assert np.array_equal(bound.qpos, physics.data.qpos[model.jnt_qposadr[ids]])
    bound.qpos = [0.3, -0.2]
    assert np.array_equal(physics.data.qpos[model.jnt_qposadr[ids]], [0.3, -0.2])
    tip = physics.bind(arm.find("site", "tip"))
    assert tip.element_id == mujoco.mj_name2id(model, Obj.mjOBJ_SITE, "arm/tip")
    expected = mujoco.MjData(model)
    mujoco.mj_copyData(expected, model, physics.data)
    mujoco.mj_forward(model, expected)
    assert np.array_equal(tip.xpos, expected.site_xpos[tip.element_id])  # tracked write
    box = physics.bind(scene.find("joint", "box"))
    assert box.qpos.shape == (7,)
    motor = physics.bind(arm.find("actuator", "elbow"))
    assert motor.gear[0] == 2.0
    if how != "from_mjcf_model":
        stray = arm.worldbody.add("site", name="stray")
        with pytest.raises(mjcf.BindingError, match=r"stray.*no site named 'arm/stray'"):
            physics.bind(stray)
        unnamed = arm.find("body", "lower").add("site")
        # Added after compiling, it has a generated name the compiled model does not have.
        with pytest.raises(mjcf.BindingError, match=r"no site named 'arm//unnamed_site_1'"):
            physics.bind(unnamed)


def test_bind_takes_every_form_of_a_collection() -> None:
    scene, arm = arm_scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    joints = arm.find_all("joint")
    expected = physics.bind(joints).qpos
    assert physics.bind(tuple(joints)) is physics.bind(joints)
    assert np.array_equal(physics.bind(iter(joints)).qpos, expected)
    assert np.array_equal(physics.bind(j for j in joints).qpos, expected)
    chosen = np.random.default_rng(0).choice(np.array(joints, dtype=object), 2, replace=False)
    assert np.array_equal(
        physics.bind(chosen).element_id, [physics.bind(j).element_id for j in chosen]
    )
    assert isinstance(physics.bind(joints[0]).element_id, int)
    with pytest.raises(ValueError):
        physics.bind(joints).element_id[0] = 3  # read-only, as dm_control's
    assert physics.bind(None) is None
    empty = physics.bind([])
    assert empty.qpos.shape == (0,) and empty.xpos.size == 0 and empty.element_id.size == 0
    empty.ctrl = np.zeros(0)  # nothing to write, fine
    empty.ctrl = ()  # a task without actuators writes its empty action
    empty["qpos"] = []
    for value in ([1.0], 5):
        with pytest.raises(ValueError, match="Cannot assign a value to an empty binding"):
            empty.ctrl = value
    with pytest.raises(mjcf.BindingError, match="takes an element or an iterable"):
        physics.bind(3)


def test_columns_by_index_slice_list_and_name() -> None:
    scene, arm = arm_scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    bodies = [arm.find("body", "upper"), arm.find("body", "lower")]
    both, lower = physics.bind(bodies), physics.bind(bodies[1])
    ids = both.element_id
    xpos = physics.data.xpos
    assert lower["xpos", "z"] == xpos[ids[1], 2]
    assert np.array_equal(lower["xpos", ["x", "z"]], xpos[ids[1], [0, 2]])
    assert np.array_equal(both["xpos", "z"], xpos[ids, 2])
    assert np.array_equal(both["xpos", ["x", "z"]], xpos[np.ix_(ids, [0, 2])])
    assert np.array_equal(both["xpos", 1:], xpos[ids, 1:])
    assert np.array_equal(both["xpos", [2, 0]], xpos[np.ix_(ids, [2, 0])])
    assert np.array_equal(both["xquat", "qw"], physics.data.xquat[ids, 0])
    assert np.array_equal(both["xmat", "zz"], physics.data.xmat[ids, 8])
    assert np.array_equal(both["xpos"], both.xpos)
    both["pos", ["x", "z"]] = [[0.1, 1.1], [0.2, -0.4]]
    assert np.array_equal(physics.model.body_pos[np.ix_(ids, [0, 2])], [[0.1, 1.1], [0.2, -0.4]])
    both["pos", "y"] += 0.5
    assert np.array_equal(physics.model.body_pos[ids, 1], [0.5, 0.5])
    lower["pos", 2] = -0.25
    assert physics.model.body_pos[ids[1], 2] == -0.25
    box = physics.bind(scene.find("geom", "floor"))
    box["rgba", "a"] = 0.5
    assert physics.named.model.geom_rgba["floor", "a"] == 0.5
    with pytest.raises(mjcf.BindingError, match=r"no column named 'w'.*\['x', 'y', 'z'\]"):
        both["xpos", "w"]
    with pytest.raises(mjcf.BindingError, match="has no columns"):
        physics.bind(arm.find_all("joint"))["qpos", 0]
    with pytest.raises(mjcf.BindingError, match="no field 'xpso'"):
        both["xpso"]


def test_named_columns_and_lists_of_names() -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    named, data = physics.named.data, physics.data
    torso = mujoco.mj_name2id(physics.model, Obj.mjOBJ_BODY, "torso")
    assert named.xpos["torso", "z"] == data.xpos[torso, 2]
    assert np.array_equal(named.xpos["torso", ["x", "z"]], data.xpos[torso, [0, 2]])
    legs = [mujoco.mj_name2id(physics.model, Obj.mjOBJ_JOINT, n) for n in ("hip_1", "ankle_1")]
    assert np.array_equal(
        named.qpos[["hip_1", "ankle_1"]], data.qpos[physics.model.jnt_qposadr[legs]]
    )
    bodies = ["torso", "aux_1"]
    ids = [mujoco.mj_name2id(physics.model, Obj.mjOBJ_BODY, n) for n in bodies]
    column = np.array(bodies).reshape(-1, 1)  # dm_control's broadcasting idiom
    assert np.array_equal(named.xpos[column, ["x", "y", "z"]], data.xpos[ids])
    assert np.array_equal(named.xquat["torso", ["qw", "qz"]], data.xquat[torso, [0, 3]])
    physics.named.model.geom_rgba["floor", "r"] = 0.25
    assert physics.named.model.geom_rgba["floor"][0] == 0.25
    with pytest.raises(mjcf.NotFoundError, match="no column named 'q'"):
        named.xpos["torso", "q"]


def test_ptr_and_names_by_type_string() -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    model, data = physics.model, physics.data
    assert model.ptr is model and data.ptr is data
    mujoco.mj_step(physics.model.ptr, physics.data.ptr)  # what dm_control code does
    hip = mujoco.mj_name2id(model, Obj.mjOBJ_JOINT, "hip_1")
    assert model.name2id("hip_1", "joint") == hip
    assert model.name2id("hip_1", Obj.mjOBJ_JOINT) == hip
    assert model.name2id("hip_1", int(Obj.mjOBJ_JOINT)) == hip
    assert model.id2name(hip, "joint") == "hip_1"
    assert model.id2name(1, "body") == "torso"
    assert model.id2name(0, "tendon") == ""  # the ant has none: '' as dm_control returns
    with pytest.raises(mjcf.NotFoundError, match="no joint named 'hipp'"):
        model.name2id("hipp", "joint")
    with pytest.raises(mjcf.NotFoundError, match=r"no MuJoCo object type 'jiont'.*'joint'"):
        model.name2id("hip_1", "jiont")


def test_state_vectors_and_controls() -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    model, data = physics.model, physics.data
    physics.set_control(np.full(model.nu, 0.5))
    physics.step(20)
    state = physics.get_state()
    assert np.array_equal(state, np.concatenate([data.qpos, data.qvel, data.act]))
    assert np.array_equal(physics.state(), state)
    later = physics.copy()
    later.step(10)
    physics.step(10)
    after = physics.get_state()
    physics.set_state(state)
    assert physics.is_dirty and np.array_equal(physics.get_state(), state)
    physics.step(10)
    # The solver's warm start is not physics state (as in dm_control): close, not bit for bit.
    assert np.allclose(physics.get_state(), after, atol=1e-6)
    assert np.array_equal(later.get_state(), after)
    with pytest.raises(mjcf.StateError, match=rf"shape \(3,\), expected \({state.size},\)"):
        physics.set_state(np.zeros(3))
    control = physics.control()
    control[:] = 9.0
    assert np.all(data.ctrl == 0.5)  # a copy
    with pytest.raises(mjcf.StateError, match="control has shape"):
        physics.set_control(np.zeros(3))
    assert np.array_equal(physics.position(), data.qpos) and physics.position() is not data.qpos
    assert np.array_equal(physics.velocity(), data.qvel)
    assert physics.activation().shape == (model.na,)
    with pytest.raises(mjcf.StateError, match="nstep"):
        physics.step(0)


def test_after_reset_computes_no_actuator_force() -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    physics.data.ctrl[:] = 1.0
    physics.after_reset()
    assert np.all(physics.data.actuator_force == 0)
    motors = physics._binding(Obj.mjOBJ_ACTUATOR, np.arange(physics.model.nu))
    assert np.all(motors.force == 1.0)  # read through a binding: with actuation


def test_check_invalid_state_as_call_and_context(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo logs its warnings to MUJOCO_LOG.TXT in the cwd
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    physics.check_invalid_state()
    with physics.check_invalid_state() as inside:
        assert inside is physics
        physics.step()
    with pytest.raises(mjcf.PhysicsError, match="BADQVEL"), physics.check_invalid_state():
        physics.named.data.qvel[:] = 1e12
        physics.step()
    with pytest.raises(mjcf.PhysicsError):
        physics.check_invalid_state()
    physics.reset()
    physics.check_invalid_state()


def test_suppress_physics_errors_logs_an_invalid_state_instead(caplog) -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    physics.named.data.qvel[:] = 1e12
    physics.step()
    with physics.suppress_physics_errors() as inside:
        assert inside is physics
        with caplog.at_level("WARNING", logger="mjcf.physics"):
            physics.check_invalid_state()
    assert "BADQVEL" in caplog.text
    with pytest.raises(mjcf.PhysicsError, match="BADQVEL"):  # raises again after the block
        physics.check_invalid_state()


def test_free_releases_the_simulation() -> None:
    physics = mjcf.Physics.from_xml_path(gym_model("ant"))
    joints = physics._binding(Obj.mjOBJ_JOINT, [1, 2])
    joints.qpos  # noqa: B018
    physics.free()
    assert physics.model is None and physics.data is None
    assert not joints._cache


def test_reload_from_xml_string_as_dm_control(tmp_path) -> None:
    """dm_control's reload: bindings are cached until the physics is reloaded, then made
    again, finding the elements by their full identifiers in the reloaded model."""
    scene, _ = arm_scene()
    physics = mjcf.Physics.from_mjcf_model(scene)
    joints = scene.find_all("joint")
    original = physics.bind(joints)
    assert physics.bind(joints) is original and physics.bind(joints[::-1]) is not original
    physics.bind(joints[1:]).qpos = 0.4
    physics.reload_from_xml_string(scene.to_xml_string(), assets=scene.get_assets())
    reloaded = physics.bind(joints)
    assert reloaded is not original
    fresh = mjcf.Physics.from_mjcf_model(scene)
    assert np.array_equal(reloaded.qpos, fresh.bind(joints).qpos)  # fresh data
    assert np.array_equal(reloaded.element_id, fresh.bind(joints).element_id)
    path = tmp_path / "scene.xml"
    path.write_text(scene.to_xml_string())
    physics.reload_from_xml_path(path)
    assert physics.bind(joints) is not reloaded and physics.model.njnt == fresh.model.njnt
    with pytest.raises(mjcf.CompileError):
        physics.reload_from_xml_string("<mujoco><worldbody><geom/></worldbody></mujoco>")
    assert physics.model.njnt == fresh.model.njnt  # a failed reload changes nothing
