"""The manipulator domain against dm_control's own suite code, beyond one random episode
(test_suite_tasks.py): episode after episode the three ways the prop starts (in the hand,
in the target, thrown) and the targets' and receptacles' poses the reset writes into the
model; the rewards where they are earned, which random actions rarely do; and the batched
step in a vector environment."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import tasks  # noqa: F401  (registers the ids)
from tasks import suite
from tests.tasks.suite import oracle
from tests.vector_runs import assert_same_runs

TASKS = suite.TASKS_BY_DOMAIN["manipulator"]


def _assert_same(observation, reference):
    """Two first observations, dm_control's keys in its order, equal to the last bit."""
    assert list(observation) == list(reference)
    for key, value in reference.items():
        np.testing.assert_array_equal(observation[key], value, err_msg=key)


def _start(env):
    """How the episode in `env` (ours) started: the prop in the target, in the hand or
    elsewhere."""
    task, physics = env.task, env.physics
    prop = physics.bind(task.manipulator.object_joints).qpos
    if np.array_equal(prop[:2], physics.bind(task.manipulator.target).pos[[0, 2]]):
        return "in_target"
    if np.array_equal(prop[:2], physics.bind(task.manipulator.arm.grasp).xpos[[0, 2]]):
        return "in_hand"
    return "uniform"


@pytest.mark.parametrize("task", TASKS)
def test_episodes_start_and_earn_as_dm_control_s(task):
    ours = suite.load("manipulator", task)
    theirs = oracle.reference("manipulator", task, seed=5)
    starts, best = set(), 0.0
    for episode in range(40):
        observation, _ = ours.reset(seed=5) if episode == 0 else ours.reset()
        _assert_same(observation, theirs.reset().observation)
        for field in ("body_pos", "body_quat"):  # the target and receptacle placed alike
            np.testing.assert_array_equal(
                getattr(ours.physics.model, field), getattr(theirs.physics.model, field)
            )
        starts.add(_start(ours))
        actions = oracle.random_actions(theirs, seed=episode, steps=3)
        best = max(best, *oracle.compare_steps(ours, theirs, actions, atol=0))
    assert starts == {"in_target", "in_hand", "uniform"}
    # A ball starting in its target earns 1; a peg, in its target 1, in the hand a third.
    assert best > 0.3


def test_the_vector_environment_equals_single_ones():
    env_id = "dm_control/manipulator-bring_ball-v0"
    vector = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    reference = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=20, seed=4)
    assert vector.unwrapped.per_environment == []  # the domain's step is batched throughout
    vector.close()
    reference.close()
