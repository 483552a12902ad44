"""The lqr domain against dm_control's own suite code, beyond one random episode
(test_suite_tasks.py): the system drawn from the seed (and kept by resets without one);
the episode's end once the system is at rest, which random actions never reach; the
optimal controller's cost, as dm_control's own lqr_test checks it; and vector environments,
whose systems differ.

dm_control's `lqr_solver` (and so its `lqr_test`) needs scipy, which is not installed: the
discrete algebraic Riccati equation is solved here by iterating it, in numpy, from the
matrices dm_control's solver builds."""

from __future__ import annotations

import math

import gymnasium
import mujoco
import numpy as np
import pytest

import composer
import tasks  # noqa: F401  (registers the ids)
from entities.suite import LQR
from tasks import suite
from tests.tasks.suite import oracle
from tests.vector_runs import assert_same_runs

TASKS = suite.TASKS_BY_DOMAIN["lqr"]


def _springs(env):
    model = env.physics.model
    return model.jnt_stiffness.copy(), model.dof_damping.copy()


@pytest.mark.parametrize("task", TASKS)
def test_the_system_is_drawn_from_the_seed_and_kept_until_the_next(task):
    ours = suite.load("lqr", task)
    ours.reset(seed=1)
    first = oracle.reference("lqr", task, seed=1)
    first.reset()
    np.testing.assert_array_equal(_springs(ours), _springs(first))
    observation, _ = ours.reset()  # a new episode of the same system, as dm_control's
    np.testing.assert_array_equal(_springs(ours), _springs(first))
    np.testing.assert_array_equal(observation["position"], first.reset().observation["position"])
    ours.reset(seed=2)
    second = oracle.reference("lqr", task, seed=2)
    np.testing.assert_array_equal(_springs(ours), _springs(second))
    assert not np.array_equal(_springs(ours)[0], _springs(first)[0])


def _optimal_gain(physics, control_cost):
    """dm_control's `lqr_solver.solve` without scipy: the linearised one-step dynamics
    (a, b) of semi-implicit Euler and the state cost on positions, as it builds them, then
    the Riccati equation's solution p by structure-preserving doubling (its iterates
    converge quadratically). Returns the gain k (u = k x), p and the closed loop's slowest
    decay rate."""
    model = physics.model
    n, m, dt = model.nq, model.nu, model.opt.timestep
    mass = np.zeros((n, n))
    mujoco.mj_fullM(model, physics.data, mass)
    springs = np.hstack((np.diag(model.jnt_stiffness), np.diag(model.dof_damping)))
    j = np.linalg.solve(-mass, springs)
    a = np.eye(2 * n) + dt * np.vstack((dt * j + np.hstack((np.zeros((n, n)), np.eye(n))), j))
    bc = np.linalg.solve(mass, np.vstack((np.eye(m), np.zeros((n - m, m)))))
    b = dt * np.vstack((dt * bc, bc))
    q = np.diag(np.hstack((np.ones(n), np.zeros(n))))
    r = control_cost * np.eye(m)
    doubled, g, p = a, b @ np.linalg.solve(r, b.T), q
    for _ in range(60):
        w = np.linalg.inv(np.eye(2 * n) + g @ p)
        doubled, g, following = (
            doubled @ w @ doubled, g + doubled @ w @ g @ doubled.T,
            p + doubled.T @ p @ w @ doubled,
        )  # fmt: skip
        converged = np.allclose(following, p, rtol=1e-14, atol=0)
        p = following
        if converged:
            break
    k = -np.linalg.solve(b.T @ p @ b + r, b.T @ p @ a)
    return k, p, np.abs(np.linalg.eigvals(a + b @ k)).max()


@pytest.mark.parametrize("task", TASKS)
def test_the_optimal_controller_costs_what_riccati_says(task):
    # dm_control's lqr_test: over the steps that bring the state to 1e-3 of itself, the
    # costs (the start's position cost, then 1 - each reward) sum to V(start) = start' p
    # start / 2. Its episodes are dm_control's step for step (test_suite_tasks.py).
    env = suite.load("lqr", task)
    observation, _ = env.reset(seed=3)
    k, p, decay = _optimal_gain(env.physics, env.task.control_cost_coef)
    state = start = np.hstack((observation["position"], observation["velocity"]))
    cost = 0.5 * observation["position"] @ observation["position"]
    for _ in range(math.ceil(math.log10(1e-3) / math.log10(decay)) - 1):
        observation, reward, terminated, truncated, _ = env.step(k @ state)
        assert not (terminated or truncated)
        cost += 1 - reward
        state = np.hstack((observation["position"], observation["velocity"]))
    np.testing.assert_allclose(cost, 0.5 * start @ p @ start, rtol=1e-3)
    assert np.linalg.norm(state) < 2e-3 * np.linalg.norm(start)


@pytest.mark.parametrize("task", TASKS)
def test_at_rest_the_episode_ends_with_discount_0_as_in_dm_control(task):
    ours = suite.load("lqr", task)
    theirs = oracle.reference("lqr", task, seed=3)
    ours.reset(seed=3)
    theirs.reset()
    stop = np.zeros((5, ours.physics.model.nu))
    # Near rest (a state norm of 1e-6 * sqrt(nq)) it goes on; at rest it ends at once, as
    # compare_steps checks: terminated, with discount 0.
    for offset, steps in ((1e-6, 5), (0.0, 1)):
        for physics in (ours.physics, theirs.physics):
            physics.data.qpos[:] = offset
            physics.data.qvel[:] = 0.0
            physics.forward()
        assert len(oracle.compare_steps(ours, theirs, stop, atol=0)) == steps


def test_vector_environments_run_each_their_own_system():
    env_id = "dm_control/lqr-lqr_2_1-v0"
    vector = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    reference = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=20, seed=4)
    assert vector.unwrapped.per_environment == []  # the domain's step is batched throughout
    stiffness = [env.physics.model.jnt_stiffness for env in vector.unwrapped.environments]
    assert not np.array_equal(stiffness[0], stiffness[1])  # seeds 4 and 5: two systems
    vector.close()
    reference.close()


def test_bad_systems_and_costs_are_refused():
    with pytest.raises(composer.EntityError, match="at most 1 actuator per body"):
        LQR(n_bodies=2, n_actuators=3)
    with pytest.raises(composer.EntityError, match="at least 1 body"):
        LQR(n_bodies=0, n_actuators=0)
    with pytest.raises(composer.TaskError, match="control_cost_coef must be positive"):
        suite.load("lqr", "lqr_2_1", task_kwargs={"control_cost_coef": 0.0})
