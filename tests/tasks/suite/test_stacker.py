"""The stacker domain against dm_control's own suite code, beyond one random episode
(test_suite_tasks.py): episode after episode the target's heights and places the reset
writes into the model; the reward where it is earned (a box at the target, the hand away),
which random actions rarely do; and the batched step in a vector environment."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import composer
import tasks  # noqa: F401  (registers the ids)
from entities.suite import Stacker
from entities.suite.planar_arm import ARM_JOINTS
from tasks import suite
from tests.tasks.suite import oracle
from tests.vector_runs import assert_same_runs

TASKS = suite.TASKS_BY_DOMAIN["stacker"]


@pytest.mark.parametrize("task", TASKS)
def test_episodes_start_and_earn_as_dm_control_s(task):
    ours = suite.load("stacker", task)
    theirs = oracle.reference("stacker", task, seed=6)
    n_boxes = len(ours.task.stacker.boxes)
    heights, best = set(), 0.0
    for episode in range(12):
        observation, _ = ours.reset(seed=6) if episode == 0 else ours.reset()
        reference = theirs.reset().observation
        assert list(observation) == list(reference)
        for key, value in reference.items():
            np.testing.assert_array_equal(observation[key], value, err_msg=key)
        np.testing.assert_array_equal(ours.physics.model.body_pos, theirs.physics.model.body_pos)
        heights.add(round(observation["target_pos"][1] / 0.022))
        # The first box onto the target, the arm upright (its hand far above): earned.
        for physics, scope in ((ours.physics, "stacker/"), (theirs.physics, "")):
            named = physics.named
            named.data.qpos[[scope + joint for joint in ARM_JOINTS]] = 0
            target = named.model.body_pos[scope + "target"]
            named.data.qpos[[scope + "box0_x", scope + "box0_z"]] = target[0], target[2]
            physics.forward()
        rewards = oracle.compare_steps(ours, theirs, oracle.random_actions(theirs, episode, 3), 0)
        best = max(best, rewards[0])
    assert heights == set(range(1, 2 * n_boxes, 2))  # the top of a stack of 1 .. n boxes
    assert best > 0.9


def test_the_vector_environment_equals_single_ones():
    env_id = "dm_control/stacker-stack_2-v0"
    vector = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    reference = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=20, seed=4)
    assert vector.unwrapped.per_environment == []  # the domain's step is batched throughout
    vector.close()
    reference.close()


@pytest.mark.parametrize("n_boxes", [0, 5, 2.0, True])
def test_a_number_of_boxes_the_suite_has_no_model_for_is_refused(n_boxes):
    with pytest.raises(composer.EntityError, match="n_boxes"):
        Stacker(n_boxes=n_boxes)
