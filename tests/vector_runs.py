"""The check the vector environment tests share: a vector environment and its reference
(Gymnasium's SyncVectorEnv of single environments) run alike, to the last bit."""

from __future__ import annotations

import numpy as np
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import VectorEnv


def assert_same_runs(vector: VectorEnv, reference: VectorEnv, *, steps: int, seed: int) -> int:
    """Both reset with `seed` and stepped `steps` times with the same random actions give
    the same observations, rewards, terminations, truncations and infos, exactly; returns
    how many episodes ended (so a caller can require runs through autoresets)."""
    got, expected = vector.reset(seed=seed), reference.reset(seed=seed)
    assert data_equivalence(got, expected, exact=True)
    rng = np.random.default_rng(seed)
    ended = 0
    for t in range(steps):
        actions = rng.uniform(-1, 1, vector.action_space.shape).astype(np.float32)
        got, expected = vector.step(actions), reference.step(actions)
        assert data_equivalence(got, expected, exact=True), (t, got, expected)
        ended += int(np.sum(got[2] | got[3]))
    return ended
