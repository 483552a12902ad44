"""The shipped tasks on composer.VectorEnvironment: nothing runs per environment, the
trajectories equal those of single environments with the same seeds and actions to the
last bit (one formula for both: each step function is written once, batched), and what
that one formula computes equals, to the last bit, one environment's formulas written
independently here."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, VectorEnv

import composer
import mjcf
from composer.batch.protocol import BATCHABLE
from composer.observation import Observable
from tasks.push import TARGET_WINDOW
from tasks.rewards import squared_norms, tolerance
from tests.vector_runs import assert_same_runs

NUM_ENVS = 4
TIME_LIMIT = 0.4  # s: 8 to 16 steps, so a run goes through several autoresets
STEPS = 40
# Each case: a registered id and the task keywords it is made with.
CASES = {
    "CartpoleSwingup": ("composer/CartpoleSwingup-v0", {}),
    "Reach": ("composer/Reach-v0", {}),
    "Reach, control cost": ("composer/Reach-v0", {"control_cost": 0.1}),
    "AntRun": ("composer/AntRun-v0", {}),
    "AntRun, falls": ("composer/AntRun-v0", {"min_height": 0.5}),  # terminates often
    "WalkerRun": ("composer/WalkerRun-v0", {}),
    "ArmPushBox": ("composer/ArmPushBox-v0", {}),
}


def make_pair(name: str, **options) -> tuple[VectorEnv, VectorEnv]:
    """Case `name` as a VectorEnvironment through make_vec's vector_entry_point, and as
    its reference: a SyncVectorEnv of NUM_ENVS single environments."""
    env_id, kwargs = CASES[name]
    kwargs = {**kwargs, "time_limit": TIME_LIMIT, **options}
    vector = gymnasium.make_vec(env_id, NUM_ENVS, vectorization_mode="vector_entry_point", **kwargs)
    autoreset = {"autoreset_mode": kwargs.pop("autoreset_mode", AutoresetMode.NEXT_STEP)}
    reference = gymnasium.make_vec(
        env_id, NUM_ENVS, vectorization_mode="sync", vector_kwargs=autoreset, **kwargs
    )
    return vector, reference


@pytest.mark.parametrize("name", list(CASES))
def test_shipped_task_runs_fully_batched_as_single_environments_would(name):
    vector, reference = make_pair(name)
    assert vector.per_environment == []
    assert vector.single_observation_space == reference.single_observation_space
    assert assert_same_runs(vector, reference, steps=STEPS, seed=5) >= NUM_ENVS * 2
    vector.close()
    reference.close()


@pytest.mark.parametrize("name", ["Reach", "AntRun"])
def test_flattened_same_step_runs_as_training_uses_them_equal_single_environments(name):
    vector, reference = make_pair(
        name, flatten_observations=True, autoreset_mode=AutoresetMode.SAME_STEP
    )
    assert vector.per_environment == []
    assert assert_same_runs(vector, reference, steps=STEPS, seed=5) >= NUM_ENVS * 2
    vector.close()
    reference.close()


@pytest.mark.parametrize("size", [2, 3, 6, 8])
def test_squared_norms_are_np_dot_of_each_row_to_the_last_bit(size):
    rows = np.random.default_rng(size).normal(size=(500, size))
    assert np.array_equal(squared_norms(rows), [np.dot(row, row) for row in rows])
    assert squared_norms(rows[0]) == np.dot(rows[0], rows[0])


def defined_below(cls: type, base: type, name: str) -> bool:
    """Whether a class of `cls`'s MRO below `base` defines `name`."""
    return any(name in vars(klass) for klass in cls.__mro__ if klass not in base.__mro__)


@pytest.mark.parametrize("name", list(CASES))
def test_shipped_tasks_define_each_step_function_once(name):
    env_id, kwargs = CASES[name]
    task = gymnasium.make(env_id, **kwargs).unwrapped.task
    for method in BATCHABLE:
        forms = [defined_below(type(task), composer.Task, f) for f in (method, f"{method}_batch")]
        assert forms != [True, True], f"{type(task).__name__} defines {method} twice"
    for key, item in task.observables.items():
        forms = [defined_below(type(item), Observable, f) for f in ("reader", "batch_reader")]
        assert forms != [True, True], f"observable {key} is read by two readers"


# One environment's formulas for each shipped task, written here independently of its
# batched methods (which a single environment runs with a batch of one), as the tasks wrote
# them before their batched forms became the only ones. Each gives, from the state after a
# step, the state before it and the action: (controls, reward, terminated, info).


def cartpole_step(task, physics: mjcf.Physics, before: dict, action: np.ndarray) -> tuple:
    slider, hinge = physics.bind(task.cartpole.slider), physics.bind(task.cartpole.hinge)
    upright = (np.cos(hinge.qpos[0]) + 1.0) / 2.0
    # tolerance of one-element arrays: of a number, numpy squares with the C library's pow,
    # which can round the last bit differently from an array's product (as in dm_control).
    centered = (1.0 + tolerance(slider.qpos[:1], margin=2.0)[0]) / 2.0
    control = tolerance(
        physics.data.ctrl[:1], margin=1.0, value_at_margin=0.0, sigmoid="quadratic"
    )[0]
    small_velocity = (1.0 + tolerance(hinge.qvel[:1], margin=5.0)[0]) / 2.0
    small_control = (4.0 + control) / 5.0
    reward = upright * centered * small_control * small_velocity
    return action, reward, False, {}


def reach_step(task, physics: mjcf.Physics, before: dict, action: np.ndarray) -> tuple:
    controls = before["qpos"][physics.bind(task.arm.joints).qposadr] + task.max_joint_step * action
    tip = physics.bind(task.arm.fingertip).xpos
    distance = float(np.hypot(*(physics.bind(task.target).mocap_pos[:2] - tip[:2])))
    ratio = distance / task.success_distance
    reward = 0.5 * (1.0 - distance / (2.0 * task.arm.reach)) + 0.5 * np.exp(-ratio * ratio)
    reward -= task.control_cost * float(np.mean(np.square(action)))
    return controls, reward, False, {"is_success": distance < task.success_distance}


def run_step(task, physics: mjcf.Physics, before: dict, action: np.ndarray) -> tuple:
    control = physics.data.ctrl
    if hasattr(task.robot, "root_x"):  # WalkerRun
        velocity = float(physics.bind(task.robot.root_x).qvel[0])
        pitch = physics.bind(task.robot.root_y).qpos[0]
        torso = physics.bind(task.robot.torso)
        fallen = torso.xpos[2] < task.min_height or abs(pitch) > 1.0
    else:  # AntRun
        velocity = float(physics.bind(task.robot.root_joint).qvel[0])
        torso = physics.bind(task.robot.torso)
        fallen = torso.xmat[8] < 0.0 or torso.xpos[2] < task.min_height
    reward = velocity - task.control_cost * float(np.dot(control, control)) + task.alive_bonus
    return action, reward, bool(fallen), {"forward_velocity": velocity}


def push_step(task, physics: mjcf.Physics, before: dict, action: np.ndarray) -> tuple:
    arm, arm_joints = physics.bind(task.arm_actuators), physics.bind(task.arm_joints)
    angles = before["qpos"][arm_joints.qposadr]
    targets = before["ctrl"][arm.element_id] + task.max_joint_step * action[:6]
    targets = np.clip(targets, angles - TARGET_WINDOW, angles + TARGET_WINDOW)
    controls = np.array(physics.data.ctrl)
    controls[arm.element_id] = np.clip(targets, *arm.ctrlrange.T)
    gripper = physics.bind(task.gripper_actuators)
    low, high = gripper.ctrlrange[0]
    controls[gripper.element_id] = low + (action[6] + 1.0) / 2.0 * (high - low)
    box, tcp = physics.bind(task.box.body).xpos, physics.bind(task.robot.tcp).xpos
    reach = float(np.linalg.norm(box - tcp))
    push = float(np.linalg.norm(physics.bind(task.target).xpos[:2] - box[:2]))
    reward = 0.3 * (1.0 - np.tanh(5.0 * reach)) + 0.7 * (1.0 - np.tanh(5.0 * push))
    fell = bool(box[2] < task.table_height - 0.1)
    return controls, reward, fell, {"is_success": push < task.target_radius}


ONE_ENVIRONMENT = {
    "CartpoleSwingup": cartpole_step,
    "Reach": reach_step,
    "Reach, control cost": reach_step,
    "AntRun": run_step,
    "AntRun, falls": run_step,
    "WalkerRun": run_step,
    "ArmPushBox": push_step,
}


@pytest.mark.parametrize("name", list(CASES))
def test_batched_step_functions_compute_what_one_environments_formulas_say(name):
    env_id, kwargs = CASES[name]
    env = gymnasium.make(env_id, time_limit=TIME_LIMIT, **kwargs).unwrapped
    task, formulas = env.task, ONE_ENVIRONMENT[name]
    env.reset(seed=7)
    rng = np.random.default_rng(7)
    ends = 0
    for t in range(STEPS * 2):
        action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        physics = env.physics
        before = {"qpos": physics.data.qpos.copy(), "ctrl": physics.data.ctrl.copy()}
        _, reward, terminated, truncated, info = env.step(action)
        controls, *expected = formulas(task, physics, before, action.astype(np.float64))
        np.testing.assert_array_equal(physics.data.ctrl, controls, err_msg=str(t))
        assert reward == expected[0], t
        assert terminated == expected[1], t
        assert info.keys() == {*expected[2], "discount"} and info["discount"] == 1.0
        for key, value in expected[2].items():
            assert type(info[key]) is type(value), key
            assert info[key] == value, (t, key)
        if terminated or truncated:
            ends += 1
            env.reset()
    assert ends >= 2
    env.close()
