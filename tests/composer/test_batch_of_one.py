"""composer.BatchOfOne: one environment's physics as the BatchPhysics batched methods get,
row for row what a VectorEnvironment's batch gives, with the same refusals."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from composer import BatchOfOne, VectorEnvironment
from tests.composer.vector_scenes import BatchedSwing, SensingSwing

SEED = 4


def stepped_pair(steps: int = 6) -> tuple[VectorEnvironment, list[composer.Environment]]:
    """A vector environment of 3 SensingSwings and the 3 single environments it equals,
    stepped alike."""
    vector = VectorEnvironment(SensingSwing, 3)
    singles = [composer.Environment(SensingSwing()) for _ in range(3)]
    vector.reset(seed=SEED)
    for i, env in enumerate(singles):
        env.reset(seed=SEED + i)
    rng = np.random.default_rng(0)
    for _ in range(steps):
        actions = rng.uniform(-1, 1, (3, 1))
        vector.step(actions)
        for env, action in zip(singles, actions, strict=True):
            env.step(action)
    return vector, singles


def test_a_batch_of_one_reads_row_for_row_what_the_vector_batch_reads():
    vector, singles = stepped_pair()
    rows = vector.batch_physics
    pendulum = vector.environments[0].task.pendulum
    sensors = vector.environments[0].task.sensors
    for i, env in enumerate(singles):
        one = BatchOfOne(env.physics)
        task = env.task
        for mine, theirs, name in (
            (task.pendulum.hinge, pendulum.hinge, "qpos"),
            (task.pendulum.hinge, pendulum.hinge, "qvel"),
            ([task.pendulum.hinge], [pendulum.hinge], "damping"),  # an MjModel field
            (task.pendulum.tip, pendulum.tip, "xpos"),  # derived, position stage
            (task.sensors, sensors, "sensordata"),  # acceleration stage sensors
            (task.pendulum.motor, pendulum.motor, "ctrl"),
        ):
            got = getattr(one.bind(mine), name)
            expected = getattr(rows.bind(theirs), name)
            assert got.shape == (1, *expected.shape[1:]), name
            assert got.dtype == expected.dtype, name
            np.testing.assert_array_equal(got[0], expected[i], err_msg=name)
        for name in ("time", "qpos", "qacc", "sensordata", "ncon", "xpos"):
            got, expected = one.field(name), rows.field(name)
            assert got.shape == (1, *expected.shape[1:]) and got.dtype == expected.dtype, name
            np.testing.assert_array_equal(got[0], expected[i], err_msg=name)


def test_reads_are_copies_and_writes_go_through_the_physics_tracked():
    env = composer.Environment(BatchedSwing())
    env.reset(seed=0)
    one = BatchOfOne(env.physics)
    hinge, tip = env.task.pendulum.hinge, env.task.pendulum.tip
    qpos = one.bind(hinge).qpos
    qpos[0, 0] = 3.0  # a copy: the simulation keeps its angle
    assert env.physics.bind(hinge).qpos[0] != 3.0
    one.bind(hinge).qpos = [[0.7]]
    assert env.physics.is_dirty and env.physics.bind(hinge).qpos[0] == 0.7
    expected = mujoco.MjData(env.physics.model)
    mujoco.mj_copyData(expected, env.physics.model, env.physics.data)
    mujoco.mj_forward(env.physics.model, expected)
    site = env.physics.bind(tip).element_id
    np.testing.assert_array_equal(one.bind(tip).xpos[0], expected.site_xpos[site])
    motor = env.task.pendulum.motor
    for elements, value in ((motor, 0.25), (motor, [0.5]), ([motor], [[0.75]]), ([motor], 1.0)):
        one.bind(elements).ctrl = value  # anything that broadcasts to the rows: (1,), (1, 1)
        assert env.physics.data.ctrl.tolist() == [np.ravel(value)[0]]
    one.set_control([[-0.5]])
    assert env.physics.data.ctrl.tolist() == [-0.5]
    with pytest.raises(mjcf.BindingError, match=r"cannot write \(1, 2\)-shaped values to 'qpos'"):
        one.bind(hinge).qpos = [[1.0, 2.0]]
    with pytest.raises(mjcf.BindingError, match="'ctrl'"):
        one.set_control([[1.0], [2.0]])


def base(pendulum: composer.Entity) -> mjcf.Element:
    return pendulum.mjcf_model.find("body", "base")


def test_what_the_vector_batch_refuses_a_batch_of_one_refuses_alike():
    vector = VectorEnvironment(BatchedSwing, 2)
    vector.reset(seed=0)
    env = composer.Environment(BatchedSwing())
    env.reset(seed=0)
    one = BatchOfOne(env.physics)
    theirs, mine = vector.environments[0].task.pendulum, env.task.pendulum
    attempts = [
        lambda physics, pendulum: setattr(physics.bind(pendulum.tip), "xpos", 0.0),
        lambda physics, pendulum: setattr(physics.bind([pendulum.hinge]), "damping", 0.2),
        lambda physics, pendulum: physics.field("efc_force"),
        lambda physics, pendulum: physics.bind(base(pendulum)).cfrc_ext,  # for sensors only
    ]
    for attempt in attempts:
        with pytest.raises(composer.BatchError) as vector_error:
            attempt(vector.batch_physics, theirs)
        with pytest.raises(composer.BatchError) as single_error:
            attempt(one, mine)
        assert str(single_error.value) == str(vector_error.value)
    with pytest.raises(mjcf.BindingError):
        one.bind(mine.hinge).no_such_field  # noqa: B018
    permissive = BatchOfOne(env.physics, strict=False)  # what observables are read with
    assert permissive.bind(base(mine)).cfrc_ext.shape == (1, 6)
    assert permissive.field("efc_force").shape[0] == 1


def test_who_the_row_is_an_environment_says():
    env = composer.Environment(BatchedSwing())
    env.reset(seed=0)
    served = env.batch_physics
    assert served.num_envs == 1 and served.ids.tolist() == [0]
    assert served.tasks == [env.task] and served.random_states == [env.random_state]
    assert isinstance(served, composer.BatchPhysics)
    bare = BatchOfOne(env.physics)
    with pytest.raises(composer.BatchError, match="without a task"):
        _ = bare.tasks
    with pytest.raises(composer.BatchError, match="no random state"):
        _ = bare.random_states
    assert bare.bind([]).qpos.shape == (1, 0)


class Drawing(composer.NullTask):
    """A reward drawn from each environment's random state (it needs to know whose rows),
    in batched form only: Task's `get_reward` runs it with a batch of one."""

    def __init__(self) -> None:
        super().__init__(Floor())

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        return np.array([state.uniform() for state in physics.random_states])


def test_a_task_called_with_its_environment_physics_runs_with_that_environment_batch():
    env = composer.Environment(Drawing())
    env.reset(seed=3)
    before = env.random_state.get_state(legacy=False)
    drawn = env.task.get_reward(env.physics)  # Task's single form: the batched one, served
    env.random_state.set_state(before)
    assert drawn == env.random_state.uniform()
    # Another physics of the same model is no environment's: a new batch, no random state.
    other = mjcf.Physics.from_mjcf_model(env.task.root_entity.mjcf_model)
    with pytest.raises(composer.BatchError, match="no random state"):
        env.task.get_reward(other)
    # A second environment of the task serves it from then on; the first no longer does.
    second = composer.Environment(env.task)
    second.reset(seed=5)
    state = second.random_state.get_state(legacy=False)
    second.task.get_reward(second.physics)
    assert second.random_state.get_state(legacy=False) != state
    with pytest.raises(composer.BatchError, match="no random state"):
        env.task.get_reward(env.physics)


def test_bindings_follow_a_recompile():
    class Recoloring(BatchedSwing):
        """Recolors its rod every episode: each reset recompiles."""

        def initialize_episode_mjcf(self, random_state):
            self.pendulum.mjcf_model.find("geom", "rod").rgba = [*random_state.uniform(size=3), 1]

    env = composer.Environment(Recoloring(), time_limit=0.1)
    for seed in range(3):
        model = env.physics.model
        env.reset(seed=seed)
        assert env.physics.model is not model
        _, reward, *_ = env.step(np.zeros(1))
        assert reward == -abs(env.physics.bind(env.task.pendulum.hinge).qpos[0])
