"""Pixel observations: a composer environment observed through a camera, as image-based RL
takes it (dm_control's suite from pixels, Atari).

    env = gym.make('composer/CartpoleSwingup-v0', pixels=True)          # (84, 84, 3) uint8
    env = gym.make('composer/Reach-v0', pixels=True, width=64, height=64, frame_stack=3)
    env = gym.make('composer/Reach-v0', pixels=True, proprioception=True)   # a Dict
    model = stable_baselines3.PPO('CnnPolicy', env)                     # no glue needed

Promises (`PixelEnvironment` states each): a frame shows the state after the step or reset
returning it; the same seed and actions give the same frames, bit for bit; new arrays each step.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import mujoco
import numpy as np
from gymnasium import spaces

from composer import errors
from composer.environment import Environment

# dm_control's suite from pixels and the image-based RL it serves use 84x84 frames.
DEFAULT_SIZE = 84


class PixelEnvironment(gymnasium.Env):
    """A composer Environment observed through a camera.

    `PixelEnvironment(env, height, width, camera, frame_stack, proprioception)` serves a
    `composer.Environment` (its actions, rewards, info, `render()`, `physics` and `task`) with
    frames of `camera` as observations (the task's render camera when made through `gym.make`),
    in Gymnasium's image layout: a `uint8` Box of shape (height, width, 3 * frame_stack) bounded
    to [0, 255], the `frame_stack` latest frames stacked along the channels, oldest first (the
    layout stable-baselines3's `CnnPolicy`, `VecTransposeImage` and `VecFrameStack` use). At a
    reset every slot holds the first frame. With `proprioception=True` the observation is a Dict
    of 'pixels' and 'proprioception', the task's observations flattened into one vector (what
    `MultiInputPolicy` takes). It is a `gymnasium.Env` of its own, not a wrapper, so
    `env.unwrapped` is it and `gymnasium.utils.env_checker.check_env(env.unwrapped)` checks the
    pixel observations.

    What it promises: a frame is the state after the step (or reset) it is returned by, drawn
    by the physics' renderer of that size (`mjcf.sim.rendering`: no shadows or multisampling up to
    128 pixels a side, unless the model's MJCF sets them); the same seed and actions give the
    same frames, bit for bit; a recompile of the scene (`initialize_episode_mjcf` changing the
    model) is drawn from the new model; each observation is a new array, safe to keep.
    `composer.vector.PixelVectorEnvironment` gives num_envs of these observations at once
    (`gym.make_vec(id, n, vectorization_mode='vector_entry_point', pixels=True)`), with the
    frame, stacking and checks of this module.
    """

    # Gymnasium reads these from the class; an instance has its environment's.
    metadata = Environment.metadata
    observation_space: spaces.Box | spaces.Dict
    action_space: spaces.Box

    def __init__(
        self,
        env: Environment,
        height: int = DEFAULT_SIZE,
        width: int = DEFAULT_SIZE,
        camera: int | str = -1,
        frame_stack: int = 1,
        proprioception: bool = False,
    ) -> None:
        """Observe `env` (a composer Environment, whose observations must be one Box when
        `proprioception`) through `camera` (an id, -1 for the free camera, or a name).
        Raises TaskError for a size or stack that is not a positive int, a camera the model
        does not have, or proprioception of an environment whose observations are a Dict."""
        for label, value in (("height", height), ("width", width), ("frame_stack", frame_stack)):
            check_positive(label, value)
        if not isinstance(env, Environment):
            raise errors.TaskError(f"PixelEnvironment serves a composer.Environment, got {env!r}")
        check_camera(env.physics.model, camera)
        if proprioception and not isinstance(env.observation_space, spaces.Box):
            raise errors.TaskError(
                "proprioception=True needs the task's observations flattened into one Box: "
                "make the environment with flatten_observations=True"
            )
        self._env = env
        self._size = (int(height), int(width))
        self._camera = camera
        self._stack = int(frame_stack)
        self._proprioception = bool(proprioception)
        self.observation_space = observation_space(
            self._size, self._stack, env.observation_space if self._proprioception else None
        )
        self.action_space = env.action_space
        self.metadata = env.metadata
        self.render_mode = env.render_mode
        self._frames = np.zeros((*self._size, 3 * self._stack), dtype=np.uint8)

    @property
    def environment(self) -> Environment:
        """The composer Environment observed."""
        return self._env

    @property
    def physics(self) -> Any:
        """The environment's `mjcf.Physics`."""
        return self._env.physics

    @property
    def task(self) -> Any:
        """The environment's task."""
        return self._env.task

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        """Reset the environment (`seed` seeds it); every stacked slot holds the first
        frame. Returns (obs, info); raises what Environment.reset raises."""
        super().reset(seed=seed)
        state, info = self._env.reset(seed=seed, options=options)
        self._frames[:] = stacked(self._frame(), self._stack)
        return self._observation(state), info

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        """Step the environment; the new frame enters the stack as its last three channels.
        Raises what Environment.step raises."""
        state, reward, terminated, truncated, info = self._env.step(action)
        push(self._frames, self._frame())
        return self._observation(state), reward, terminated, truncated, info

    # Gymnasium 1.2's Env.render returns a type variable no override can name.
    def render(self) -> np.ndarray | None:  # type: ignore[override, unused-ignore]
        """The environment's `render()` frame (its render mode, size and camera)."""
        return self._env.render()

    def close(self) -> None:
        """Free the environment's rendering resources; safe to call more than once."""
        self._env.close()

    def _frame(self) -> np.ndarray:
        return frame(self._env.physics, self._size, self._camera)

    def _observation(self, state: Any) -> Any:
        pixels = self._frames.copy()
        if self._proprioception:
            return {"pixels": pixels, "proprioception": state}
        return pixels


class CameraError(errors.TaskError):
    """A camera the model does not have, or not an id or name."""


def observation_space(
    size: tuple[int, int], frame_stack: int, proprioception: spaces.Space | None
) -> spaces.Box | spaces.Dict:
    """The pixel observations' space: `frame_stack` RGB frames of `size` stacked along the
    channels, alone or (with the task's `proprioception` space) in a Dict."""
    pixels = spaces.Box(0, 255, (*size, 3 * frame_stack), dtype=np.uint8)
    if proprioception is None:
        return pixels
    return spaces.Dict({"pixels": pixels, "proprioception": proprioception})


def frame(physics: Any, size: tuple[int, int], camera: int | str) -> np.ndarray:
    """A pixel observation's frame: (height, width, 3) uint8 of `camera` in `physics` (an
    `mjcf.Physics`), drawn by its renderer of `size` (height, width). Raises
    mjcf.RenderError when nothing can render."""
    return physics.render(*size, camera_id=camera)


def stacked(first: np.ndarray, frame_stack: int) -> np.ndarray:
    """A reset's stack: `first` ((..., 3) frames) in every one of `frame_stack` slots
    along the channels."""
    return np.tile(first, frame_stack)


def push(stack: np.ndarray, new: np.ndarray) -> None:
    """Enter `new` ((..., 3) frames) into `stack` ((..., 3 * k), in place) as its last
    three channels; the oldest frame leaves."""
    stack[..., :-3] = stack[..., 3:]
    stack[..., -3:] = new


def check_camera(model: Any, camera: int | str) -> None:
    """Raise CameraError (a TaskError) unless `model` (an MjModel) has `camera`: a name,
    or an id from -1 (the free camera) to ncam - 1."""
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_CAMERA, i) for i in range(model.ncam)]
    if isinstance(camera, str):
        if camera not in names:
            raise CameraError(f"the model has no camera named {camera!r}; it has {names}")
        return
    if isinstance(camera, bool) or not isinstance(camera, int | np.integer):
        raise CameraError(f"a camera is an id (int) or a name (str), got {camera!r}")
    if not -1 <= camera < model.ncam:
        raise CameraError(
            f"camera id {camera} is out of range: the model has {model.ncam} camera(s) "
            f"{names}, and -1 is the free camera"
        )


def check_positive(label: str, value: Any) -> None:
    """Raise TaskError unless `value` is a positive int (`label` names it)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise errors.TaskError(f"{label} must be a positive int, got {value!r}")
