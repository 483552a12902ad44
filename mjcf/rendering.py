"""Rendering a physics: an offscreen `mujoco.Renderer` per image size, and errors that say
which system library is missing when no OpenGL context can be made.

    renderer = rendering.make_renderer(model, 240, 320)     # RenderError if no backend
    rgb = rendering.render(renderer, data, camera_id=-1, depth=False, segmentation=False)

`mjcf.Physics.render` keeps one renderer per size and calls these.
"""

from __future__ import annotations

import ctypes.util
import os
import platform

import mujoco
import numpy as np

from mjcf import errors


def make_renderer(model: mujoco.MjModel, height: int, width: int) -> mujoco.Renderer:
    """An offscreen renderer of `height` x `width`; raises RenderError when the size exceeds
    the model's framebuffer or no OpenGL backend can be created (naming the fix)."""
    try:
        return mujoco.Renderer(model, height, width)
    except ValueError as e:  # larger than the model's offscreen framebuffer
        raise errors.RenderError(str(e)) from e
    except (ImportError, OSError, RuntimeError, AttributeError, mujoco.FatalError) as e:
        raise errors.RenderError(_no_backend_message(e)) from e


def render(
    renderer: mujoco.Renderer,
    data: mujoco.MjData,
    camera_id: int | str,
    depth: bool,
    segmentation: bool,
    scene_option: mujoco.MjvOption | None,
) -> np.ndarray:
    """An image of `data`: (h, w, 3) uint8 RGB, (h, w) float depth, or (h, w, 2) int32
    segmentation; raises RenderError for a camera the model does not have."""
    try:
        renderer.update_scene(data, camera=camera_id, scene_option=scene_option)
    except ValueError as e:
        raise errors.RenderError(f"cannot render camera {camera_id!r}: {e}") from e
    if depth:
        renderer.enable_depth_rendering()
    elif segmentation:
        renderer.enable_segmentation_rendering()
    try:
        return renderer.render()
    finally:
        renderer.disable_depth_rendering()
        renderer.disable_segmentation_rendering()


# The system library each MUJOCO_GL backend loads, and the Debian/Ubuntu packages providing it.
_BACKEND_LIBRARIES = {
    "egl": ("EGL", "libEGL.so.1", "libegl1 libegl-mesa0 libgl1"),
    "osmesa": ("OSMesa", "libOSMesa.so", "libosmesa6"),
    "glfw": ("GL", "libGL.so.1", "libgl1 libglfw3"),
}


def _no_backend_message(cause: BaseException) -> str:
    """Why no OpenGL context could be made, naming the missing library and the fix."""
    backend = os.environ.get("MUJOCO_GL", "").strip().lower() or "glfw"
    lib, soname, packages = _BACKEND_LIBRARIES.get(backend, _BACKEND_LIBRARIES["glfw"])
    if ctypes.util.find_library(lib) is None:
        reason = f"{soname} is not installed (apt-get install {packages})"
    elif backend == "glfw" and platform.system() == "Linux" and not os.environ.get("DISPLAY"):
        reason = "GLFW needs a display and $DISPLAY is not set"
    else:
        reason = f"{type(cause).__name__}: {cause}"
    return (
        f"no OpenGL backend could be created with MUJOCO_GL={backend!r}: {reason}. "
        "For headless rendering set MUJOCO_GL=egl (apt-get install libegl1 libegl-mesa0 "
        "libgl1) or MUJOCO_GL=osmesa (apt-get install libosmesa6) before Python imports "
        "mujoco."
    )
