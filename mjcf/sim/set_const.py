"""The model constants MuJoCo derives from model parameters, kept true after a binding
writes a parameter.

    set_const.update(model, scratch, undo, "'ipos' of body 'object'")

`mj_setConst` recomputes what MuJoCo derives from positions, orientations, masses and sizes
(sameframe flags, bounding volumes, subtree masses, dof_M0 ...). A body compiled as "simple"
whose inertial frame moves off its body frame stops being simple, exactly as compiling the
model with the new values would make it; a value MuJoCo refuses is undone (BindingError).
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np

from mjcf import errors


def update(
    model: mujoco.MjModel, scratch: mujoco.MjData, undo: Callable[[], None], what: str
) -> None:
    """Run mj_setConst on `model` (with `scratch`, an MjData it may clobber) after `what`
    was written, clearing the "simple" flags that no longer hold. If MuJoCo refuses the
    new value, call `undo`, restore the constants and raise mjcf.BindingError naming
    `what`."""
    try:
        try:
            mujoco.mj_setConst(model, scratch)
        except mujoco.FatalError as e:
            if "compiled as simple" not in str(e):
                raise
            _unsimplify(model, scratch)
    except mujoco.FatalError as e:
        undo()
        mujoco.mj_setConst(model, scratch)
        raise errors.BindingError(
            f"writing {what}: MuJoCo cannot update the model for the new value, so it "
            f"was not applied: {e}"
        ) from None


def _unsimplify(model: mujoco.MjModel, scratch: mujoco.MjData) -> None:
    """The bodies whose inertial frame is no longer their body frame lose the "simple"
    flag, and `dof_simplenum` is counted again; then mj_setConst. Raises
    mujoco.FatalError, the flags as they were, if MuJoCo still refuses.

    mj_setConst only checks this one derived flag: a body compiled as "simple" (a fast path
    for its mass matrix) must keep its inertial frame on its body frame. Moving it off
    (randomising a center of mass) makes the body no longer simple, and its dofs no longer
    counted in `dof_simplenum`, exactly as compiling the model with the new values would
    make them; dm_control instead zeroes the sameframe flags, which MuJoCo 4 refuses for
    simple bodies."""
    simple, simplenum = model.body_simple.copy(), model.dof_simplenum.copy()
    try:
        model.body_simple[:] = 0  # mj_setConst then finds every body's sameframe
        model.dof_simplenum[:] = 0
        mujoco.mj_setConst(model, scratch)
        same = model.body_sameframe == mujoco.mjtSameFrame.mjSAMEFRAME_BODY
        model.body_simple[:] = np.where(same, simple, 0)
        # dof_simplenum: the length of the run of dofs of simple bodies starting at each
        # dof, found on the dofs taken backwards.
        backwards = (model.body_simple[model.dof_bodyid] != 0)[::-1]
        index = np.arange(model.nv)
        last_break = np.maximum.accumulate(np.where(backwards, -1, index))
        model.dof_simplenum[:] = (index - last_break)[::-1]
        mujoco.mj_setConst(model, scratch)
    except mujoco.FatalError:
        model.body_simple[:] = simple
        model.dof_simplenum[:] = simplenum
        raise
