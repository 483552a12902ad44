"""untimed: a call into MuJoCo without the Python bindings' profiling timer.

    untimed(batch.step, None, nstep, stage)   # batch.step(...), MuJoCo's timer unset

The physics computes the same numbers (the timer only measures `MjData.timer`'s
durations), faster: `untimed` says what it changes and what it leaves alone.
"""

from __future__ import annotations

import ctypes
import glob
import os
from collections.abc import Callable
from typing import Any, TypeVar

import mujoco

T = TypeVar("T")


def _callback() -> ctypes.c_void_p | None:
    """MuJoCo's `mjcb_time` global, or None where its library is not found."""
    folder = os.path.dirname(mujoco.__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        for path in sorted(glob.glob(os.path.join(folder, pattern))):
            try:
                return ctypes.c_void_p.in_dll(ctypes.CDLL(path), "mjcb_time")
            except (OSError, ValueError):
                continue
    return None


_MJCB_TIME = _callback()
# The bindings' own timer: what `mjcb_time` holds while mujoco.get_mjcb_time() is None.
_BINDINGS = _MJCB_TIME.value if _MJCB_TIME is not None and mujoco.get_mjcb_time() is None else None


def untimed(call: Callable[..., T], *arguments: Any) -> T:
    """`call(*arguments)` with the bindings' timer callback unset, restored after it.

    mujoco's Python bindings install a C timer callback (`mjcb_time`, the clock behind
    `MjData.timer`'s durations) that MuJoCo calls around every section of a step, a
    sizeable part of a small model's step (docs/performance_profile.md, section 8); C
    MuJoCo's own default, as envpool's C++ has it, is none. Inside the call the timer
    counts (`MjData.timer[...].number`) still count and their durations are not added to.
    The callback is process-wide: steps other threads run meanwhile go untimed too (their
    durations meaningless, never their physics). Any other timer callback (a C function
    installed through ctypes: MuJoCo's batch refuses Python ones) is left in place, as is
    the bindings' one where MuJoCo's library is not found."""
    callback = _MJCB_TIME
    if _BINDINGS is None or callback is None or callback.value != _BINDINGS:
        return call(*arguments)
    callback.value = None
    try:
        return call(*arguments)
    finally:
        callback.value = _BINDINGS
