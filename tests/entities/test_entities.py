"""The hand-made robots and the props: models that compile, observables, actuators, physics."""

from __future__ import annotations

import numpy as np
import pytest

import composer
import entities
from arenas import Floor
from entities import features


def serve(*parts: composer.Entity, enable: bool = True) -> composer.Environment:
    """An environment of the parts attached to a floor, their observables enabled."""
    arena = Floor(size=(3, 3))
    for part in parts:
        arena.attach(part)
        if enable:
            part.observables.enable_all()
    return composer.Environment(composer.NullTask(arena))


@pytest.mark.parametrize(
    ("entity", "actuators", "observations"),
    [
        (entities.CartPole, 1, {"cart_position": 1, "pole_angle": 2, "velocities": 2}),
        (entities.PlanarArm, 2,
         {"joint_angles": 4, "joint_velocities": 2, "fingertip_position": 2}),
        (entities.Quadruped, 8,
         {"joint_positions": 8, "joint_velocities": 8, "torso_height": 1,
          "torso_orientation": 4, "torso_upright": 1, "torso_velocity": 6}),
        (entities.Walker, 6,
         {"joint_positions": 6, "joint_velocities": 9, "torso_height": 1, "torso_pitch": 2}),
    ],
)  # fmt: skip
def test_robots_compile_with_their_actuators_and_bounded_observables(
    entity, actuators, observations
):
    robot = entity()
    env = serve(robot)
    assert len(robot.actuators) == actuators
    assert env.action_space.shape == (actuators,)
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    name = robot.name
    assert {k: v.shape[0] for k, v in env.observation_space.items()} == {
        f"{name}/{key}": size for key, size in observations.items()
    }
    for space in env.observation_space.values():
        assert np.all(np.isfinite(space.low)) and np.all(np.isfinite(space.high))
    obs, _ = env.reset(seed=0)
    for _ in range(20):
        obs, *_ = env.step(env.action_space.sample())
    assert obs in env.observation_space


def test_cartpole_angle_is_zero_upright_and_the_motor_pushes_the_cart():
    cartpole = entities.CartPole(gear=10.0, cart_mass=1.0)
    env = serve(cartpole)
    env.reset(seed=0)
    physics = env.physics
    physics.bind(cartpole.hinge).qpos = np.pi
    physics.forward()
    assert cartpole.pole_angle_cosine(physics) == pytest.approx(-1.0)
    tip = physics.bind(cartpole.pole_tip).xpos
    assert tip[2] == pytest.approx(1.2 - 1.0)  # hanging a pole length below the rail
    for _ in range(10):
        env.step(np.ones(1))
    assert physics.bind(cartpole.slider).qvel[0] > 0.1  # 0.02 s at about 9 m/s^2


def test_planar_arm_fingertip_is_at_the_links_end_and_the_elbow_is_limited():
    arm = entities.PlanarArm(link_lengths=(0.1, 0.15))
    env = serve(arm)
    physics = env.physics
    physics.bind(arm.joints).qpos = [np.pi / 2, 0.0]
    physics.forward()
    np.testing.assert_allclose(physics.bind(arm.fingertip).xpos[:2], [0, 0.25], atol=1e-9)
    np.testing.assert_allclose(physics.bind(arm.elbow).range, [-2.8, 2.8])  # radians


def test_quadruped_stands_and_walker_falls_without_control():
    ant, walker = entities.Quadruped(), entities.Walker()
    env = serve(ant)
    env.reset(seed=0)
    for _ in range(100):
        env.step(np.zeros(8))
    torso = env.physics.bind(ant.torso)
    assert 0.3 < torso.xpos[2] < 0.6 and torso.xmat[8] > 0.99
    ant.set_pose(env.physics, position=[1.0, 2.0, 0.6])
    assert ant.get_pose(env.physics)[0].tolist() == [1.0, 2.0, 0.6]
    env = serve(walker)
    env.reset(seed=0)
    start = env.physics.bind(walker.torso).xpos[2]
    for _ in range(1000):  # 2 s
        env.step(np.zeros(6))
    assert start > 1.2 and env.physics.bind(walker.torso).xpos[2] < 0.7


@pytest.mark.parametrize(
    ("prop", "geom_type"),
    [(entities.Box(mass=0.3), "box"), (entities.Sphere(mass=0.3), "sphere"),
     (entities.Capsule(mass=0.3), "capsule"), (entities.Cylinder(mass=0.3), "cylinder")],
)  # fmt: skip
def test_free_props_have_their_mass_and_fall(prop, geom_type):
    env = serve(prop)
    physics = env.physics
    assert prop.geom.type == geom_type
    assert physics.bind(prop.body).mass == pytest.approx(0.3)
    prop.set_pose(physics, position=[0, 0, 1.0])
    obs, _ = env.reset(seed=0)
    prop.set_pose(physics, position=[0, 0, 1.0])
    for _ in range(250):  # 0.5 s
        obs, *_ = env.step(np.zeros(0))
    assert obs[f"{prop.name}/position"][2] < 0.9
    assert obs[f"{prop.name}/velocity"].shape == (6,)


def test_a_fixed_prop_has_no_free_joint_and_is_posed_by_its_frame():
    pillar = entities.Cylinder(radius=0.1, half_length=0.5, free=False, rgba=(1, 0, 0, 1))
    env = serve(pillar)
    physics = env.physics
    assert "cylinder/velocity" not in env.observation_space.spaces
    with pytest.raises(composer.EntityError, match="no free joint"):
        pillar.set_velocity(physics, [0, 0, 1])
    before = np.array(physics.bind(pillar.geom).xpos)
    position, _ = pillar.get_pose(physics)
    pillar.set_pose(
        physics, position=np.add(position, [0, 0, 1])
    )  # its frame moves, as dm_control's
    np.testing.assert_allclose(physics.bind(pillar.geom).xpos, np.add(before, [0, 0, 1]))
    np.testing.assert_allclose(physics.bind(pillar.geom).rgba, [1, 0, 0, 1])


def test_mesh_prop_loads_its_file_scaled(tmp_path):
    mesh = tmp_path / "wedge.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    wedge = entities.MeshProp(mesh, scale=0.2, mass=0.5)
    unit = entities.MeshProp(mesh, name="unit")
    assert wedge.name == "wedge"
    env = serve(wedge, unit)
    radius = env.physics.bind([wedge.geom, unit.geom]).rbound
    assert radius[0] == pytest.approx(0.2 * radius[1])
    assert env.physics.bind(wedge.body).mass == pytest.approx(0.5)


@pytest.mark.parametrize(
    ("make", "message"),
    [(lambda: entities.Box(half_sizes=(0.1, 0.1)), "takes 3 numbers"),
     (lambda: entities.Sphere(radius=-1), "radius must be positive"),
     (lambda: entities.Capsule(mass=0), "mass must be positive"),
     (lambda: entities.MeshProp("/no/such/mesh.stl"), "cannot read mesh file")],
)  # fmt: skip
def test_props_reject_bad_sizes_masses_and_files(make, message):
    with pytest.raises(entities.PropError, match=message):
        make()


def test_clipped_features_stay_within_their_bounds():
    arm = entities.PlanarArm()
    env = serve(arm, enable=False)
    speed = features.velocities(arm.joints)
    env.physics.bind(arm.joints).qvel = [1e6, -1e6]
    value = speed(env.physics)
    np.testing.assert_array_equal(value, [features.VELOCITY_LIMIT, -features.VELOCITY_LIMIT])
