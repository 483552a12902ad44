"""SameModels: whether the simulations of a VectorEnvironment can all run on one MjModel
(which MuJoCo's batch steps faster than a model each: docs/performance_profile.md).

    same = SameModels(num_envs)
    same.update(models, changed)      # after resets: `changed` environments' models may differ
    same.identical                    # True: every model is models[0], bit for bit

Promise: `identical` only when every model equals the first as MuJoCo saves it.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import mujoco
import numpy as np

# A model larger than this is never compared: saving it costs more than sharing saves.
LARGEST = 8 << 20  # bytes of a saved model (mj_sizeModel)


def _saved(model: mujoco.MjModel, into: np.ndarray | None = None) -> np.ndarray:
    """`model` as MuJoCo saves it (MJB bytes)."""
    size = mujoco.mj_sizeModel(model)
    if into is None or into.size != size:
        into = np.empty(size, dtype=np.uint8)
    mujoco.mj_saveModel(model, None, into)
    return into


class SameModels:
    """Which of n models are the first one's, bit for bit. The environments' models are
    compiled apart, and tasks and variations may edit them at each reset: they are compared
    as MuJoCo saves them (`mj_saveModel`, every field and asset), and shared only while all
    are the same; a model larger than `LARGEST` is never compared."""

    def __init__(self, num_envs: int) -> None:
        """Know nothing yet: no model is taken to be the first one's."""
        self._same = np.zeros(num_envs, dtype=bool)
        self._first: np.ndarray | None = None  # models[0] saved
        self._scratch: np.ndarray | None = None

    @property
    def identical(self) -> bool:
        """Whether every model was the first one's at the last `update`."""
        return bool(self._same.all())

    def update(self, models: Sequence[mujoco.MjModel], changed: Iterable[int]) -> None:
        """Compare the models of environments `changed` (which may have been edited or
        recompiled since the last update) with the first; all of them if the first is
        among them."""
        changed = [int(i) for i in changed]
        if mujoco.mj_sizeModel(models[0]) > LARGEST:
            self._same[:] = False
            return
        if self._first is None or 0 in changed:
            self._first = _saved(models[0], self._first)
            changed = list(range(len(models)))
        first = self._first
        for i in changed:
            self._scratch = _saved(models[i], self._scratch)
            self._same[i] = np.array_equal(self._scratch, first)
