"""Stepping, forwarding and resetting a physics, and keeping MjData's derived fields fresh
between them: what each leaves behind is recomputed when a binding or named access reads it.

    physics.step(10)                # legacy_step: MjData consistent with the new state
    physics.bind(joint).qpos = 0.3  # a tracked write: the next derived read forwards first
    physics.reset(keyframe=0)       # the keyframe's state, then forward

`Stepping` is a base of `mjcf.Physics`, which inherits these methods; the rules are
`Physics.step`'s and `mjcf.sim.binding.Binding`'s.
"""

from __future__ import annotations

from typing import Any

import mujoco

from mjcf import errors
from mjcf.sim import fields, set_const, staleness
from mjcf.sim.binding import ACC_BEHIND, LAGGING, POS_BEHIND, WRITTEN, BoundPhysics
from mjcf.sim.physics_state import STATE_WRITE

# As ints: comparing MuJoCo's pybind11 enums costs microseconds, and step() is hot.
_RK4 = int(mujoco.mjtIntegrator.mjINT_RK4)
_FWDINV = int(mujoco.mjtEnableBit.mjENBL_FWDINV)
# Steps after which MuJoCo's mj_checkAcc has seen data.qacc as it is left: not with RK4
# (data.qacc is its last stage's), sleep (waking recomputes it) or the forward/inverse
# comparison.
_RECOMPUTES_QACC = int(mujoco.mjtEnableBit.mjENBL_SLEEP) | _FWDINV
_VEL = int(mujoco.mjtStage.mjSTAGE_VEL)


class Stepping(BoundPhysics):
    """The stepping, forwarding and resetting of `mjcf.Physics` (see `step`), and the
    refreshes `BoundPhysics` asks for; a base of Physics, not used alone. Physics sets
    these attributes, each explained where (`Physics._attach`)."""

    legacy_step: bool
    _opt: Any
    _qacc_checked: int | None
    _on_demand: tuple[Any, ...]
    _scratch: mujoco.MjData | None

    @property
    def is_dirty(self) -> bool:
        """Whether state, controls or model fields were written through bindings or named
        access since the last `forward()` or `step()`: whether a derived read forwards
        first. dm_control keeps it set through a step; here a step clears it, since the
        step leaves every derived quantity fresh (see `step`)."""
        return bool(self._stale & WRITTEN)

    def mark_as_dirty(self) -> None:
        """Say the state changed behind the physics' back (e.g. written into `data`):
        derived reads forward first and the next step starts with a full `mj_step`."""
        self._stale |= STATE_WRITE

    def step(self, nstep: int = 1) -> None:
        """Advance the simulation by `nstep` timesteps; does not check divergence.

        With `legacy_step` True (the default, as in dm_control) the step leaves MjData
        consistent with the new state: positions, velocities, contacts, tendon lengths and
        position/velocity sensors are computed after the last integration (mj_step2, then
        mj_step1, as dm_control splits it; for RK4, the acceleration stage and
        mj_RungeKutta). This costs nothing over `mj_step`: the next step continues from those
        stages. Acceleration-dependent fields (qacc, actuator_force, contact forces, touch
        and accelerometer sensors) are recomputed at the new state when first read through
        a binding or named access, so they match mj_forward too, where dm_control's are one
        step old (and its contact forces can belong to other contacts); raw `data` keeps
        the last step's until then, so call `forward()` before reading those from it. The
        state itself is bit for bit what `mj_step` gives.

        With `legacy_step` False this is a plain `mj_step`: derived fields describe the state
        before the last integration, as with `mujoco.mj_step` and Gymnasium's MuJoCo envs.

        Raises StateError for `nstep` below 1.
        """
        model, data, opt = self._model, self._data, self._opt
        if nstep < 1:
            raise errors.StateError(f"nstep must be at least 1, got {nstep!r}")
        rk4 = opt.integrator == _RK4
        if not self.legacy_step:
            mujoco.mj_step(model, data, nstep)
            self._stale = LAGGING
        else:
            if self._stale & (POS_BEHIND | LAGGING):
                # The position/velocity stages do not describe this state: start afresh.
                mujoco.mj_step(model, data, nstep)
            else:
                if not rk4:
                    mujoco.mj_step2(model, data)
                elif opt.enableflags & _FWDINV:
                    mujoco.mj_step(model, data)  # mj_step also compares forward and inverse
                else:
                    # mj_step2 has no RK4: finish this step's forward pass, then integrate.
                    mujoco.mj_forwardSkip(model, data, _VEL, 0)
                    mujoco.mj_checkAcc(model, data)
                    mujoco.mj_RungeKutta(model, data, 4)
                if nstep > 1:
                    mujoco.mj_step(model, data, nstep - 1)
            mujoco.mj_step1(model, data)  # positions and velocities: qacc stays the step's
            self._stale = ACC_BEHIND
        checked = not rk4 and not opt.enableflags & _RECOMPUTES_QACC
        self._qacc_checked = self._stale if checked else None

    def forward(self) -> None:
        """Recompute every derived quantity from the state (mj_forward); clears is_dirty."""
        mujoco.mj_forward(self._model, self._data)
        self._computed()

    def after_reset(self) -> None:
        """dm_control's hook after a reset: forward with actuation disabled, so that no
        actuator force is computed before a control was given. Acceleration-dependent
        fields read through bindings are then recomputed with actuation."""
        opt = self._opt
        flags = opt.disableflags
        opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_ACTUATION
        try:
            mujoco.mj_forward(self._model, self._data)
        finally:
            opt.disableflags = flags
        self._computed()
        self._stale = ACC_BEHIND

    def _computed(self) -> None:
        """mj_forward just ran: compute the fields bindings asked for that MuJoCo computes
        only on demand, and mark everything fresh."""
        model, data = self._model, self._data
        for compute in self._on_demand:
            compute(model, data)
        self._stale = 0
        self._qacc_checked = None  # qacc is mj_forward's: no MuJoCo check saw it

    def _refresh(self) -> None:
        """Bring derived fields up to the state: the acceleration stage alone when only it
        is behind (after a step, or a control write), else a whole mj_forward."""
        model, data = self._model, self._data
        if self._stale & (POS_BEHIND | LAGGING):
            mujoco.mj_forward(model, data)
        else:
            mujoco.mj_forwardSkip(model, data, _VEL, 0)
        self._computed()

    def _compute_on_demand(self, field: str) -> None:
        """A binding reads `field`, which MuJoCo computes only for sensors that need it:
        compute it after every forward pass from now on (and now, if the data is fresh)."""
        compute = getattr(mujoco, staleness.ON_DEMAND[field][1])
        if compute not in self._on_demand:
            self._on_demand = (*self._on_demand, compute)
            if not self._stale & (POS_BEHIND | ACC_BEHIND):
                compute(self._model, self._data)

    def _update_constants(self, undo: Any, what: str) -> None:
        """A model field mj_setConst reads was written: recompute the model constants
        derived from it (see `mjcf.sim.set_const`). If MuJoCo refuses the new value,
        call `undo`, restore the constants and raise BindingError."""
        if self._scratch is None:
            self._scratch = mujoco.MjData(self._model)
        set_const.update(self._model, self._scratch, undo, what)

    def reset(self, keyframe: int | str | None = None) -> None:
        """Reset the state to qpos0, or to a keyframe (index or name), then forward.

        Raises NotFoundError for a keyframe the model does not have.
        """
        self._reset_state(keyframe)
        self.forward()

    def _reset_state(self, keyframe: int | str | None) -> None:
        """The state of qpos0 or a keyframe, its derived fields not computed yet (bindings
        and named access compute them when first read)."""
        if keyframe is None:
            mujoco.mj_resetData(self._model, self._data)
        else:
            mujoco.mj_resetDataKeyframe(self._model, self._data, self._keyframe_id(keyframe))
        self._stale = POS_BEHIND | ACC_BEHIND
        self._qacc_checked = None

    def _keyframe_id(self, keyframe: int | str) -> int:
        nkey = self._model.nkey
        names = fields.names(self._model, mujoco.mjtObj.mjOBJ_KEY)
        if isinstance(keyframe, str):
            key_id = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_KEY, keyframe)
            if key_id < 0:
                raise errors.NotFoundError(
                    f"no keyframe named {keyframe!r}{errors.did_you_mean(keyframe, names)}; "
                    f"keyframes: {list(names)}"
                )
            return key_id
        if not 0 <= int(keyframe) < nkey:
            raise errors.NotFoundError(
                f"keyframe index {keyframe} is out of range: the model has {nkey} keyframes"
            )
        return int(keyframe)
