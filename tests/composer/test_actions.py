"""The action policy: non-finite actions are refused, out-of-range ones clipped."""

from __future__ import annotations

import numpy as np
import pytest

import composer
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


def test_out_of_range_actions_are_clipped_to_ctrlrange(env: composer.Environment) -> None:
    env.step(np.array([25.0]))
    assert env.physics.data.ctrl.tolist() == [1.0]
    env.step(np.array([-3.0]))
    assert env.physics.data.ctrl.tolist() == [-1.0]
