"""One step, batched or not: a single Environment runs a task's batched methods with a batch
of one, keeps the single forms where a task wrote those, and both environments keep the
rules of composer.stepping."""

from __future__ import annotations

import math

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import SyncVectorEnv

import composer
from arenas import Floor
from composer import BatchOfOne, observation, stepping
from composer.vector import VectorEnvironment, info_layout
from tests.composer.vector_scenes import BatchedSwing


def test_single_forms_of_a_batched_task_run_its_batched_methods_with_a_batch_of_one():
    task = BatchedSwing()
    env = composer.Environment(task)
    env.reset(seed=0)
    physics = env.physics
    angle = physics.bind(task.pendulum.hinge).qpos[0]
    assert task.get_reward(physics) == -abs(angle)
    assert task.get_reward(physics) == task.get_reward_batch(BatchOfOne(physics))[0]
    info = task.get_info(physics)
    assert info == {"low": angle < 0} and type(info["low"]) is bool  # as a single form gives
    assert task.should_terminate_episode(physics) is False
    assert task.get_discount(physics) == 1.0
    task.before_step(physics, np.array([0.5]), env.random_state)
    assert physics.data.ctrl.tolist() == [0.5]


def test_task_defaults_and_null_task_in_both_forms():
    env = composer.Environment(composer.NullTask(Floor()))
    env.reset(seed=0)
    task, physics = env.task, env.physics
    one = BatchOfOne(physics)
    assert task.get_reward(physics) == 0.0 and task.get_reward_batch(one).tolist() == [0.0]
    assert task.get_discount_batch(one).tolist() == [1.0]
    assert task.should_terminate_episode_batch(one).tolist() == [False]
    assert task.get_info(physics) == {} and task.get_info_batch(one) == {}
    _, reward, terminated, truncated, info = env.step(np.zeros(0))
    assert (reward, terminated, truncated, info) == (0.0, False, False, {"discount": 1.0})

    class Lazy(composer.Task):
        root_entity = Floor()

    with pytest.raises(NotImplementedError, match=r"get_reward\(physics\) or get_reward_batch"):
        Lazy().get_reward(physics)


class SingleReward(BatchedSwing):
    """Overrides the single form only: it runs, in a single environment too."""

    def get_reward(self, physics):
        return 7.0


class WrongShapeReward(BatchedSwing):
    def get_reward_batch(self, physics):
        return np.zeros(physics.num_envs + 1)


def test_a_single_form_over_a_batched_one_runs_and_a_bad_batched_one_raises_alike():
    env = composer.Environment(SingleReward())
    env.reset(seed=0)
    assert env.step(np.zeros(1))[1] == 7.0
    env = composer.Environment(WrongShapeReward())
    env.reset(seed=0)
    with pytest.raises(composer.BatchError, match=r"get_reward_batch returned shape \(2,\)"):
        env.step(np.zeros(1))


class Recorder(BatchedSwing):
    """Records when its batched before_step and after_step run, next to the entities'."""

    def __init__(self, calls: list) -> None:
        super().__init__()
        self.calls = calls
        self.pendulum.before_step = lambda physics, random_state: calls.append("entity before")
        self.pendulum.after_step = lambda physics, random_state: calls.append("entity after")

    def before_step_batch(self, physics, actions):
        self.calls.append(("before", physics.num_envs, actions.shape))
        super().before_step_batch(physics, actions)

    def after_step_batch(self, physics):
        self.calls.append(("after", float(physics.field("time")[0])))


def test_batched_step_hooks_run_first_then_the_entities_in_a_single_environment():
    calls: list = []
    env = composer.Environment(Recorder(calls))
    env.reset(seed=0)
    env.step(np.array([0.3]))
    control_timestep = env.control_timestep
    assert calls == [("before", 1, (1, 1)), "entity before",
                     ("after", pytest.approx(control_timestep)), "entity after"]  # fmt: skip
    assert env.physics.data.ctrl.tolist() == [0.3]


def test_a_vector_environment_runs_the_same_batched_hooks_for_all_environments():
    calls: list = []
    vector = VectorEnvironment(lambda: Recorder(calls), 3)
    vector.reset(seed=0)
    calls.clear()
    vector.step(np.full((3, 1), 0.3))
    assert calls[0] == ("before", 3, (3, 1)) and calls[-3:] == ["entity after"] * 3
    assert calls.count(("after", pytest.approx(vector.control_timestep))) == 1


def test_a_batched_observable_is_read_by_one_environment_as_row_0():
    task = BatchedSwing()
    env = composer.Environment(task)
    obs, _ = env.reset(seed=0)
    hinge = task.pendulum.hinge
    assert obs["angle_cos"][0] == np.cos(env.physics.bind(hinge).qpos[0])
    assert task.task_observables["angle_cos"](env.physics).shape == (1,)
    with pytest.warns(DeprecationWarning, match="batch_function"):
        old = observation.BatchGeneric(
            lambda physics: 0.0, batch_function=lambda physics: np.cos(physics.bind(hinge).qpos)
        )
    np.testing.assert_array_equal(old(env.physics), obs["angle_cos"])

    class Neither(observation.Observable):
        pass

    with pytest.raises(NotImplementedError, match=r"reader\(physics\) or batch_reader"):
        Neither()(env.physics)


def test_step_limit_and_action_rule():
    assert stepping.step_limit(None, 0.02) == math.inf
    assert stepping.step_limit(1.0, 0.3) == 4  # rounded up to whole control steps
    assert stepping.step_limit(1.0, 0.25, max_episode_steps=3) == 3
    assert stepping.step_limit(0.3, 0.1) == 3  # not 4 from 0.30000000000000004 / 0.1
    rule = stepping.ActionRule(gymnasium.spaces.Box(-1.0, 1.0, (2,)), num_envs=3)
    actions = rule.shaped(np.full((3, 2), 5.0, dtype=np.float32))
    np.testing.assert_array_equal(rule.clipped(actions, np.arange(3)), np.ones((3, 2)))
    actions[1, 0] = np.nan
    with pytest.raises(composer.EpisodeError, match=r"environments \[4\]"):
        rule.clipped(actions, np.array([3, 4, 5]))
    with pytest.raises(composer.EpisodeError, match=r"shape \(2,\), expected \(3, 2\)"):
        rule.shaped(np.zeros(2))


class Informative(gymnasium.Env):
    """Gives every kind of info entry Gymnasium's vector layout knows."""

    observation_space = gymnasium.spaces.Box(-1, 1, (1,))
    action_space = gymnasium.spaces.Box(-1, 1, (1,))

    def __init__(self, i: int) -> None:
        self.i = i

    def entries(self) -> dict:
        i = self.i
        return {"count": i, "speed": 0.5 * i, "done": i % 2 == 0, "flag": np.bool_(i),
                "number": np.float32(i), "vector": np.full(2, i), "name": f"env{i}",
                "nested": {"depth": i}}  # fmt: skip

    def reset(self, *, seed=None, options=None):
        return np.zeros(1, np.float32), self.entries()

    def step(self, action):
        return np.zeros(1, np.float32), 0.0, False, False, self.entries()


def test_per_environment_info_entries_are_laid_out_as_gymnasium_lays_them_out():
    reference = SyncVectorEnv([lambda i=i: Informative(i) for i in range(3)])
    _, expected = reference.reset(seed=0)
    info: dict = {}
    for i in (0, 2, 1):
        info_layout.add(info, Informative(i).entries(), i, 3)
    assert data_equivalence(info, expected, exact=True)
    partial: dict = {}
    info_layout.add(partial, Informative(1).entries(), 1, 3)
    assert partial["_count"].tolist() == [False, True, False]


def test_only_tasks_keeping_tasks_control_write_have_it_written_directly():
    """One environment writes a checked action to ctrl itself only where the task's
    batched before_step is Task's (which writes it and does nothing else)."""

    class Overriding(composer.Task):
        def before_step_batch(self, physics, actions):
            physics.set_control(actions / 2)

    class Single(composer.Task):
        def before_step(self, physics, action, random_state):
            physics.set_control(action)

    assert stepping.TaskStep(composer.Task()).writes_controls
    assert not stepping.TaskStep(Overriding()).writes_controls
    assert not stepping.TaskStep(Single()).writes_controls
