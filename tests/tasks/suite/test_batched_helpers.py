"""The suite's batched geometry helpers give, to the last bit, what dm_control computes one
vector or one pair at a time: `frames.in_frame` its `vector.dot(xmat.reshape(3, 3))`, and
`planar.SiteDistances` the `site_distances` of each of its pairs (a reward reads several
together)."""

from __future__ import annotations

import gymnasium
import numpy as np

import tasks  # noqa: F401  (registers the ids)
from tasks.suite import planar
from tasks.suite.frames import in_frame


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
