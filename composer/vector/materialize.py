"""Each environment's own physics beside its row of MuJoCo's batch: the batch steps every
simulation, and an environment's own `mjcf.Physics` (its MjData) is brought up to date only
when something runs on it (a per-environment method, hook, observable or frame), then
written back to its row. `VectorEnvironment` inherits this (`Materialize`); not used alone.
"""

from __future__ import annotations

import mujoco
import numpy as np
from mujoco import batch as mujoco_batch

import mjcf
from composer.batch.vector import Simulations
from composer.environment import Environment

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
# What an environment's own MjData holds of its simulation (`Materialize._held`): nothing
# since its last physics step, all of it, or its derived fields while a batched write has
# changed the state since.
STALE, SYNCED, DERIVED = 0, 1, 2


class Materialize:
    """Each environment's own physics, up to date when something per environment needs it
    (`_materialize`) and saved into its row after (`_save`); a base of `VectorEnvironment`,
    which sets these attributes (`__init__`), not used alone."""

    _envs: list[Environment]
    _batch: mujoco_batch.Batch
    _simulations: Simulations
    _state: np.ndarray  # the batch's state rows, (num_envs, state size)
    _warning: np.ndarray  # the batch's warning counters, (num_envs, mjNWARNING, 2)
    _held: np.ndarray  # STALE, SYNCED or DERIVED, each environment's
    _any_synced: bool  # whether some environment may be SYNCED

    def _materialize(self, i: int) -> mjcf.Physics:
        """Environment i's physics, holding its simulation (state and derived fields)."""
        physics = self._envs[i].physics
        held = self._held[i]
        if held == STALE:
            self._batch.get_data(int(i), physics.data)
            if physics.legacy_step:
                # Derived fields a single environment would recompute when read: the
                # acceleration stage.
                physics.mark_as_dirty()
        elif held == DERIVED:
            mujoco.mj_setState(physics.model, physics.data, self._state[i], _STATE)
            physics.mark_as_dirty()
        self._held[i] = SYNCED
        self._any_synced = True
        return physics

    def _wrote(self, ids: np.ndarray) -> None:
        """A batched method may have written the state rows of environments `ids`."""
        if not self._any_synced:
            return  # none holds its whole simulation: none can hold derived fields alone
        held = self._held[ids]
        self._held[ids] = np.where(held == SYNCED, DERIVED, held)

    def _save(self, i: int) -> None:
        """Write environment i's physics state (and warning counters) into its row."""
        physics = self._envs[i].physics
        mujoco.mj_getState(physics.model, physics.data, self._state[i], _STATE)
        self._warning[i, :, 0] = physics.data.warning.lastinfo
        self._warning[i, :, 1] = physics.data.warning.number
        self._simulations.changed(i)

    def _read_env(self, i: int, channel: int) -> np.ndarray:
        """Observable `channel` of environment i, read from its own physics."""
        self._materialize(i)
        return self._envs[i].updater.readers[channel]()
