"""dm_control's accessors of a physics' state: time and timestep, the whole state as one
vector, and the controls, activations, positions and velocities.

    state = physics.get_state()           # qpos, qvel, act (+ history, plugin, plastic state)
    physics.set_state(state)              # derived fields follow at the next read or step
    physics.set_control(u)                # what the next step applies
    physics.position(), physics.velocity(), physics.activation(), physics.control()

Reads return copies. Writes are tracked as writes through bindings are: after a state write,
derived reads forward first; after a control write, only what depends on it is recomputed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import staleness
from mjcf.sim.binding import WRITE_BITS, BoundPhysics

if TYPE_CHECKING:
    from mjcf.sim.physics import Physics

# get_state(): dm_control's physics state (qpos, qvel, act, plugin state), plus MuJoCo 4's
# history and plastic state when a model has them, in mj_getState's order.
_PHYSICS_STATE = mujoco.mjtState.mjSTATE_PHYSICS | mujoco.mjtState.mjSTATE_PLUGIN
STATE_WRITE = WRITE_BITS[staleness.Effect.STATE]
_INPUT_WRITE = WRITE_BITS[staleness.Effect.STEP_INPUT]


class StateAccess(BoundPhysics):
    """The state accessors of `mjcf.Physics` (see the module docstring), which inherits
    them; a base of Physics, not used alone."""

    _model: mujoco.MjModel
    _data: mujoco.MjData
    _opt: Any
    _stale: int

    def timestep(self) -> float:
        """The simulation timestep in seconds (model.opt.timestep)."""
        return float(self._opt.timestep)

    def time(self) -> float:
        """The simulation time in seconds (data.time)."""
        return float(self._data.time)

    def get_state(self) -> np.ndarray:
        """The physics state as one vector: qpos, qvel, act (and the history, plugin and
        plastic state of models that have them), in mj_getState's order; a copy. As in
        dm_control it leaves out the solver's warm start, so `set_state` then continues
        close to, not bit for bit as, the original (`copy()` and pickling are exact)."""
        model = self._model
        out = np.empty(mujoco.mj_stateSize(model, _PHYSICS_STATE))
        mujoco.mj_getState(model, self._data, out, _PHYSICS_STATE)
        return out

    def state(self) -> np.ndarray:
        """dm_control's alias of `get_state()`."""
        return self.get_state()

    def set_state(self, physics_state: np.ndarray) -> None:
        """Set the state `get_state()` returned; derived fields follow at the next read
        through bindings, `forward()` or `step()`. Raises StateError for a wrong size."""
        model = self._model
        size = mujoco.mj_stateSize(model, _PHYSICS_STATE)
        state = np.asarray(physics_state, dtype=np.float64)
        if state.shape != (size,):
            raise errors.StateError(
                f"physics state has shape {state.shape}, expected ({size},): qpos ({model.nq}), "
                f"qvel ({model.nv}), act ({model.na}) and, where the model has them, "
                "history, plugin and plastic state, as get_state() returns"
            )
        mujoco.mj_setState(model, self._data, state, _PHYSICS_STATE)
        self._stale |= STATE_WRITE

    def control(self) -> np.ndarray:
        """A copy of the controls (data.ctrl)."""
        return self._data.ctrl.copy()

    def set_control(self, control: Any) -> None:
        """Set the controls the next step applies; raises StateError for a wrong size."""
        try:
            np.copyto(self._data.ctrl, control)
        except ValueError as e:
            raise errors.StateError(
                f"control has shape {np.shape(control)}, expected ({self._model.nu},)"
            ) from e
        self._stale |= _INPUT_WRITE

    def activation(self) -> np.ndarray:
        """A copy of the actuator activations (data.act)."""
        return self._data.act.copy()

    def position(self) -> np.ndarray:
        """A copy of the generalized positions (data.qpos)."""
        return self._data.qpos.copy()

    def velocity(self) -> np.ndarray:
        """A copy of the generalized velocities (data.qvel)."""
        return self._data.qvel.copy()


class ResetContext:
    """`physics.reset_context(keyframe)`: `start()` resets when the block starts (derived
    fields computed when first read); the block ends with a forward and a validity check,
    unless it raised. A class, not a generator: a reset every episode pays a third of the
    cost."""

    __slots__ = ("_physics", "_start")

    def __init__(self, physics: Physics, start: Callable[[], None]) -> None:
        self._physics = physics
        self._start = start

    def __enter__(self) -> Physics:
        self._start()
        return self._physics

    def __exit__(self, kind: type | None, *rest: Any) -> None:
        if kind is None:
            physics = self._physics
            physics.forward()
            physics.check_invalid_state()
