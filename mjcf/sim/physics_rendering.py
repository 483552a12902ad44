"""How a physics draws its current state: a renderer per image size (and per thread that
found another's OpenGL context busy), kept until `close()`.

    frame = physics.render(240, 320, camera_id="side")     # (240, 320, 3) uint8
    depth = physics.render(240, 320, depth=True)           # (240, 320) float, meters
    physics.close()                                        # free the OpenGL resources

`Rendering` is a base of `mjcf.Physics`, which inherits these methods; the backends, contexts
and scene settings are `mjcf.sim.rendering`'s.
"""

from __future__ import annotations

import threading
from typing import Any

import mujoco
import numpy as np

from mjcf.sim import rendering
from mjcf.sim.binding import POS_BEHIND, BoundPhysics


class Rendering(BoundPhysics):
    """The rendering of `mjcf.Physics` (see `render`); a base of Physics, not used alone.
    Physics keeps the renderers in `_renderers` (see `Physics._attach`)."""

    _renderers: dict[tuple[Any, ...], mujoco.Renderer]

    def render(
        self,
        height: int = 240,
        width: int = 320,
        camera_id: int | str = -1,
        depth: bool = False,
        segmentation: bool = False,
        scene_option: mujoco.MjvOption | None = None,
    ) -> np.ndarray:
        """An image of the current state: (h, w, 3) uint8 RGB, (h, w) float depth in meters,
        or (h, w, 2) int32 segmentation (object id, object type).

        camera_id -1 is the free camera; a camera id or name picks a model camera. Any
        thread may render: one that finds the renderer's OpenGL context held by another
        thread (which drew last and did not `mjcf.sim.rendering.release_context()`) draws with
        a renderer of its own, kept until `close()`. Raises RenderError when no OpenGL
        backend can be created or the request is invalid.
        """
        if self._stale & POS_BEHIND:
            self._refresh()  # a picture of the state written, not of the one before
        size = (int(height), int(width))
        own = (size, threading.get_ident())  # a renderer this thread made for itself
        renderer = self._renderers.get(own)
        if renderer is None:
            renderer = self._renderers.get(size)
            if renderer is None:
                renderer = self._renderers[size] = self._renderer(size)
            try:
                return rendering.render(
                    renderer, self._data, camera_id, depth, segmentation, scene_option
                )
            except rendering.ContextBusyError:
                # Its context is current in the thread that drew last (EGL's are current in
                # one thread at a time): this thread draws with a renderer of its own.
                renderer = self._renderers[own] = self._renderer(size)
        try:
            return rendering.render(
                renderer, self._data, camera_id, depth, segmentation, scene_option
            )
        finally:
            # Left current, its context would outlive the thread, and no other could free it.
            rendering.release_context()

    def _renderer(self, size: tuple[int, int]) -> mujoco.Renderer:
        compiled = self.__dict__.get("_compiled")
        return rendering.make_renderer(
            self._model, *size, mjcf_xml=None if compiled is None else compiled.xml
        )

    def close(self) -> None:
        """Free the renderers' OpenGL resources; the physics itself stays usable."""
        renderers = self.__dict__.get("_renderers") or {}
        for renderer in renderers.values():
            rendering.close(renderer)
        renderers.clear()
