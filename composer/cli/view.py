"""`composer view TASK`: watch a policy act in MuJoCo's interactive viewer (`mujoco.viewer`).

    $ composer view AntRun                                # random actions
    $ composer view Reach --policy runs/Reach-ppo         # a policy from `composer train`
    episode 1: return 57.12 over 75 steps, success

Close the window or press Ctrl-C to quit (`--episodes N`: after N episodes). It needs a
display: without one it says so in one line (`composer run TASK --video FILE` records a
video instead). On macOS run it with `mjpython -m composer view ...`, as MuJoCo's viewer requires.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import threading
import time
from typing import Any

import mujoco

from composer.cli import catalog, describe, engines, rollout
from composer.cli.errors import CliError
from composer.environment import Environment
from composer.pixels import PixelEnvironment


class DisplayError(CliError):
    """No window can be opened: no display, or one that cannot be reached."""


def run(args: argparse.Namespace) -> int:
    """Open the viewer and run episodes until it is closed; returns the exit status."""
    viewer = open_viewer_module()
    env = catalog.make(args.info)
    try:
        if args.policy == "random":
            policy = rollout.random_policy(env, args.seed)
        else:
            policy = rollout.model_policy(engines.load_policy(args.policy, env, args.trust_policy))
        watch(env, policy, viewer, args.seed, args.episodes)
    finally:
        env.close()
    return 0


def open_viewer_module() -> Any:
    """`mujoco.viewer`, once a window is known to be possible; raises DisplayError."""
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        raise DisplayError(
            "composer view needs a display and DISPLAY is not set; on a machine without "
            "one, record a video instead: composer run TASK --video FILE"
        )
    try:
        import glfw
        import mujoco.viewer
    except ImportError as e:
        raise DisplayError(f"MuJoCo's viewer cannot start: {e}") from e
    problems: list[str] = []
    glfw.set_error_callback(lambda code, text: problems.append(_text(text)))
    if not glfw.init():
        reason = problems[-1] if problems else "GLFW could not be initialized"
        raise DisplayError(f"cannot open a window on display {_display()}: {reason}")
    return mujoco.viewer


def watch(
    env: Environment | PixelEnvironment,
    policy: rollout.Policy,
    viewer: Any,
    seed: int = 0,
    episodes: int | None = None,
) -> int:
    """Run episodes of `policy` in `env` shown by `viewer` (`mujoco.viewer`) at real-time
    pace, until the window closes or `episodes` have ended; returns the episodes ended.

    The viewer shows the environment's own simulation, one action per control step; when an
    episode ends the next starts, from the next seed. The view starts at the task's render
    camera, if it names one (Esc frees the camera); Tab and Shift+Tab show MuJoCo's panels.
    """
    observation, _ = env.reset(seed=seed)
    window = _Window.open(env, viewer)
    done, tally = 0, rollout.Tally()
    pace = env.task.control_timestep
    next_frame = time.perf_counter()
    try:
        while window.handle.is_running() and (episodes is None or done < episodes):
            # The passive viewer reads the simulation only in sync(), so steps need no lock.
            observation, reward, terminated, truncated, info = env.step(policy(observation))
            tally.add(reward, info)
            if terminated or truncated:
                done += 1
                print(f"episode {done}: {describe.episode(tally.episode(info))}", flush=True)
                model = env.physics.model
                observation, _ = env.reset(seed=seed + done)
                tally = rollout.Tally()
                if env.physics.model is not model:  # recompiled: show the new model
                    window.close()
                    window = _Window.open(env, viewer)
            window.handle.sync()
            next_frame += pace
            time.sleep(max(0.0, next_frame - time.perf_counter()))
    finally:
        window.close()
    return done


@dataclasses.dataclass
class _Window:
    """A passive viewer's handle and the threads it started."""

    handle: Any
    threads: set[threading.Thread]

    @classmethod
    def open(cls, env: Environment | PixelEnvironment, viewer: Any) -> _Window:
        """A passive viewer of `env`'s model and data, at the task's render camera if it
        names one; raises DisplayError where the viewer cannot run (macOS outside mjpython)."""
        physics = env.physics
        before = set(threading.enumerate())
        try:
            handle = viewer.launch_passive(
                physics.model, physics.data, show_left_ui=False, show_right_ui=False
            )
        except RuntimeError as e:
            raise DisplayError(f"{e}: mjpython -m composer view ...") from e
        camera = getattr(env.task, "render_camera", None)
        if isinstance(camera, str):
            camera_id = mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_CAMERA, camera)
            if camera_id >= 0:
                with handle.lock():
                    handle.cam.type = mujoco.mjtCamera.mjCAMERA_FIXED
                    handle.cam.fixedcamid = camera_id
        return cls(handle, set(threading.enumerate()) - before)

    def close(self, timeout: float = 10.0) -> None:
        """Close the window and wait for its threads: a process that exits while they still
        tear down the window and its GL context can crash."""
        self.handle.close()
        for thread in self.threads:
            thread.join(timeout)


def _display() -> str:
    return os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or "(none)"


def _text(message: bytes | str) -> str:
    return message.decode(errors="replace") if isinstance(message, bytes) else str(message)
