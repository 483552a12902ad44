"""PixelVectorEnvironment: num_envs environments of one task observed through a camera, the
observations of num_envs `composer.pixels.PixelEnvironment`s in one VectorEnvironment.

    venv = PixelVectorEnvironment(Swing, 16, height=64, width=64, frame_stack=3)
    obs, info = venv.reset(seed=0)            # (16, 64, 64, 9) uint8
    vec = gym.make_vec('composer/CartpoleSwingup-v0', num_envs=16,
                       vectorization_mode='vector_entry_point', pixels=True)

Promise: the same frames, bit for bit, as num_envs PixelEnvironments in Gymnasium's
`SyncVectorEnv` with the same seeds, actions and autoreset mode.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from composer import errors
from composer.pixels import (
    DEFAULT_SIZE,
    check_camera,
    check_positive,
    frame,
    observation_space,
    push,
    stacked,
)
from composer.task import Task
from composer.vector.environment import VectorEnvironment


class PixelVectorEnvironment(VectorEnvironment):
    """A VectorEnvironment whose observations are camera frames; its other results,
    `render()` and `environments` are VectorEnvironment's.

    Each environment's frame is drawn by its own physics' renderer (`composer.pixels.frame`,
    what a PixelEnvironment draws), every environment's on the render threads at once
    (`composer.vector.rendering`), after the control step (or reset) it is returned by; stacks
    and spaces are PixelEnvironment's with a leading environment axis. The same seeds and
    actions give the same frames, bit for bit, as num_envs PixelEnvironments in Gymnasium's
    `SyncVectorEnv` with the same autoreset mode: an environment reset (NEXT_STEP's step after
    its end, SAME_STEP's step that ends it, a `reset_mask`) holds its first frame in every
    slot, and SAME_STEP's info['final_obs'] holds the stack with the last frame.
    """

    def __init__(
        self,
        task_factory: Callable[[], Task],
        num_envs: int,
        *,
        height: int = DEFAULT_SIZE,
        width: int = DEFAULT_SIZE,
        camera: int | str | None = None,
        frame_stack: int = 1,
        proprioception: bool = False,
        **options: Any,
    ) -> None:
        """Observe num_envs `task_factory()`s through `camera` (an id, -1 for the free
        camera, or a name; None: the task's `render_camera`, else the free camera) with
        PixelEnvironment's options; `options` are VectorEnvironment's (with
        `proprioception`, `flatten_observations` is True). Raises TaskError as
        PixelEnvironment does, and what VectorEnvironment raises."""
        for label, value in (("height", height), ("width", width), ("frame_stack", frame_stack)):
            check_positive(label, value)
        if proprioception:
            options["flatten_observations"] = True
        super().__init__(task_factory, num_envs, **options)
        first = self.environments[0]
        if camera is None:
            camera = getattr(first.task, "render_camera", -1)
        try:
            check_camera(first.physics.model, camera)
        except errors.TaskError:
            self.close()
            raise
        self._size = (int(height), int(width))
        self._camera = camera
        self._stack = int(frame_stack)
        self._proprioception = bool(proprioception)
        state_space = self.single_observation_space
        self.single_observation_space = observation_space(
            self._size, self._stack, state_space if self._proprioception else None
        )
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self._frames = np.zeros((num_envs, *self._size, 3 * self._stack), dtype=np.uint8)

    def reset(
        self, *, seed: Any = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        """VectorEnvironment's reset; every stacked slot of an environment reset holds
        its first frame. Raises what VectorEnvironment.reset raises."""
        state, info = super().reset(seed=seed, options=options)
        mask = (options or {}).get("reset_mask")
        ids = np.arange(self.num_envs) if mask is None else np.flatnonzero(mask)
        self._frames[ids] = stacked(self._draw_frames(ids), self._stack)
        return self._observation(state), info

    def step(self, actions: Any) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict]:
        """VectorEnvironment's step; each environment's new frame enters its stack, or
        fills it when the environment was reset. Raises what VectorEnvironment.step
        raises."""
        reset_first = self._over.copy()
        state, rewards, terminated, truncated, info = super().step(actions)
        if self.autoreset_mode is AutoresetMode.SAME_STEP:
            reset = terminated | truncated
        elif self.autoreset_mode is AutoresetMode.NEXT_STEP:
            reset = reset_first
        else:
            reset = np.zeros(self.num_envs, dtype=bool)
        frames = self._draw_frames(np.arange(self.num_envs))
        if reset.any():
            self._frames[reset] = stacked(frames[reset], self._stack)
            kept = ~reset
            stack = self._frames[kept]
            push(stack, frames[kept])
            self._frames[kept] = stack
        else:
            push(self._frames, frames)
        return self._observation(state), rewards, terminated, truncated, info

    def _final_observations(self, ended: np.ndarray) -> list[Any]:
        """SAME_STEP: each ended environment's stack with its last frame, before reset."""
        states = super()._final_observations(ended)
        stacks = self._frames[ended]
        push(stacks, self._draw_frames(ended))
        return [self._one(stack, state) for stack, state in zip(stacks, states, strict=True)]

    def _draw_frames(self, ids: np.ndarray) -> np.ndarray:
        """The current frame of environments `ids`: (len(ids), height, width, 3)."""
        envs, size, camera = self.environments, self._size, self._camera
        return np.stack(self.draw(ids, lambda i: frame(envs[i].physics, size, camera)))

    def _one(self, pixels: np.ndarray, state: Any) -> Any:
        if self._proprioception:
            return {"pixels": pixels, "proprioception": state}
        return pixels

    def _observation(self, state: Any) -> Any:
        return self._one(self._frames.copy(), state)
