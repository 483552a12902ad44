"""composer.VectorEnvironment: the gymnasium vector API, equivalence with single
environments (SyncVectorEnv over composer.Environment as the reference), autoreset modes,
divergence, the batch protocol and its per-environment fallback, make_vec."""

from __future__ import annotations

import pickle
import warnings

import gymnasium
import mujoco
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import composer
import mjcf
from composer.vector import BatchError, VectorEnvironment, make_vector_environment
from tests.composer.scenes import Block, SwingTask
from tests.composer.vector_scenes import (
    BatchedSwing,
    HookedSwing,
    LateSight,
    SensingSwing,
    SingleFormSensingSwing,
    SingleFormSwing,
    TowerTask,
    VariedSwing,
)
from tests.vector_runs import assert_same_runs

TEST_ID = "composer_tests/BatchedSwing-v0"
if TEST_ID not in gymnasium.registry:
    gymnasium.register(
        TEST_ID,
        entry_point="composer.registration:make_environment",
        vector_entry_point="composer.vector:make_vector_environment",
        kwargs={"task": "tests.composer.vector_scenes:BatchedSwing", "time_limit": 0.3},
    )

TASKS = {
    "batched": lambda: BatchedSwing(terminate_above=1.0),
    "batched, scheduled observables": lambda: BatchedSwing(schedule=True, terminate_above=1.0),
    "per-environment fallback": lambda: SwingTask(terminate_above=1.0, substeps=5),
    "entity hooks, per environment": HookedSwing,
    "acceleration-stage sensors, batched": lambda: SensingSwing(terminate_above=1.0),
}


def pair(factory, n=4, mode=AutoresetMode.NEXT_STEP, **kwargs):
    """The vector environment and its reference: SyncVectorEnv of single Environments."""
    vector = VectorEnvironment(factory, n, autoreset_mode=mode, **kwargs)
    flatten = kwargs.get("flatten_observations", False)
    reference = SyncVectorEnv(
        [lambda: composer.Environment(factory(), time_limit=kwargs.get("time_limit", np.inf),
                                      flatten_observations=flatten) for _ in range(n)],
        autoreset_mode=mode,
    )  # fmt: skip
    return vector, reference


@pytest.mark.parametrize("name", list(TASKS))
def test_trajectories_equal_single_environments_with_the_same_seeds(name):
    vector, reference = pair(TASKS[name], time_limit=0.3)
    assert assert_same_runs(vector, reference, steps=60, seed=3) >= 8  # through several autoresets


def test_derived_fields_first_read_mid_episode_equal_single_environments():
    # Until something reads a derived field, a step leaves the new state's stages
    # uncomputed; the first read computes them: the values must be a single
    # environment's all the same, through autoresets.
    vector, reference = pair(LateSight, time_limit=0.3)
    assert assert_same_runs(vector, reference, steps=40, seed=3) >= 8
    _, _, _, _, info = vector.step(np.zeros(vector.action_space.shape))
    assert {"tip_height", "acceleration"} <= set(info)


def test_one_model_for_all_while_all_are_the_same_and_each_its_own_once_they_differ():
    # Simulations run on the first environment's MjModel while every model is the same,
    # bit for bit, and each on its own once a reset edited them apart: single
    # environments' trajectories either way, through autoresets.
    vector, reference = pair(lambda: BatchedSwing(terminate_above=1.0), time_limit=0.3)
    assert assert_same_runs(vector, reference, steps=60, seed=3) >= 8
    assert isinstance(vector.batch_physics.batch.models, mujoco.MjModel)
    vector, reference = pair(VariedSwing, time_limit=0.3)
    assert assert_same_runs(vector, reference, steps=60, seed=3) >= 8
    models = vector.batch_physics.batch.models
    assert isinstance(models, tuple)
    assert all(m is env.physics.model for m, env in zip(models, vector.environments, strict=True))


@pytest.mark.parametrize(
    ("batched", "single"),
    [(BatchedSwing, SingleFormSwing), (SensingSwing, SingleFormSensingSwing)],
    ids=["batched", "acceleration-stage sensors"],
)
def test_batched_forms_equal_the_single_forms_they_replace(batched, single):
    # The reference above runs the batched forms too (a single environment runs them with
    # a batch of one): here it runs independent single-environment formulas instead.
    vector = VectorEnvironment(lambda: batched(terminate_above=1.0), 4, time_limit=0.3)
    reference = SyncVectorEnv(
        [lambda: composer.Environment(single(terminate_above=1.0), time_limit=0.3)] * 4
    )
    assert VectorEnvironment(single, 1).per_environment == [  # what runs in single form
        "task.get_reward", "task.should_terminate_episode", "task.get_info",
        "observable angle_cos", "observable tip_height",
    ]  # fmt: skip
    assert vector.per_environment == []
    assert assert_same_runs(vector, reference, steps=60, seed=3) >= 8


@pytest.mark.parametrize(
    "name", ["batched, scheduled observables", "entity hooks, per environment"]
)
def test_flattened_observations_and_same_step_autoreset_equal_single_environments(name):
    factory = TASKS[name]
    vector, reference = pair(
        factory, mode=AutoresetMode.SAME_STEP, time_limit=0.3, flatten_observations=True
    )
    assert vector.metadata["autoreset_mode"] is AutoresetMode.SAME_STEP
    assert assert_same_runs(vector, reference, steps=60, seed=3) > 4


def test_a_seed_at_construction_seeds_environment_i_with_seed_plus_i():
    vector = VectorEnvironment(TASKS["batched"], 3, seed=10)
    singles = [composer.Environment(TASKS["batched"](), random_state=10 + i) for i in range(3)]
    obs, _ = vector.reset()
    expected = [env.reset()[0] for env in singles]
    for key, rows in obs.items():
        np.testing.assert_array_equal(rows, np.stack([e[key] for e in expected]))
    assert len(np.unique(obs["pendulum/joint_positions"])) == 3


def test_fast_path_needs_no_per_environment_work_and_fallback_says_what_it_loops_over():
    fast = VectorEnvironment(TASKS["batched, scheduled observables"], 2)
    assert fast.per_environment == []
    assert fast.batch_physics.batch.persistent  # each step continues from the last one's stages
    slow = VectorEnvironment(TASKS["per-environment fallback"], 2)
    assert set(slow.per_environment) == {
        "task.get_reward", "task.should_terminate_episode",
        "observable pendulum/angular_velocity", "observable pendulum/orientation",
    }  # fmt: skip
    assert slow.batch_physics.batch.persistent


def test_spaces_are_the_single_environments_batched():
    vector = VectorEnvironment(TASKS["batched"], 3)
    single = composer.Environment(TASKS["batched"]())
    assert vector.single_observation_space == single.observation_space
    assert vector.single_action_space == single.action_space
    assert vector.action_space == spaces.Box(-1.0, 1.0, (3, 1), np.float32)
    assert vector.observation_space["pendulum/joint_positions"].shape == (3, 1)
    assert vector.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
    obs, info = vector.reset(seed=0)
    assert obs in vector.observation_space and info == {}
    vector.action_space.seed(0)
    obs, reward, terminated, truncated, info = vector.step(vector.action_space.sample())
    assert obs in vector.observation_space
    assert reward.shape == (3,) and reward.dtype == np.float64
    assert terminated.dtype == truncated.dtype == np.bool_
    assert info["_discount"].all() and (info["discount"] == 1.0).all()


def test_next_step_autoreset_ignores_the_action_and_returns_the_reset_observation():
    vector = VectorEnvironment(lambda: BatchedSwing(terminate_above=0.2), 2)
    obs, _ = vector.reset(seed=0)
    actions = np.array([[1.0], [0.0]], dtype=np.float32)
    for _ in range(40):
        obs, reward, terminated, truncated, _ = vector.step(actions)
        if terminated[0]:
            break
    assert terminated[0]
    state = vector.environments[0].physics.data  # holds the new episode after reset
    obs, reward, terminated, truncated, info = vector.step(actions)
    assert reward[0] == 0.0 and not terminated[0] and not truncated[0]
    assert not info["_discount"][0]  # a reset, not a step
    np.testing.assert_array_equal(obs["pendulum/joint_positions"][0], state.qpos)


def test_disabled_autoreset_needs_a_reset_mask():
    vector = VectorEnvironment(TASKS["batched"], 2, time_limit=0.04, autoreset_mode="Disabled")
    vector.reset(seed=0)
    vector.step(np.zeros((2, 1)))
    *_, truncated, _ = vector.step(np.zeros((2, 1)))
    assert truncated.all()
    with pytest.raises(composer.EpisodeError, match="reset_mask"):
        vector.step(np.zeros((2, 1)))
    with pytest.raises(composer.EpisodeError, match="bool array"):
        vector.reset(options={"reset_mask": np.array([1, 0])})
    vector.reset(options={"reset_mask": np.array([True, False])})
    with pytest.raises(composer.EpisodeError, match=r"environments \[1\]"):
        vector.step(np.zeros((2, 1)))
    vector.reset(seed=[5, 6])
    assert not vector.step(np.zeros((2, 1)))[3].any()


def test_time_limit_and_max_episode_steps_truncate():
    vector = VectorEnvironment(TASKS["batched"], 2, time_limit=0.1, max_episode_steps=3)
    vector.reset(seed=0)
    truncations = [vector.step(np.zeros((2, 1)))[3].all() for _ in range(3)]
    assert truncations == [False, False, True]


def test_divergence_truncates_that_environment_only_as_a_single_one_would():
    vector, reference = pair(lambda: BatchedSwing(gear=1e30), n=3, time_limit=1.0)
    actions = np.array([[1.0], [0.0], [0.0]])
    vector.reset(seed=0), reference.reset(seed=0)
    with pytest.warns(composer.DivergenceWarning, match="environment 0"):
        for _ in range(50):
            obs, reward, terminated, truncated, info = vector.step(actions)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", composer.DivergenceWarning)
                _, _, _, _, expected = reference.step(actions)
            if truncated[0]:
                break
    assert truncated.tolist() == [True, False, False] and not terminated.any()
    assert "physics state is invalid" in info["physics_error"][0]
    assert info["physics_error"][0] == expected["physics_error"][0]
    assert info["_physics_error"].tolist() == [True, False, False] and reward[0] == 0.0
    obs, reward, terminated, truncated, info = vector.step(actions * 0)  # env 0 resets
    obs, reward, terminated, truncated, info = vector.step(actions * 0)
    assert not truncated.any() and "physics_error" not in info
    assert np.isfinite(obs["pendulum/joint_velocities"]).all()


def test_mujoco_errors_in_a_simulation_truncate_instead_of_raising():
    vector = VectorEnvironment(TowerTask, 2)
    vector.reset(seed=0)
    with pytest.warns(composer.DivergenceWarning, match="mj_stackAlloc"):
        for _ in range(30):
            *_, truncated, info = vector.step(np.zeros((2, 0)))
            if truncated.any():
                break
    assert truncated.all() and info["physics_error"][0].startswith("MuJoCo raised")
    *_, truncated, info = vector.step(np.zeros((2, 0)))  # the reset episode runs
    assert not truncated.any() and "physics_error" not in info


def with_block(task: composer.Task) -> composer.Task:
    """`task` with a free box added: the same spaces, another MuJoCo data layout."""
    task.root_entity.add_free_entity(Block())
    return task


def test_bad_use_raises_composer_errors():
    with pytest.raises(composer.TaskError, match="positive int"):
        VectorEnvironment(TASKS["batched"], 0)
    task = BatchedSwing()
    with pytest.raises(composer.TaskError, match="same task twice"):
        VectorEnvironment(lambda: task, 2)
    with pytest.raises(composer.TaskError, match=r"not a composer\.Task"):
        VectorEnvironment(lambda: "swing", 2)
    tasks = iter([BatchedSwing(), SwingTask()])
    with pytest.raises(composer.TaskError, match="environment 1's observation_space"):
        VectorEnvironment(lambda: next(tasks), 2)
    tasks = iter([BatchedSwing(), with_block(BatchedSwing())])
    with pytest.raises(composer.TaskError, match="data layout"):
        VectorEnvironment(lambda: next(tasks), 2)
    vector = VectorEnvironment(TASKS["batched"], 2)
    with pytest.raises(composer.EpisodeError, match="before reset"):
        vector.step(np.zeros((2, 1)))
    vector.reset(seed=0)
    with pytest.raises(composer.EpisodeError, match=r"shape \(1,\)"):
        vector.step(np.zeros(1))
    with pytest.raises(composer.EpisodeError, match=r"environments \[1\]"):
        vector.step(np.array([[0.0], [np.nan]]))
    drawn = pickle.dumps(vector.environments[0].random_state)
    for seed in (1.5, -1, "3", [1, 2, 3], [1, 2.5], np.array([0.5, 1.5]), {0: 1}):
        # Refused before any environment is reset (the first of [1, 2.5] was reset before).
        with pytest.raises(composer.EpisodeError, match="or 2 of them"):
            vector.reset(seed=seed)
        assert pickle.dumps(vector.environments[0].random_state) == drawn
    vector.reset(seed=[1, None])
    vector.reset(seed=np.array([1, 2]))
    for actions in (np.zeros((2, 1), complex), [["a"], ["b"]], [[None], [0.0]], [[1], [2, 3]]):
        with pytest.raises(composer.EpisodeError, match=r"the actions (hold|are not)"):
            vector.step(actions)


class WrongShapeReward(BatchedSwing):
    def get_reward_batch(self, physics):
        return np.zeros(physics.num_envs + 1)


def test_a_batched_method_of_the_wrong_shape_is_an_error():
    vector = VectorEnvironment(WrongShapeReward, 2)
    vector.reset(seed=0)
    with pytest.raises(BatchError, match=r"get_reward_batch returned shape \(3,\)"):
        vector.step(np.zeros((2, 1)))


class OnlySingleReward(BatchedSwing):
    """Overrides get_reward only: the inherited get_reward_batch would be stale."""

    def get_reward(self, physics):
        return 7.0


def test_a_subclass_overriding_only_the_single_method_is_not_batched_with_a_stale_twin():
    vector = VectorEnvironment(OnlySingleReward, 2)
    assert vector.per_environment == ["task.get_reward"]
    vector.reset(seed=0)
    assert (vector.step(np.zeros((2, 1)))[1] == 7.0).all()


def test_batch_physics_reads_and_writes_the_simulations():
    vector = VectorEnvironment(TASKS["batched"], 3)
    vector.reset(seed=1)
    vector.step(np.full((3, 1), 0.5))
    physics = vector.batch_physics
    task = vector.environments[0].task
    hinge = physics.bind(task.pendulum.hinge)
    assert hinge.qpos.shape == (3, 1)  # as mjcf: a hinge's qpos is (1,), a motor's ctrl ()
    np.testing.assert_array_equal(hinge.qpos, physics.field("qpos"))
    assert len(np.unique(hinge.qpos)) == 3  # three episodes, seeded 1, 2, 3
    np.testing.assert_array_equal(physics.bind(task.pendulum.motor).ctrl, np.full(3, 0.5))
    assert physics.bind(task.pendulum.tip).xpos.shape == (3, 3)
    np.testing.assert_array_equal(physics.bind([task.pendulum.hinge]).damping, np.full((3, 1), 0.1))
    physics.bind(task.pendulum.motor).ctrl = [0.1, 0.2, 0.3]
    np.testing.assert_array_equal(physics.field("ctrl"), [[0.1], [0.2], [0.3]])
    with pytest.raises(BatchError, match="derived by MuJoCo"):
        physics.bind(task.pendulum.tip).xpos = np.zeros((3, 3))
    with pytest.raises(BatchError, match="efc_force"):
        physics.field("efc_force")
    with pytest.raises(mjcf.BindingError):
        physics.bind(task.pendulum.hinge).no_such_field  # noqa: B018
    other = BatchedSwing()  # another model: its elements are found by name, as in dm_control
    np.testing.assert_array_equal(physics.bind(other.pendulum.hinge).qpos, hinge.qpos)
    stray = other.pendulum.mjcf_model.worldbody.add("body", name="stray")
    with pytest.raises(mjcf.BindingError, match="no body named"):
        physics.bind(stray)


def test_render_gives_every_environment_frame_as_single_environments_render_them():
    vector = VectorEnvironment(TASKS["batched"], 2, render_mode="rgb_array")
    vector.reset(seed=4)
    frames = vector.render()
    assert isinstance(frames, tuple) and len(frames) == 2  # Gymnasium's VectorEnv.render
    for i, frame in enumerate(frames):
        single = composer.Environment(TASKS["batched"](), render_mode="rgb_array")
        single.reset(seed=4 + i)
        assert frame.shape == (240, 320, 3) and frame.dtype == np.uint8
        np.testing.assert_array_equal(frame, single.render())
        single.close()
    assert not np.array_equal(frames[0], frames[1])  # each its own state
    assert VectorEnvironment(TASKS["batched"], 1).render() is None
    vector.close()
    assert vector.closed


def test_make_vec_through_the_vector_entry_point():
    vector = gymnasium.make_vec(TEST_ID, num_envs=8, vectorization_mode="vector_entry_point")
    assert isinstance(vector, VectorEnvironment) and vector.num_envs == 8
    reference = gymnasium.make_vec(TEST_ID, num_envs=8, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=20, seed=3)
    with pytest.raises(composer.TaskError, match="unknown keyword"):
        make_vector_environment(2, "tests.composer.vector_scenes:BatchedSwing", colour="red")


def test_make_vec_of_a_shipped_task():
    import tasks  # noqa: F401  registers the composer/ ids

    vector = gymnasium.make_vec(
        "composer/CartpoleSwingup-v0", num_envs=3, vectorization_mode="vector_entry_point"
    )
    reference = gymnasium.make_vec("composer/CartpoleSwingup-v0", num_envs=3)
    assert isinstance(vector, VectorEnvironment)
    assert_same_runs(vector, reference, steps=15, seed=3)


def test_batch_physics_binds_what_mjcf_physics_binds() -> None:
    """Any iterable of elements, and no elements: (n, 0) fields."""
    vector = VectorEnvironment(BatchedSwing, 2)
    vector.reset(seed=0)
    physics = vector.batch_physics
    hinge = vector.environments[0].task.pendulum.hinge
    assert physics.bind(np.array([hinge], dtype=object)).qpos.shape == (2, 1)
    assert physics.bind(iter([hinge])).qpos.shape == (2, 1)
    assert physics.bind([]).qpos.shape == (2, 0)
    physics.bind([]).ctrl = np.zeros((2, 0))
    with pytest.raises(mjcf.BindingError, match="binding of no elements"):
        physics.bind([]).ctrl = 1.0
