"""Whether MuJoCo gave up on a simulation: its invalid-state warnings, and a non-finite
acceleration, reported with the joint or actuator they concern.

    validity.raise_if_invalid(model, data, data.warning.number)   # PhysicsError if invalid
    with validity.StateCheck(physics): ...                         # checks when the block ends

`mjcf.Physics.check_invalid_state()` and `check_divergence()` are built on these.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import fields

if TYPE_CHECKING:
    from mjcf.sim.physics import Physics

# MuJoCo warnings that mean the state was invalid: non-finite or huge qpos/qvel, bad qacc
# (the solver or integrator diverged; MuJoCo then resets the data itself), bad controls;
# each with the array whose index the warning's lastinfo reports.
_INVALID_STATE_WARNINGS = {
    mujoco.mjtWarning.mjWARN_BADQPOS: "qpos",
    mujoco.mjtWarning.mjWARN_BADQVEL: "qvel",
    mujoco.mjtWarning.mjWARN_BADQACC: "qvel",
    mujoco.mjtWarning.mjWARN_BADCTRL: "ctrl",
}
_INVALID_STATE_IDS = np.array([int(w) for w in _INVALID_STATE_WARNINGS])


def raise_if_invalid(
    model: mujoco.MjModel, data: mujoco.MjData, warnings: np.ndarray, qacc_checked: bool = False
) -> None:
    """Raise PhysicsError if MuJoCo flagged a bad qpos, qvel, qacc or ctrl since the last
    reset (`warnings`: data.warning.number, a live view), or qacc is not finite.
    `qacc_checked`: MuJoCo's own check (mj_checkAcc, in a step) saw data.qacc as it is, so
    a non-finite value there has set a warning already and qacc is not looked at again."""
    # any() over a list first: benign warnings aside, nothing is set, and this is cheapest.
    if any(warnings.tolist()) and warnings[_INVALID_STATE_IDS].any():
        found = []
        for warning, field in _INVALID_STATE_WARNINGS.items():
            if warnings[warning]:
                where = _locate(model, field, data.warning[warning].lastinfo)
                found.append(f"{warning.name} x{warnings[warning]} ({where})")
        raise errors.PhysicsError(
            f"physics state is invalid at t={data.time:.6g}: MuJoCo reported "
            f"{', '.join(found)}; reset the physics to continue"
        )
    if qacc_checked:
        return
    # MuJoCo checks the state only when stepping; a state set since then and forwarded
    # (reset_context) shows in qacc. The dot product is not finite if any entry is not,
    # or above 1e154, far past MuJoCo's own 1e10 bound (ndarray.dot: half of `@`'s cost).
    qacc = data.qacc
    if not math.isfinite(qacc.dot(qacc)):
        bad = np.flatnonzero(~np.isfinite(qacc))
        index = int(bad[0]) if bad.size else int(np.argmax(np.abs(qacc)))
        raise errors.PhysicsError(
            f"physics state is invalid at t={data.time:.6g}: qacc is not finite at "
            f"{_locate(model, 'qvel', index)}; was a NaN or infinite qpos/qvel set?"
        )


def _locate(model: mujoco.MjModel, field: str, index: int) -> str:
    """'<field> index <i>, joint <name>': the object owning row `index` of qpos/qvel/ctrl."""
    spec = fields.indexed_field(field)
    assert spec.address is not None, "qpos, qvel and ctrl rows are addressed"
    starts, counts = fields.rows(model, spec.address)
    owner = np.flatnonzero((starts <= index) & (index < starts + counts))
    if owner.size == 0:
        return f"{field} index {index}"
    name = fields.names(model, spec.kind)[owner[0]] or f"#{owner[0]}"
    return f"{field} index {index}, {fields.kind_name(spec.kind)} {name!r}"


class StateCheck:
    """`physics.check_invalid_state()` used as a context manager: checks when the block
    ends (unless the block raised)."""

    __slots__ = ("_physics",)

    def __init__(self, physics: Physics) -> None:
        self._physics = physics

    def __enter__(self) -> Physics:
        return self._physics

    def __exit__(self, kind: type | None, *rest: Any) -> None:
        if kind is None:
            self._physics._raise_if_invalid()
