"""The action policy: non-finite actions are refused, out-of-range ones clipped."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from gymnasium import spaces

import composer
from composer import stepping
from tests.composer.scenes import SwingTask


@pytest.fixture
def env() -> composer.Environment:
    environment = composer.Environment(SwingTask(), time_limit=1.0)
    environment.reset(seed=0)
    return environment


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_actions_raise_and_leave_the_state(
    env: composer.Environment, bad: float
) -> None:
    qpos = env.physics.data.qpos.copy()
    with pytest.raises(composer.EpisodeError, match="non-finite values at indices \\[0\\]"):
        env.step(np.array([bad]))
    assert np.array_equal(env.physics.data.qpos, qpos)
    env.step(np.array([0.5]))  # the episode goes on


@pytest.mark.parametrize(
    ("action", "expected"),
    [
        (np.array([0.5 + 1e-3j]), r"complex numbers \(an imaginary part cannot be applied"),
        ([0.5 + 0j], "complex numbers"),
        (["0.5"], "values of type <U3: actions are real numbers, an array of shape \\(1,\\)"),
        ("x", "values of type <U1"),
        (np.array([object()]), "values of type object"),
        ([None], "values of type object"),
        ([[0.5], [0.1, 0.2]], "the action is not an array of numbers"),
    ],
)
def test_actions_that_are_not_real_numbers_raise_and_leave_the_state(
    env: composer.Environment, action, expected: str
) -> None:
    """Nothing is converted: a string of a number, an object, a complex number whose
    imaginary part numpy would drop with a warning are refused, the state unchanged."""
    qpos, ctrl = env.physics.data.qpos.copy(), env.physics.data.ctrl.copy()
    with pytest.raises(composer.EpisodeError, match=expected):
        env.step(action)
    assert np.array_equal(env.physics.data.qpos, qpos)
    assert np.array_equal(env.physics.data.ctrl, ctrl)
    env.step([0.5])  # integers, floats of any width, lists: real numbers all
    env.step(np.array([1], np.int8))


def test_out_of_range_actions_are_clipped_to_ctrlrange(env: composer.Environment) -> None:
    env.step(np.array([25.0]))
    assert env.physics.data.ctrl.tolist() == [1.0]
    env.step(np.array([-3.0]))
    assert env.physics.data.ctrl.tolist() == [-1.0]


def _exact_verdict(actions: np.ndarray) -> bool:
    return bool(np.isfinite(actions).all())


@pytest.mark.parametrize("num_envs", [None, 3])
def test_the_finiteness_test_agrees_with_isfinite_on_every_kind_of_value(num_envs) -> None:
    # Huge finite values overflow the cheap test's sum of squares; they must still pass,
    # and every NaN or infinity, alone or among huge values, must still be refused, with no
    # warning of the overflow (a finite action is valid, whatever its size).
    warnings.simplefilter("error")
    space = spaces.Box(-np.inf, np.inf, (4,), dtype=np.float64)
    rule = stepping.ActionRule(space, num_envs)
    values = [0.0, -2.5, 1e-300, 1e154, 1e200, -1.7e308, np.inf, -np.inf, np.nan]
    rng = np.random.default_rng(0)
    for _ in range(400):
        actions = rng.choice(values, size=rule.shape)
        if _exact_verdict(actions):
            clipped = rule.clipped(actions, None if num_envs is None else np.arange(num_envs))
            np.testing.assert_array_equal(clipped, actions)
        else:
            with pytest.raises(composer.EpisodeError, match="non-finite"):
                rule.clipped(actions, None if num_envs is None else np.arange(num_envs))
