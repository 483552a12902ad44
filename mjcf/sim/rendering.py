"""Rendering a physics offscreen: a `mujoco.Renderer` per image size, on an OpenGL backend
chosen once per process, settings fitted to the size, errors naming the missing library.

    renderer = rendering.make_renderer(model, 240, 320)     # RenderError if no backend
    rgb = rendering.render(renderer, data, camera_id=-1, depth=False, segmentation=False)
    with rendering.context_group(key): physics.render(64, 64)  # one OpenGL context for many

It works without a display or MUJOCO_GL (`backend`); small images are drawn cheaply, the
model never changed (`frame_settings`); renderers draw from threads (`threaded`). A context
that cannot be made is a RenderError at every attempt, never the abort MuJoCo itself makes.
"""

from __future__ import annotations

import ctypes.util
import importlib
import os
import platform
import re
import sys
import threading
import warnings
from collections.abc import Hashable, Iterator
from contextlib import contextmanager
from typing import Any

import mujoco
import numpy as np
from lxml import etree

from mjcf import errors
from mjcf.sim import render_meshes


def make_renderer(
    model: mujoco.MjModel, height: int, width: int, mjcf_xml: str | None = None
) -> mujoco.Renderer:
    """An offscreen renderer of `height` x `width` on `backend()`, with `frame_settings` in
    place of the render settings `model` leaves to MuJoCo's defaults (`mjcf_xml`: the MJCF
    text it was compiled from, which says which it sets; None: a value other than MuJoCo's
    default counts as set). Raises RenderError when the size exceeds a framebuffer the model
    sets or the OpenGL implementation can make, or no OpenGL context can be made (naming
    the fix)."""
    name = backend()
    chosen = fitted_settings(model, height, width, mjcf_xml)
    budget = render_meshes.face_budget(height, width) if _small(height, width) else None
    drawn = None if budget is None else render_meshes.simplified(model, budget)
    try:
        if drawn is not None:
            with _swapped(drawn, chosen):
                renderer: _Renderer = _SimplifiedRenderer(model, drawn, height, width)
        else:
            with _settings_lock, _swapped(model, chosen):
                renderer = _Renderer(model, height, width)
        renderer._drawn_in = threading.current_thread()  # its context is current here
        return renderer
    except ValueError as e:  # larger than the model's offscreen framebuffer
        raise errors.RenderError(str(e)) from e
    except _NoContextError as e:
        raise errors.RenderError(_explicit_failure(name, str(e))) from e
    except mujoco.FatalError as e:
        if _INCOMPLETE_FRAMEBUFFER not in str(e):
            raise errors.RenderError(_explicit_failure(name, f"FatalError: {e}")) from e
        samples = chosen.get("quality.offsamples", _read(model, "quality.offsamples"))
        raise errors.RenderError(_framebuffer_failure(name, height, width, samples, e)) from e
    except (ImportError, OSError, RuntimeError, AttributeError) as e:
        raise errors.RenderError(_explicit_failure(name, f"{type(e).__name__}: {e}")) from e


def frame_settings(height: int, width: int) -> dict[str, int]:
    """The render settings for an image of `height` x `width`, by `<visual>` child and
    attribute ('quality.shadowsize').

    Each renderer gets them in place of what the model leaves to MuJoCo's defaults: an
    offscreen buffer of the image's size (any size renders), and for images up to
    SMALL_FRAME pixels a side (observations) no shadows, no multisampling, meshes
    simplified to at most 8 triangles a pixel (`mjcf.sim.render_meshes`); larger images
    are drawn as MuJoCo draws them. What the model's MJCF sets is kept, and the model is
    never changed. Why (the costs measured): docs/performance_profile.md, "Costs behind
    choices"."""
    settings = {"global.offwidth": int(width), "global.offheight": int(height)}
    if _small(height, width):
        settings.update({"quality.shadowsize": 0, "quality.offsamples": 0})
    return settings


def fitted_settings(
    model: mujoco.MjModel, height: int, width: int, mjcf_xml: str | None = None
) -> dict[str, int]:
    """The `frame_settings` of this size that `model` leaves unset (see `make_renderer`),
    to be used in place of its values."""
    if mjcf_xml is None:
        given = {key for key in _MUJOCO_DEFAULTS if _read(model, key) != _MUJOCO_DEFAULTS[key]}
    else:
        given = set(visual_settings_given(mjcf_xml))
    return {k: v for k, v in frame_settings(height, width).items() if k not in given}


def visual_settings_given(mjcf_xml: str) -> frozenset[str]:
    """The `<visual>` settings MJCF text gives ('quality.shadowsize', 'global.offwidth' ...)."""
    found = _VISUAL.search(mjcf_xml)
    if found is None:
        return frozenset()
    section = etree.fromstring(found.group(0).encode("utf-8"))
    return frozenset(
        f"{child.tag}.{attribute}"
        for child in section
        if isinstance(child.tag, str)
        for attribute in child.attrib
    )


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
        if isinstance(renderer, _Renderer):
            renderer.select_buffers()
        frame = renderer.render()
    except (RuntimeError, _opengl_error()) as e:  # its context cannot be made current here
        drew = getattr(renderer, "_drawn_in", None)  # a _Renderer's
        here = threading.current_thread()
        if drew is not None and drew is not here:
            raise ContextBusyError(
                f"cannot draw in thread {here.name!r} with a renderer thread {drew.name!r} drew "
                f"with, whose OpenGL context is current there ({type(e).__name__}); "
                "mjcf.Physics.render draws with a renderer of the thread's own"
            ) from e
        raise errors.RenderError(f"cannot draw: {type(e).__name__}: {e}") from e
    finally:
        renderer.disable_depth_rendering()
        renderer.disable_segmentation_rendering()
    if isinstance(renderer, _Renderer):
        renderer._drawn_in = threading.current_thread()
    return frame


class ContextBusyError(errors.RenderError):
    """A renderer's OpenGL context is current in the thread that drew with it last, and an
    EGL context is current in one thread at a time: another thread cannot draw with it
    until that thread calls `release_context()` (`mjcf.Physics.render` then draws with a
    renderer of the calling thread's own)."""


def _opengl_error() -> type[BaseException]:
    """PyOpenGL's base error (EGL's errors are of it), or RuntimeError without it."""
    module = sys.modules.get("OpenGL.error")
    return getattr(module, "Error", RuntimeError)


def close(renderer: mujoco.Renderer) -> None:
    """Free `renderer`'s OpenGL resources. A renderer whose context another thread holds (one
    that drew with it last and did not `release_context()`, perhaps ended since) cannot be
    freed from this thread: it is kept, unused, until the process ends, rather than raise."""
    try:
        renderer.close()
    except (RuntimeError, _opengl_error()):
        if not isinstance(renderer, _Renderer):
            raise
        renderer.abandon()


def release_context() -> None:
    """Make no OpenGL context current in the calling thread, so that another thread can
    draw with the renderers this one used last (a context is current in one thread at a
    time, and `mujoco.Renderer` leaves its own current after each frame). Only EGL's
    contexts move between threads here: other backends render in one thread, and this does
    nothing for them."""
    if _chosen != "egl":
        return
    egl = importlib.import_module("mujoco.egl")
    if egl.EGL_DISPLAY is not None and egl.EGL.eglGetCurrentContext():
        no_surface = egl.EGL.EGL_NO_SURFACE
        egl.EGL.eglMakeCurrent(egl.EGL_DISPLAY, no_surface, no_surface, egl.EGL.EGL_NO_CONTEXT)


@contextmanager
def context_group(key: Hashable | None) -> Iterator[None]:
    """Renderers made in this block, in this thread, share one OpenGL context with every
    renderer made in group `key` (None: each its own, as outside any group), on EGL; on
    other backends each keeps its own. A new OpenGL context costs 150 ms and 20 MB on
    Mesa's software rasterizer (its shaders are compiled in each), a renderer in one made
    already 7 ms; and drawing with a context other than the last one drawn with costs
    about a quarter more. Each renderer keeps its own buffers and assets in the shared
    context (drawn with pixel for pixel the frames of a context of its own). A group's
    renderers are drawn in one thread at a time, `release_context()` between threads."""
    previous = getattr(_group, "key", None)
    _group.key = key
    try:
        yield
    finally:
        _group.key = previous


def threaded() -> bool:
    """Whether renderers may draw from several threads, one renderer in one thread at a
    time (`release_context` between): on EGL, whose contexts each thread makes current on
    its own. Raises RenderError as `backend()`.

    Renderers of different physics draw at once from threads of their own (MuJoCo releases
    the GIL); on EGL a thread calls `release_context()` when it has drawn; renderers made
    inside `context_group(key)` share one OpenGL context. A thread that draws with a
    renderer whose context another thread holds gets `ContextBusyError` (a RenderError),
    and `mjcf.Physics.render` then makes that thread a renderer of its own: an environment
    renders from any thread."""
    return backend() == "egl"


def backend() -> str:
    """The OpenGL backend renderers use ('egl', 'osmesa', 'glfw', 'cgl'), chosen at the first
    call: MUJOCO_GL's when set; else the first that works at the first renderer (Linux: EGL,
    OSMesa, then GLFW with a display; macOS: CGL, GLFW; Windows: GLFW), which becomes
    MuJoCo's own and child processes'. Rendering works without a display or MUJOCO_GL.
    Raises RenderError, naming what each backend lacks, when none can make a context (then,
    and at every later call)."""
    global _chosen, _failure
    with _lock:
        if _chosen is None and _failure is None:
            try:
                _chosen = _choose()
            except errors.RenderError as e:
                _failure = str(e)
        if _failure is not None:
            raise errors.RenderError(_failure)
        assert _chosen is not None
        return _chosen


# MUJOCO_GL values, as MuJoCo reads them: rendering turned off, and the names of GLFW.
_OFF = ("disable", "disabled", "off", "false", "0")
_GLFW_NAMES = ("glfw", "glx", "wgl", "enable", "enabled", "on", "true", "1")
# The module of each backend's context class in the mujoco package.
_MODULES = {"egl": "mujoco.egl", "osmesa": "mujoco.osmesa", "glfw": "mujoco.glfw",
            "cgl": "mujoco.cgl"}  # fmt: skip
# The system library each backend loads on Linux, and the Debian/Ubuntu packages with it.
_LIBRARIES = {
    "egl": ("EGL", "libEGL.so.1", "libegl1 libegl-mesa0 libgl1"),
    "osmesa": ("OSMesa", "libOSMesa.so", "libosmesa6"),
    "glfw": ("GL", "libGL.so.1", "libgl1 libglfw3"),
}
_HEADLESS_FIX = (
    "For rendering without a display install EGL (apt-get install libegl1 libegl-mesa0 "
    "libgl1) or OSMesa (apt-get install libosmesa6)"
)

_lock = threading.Lock()
# Images up to this many pixels a side render without shadows and multisampling.
SMALL_FRAME = 128
# MuJoCo's defaults of the settings frame_settings gives (mjVisual's, in a compiled model).
_MUJOCO_DEFAULTS = {
    "quality.shadowsize": 4096,
    "quality.offsamples": 4,
    "global.offwidth": 640,
    "global.offheight": 480,
}
# The `<visual>` section of MJCF text (a top-level section: the one element of that name).
_VISUAL = re.compile(r"<visual\b(?:[^>]*/>|.*?</visual>)", re.DOTALL)
# Held while a model's settings are swapped: two renderers made at once see their own.
_settings_lock = threading.Lock()
# Freed EGL contexts kept for the next renderers, by context class (see _egl_reuse).
_IDLE_CONTEXTS = 4
_idle_contexts: dict[type, list[Any]] = {}
_handed_out: set[int] = set()  # ids of kept contexts __new__ returned, __init__ not yet run
_idle_lock = threading.Lock()
_chosen: str | None = None
_failure: str | None = None
# Context groups (`context_group`): this thread's group, each group's shared EGL context by
# (context class, key), and how many renderers draw with each shared context, by its id.
_group = threading.local()
_group_contexts: dict[tuple[type, Hashable], Any] = {}
_group_users: dict[int, int] = {}
# The render and OpenGL contexts of renderers whose contexts other threads hold, which
# `close` could not free.
_abandoned: list[tuple[Any, Any]] = []


class _Renderer(mujoco.Renderer):
    """A mujoco.Renderer that may share its OpenGL context with others (`context_group`),
    and knows the thread that drew with it last (`_drawn_in`), where its context is current
    unless that thread released it."""

    _drawn_in: threading.Thread | None = None

    def __init__(self, model: mujoco.MjModel, height: int, width: int) -> None:
        try:
            super().__init__(model, height, width)
        except BaseException:
            # MuJoCo does not free what it made in the OpenGL context before failing to make
            # its render context there (a 10,000 x 10,000 framebuffer's buffers hold 1.5 GB
            # on Mesa): the context is destroyed, never kept for reuse, which frees them.
            if self._gl_context is not None and self._mjr_context is None:
                self._gl_context.spoiled = True
                self.close()
            raise

    def abandon(self) -> None:
        """Keep this renderer's contexts unfreed until the process ends (another thread
        holds its OpenGL context, so they cannot be freed from this one), and empty it, so
        that its __del__ does not try again (a GLContext here frees nothing by itself)."""
        contexts: tuple[Any, Any] = (self._mjr_context, self._gl_context)  # type: ignore[has-type]
        _abandoned.append(contexts)
        self._mjr_context = self._gl_context = None

    def select_buffers(self) -> None:
        """Before a frame: when its context holds other renderers' buffers too, make it
        current and this renderer's offscreen buffers the ones drawn into (MuJoCo selects
        them only when it makes its render context)."""
        context = self._gl_context
        if context is not None and id(context) in _group_users:
            context.make_current()
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr_context)


def _small(height: int, width: int) -> bool:
    """Whether an image of this size is drawn without shadows, multisampling and full meshes."""
    return max(int(height), int(width)) <= SMALL_FRAME


class _SimplifiedRenderer(_Renderer):
    """A renderer whose context holds `drawn`'s simplified meshes (see mjcf.sim.render_meshes)
    while its scenes are built from `model`, so what is written to `model` at run time shows.
    `drawn` is not kept."""

    def __init__(self, model: mujoco.MjModel, drawn: mujoco.MjModel, height: int, width: int):
        super().__init__(drawn, height, width)
        self._model = model  # mujoco.Renderer builds each scene from its _model


class _NoContextError(RuntimeError):
    """A backend's context class made no OpenGL context (GLFW without a display)."""


def _choose() -> str:
    """The backend MUJOCO_GL names, else the first of this system's that makes a context;
    installs it as MuJoCo's. Raises RenderError."""
    explicit = os.environ.get("MUJOCO_GL", "").strip().lower()
    if explicit in _OFF:
        raise errors.RenderError(f"rendering is turned off: MUJOCO_GL={explicit!r}")
    if explicit:
        name = "glfw" if explicit in _GLFW_NAMES else explicit
        if name not in _MODULES:
            raise errors.RenderError(
                f"MUJOCO_GL={explicit!r} names no OpenGL backend; use one of "
                f"{sorted(set(_MODULES) | {'glfw'})}, or unset it to choose one that works"
            )
        try:
            _install(name)
        except _NoContextError as e:
            raise errors.RenderError(_explicit_failure(name, str(e))) from e
        return name
    failures = []
    for name in _candidates():
        try:
            _install(name)
        except _NoContextError as e:
            failures.append(f"{name.upper()}: {e}")
            continue
        os.environ["MUJOCO_GL"] = name  # child processes render with it too
        return name
    raise errors.RenderError(
        f"no OpenGL backend can render here ({'; '.join(failures)}). {_HEADLESS_FIX}, or "
        "run with a display."
    )


def _candidates() -> list[str]:
    """The backends to try, in order, when MUJOCO_GL is not set."""
    system = platform.system()
    if system == "Darwin":
        return ["cgl", "glfw"]
    if system != "Linux":
        return ["glfw"]
    display = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    return ["egl", "osmesa", *(["glfw"] if display else [])]


def _install(name: str) -> None:
    """Make one context of backend `name` to check it works, then have `mujoco.Renderer`
    make its contexts with it (checked each time); raises _NoContextError saying why not."""
    checked = _checked_context_class(name)
    with warnings.catch_warnings(record=True) as caught:  # GLFW reports errors as warnings
        warnings.simplefilter("always")
        try:
            probe = checked(1, 1)
            probe.make_current()
        except _NoContextError as e:
            details = "; ".join(str(w.message) for w in caught)
            raise _NoContextError(_glfw_reason(details) if name == "glfw" else str(e)) from e
        except Exception as e:  # each backend fails its own way (ImportError, GLError ...)
            raise _NoContextError(f"{type(e).__name__}: {e}") from e
    probe.free()
    _renderer_gl_module().GLContext = checked


def _checked_context_class(name: str) -> type:
    """Backend `name`'s context class, made to raise _NoContextError when it creates no
    context; raises _NoContextError when its library or module cannot be loaded."""
    library = _LIBRARIES.get(name) if platform.system() == "Linux" else None
    if library is not None and ctypes.util.find_library(library[0]) is None:
        raise _NoContextError(f"{library[1]} is not installed (apt-get install {library[2]})")
    try:
        base = importlib.import_module(_MODULES[name]).GLContext
    except Exception as e:  # ImportError, OSError; PyOpenGL raises others for a bad library
        raise _NoContextError(f"{type(e).__name__}: {e}") from e

    def __init__(self: Any, max_width: int, max_height: int) -> None:
        if id(self) in _handed_out:  # a kept or shared context: made already
            _handed_out.discard(id(self))
        else:
            base.__init__(self, max_width, max_height)
            if not getattr(self, "_context", True):
                raise _NoContextError(f"{name.upper()} made no OpenGL context")
        if name == "egl":
            _join_group(self)

    methods: dict[str, Any] = {"__init__": __init__, "backend": name}
    if name == "egl":
        methods.update(_egl_reuse(base))
    return type(f"Checked{base.__name__}", (base,), methods)


def _egl_reuse(base: type) -> dict[str, Any]:
    """`__new__` and `free` that keep up to _IDLE_CONTEXTS freed EGL contexts and hand them
    to the next renderers: MuJoCo's first render context in an OpenGL context costs 120-140
    ms on Mesa's software rasterizer (its shaders are compiled then), a later one 7 ms, so a
    renderer made after a recompile costs 10 ms instead of 150. An EGL context has no size
    and keeps no MuJoCo state once its renderer freed its render context; one marked
    `spoiled` (a render context failed in it) is destroyed instead."""
    egl = importlib.import_module("mujoco.egl")

    def __new__(cls: type, max_width: int, max_height: int) -> Any:
        key = getattr(_group, "key", None)
        with _idle_lock:
            shared = None if key is None else _group_contexts.get((cls, key))
            if shared is not None:
                _group_users[id(shared)] += 1
                _handed_out.add(id(shared))
                return shared
            idle = _idle_contexts.get(cls)
            if idle:
                context = idle.pop()
                _handed_out.add(id(context))
                return context
        return object.__new__(cls)

    def free(self: Any) -> None:
        with _idle_lock:
            users = _group_users.pop(id(self), 0)
            if users > 1:  # other renderers draw with it still
                _group_users[id(self)] = users - 1
                return
            for slot in [slot for slot, shared in _group_contexts.items() if shared is self]:
                del _group_contexts[slot]
        context = getattr(self, "_context", None)
        if context and egl.EGL_DISPLAY is not None and not getattr(self, "spoiled", False):
            with _idle_lock:
                idle = _idle_contexts.setdefault(type(self), [])
                if len(idle) < _IDLE_CONTEXTS:
                    current = egl.EGL.eglGetCurrentContext()
                    if current and current.address == context.address:
                        no_surface = egl.EGL.EGL_NO_SURFACE
                        egl.EGL.eglMakeCurrent(
                            egl.EGL_DISPLAY, no_surface, no_surface, egl.EGL.EGL_NO_CONTEXT
                        )
                    idle.append(self)
                    return
        base.free(self)  # type: ignore[attr-defined]

    return {"__new__": __new__, "free": free}


def _join_group(context: Any) -> None:
    """Make `context`, just handed to a renderer, its context group's shared context when
    the group (`context_group`) has none yet."""
    key = getattr(_group, "key", None)
    if key is None:
        return
    with _idle_lock:
        slot = (type(context), key)
        if slot not in _group_contexts:
            _group_contexts[slot] = context
            _group_users[id(context)] = 1


def _renderer_gl_module() -> Any:
    """The module whose `GLContext` `mujoco.Renderer` makes its contexts with."""
    return sys.modules[mujoco.Renderer.__module__].gl_context


def _glfw_reason(details: str) -> str:
    if platform.system() == "Linux" and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        return "GLFW needs a display and $DISPLAY is not set"
    return details or "GLFW made no OpenGL context"


# What MuJoCo's FatalError says when OpenGL made a context but not the frame's buffers.
_INCOMPLETE_FRAMEBUFFER = "Offscreen framebuffer is not complete"


def _framebuffer_failure(
    name: str, height: int, width: int, samples: int, error: mujoco.FatalError
) -> str:
    """Why a frame of `height` x `width` drawn with `samples` multisamples got no buffers
    (the context itself was made: the backend is not at fault)."""
    multisampled = (
        f" Drawn with {samples} samples a pixel (`<visual><quality offsamples>`), a frame "
        "needs that many times the memory of one: offsamples=\"0\" draws larger ones."
        if samples > 0 else ""
    )  # fmt: skip
    return (
        f"a frame of {height} x {width} pixels (height x width) cannot be drawn with "
        f"MUJOCO_GL={name!r}: its OpenGL implementation made no offscreen framebuffer that "
        f"large (MuJoCo: {error}). Each side can be at most the implementation's "
        f"GL_MAX_RENDERBUFFER_SIZE (16384 on Mesa); render a smaller frame.{multisampled}"
    )


def _explicit_failure(name: str, reason: str) -> str:
    """Why the backend MUJOCO_GL (or the automatic choice) names cannot make a context."""
    return (
        f"no OpenGL context could be made with MUJOCO_GL={name!r}: {reason}. Unset MUJOCO_GL "
        f"to use the first backend that works. {_HEADLESS_FIX}."
    )


def _section(model: mujoco.MjModel, key: str) -> tuple[Any, str]:
    child, attribute = key.split(".")
    return getattr(model.vis, "global_" if child == "global" else child), attribute


def _read(model: mujoco.MjModel, key: str) -> int:
    section, attribute = _section(model, key)
    return int(getattr(section, attribute))


@contextmanager
def _swapped(model: mujoco.MjModel, settings: dict[str, int]) -> Iterator[None]:
    """`model` with `settings` in place of its own until the block ends."""
    saved = {key: _read(model, key) for key in settings}
    try:
        for key, value in settings.items():
            section, attribute = _section(model, key)
            setattr(section, attribute, value)
        yield
    finally:
        for key, value in saved.items():
            section, attribute = _section(model, key)
            setattr(section, attribute, value)
