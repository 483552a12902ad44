"""What dm_control's suite code imports as `dm_control.mujoco`, on our `mjcf.Physics` (tests
only: the oracle, `tests/tasks/suite/oracle.py`, rewrites the suite's imports to this).

dm_control's own `mujoco` package wraps MuJoCo through ctypes and does not run on MuJoCo 4;
the suite needs little of it: a Physics class to subclass (with `from_xml_string`, `named`,
`model`, `data`, `control()`, `velocity()`, `reset_context()` ...: ours has them), the
actuators' `action_spec`, and `wrapper.mjbindings` for MuJoCo's enums and functions, which
the `mujoco` bindings provide under the same names (`.ptr` of our model and data is the
object itself, `mjcf.sim.raw_access`).
"""

from __future__ import annotations

import types

import mujoco
import numpy as np
from dm_env import specs

import mjcf


class Physics(mjcf.Physics):
    """dm_control's `mujoco.Physics`: ours."""


def action_spec(physics: mjcf.Physics) -> specs.BoundedArray:
    """dm_control's `mujoco.action_spec`: the actuators' control ranges, +-mjMAXVAL where
    an actuator is not control-limited."""
    count = physics.model.nu
    limited = physics.model.actuator_ctrllimited.ravel().astype(bool)
    minima = np.full(count, -mujoco.mjMAXVAL, dtype=float)
    maxima = np.full(count, mujoco.mjMAXVAL, dtype=float)
    minima[limited], maxima[limited] = physics.model.actuator_ctrlrange[limited].T
    return specs.BoundedArray(shape=(count,), dtype=float, minimum=minima, maximum=maxima)


mjbindings = types.SimpleNamespace(enums=mujoco, mjlib=mujoco, constants=mujoco)
wrapper = types.SimpleNamespace(mjbindings=mjbindings)
