"""The shipped tasks on composer.VectorEnvironment: nothing runs per environment, the
trajectories equal those of single environments with the same seeds and actions to the
last bit (one formula for both: each step function is written once, batched)."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import AutoresetMode, VectorEnv

import composer
from composer.batched import BATCHABLE
from composer.observation import Observable
from tasks.rewards import squared_norms

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


def assert_same_runs(vector: VectorEnv, reference: VectorEnv, seed: int = 5) -> int:
    """Both reset with `seed` and stepped with the same random actions give the same
    observations, rewards, terminations, truncations and infos; returns the episodes
    that ended."""
    got, expected = vector.reset(seed=seed), reference.reset(seed=seed)
    assert data_equivalence(got, expected, exact=True)
    rng = np.random.default_rng(seed)
    ended = 0
    for t in range(STEPS):
        actions = rng.uniform(-1, 1, vector.action_space.shape).astype(np.float32)
        got, expected = vector.step(actions), reference.step(actions)
        assert data_equivalence(got, expected, exact=True), (t, got, expected)
        ended += int(np.sum(got[2] | got[3]))
    return ended


@pytest.mark.parametrize("name", list(CASES))
def test_shipped_task_runs_fully_batched_as_single_environments_would(name):
    vector, reference = make_pair(name)
    assert vector.per_environment == []
    assert vector.single_observation_space == reference.single_observation_space
    assert assert_same_runs(vector, reference) >= NUM_ENVS * 2
    vector.close()
    reference.close()


@pytest.mark.parametrize("name", ["Reach", "AntRun"])
def test_flattened_same_step_runs_as_training_uses_them_equal_single_environments(name):
    vector, reference = make_pair(
        name, flatten_observations=True, autoreset_mode=AutoresetMode.SAME_STEP
    )
    assert vector.per_environment == []
    assert assert_same_runs(vector, reference) >= NUM_ENVS * 2
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
