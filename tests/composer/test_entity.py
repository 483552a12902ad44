"""Entities and arenas: the entity tree, attachment, free-body poses and velocities."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from tests.composer.scenes import Block, Pendulum


def test_attach_detach_and_iterate_the_entity_tree():
    arena, arm, gripper = Floor(name="arena"), Pendulum("arm"), Pendulum("gripper")
    frame = arena.attach(arm)
    arm.attach(gripper, attach_site=arm.tip)
    assert [e.name for e in arena.iter_entities()] == ["arena", "arm", "gripper"]
    assert gripper.parent is arm and arm.attachment_frame is frame
    assert arena.mjcf_model.find("joint", "arm/gripper/hinge") is gripper.hinge
    assert [e.scope_in(arena) for e in arena.iter_entities()] == ["", "arm", "arm/gripper"]
    assert gripper.scope_in(arm) == "gripper"
    with pytest.raises(composer.EntityError, match="'arm' is not attached under entity 'gripper'"):
        arm.scope_in(gripper)
    with pytest.raises(composer.EntityError, match="'gripper' is already attached to 'arm'"):
        arena.attach(gripper)
    gripper.detach()
    assert [e.name for e in arena.iter_entities()] == ["arena", "arm"]
    assert arena.mjcf_model.find("joint", "arm/gripper/hinge") is None
    with pytest.raises(composer.EntityError, match="'gripper' is not attached"):
        gripper.detach()
    with pytest.raises(composer.EntityError, match="cannot attach entity 'arm2'"):
        arena.attach(Pendulum("arm2"), attach_site=arena.floor)


def test_an_entity_must_build_a_model():
    class Empty(composer.Entity):
        def _build(self):
            pass

    with pytest.raises(composer.EntityError, match=r"Empty._build\(\) must set self._mjcf_root"):
        _ = Empty().mjcf_model
    with pytest.raises(composer.EntityError, match="RootElement"):
        composer.Entity.from_mjcf_model("not a model")


def test_actuators_are_the_entity_own():
    arm, gripper = Pendulum("arm"), Pendulum("gripper")
    arm.attach(gripper)
    assert arm.actuators == [arm.motor] and gripper.actuators == [gripper.motor]


def test_the_base_arena_is_an_empty_world_with_dm_control_settings():
    """dm_control's arena subclasses add their own floor and lights: the base adds none."""
    arena = composer.Arena()
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    model = physics.model
    assert (model.ngeom, model.nlight, model.ntex, model.nbody) == (0, 0, 0, 1)
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC and model.opt.noslip_iterations == 5
    assert arena.mjcf_model.compiler.angle == "radian"
    assert composer.Arena(name="room").name == "room"


def test_an_arena_from_a_file(tmp_path):
    path = tmp_path / "room.xml"
    path.write_text('<mujoco model="room"><worldbody><geom type="plane" size="1 1 .1"/>'
                    "</worldbody></mujoco>")  # fmt: skip
    arena = composer.Arena(xml_path=path)
    assert arena.name == "room" and len(arena.mjcf_model.find_all("geom")) == 1
    assert composer.Arena(name="hall", xml_path=path).name == "hall"


def free_block_scene():
    arena, block = Floor(), Block()
    arena.add_free_entity(block)
    return arena, block, mjcf.Physics.from_mjcf_model(arena.mjcf_model)


def test_set_pose_and_get_pose_of_a_free_entity():
    _, block, physics = free_block_scene()
    quat = [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)]  # 90 degrees about z
    block.set_pose(physics, position=[1, 2, 3], quaternion=quat)
    physics.forward()
    np.testing.assert_allclose(physics.bind(block.body).xpos, [1, 2, 3])
    position, quaternion = block.get_pose(physics)
    np.testing.assert_allclose(position, [1, 2, 3])
    np.testing.assert_allclose(quaternion, quat)
    block.set_pose(physics, position=[0, 0, 1])  # keeps the orientation
    np.testing.assert_allclose(block.get_pose(physics)[1], quat)


def test_set_velocity_takes_the_angular_velocity_in_the_body_frame_as_dm_control():
    _, block, physics = free_block_scene()
    block.set_pose(physics, quaternion=[np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])
    block.set_velocity(physics, velocity=[1, 0, 0], angular_velocity=[1, 0, 0])
    qvel = physics.bind(mjcf.get_frame_freejoint(block.mjcf_model)).qvel
    np.testing.assert_array_equal(qvel, [1, 0, 0, 1, 0, 0])  # the free joint's own
    velocity, angular = block.get_velocity(physics)
    np.testing.assert_array_equal(velocity, [1, 0, 0])
    np.testing.assert_array_equal(angular, [1, 0, 0])
    physics.forward()
    world = np.zeros(6)
    mujoco.mj_objectVelocity(
        physics.model, physics.data, mujoco.mjtObj.mjOBJ_BODY, physics.bind(block.body).ids,
        world, 0,
    )  # fmt: skip
    np.testing.assert_allclose(world[:3], [0, 1, 0], atol=1e-12)  # body x is world y


def test_velocities_of_a_fixed_entity_are_an_error_naming_it():
    arena, arm = Floor(), Pendulum("arm")
    arena.attach(arm)
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    with pytest.raises(composer.PoseError, match="non-free entity: 'arm'"):
        arm.get_velocity(physics)
    with pytest.raises(ValueError, match="'arm' has no free joint"):
        arm.set_velocity(physics, [1, 0, 0])


def _fixed_scene(position=None, quaternion=None):
    """An arena with a fixed pendulum attached at a rotated site; the pendulum's frame
    placed at `position`/`quaternion` in the MJCF when given."""
    arena, arm = Floor(), Pendulum("arm")
    site = arena.mjcf_model.worldbody.add("site", name="mount", pos=[0.5, 0, 1], euler=[0, 0, 30])
    frame = arena.attach(arm, attach_site=site)
    if position is not None:
        frame.pos, frame.quat = position, quaternion
        del frame.euler
    return arena, arm, mjcf.Physics.from_mjcf_model(arena.mjcf_model)


def test_set_pose_of_a_fixed_entity_moves_it_as_a_recompile_with_the_frame_moved():
    """dm_control moves the attachment frame; here the frame is a MuJoCo <frame>, folded into
    what it holds, moved through its binding: the same as compiling the moved frame."""
    _, arm, physics = _fixed_scene()
    position, quaternion = arm.get_pose(physics)
    np.testing.assert_allclose(position, [0.5, 0, 1])
    np.testing.assert_allclose(quaternion, [np.cos(np.pi / 12), 0, 0, np.sin(np.pi / 12)])
    target = ([0.1, -0.2, 1.5], [np.cos(0.3), np.sin(0.3), 0, 0])
    arm.set_pose(physics, *target)
    np.testing.assert_allclose(arm.get_pose(physics)[0], target[0])
    physics.forward()
    _, moved_arm, expected = _fixed_scene(*target)
    expected.forward()
    for field in ("xpos", "xquat"):
        np.testing.assert_allclose(
            getattr(physics.bind(arm.mjcf_model.find_all("body")), field),
            getattr(expected.bind(moved_arm.mjcf_model.find_all("body")), field),
            atol=1e-12,
        )
    np.testing.assert_allclose(physics.model.body_pos, expected.model.body_pos, atol=1e-12)
    for field in ("xpos", "xquat", "xmat"):  # the frame's binding: one owner of its pose
        np.testing.assert_allclose(
            getattr(physics.bind(arm.attachment_frame), field),
            getattr(expected.bind(moved_arm.attachment_frame), field),
            atol=1e-12,
        )
    np.testing.assert_allclose(
        arm.global_vector_to_local_frame(physics, [0, 0, 1]),
        moved_arm.global_vector_to_local_frame(expected, [0, 0, 1]),
        atol=1e-12,
    )
    arm.shift_pose(physics, position=[0, 0, 0.5])
    np.testing.assert_allclose(arm.get_pose(physics)[0], [0.1, -0.2, 2.0])
    np.testing.assert_allclose(physics.bind(arm.mjcf_model.worldbody).xpos, [0.1, -0.2, 2.0])


def test_posing_an_unattached_entity_is_an_error_naming_it():
    arm = Pendulum("arm")
    physics = mjcf.Physics.from_mjcf_model(arm.mjcf_model)
    with pytest.raises(composer.EntityError, match="entity 'arm' has no free joint and is not"):
        arm.set_pose(physics, position=[0, 0, 1])


# -- standalone model files as entities ------------------------------------------------------


class _Stand(composer.Task):
    """Entities from files, free or attached, in an arena; a reward of the height."""

    def __init__(self, paths, free=True):
        self._arena = Floor()
        self.entities = [composer.Entity.from_path(path) for path in paths]
        for entity in self.entities:
            if free:
                self._arena.add_free_entity(entity)
            else:
                self._arena.attach(entity)
        self.set_timesteps(control_timestep=0.02, physics_timestep=0.01)

    @property
    def root_entity(self):
        return self._arena

    def get_reward(self, physics):
        return float(self.entities[0].get_pose(physics)[0][2])


@pytest.mark.filterwarnings("ignore:.*infinity:UserWarning")  # gymnasium's too: unbounded
@pytest.mark.filterwarnings("ignore:.*render modes:UserWarning")
@pytest.mark.parametrize("name", ["ant", "humanoid"])
@pytest.mark.parametrize("free", [True, False], ids=["add_free_entity", "attach"])
def test_gymnasium_robot_files_are_entities_of_an_environment(name, free):
    """Their top body floats already: it keeps its one free joint, and their own floor
    stays static beside the arena's."""
    from gymnasium.utils.env_checker import check_env

    from tests.conftest import gym_model

    task = _Stand([gym_model(name)], free=free)
    entity = task.entities[0]
    frame = entity.attachment_frame
    assert mjcf.get_frame_freejoint(frame) is None and frame.all_children() == []
    env = composer.Environment(task, time_limit=0.2)
    check_env(env)
    obs, _ = env.reset(seed=0)
    physics = env.physics
    reference = mujoco.MjModel.from_xml_path(str(gym_model(name)))
    assert physics.model.nq == reference.nq and physics.model.nu == reference.nu
    floor = entity.mjcf_model.find("geom", "floor")
    assert physics.bind(floor).bodyid == 0  # static, in the world body
    entity.set_pose(physics, position=[0.5, 0, 1.5])
    assert physics.bind(entity._free_joint()).qpos[0] == 0.5
    for _ in range(5):
        obs, reward, *_ = env.step(env.action_space.sample())
        assert np.isfinite(reward)
    assert np.all(np.isfinite(obs[f"{entity.name}/joint_positions"]))
    env.close()


def test_two_copies_of_one_robot_file():
    from tests.conftest import gym_model

    task = _Stand([gym_model("ant"), gym_model("ant")])
    assert [e.name for e in task.entities] == ["ant", "ant_1"]
    env = composer.Environment(task, time_limit=0.1)
    env.reset(seed=1)
    assert env.physics.model.nu == 16


def test_a_file_whose_body_does_not_float_gets_the_free_joint_or_a_clear_error(tmp_path):
    path = tmp_path / "crate.xml"
    path.write_text(
        '<mujoco model="crate"><worldbody><body name="box"><geom type="box" size=".1 .1 .1"/>'
        "</body></worldbody></mujoco>"
    )
    arena = Floor(name="arena")
    crate = composer.Entity.from_path(path)
    frame = arena.add_free_entity(crate)
    assert mjcf.get_frame_freejoint(frame) is not None
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    crate.set_pose(physics, position=[0, 0, 1])
    grounded = tmp_path / "grounded.xml"
    grounded.write_text(
        '<mujoco model="grounded"><worldbody><geom name="ground" type="plane" size="1 1 .1"/>'
        '<body name="box"><geom type="box" size=".1 .1 .1"/></body></worldbody></mujoco>'
    )
    with pytest.raises(composer.EntityError, match=r"ground.*a plane.*arena\.attach"):
        arena.add_free_entity(composer.Entity.from_path(grounded))
    assert [e.name for e in arena.iter_entities()] == ["arena", "crate"]
