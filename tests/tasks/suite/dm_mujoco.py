"""What dm_control's suite code imports as `dm_control.mujoco`, on our `mjcf.Physics` (tests
only: the oracle, `tests/tasks/suite/oracle.py`, rewrites the suite's imports to this).

dm_control's own `mujoco` package wraps MuJoCo through ctypes and does not run on MuJoCo 4;
the suite needs little of it: a Physics class to subclass (with `from_xml_string`, `named`,
`model`, `data`, `control()`, `velocity()`, `reset_context()` ...: ours has them, and the
hook and attribute dm_control's adds, `_reload_from_data` and `contexts`), the
actuators' `action_spec`, and `wrapper.mjbindings` for MuJoCo's enums and functions, which
the `mujoco` bindings provide under the same names (`.ptr` of our model and data is the
object itself, `mjcf.sim.raw_access`).
"""

from __future__ import annotations

import types
from typing import Any

import mujoco
import numpy as np
from dm_env import specs

import mjcf
from mjcf.sim.binding import ACC_BEHIND


class Physics(mjcf.Physics):
    """dm_control's `mujoco.Physics`: ours, with the two seams suite domains use, and one
    change.

    The seams: the `_reload_from_data` hook, run when the physics is made (the quadruped
    sets up its caches there; the suite never reloads one), and `contexts`, the render
    contexts, which do not exist here (the quadruped's escape re-uploads its heightfield
    only when they do).

    The change: on dm_control, reading MjData raw (`physics.data.sensordata`) and by name
    (`physics.named.data.sensordata`) gives the same values, both one physics step old for
    acceleration-dependent fields after a step (touch sensors, contact forces). Ours
    computes those afresh for named reads and bindings (`mjcf.Physics.step`), as our tasks
    read them; so that dm_control's code sees one physics whichever way it reads (stacker
    reads its touch sensors raw, manipulator by name), a raw read of `data` right after a
    step brings them up to date as a named read would. The trajectory is unaffected: the
    next step recomputes that stage anyway. docs/suite.md lists this difference."""

    contexts = None

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        super().__init__(model, data)
        self._reload_from_data(data)

    def _reload_from_data(self, data: Any) -> None:
        """dm_control's hook after a new model or data; nothing here."""

    @property
    def data(self) -> mujoco.MjData:
        """The raw MjData, its acceleration stage first brought up to date if a step (or
        `after_reset`) left only that behind."""
        if self._stale == ACC_BEHIND:
            self._refresh()
        return self._data


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
