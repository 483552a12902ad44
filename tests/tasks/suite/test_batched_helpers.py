"""The suite's batched geometry helpers give, to the last bit, what dm_control computes one
vector or one pair at a time: `frames.in_frame` its `vector.dot(xmat.reshape(3, 3))`, and
`planar.SiteDistances` the `site_distances` of each of its pairs (a reward reads several
together)."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import tasks  # noqa: F401  (registers the ids)
from tasks.suite import planar
from tasks.suite.frames import in_frame
from tasks.suite.observables import BoundField, Concatenated


def test_in_frame_is_each_vector_dot_its_frame_bit_for_bit():
    rng = np.random.default_rng(0)
    scales = 10.0 ** rng.uniform(-3, 3, size=(50, 4, 3))
    vectors = rng.normal(size=(50, 4, 3)) * scales
    xmat = rng.normal(size=(50, 9))
    expected = np.array(
        [[vector.dot(xmat[i].reshape(3, 3)) for vector in vectors[i]] for i in range(50)]
    )
    assert in_frame(vectors, xmat).tobytes() == expected.tobytes()
    assert in_frame(vectors[:1, :1], xmat[:1]).tobytes() == expected[:1, :1].tobytes()


def test_site_distances_together_are_each_pairs_bit_for_bit():
    env = gymnasium.make("dm_control/manipulator-bring_peg-v0").unwrapped
    env.reset(seed=3)
    for _ in range(5):
        env.step(env.action_space.sample())
    robot, batch = env.task.manipulator, env.batch_physics
    pairs = [
        (robot.peg_grasp, robot.arm.grasp),
        (robot.object_site, robot.target_site),
        (robot.target_peg_tip, robot.peg_tip),
    ]
    together = planar.SiteDistances(pairs)(batch)
    assert together.shape == (1, len(pairs))
    for column, (first, second) in enumerate(pairs):
        apart = planar.site_distances(batch, first, second)
        assert together[:, column].tobytes() == apart.tobytes()
        assert apart[0] > 0
    env.close()


@pytest.mark.parametrize(
    "env_id",
    [
        "cheetah-run",
        "walker-walk",
        "humanoid-run",
        "humanoid-run_pure_state",
        "quadruped-run",
        "finger-turn_hard",
        "hopper-hop",
        "cartpole-three_poles",
        "quadruped-fetch",
    ],
)
def test_bound_fields_read_together_show_what_their_readers_read(env_id):
    """`observables.BoundField`s (and Concatenated ones), which one environment reads in
    one gather, show in each observation what their batched readers read, after steps and
    resets."""
    env = gymnasium.make(f"dm_control/{env_id}-v0", time_limit=0.5).unwrapped
    updater = env.updater
    fused = set(updater.fused_names)
    assert fused == {name for name, item in env.task.task_observables.items()
                     if isinstance(item, BoundField | Concatenated)}  # fmt: skip
    rng = np.random.default_rng(4)
    obs, _ = env.reset(seed=4)
    for step in range(60):
        for name, read in zip(updater.names, updater.readers, strict=True):
            assert obs[name].tobytes() == np.asarray(read(), np.float64).tobytes(), (step, name)
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        if terminated or truncated:
            obs, _ = env.reset()
    env.close()
