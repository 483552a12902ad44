"""Where MuJoCo's own warnings go: the 'mujoco' logger of Python's `logging`, instead of
MuJoCo's default, which prints them and appends them to MUJOCO_LOG.TXT in the current
folder (a stray file in whatever folder a script or a test runs in).

    import logging
    logging.getLogger("mujoco").setLevel(logging.ERROR)     # silence them
    logging.getLogger("mujoco").addHandler(logging.FileHandler("mujoco.log"))   # keep them

`install()` (run when `mjcf.sim.physics` is imported) routes them so, unless a handler of
your own is already installed with `mujoco.set_mju_user_warning`.
"""

from __future__ import annotations

import contextlib
import logging

import mujoco

# The messages are MuJoCo's words: a compiler's note, "Nan, Inf or huge value in QACC at DOF
# 3. The simulation is unstable." (which `Physics.check_invalid_state` and composer's
# divergence handling also report, as exceptions and `composer.DivergenceWarning`s).
LOGGER = logging.getLogger("mujoco")


def install() -> None:
    """Send MuJoCo's warnings to LOGGER from now on, unless a handler is already set."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(_log)


def _log(message: str) -> None:
    # MuJoCo calls this from C, on its own threads too: an exception escaping here would
    # abort the process, so none may (hence logging rather than `warnings`, which raises
    # under `-W error`).
    with contextlib.suppress(BaseException):
        LOGGER.warning("MuJoCo warning: %s", message.strip())
