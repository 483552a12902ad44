"""Each task's reward, success and termination on hand-set states, and its options."""

from __future__ import annotations

from pathlib import Path

import gymnasium
import numpy as np
import pytest

import composer
import tasks
from entities import menagerie, robots


def make(task: composer.Task, **kwargs) -> composer.Environment:
    env = composer.Environment(task, **kwargs)
    env.reset(seed=0)
    return env


def test_cartpole_reward_is_one_balanced_and_near_zero_hanging():
    task = tasks.CartpoleSwingup(randomize=False)
    env = make(task)
    assert env.physics.bind(task.cartpole.hinge).qpos[0] == pytest.approx(np.pi)
    assert task.get_reward(env.physics) == pytest.approx(0.0, abs=1e-9)
    env.physics.bind(task.cartpole.hinge).qpos = 0.0
    assert task.get_reward(env.physics) == pytest.approx(1.0)
    env.physics.data.ctrl[:] = 1.0  # full force costs a fifth
    assert task.get_reward(env.physics) == pytest.approx(0.8)
    balance = make(tasks.CartpoleSwingup(start_upright=True))
    _, reward, *_ = balance.step(np.zeros(1))
    assert reward > 0.95


def test_reach_succeeds_with_the_fingertip_on_the_target():
    task = tasks.Reach(randomize=False)
    env = make(task)
    physics = env.physics
    physics.bind(task.arm.joints).qpos = [np.pi / 4, 0.0]
    physics.forward()
    tip = physics.bind(task.arm.fingertip).xpos
    physics.bind(task.target).mocap_pos = [tip[0] + 0.01, tip[1], 0.02]
    assert task.get_info(physics) == {"is_success": True}
    near = task.get_reward(physics)
    physics.bind(task.target).mocap_pos = [-tip[0], -tip[1], 0.02]
    assert task.get_info(physics) == {"is_success": False}
    assert near > 0.85 > 0.5 > task.get_reward(physics) > 0.0


def test_reach_zero_action_holds_the_arm_and_randomize_off_repeats_the_episode():
    env = gymnasium.make("composer/Reach-v0", randomize=False, flatten_observations=True)
    first, _ = env.reset(seed=1)
    for _ in range(10):
        obs, *_ = env.step(np.zeros(2, np.float32))
    np.testing.assert_allclose(obs[:4], first[:4], atol=1e-3)
    again, _ = env.reset(seed=2)
    np.testing.assert_array_equal(first, again)
    randomized = gymnasium.make("composer/Reach-v0", flatten_observations=True)
    assert not np.array_equal(randomized.reset(seed=1)[0], randomized.reset(seed=2)[0])


def test_ant_terminates_when_turned_over_and_is_paid_for_running_forward():
    task = tasks.AntRun(randomize=False)
    env = make(task)
    physics = env.physics
    _, still, terminated, *_ = env.step(np.zeros(8))
    assert not terminated and still == pytest.approx(task.alive_bonus, abs=0.1)
    task.robot.set_velocity(physics, velocity=[2.0, 0, 0])
    assert task.get_reward(physics) == pytest.approx(2.0 + task.alive_bonus)
    task.robot.set_pose(physics, position=[0, 0, 1.0], quaternion=[0, 1, 0, 0])  # upside down
    _, _, terminated, *_ = env.step(np.zeros(8))
    assert terminated


def test_ant_arena_options_build_rough_terrain_or_a_corridor_with_gaps():
    terrain = tasks.AntRun(arena="terrain", terrain_seed=5)
    assert terrain.arena.mjcf_model.find("hfield", "terrain") is not None
    gaps = tasks.AntRun(walls=False, gaps=[(2.0, 1.0)])
    assert gaps.arena.gaps == [(2.0, 1.0)]
    assert gaps.arena.mjcf_model.find("geom", "left_wall") is None
    with pytest.raises(composer.TaskError, match="arena must be one of"):
        tasks.AntRun(arena="moon")


def test_walker_terminates_when_it_falls_and_control_timestep_sets_the_step():
    task = tasks.WalkerRun(control_timestep=0.05)
    env = make(task)
    assert env.control_timestep == pytest.approx(0.05)
    steps = 0
    terminated = False
    while not terminated and steps < 100:  # 5 s without control: it falls
        _, _, terminated, _, _ = env.step(np.zeros(6))
        steps += 1
    assert terminated and steps > 3
    with pytest.raises(composer.TaskError, match="multiple of the physics timestep"):
        tasks.WalkerRun(control_timestep=0.012)


@pytest.fixture
def push_task():
    return tasks.ArmPushBox(randomize=False)


def test_arm_push_box_composes_the_real_ur5e_and_2f85(push_task):
    env = make(push_task, flatten_observations=True)
    names = {e.name for e in push_task.root_entity.iter_entities()}
    assert {"robot", "ur5e", "robotiq_2f85", "box"} <= names
    assert env.physics.model.nu == 7 and env.action_space.shape == (7,)
    tcp = env.physics.bind(push_task.robot.tcp).xpos
    assert tcp[2] > push_task.table_height + 0.1  # the tool starts above the table
    before = env.physics.bind(push_task.arm_joints).qpos.copy()
    env.step(np.array([1, 0, 0, 0, 0, 0, 1], np.float32))  # turn the base's target, close
    for _ in range(25):  # zero actions hold the targets: the base gets there and stays
        env.step(np.zeros(7, np.float32))
    turned = env.physics.bind(push_task.arm_joints).qpos - before
    assert turned[0] == pytest.approx(push_task.max_joint_step, abs=0.003)
    assert np.abs(turned[1:]).max() < 0.02


def test_arm_push_box_succeeds_with_the_box_on_the_target_and_ends_when_it_falls(push_task):
    env = make(push_task)
    physics = env.physics
    target = physics.bind(push_task.target).xpos
    push_task.box.set_pose(physics, position=[target[0] + 0.02, target[1], 0.43])
    physics.forward()
    assert push_task.get_info(physics) == {"is_success": True}
    push_task.box.set_pose(physics, position=[2.0, 2.0, 0.05])  # on the floor
    _, _, terminated, _, info = env.step(np.zeros(7, np.float32))
    assert terminated and info["is_success"] is False


def test_arm_push_box_uses_the_robot_files_shipped_with_the_package(monkeypatch, tmp_path):
    """No $MENAGERIE_ROOT, no Menagerie package, run from elsewhere: as on a fresh install."""
    monkeypatch.setenv(robots.MENAGERIE_ENV, str(tmp_path / "empty"))
    monkeypatch.setitem(__import__("sys").modules, "mujoco_menagerie", None)
    monkeypatch.chdir(tmp_path)
    env = gymnasium.make("composer/ArmPushBox-v0")
    env.reset(seed=0)
    robot = env.unwrapped.task.robot.mjcf_model
    folders = [Path(mesh.file.path).parents[1] for mesh in robot.find_all("mesh")]
    assert len(folders) == 20 + 8  # the arm's meshes and the gripper's
    assert set(folders) == {menagerie.ROOT / name for name in menagerie.ROBOTS}
