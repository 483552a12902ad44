"""Physics: one MuJoCo simulation (MjModel + MjData) with bindings, named access and rendering.

    physics = Physics.from_xml_path("humanoid.xml")
    with physics.reset_context():                       # reset, then forward on exit
        physics.named.data.qpos["root"][:3] = [0, 0, 1.4]
    physics.named.model.geom_rgba["floor"] = [1, 0, 0, 1]
    hips = physics.bind_names(mujoco.mjtObj.mjOBJ_JOINT, ["right_hip_x", "right_hip_y"])
    hips.qpos = [0.1, 0.2]                              # live views; see mjcf.binding
    with physics.check_divergence():                    # PhysicsError if MuJoCo gave up
        physics.step(10)
    frame = physics.render(240, 320, camera_id=-1)      # needs MUJOCO_GL=egl when headless
    clone = pickle.loads(pickle.dumps(physics))         # same state, same next steps

`model` and `data` are the raw `mujoco.MjModel` / `MjData`; they stay the same objects for the
life of the physics (reset works in place), so bindings and views stay valid. `copy()` and
unpickling give a physics with its own MjData (and MjModel, unless shared). Subclasses (e.g.
composer's) keep their extra attributes, bindings included, through `copy()` and pickling;
they override nothing to get that, as long as their attributes are picklable.

Stepping does not check for divergence (a check costs about two microseconds): call
`check_invalid_state()` or step inside `check_divergence()` where it matters.
"""

from __future__ import annotations

import contextlib
import copy as copy_module
import ctypes.util
import difflib
import math
import os
import platform
import weakref
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import binding as binding_module
from mjcf import compiler, errors, fields, named, tree_binding

if TYPE_CHECKING:
    from mjcf.element import Element
    from mjcf.root import RootElement

# MuJoCo warnings that mean the state was invalid: non-finite or huge qpos/qvel, bad qacc
# (the solver or integrator diverged; MuJoCo then resets the data itself), bad controls;
# each with the array whose index the warning's lastinfo reports.
_INVALID_STATE_WARNINGS = {
    mujoco.mjtWarning.mjWARN_BADQPOS: "qpos",
    mujoco.mjtWarning.mjWARN_BADQVEL: "qvel",
    mujoco.mjtWarning.mjWARN_BADQACC: "qvel",
    mujoco.mjtWarning.mjWARN_BADCTRL: "ctrl",
}
_INVALID_STATE_IDS = np.array([int(w) for w in _INVALID_STATE_WARNINGS])
_STATE = mujoco.mjtState.mjSTATE_INTEGRATION

# Attributes rebuilt for each MjModel/MjData: never copied between physics nor pickled.
_TRANSIENT = (
    "_model",
    "_data",
    "_warnings",
    "_bindings",
    "_element_bindings",
    "_live_bindings",
    "_named",
    "_renderers",
)
# Attributes a copy shares with its original instead of copying: the model tree a
# physics was compiled from (bind(element) needs the user's own element objects).
_SHARED = ("_compiled",)


class Physics:
    """A MuJoCo simulation: an MjModel, its MjData, and access to both by object and name."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        """Wrap `model` and `data` (a new MjData, forwarded, if None)."""
        if data is None:
            data = mujoco.MjData(model)
            mujoco.mj_forward(model, data)
        self._attach(model, data)

    def _attach(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Hold `model` and `data`, dropping every cache built for the previous ones.

        The one place a physics changes its MjModel/MjData. Bindings made before then read
        the new MjData if the model is the same, else raise BindingError; named views
        re-resolve their indices.
        """
        live = self.__dict__.get("_live_bindings")
        if live is None:
            live = self._live_bindings = weakref.WeakSet()
        for binding in live:
            binding._detach()
        self._model = model
        self._data = data
        self._warnings = data.warning.number  # a live view of MuJoCo's warning counters
        self._bindings: dict[tuple, binding_module.Binding] = {}
        self._element_bindings: dict[object, binding_module.Binding] = {}
        self._named: named.NamedAccess | None = None
        self._renderers: dict[tuple[int, int], mujoco.Renderer] = {}

    # -- construction --------------------------------------------------------------------

    @classmethod
    def from_model(cls, model: mujoco.MjModel) -> Physics:
        """A physics on `model` (not copied) with a new, forwarded MjData."""
        return cls(model)

    @classmethod
    def from_xml_string(
        cls, xml: str | bytes, assets: Mapping[str, bytes] | None = None
    ) -> Physics:
        """Compile MJCF text (assets: {file name: contents}); raises CompileError."""
        if isinstance(xml, bytes):
            xml = xml.decode("utf-8")
        return cls(_compile(mujoco.MjModel.from_xml_string, xml, dict(assets or {})))

    @classmethod
    def from_xml_path(cls, path: str | os.PathLike[str]) -> Physics:
        """Compile the MJCF file at `path`; raises CompileError."""
        return cls(_compile(mujoco.MjModel.from_xml_path, os.fspath(path), None))

    @classmethod
    def from_binary_path(cls, path: str | os.PathLike[str]) -> Physics:
        """Load a compiled MJB file; raises CompileError."""
        return cls(_compile(mujoco.MjModel.from_binary_path, os.fspath(path), None))

    @classmethod
    def from_mjcf_model(cls, mjcf_model: RootElement) -> Physics:
        """Compile an `mjcf.RootElement` (with its attached models); its elements can
        then be bound with `bind`. Raises CompileError naming the offending element."""
        compiled = compiler.compile_composition(mjcf_model)
        physics = cls(compiled.model)
        physics._compiled = compiled
        return physics

    def reload_from_mjcf_model(self, mjcf_model: RootElement) -> None:
        """Recompile `mjcf_model` into this physics, keeping time and the state of the
        joints, actuators and mocap bodies that still exist; bindings made before must
        be made again. Raises CompileError (and then changes nothing)."""
        compiled = compiler.compile_composition(mjcf_model)
        data = mujoco.MjData(compiled.model)
        unnamed = compiler.unnamed_pairs(self.__dict__.get("_compiled"), compiled)
        tree_binding.transfer_state(self._model, self._data, compiled.model, data, unnamed)
        mujoco.mj_forward(compiled.model, data)
        self.close()
        self._attach(compiled.model, data)
        self._compiled = compiled

    def bind(self, elements: Element | Sequence[Element]) -> binding_module.Binding:
        """Live access to the simulation fields of model elements: `bind(joint).qpos`,
        `bind(bodies).xpos`, `bind(actuators).ctrl = u`. One element gives fields without
        the leading element axis. The binding is made once and cached. Raises
        BindingError for elements of another model, removed elements, an empty list or
        mixed kinds."""
        key = elements if not isinstance(elements, list | tuple) else tuple(elements)
        found = self._element_bindings.get(key)
        if found is not None:
            return found
        compiled = self.__dict__.get("_compiled")
        if compiled is None:
            raise errors.BindingError(
                "this physics was not compiled from an mjcf model (use Physics.from_mjcf_model)"
            )
        single = not isinstance(elements, list | tuple)
        items = [elements] if single else list(elements)
        kind, ids = tree_binding.element_ids(compiled, self._model, items)
        found = self._binding(kind, int(ids[0]) if single else ids)
        self._element_bindings[key] = found
        return found

    # -- state ---------------------------------------------------------------------------

    @property
    def model(self) -> mujoco.MjModel:
        """The raw mujoco.MjModel."""
        return self._model

    @property
    def data(self) -> mujoco.MjData:
        """The raw mujoco.MjData."""
        return self._data

    @property
    def named(self) -> named.NamedAccess:
        """Named indexing: `physics.named.data.qpos['hip']`, `.model.geom_rgba['floor']`."""
        if self._named is None:
            self._named = named.NamedAccess(self)
        return self._named

    def timestep(self) -> float:
        """The simulation timestep in seconds (model.opt.timestep)."""
        return float(self._model.opt.timestep)

    def time(self) -> float:
        """The simulation time in seconds (data.time)."""
        return float(self._data.time)

    def step(self, nstep: int = 1) -> None:
        """Advance the simulation by `nstep` timesteps (mj_step); does not check divergence."""
        mujoco.mj_step(self._model, self._data, nstep)

    def forward(self) -> None:
        """Recompute every derived quantity from the state (mj_forward)."""
        mujoco.mj_forward(self._model, self._data)

    def reset(self, keyframe: int | str | None = None) -> None:
        """Reset the state to qpos0, or to a keyframe (index or name), then forward.

        Raises NotFoundError for a keyframe the model does not have.
        """
        if keyframe is None:
            mujoco.mj_resetData(self._model, self._data)
        else:
            mujoco.mj_resetDataKeyframe(self._model, self._data, self._keyframe_id(keyframe))
        mujoco.mj_forward(self._model, self._data)

    def _keyframe_id(self, keyframe: int | str) -> int:
        nkey = self._model.nkey
        names = fields.names(self._model, mujoco.mjtObj.mjOBJ_KEY)
        if isinstance(keyframe, str):
            key_id = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_KEY, keyframe)
            if key_id < 0:
                raise errors.NotFoundError(
                    f"no keyframe named {keyframe!r}{_did_you_mean(keyframe, names)}; "
                    f"keyframes: {list(names)}"
                )
            return key_id
        if not 0 <= int(keyframe) < nkey:
            raise errors.NotFoundError(
                f"keyframe index {keyframe} is out of range: the model has {nkey} keyframes"
            )
        return int(keyframe)

    @contextlib.contextmanager
    def reset_context(self, keyframe: int | str | None = None) -> Iterator[Physics]:
        """Reset, let the block set up the state, then forward and check it is valid.

        Raises PhysicsError if the state set in the block is invalid.
        """
        self.reset(keyframe)
        yield self
        self.forward()
        self.check_invalid_state()

    def check_invalid_state(self) -> None:
        """Raise PhysicsError if the state is invalid: MuJoCo flagged a bad qpos, qvel, qacc or
        ctrl since the last reset, or the last forward pass gave a non-finite qacc.

        For bad qpos/qvel/qacc MuJoCo has also reset the state itself, so the simulation did
        not continue from the bad values; the warning counters stay set until `reset()`.
        """
        warnings = self._warnings
        # any() over a list first: benign warnings aside, nothing is set, and this is cheapest.
        if any(warnings.tolist()) and warnings[_INVALID_STATE_IDS].any():
            found = []
            for warning, field in _INVALID_STATE_WARNINGS.items():
                if warnings[warning]:
                    where = self._locate(field, self._data.warning[warning].lastinfo)
                    found.append(f"{warning.name} x{warnings[warning]} ({where})")
            raise errors.PhysicsError(
                f"physics state is invalid at t={self.time():.6g}: MuJoCo reported "
                f"{', '.join(found)}; reset the physics to continue"
            )
        # MuJoCo checks the state only when stepping; a state set since then and forwarded
        # (reset_context) shows in qacc. The dot product is not finite if any entry is not,
        # or above 1e154, far past MuJoCo's own 1e10 bound.
        qacc = self._data.qacc
        if not math.isfinite(qacc @ qacc):
            bad = np.flatnonzero(~np.isfinite(qacc))
            index = int(bad[0]) if bad.size else int(np.argmax(np.abs(qacc)))
            raise errors.PhysicsError(
                f"physics state is invalid at t={self.time():.6g}: qacc is not finite at "
                f"{self._locate('qvel', index)}; was a NaN or infinite qpos/qvel set?"
            )

    def _locate(self, field: str, index: int) -> str:
        """'<field> index <i>, joint <name>': the object owning row `index` of qpos/qvel/ctrl."""
        spec = fields.indexed_field(field)
        starts, counts = fields.rows(self._model, spec.address)
        owner = np.flatnonzero((starts <= index) & (index < starts + counts))
        if owner.size == 0:
            return f"{field} index {index}"
        name = fields.names(self._model, spec.kind)[owner[0]] or f"#{owner[0]}"
        return f"{field} index {index}, {fields.kind_name(spec.kind)} {name!r}"

    @contextlib.contextmanager
    def check_divergence(self) -> Iterator[Physics]:
        """Run the block, then raise PhysicsError if the simulation became invalid in it."""
        yield self
        self.check_invalid_state()

    # -- copies and pickling -------------------------------------------------------------

    def copy(self, share_model: bool = True) -> Physics:
        """A physics of the same class with a copy of the MjData (and MjModel unless shared).

        Extra attributes of subclasses are deep-copied, as pickling would, except that
        references to this physics (e.g. in bindings) and to a shared model point at the copy
        and the shared model. Caches and renderers are not copied.
        """
        model = self._model if share_model else copy_module.copy(self._model)
        data = mujoco.MjData(model)
        mujoco.mj_copyData(data, model, self._data)
        new = type(self).__new__(type(self))
        new._attach(model, data)
        memo = {id(self): new, id(self._model): model, id(self._data): data}
        for name in _SHARED:
            if name in self.__dict__:
                memo[id(self.__dict__[name])] = self.__dict__[name]
        extras = {k: v for k, v in self.__dict__.items() if k not in _TRANSIENT}
        new.__dict__.update(copy_module.deepcopy(extras, memo))
        return new

    def __copy__(self) -> Physics:
        return self.copy(share_model=True)

    def __deepcopy__(self, memo: dict[int, Any]) -> Physics:
        return self.copy(share_model=False)

    def __getstate__(self) -> dict[str, Any]:
        """The model (pickled by mujoco as MJB bytes), the integration state, extra attributes."""
        state = np.empty(mujoco.mj_stateSize(self._model, _STATE))
        mujoco.mj_getState(self._model, self._data, state, _STATE)
        extras = {k: v for k, v in self.__dict__.items() if k not in _TRANSIENT}
        return {"model": self._model, "state": state, "extras": extras}

    def __setstate__(self, state: dict[str, Any]) -> None:
        model = state["model"]
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, state["state"], _STATE)
        # Derived quantities are not part of the state: recompute them from it.
        mujoco.mj_forward(model, data)
        self.__dict__.update(state["extras"])
        self._attach(model, data)

    # -- bindings ------------------------------------------------------------------------

    def _binding(
        self, kind: mujoco.mjtObj, ids: int | Sequence[int] | np.ndarray
    ) -> binding_module.Binding:
        """The binding of objects `ids` of `kind` (cached); raises BindingError.

        An int binds one object (fields without a leading axis); a list binds several.
        """
        array = np.asarray(ids)
        if array.dtype.kind in "iu":  # one cache entry per id list, whatever its int type
            array = array.astype(np.intp, copy=False)
        cache_key = (int(kind), array.ndim, array.dtype.str, array.tobytes())
        found = self._bindings.get(cache_key)
        if found is None:
            kind = mujoco.mjtObj(kind)
            found = self._bindings[cache_key] = binding_module.binding_class(kind)(self, kind, ids)
        return found

    def bind_names(self, kind: mujoco.mjtObj, names: str | Sequence[str]) -> binding_module.Binding:
        """The binding of the objects of `kind` called `names` (one str: a single object).

        Raises NotFoundError for a name the model does not have.
        """
        single = isinstance(names, str)
        wanted = [names] if single else list(names)
        ids = [mujoco.mj_name2id(self._model, kind, name) for name in wanted]
        if min(ids, default=0) < 0:
            missing = wanted[ids.index(-1)]
            known = [n for n in fields.names(self._model, kind) if n]
            raise errors.NotFoundError(
                f"no {fields.kind_name(kind)} named {missing!r}{_did_you_mean(missing, known)}"
            )
        return self._binding(kind, ids[0] if single else np.array(ids, dtype=np.intp))

    # -- rendering -----------------------------------------------------------------------

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

        camera_id -1 is the free camera; a camera id or name picks a model camera.
        Raises RenderError when no OpenGL backend can be created or the request is invalid.
        """
        renderer = self._renderer(int(height), int(width))
        try:
            renderer.update_scene(self._data, camera=camera_id, scene_option=scene_option)
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

    def _renderer(self, height: int, width: int) -> mujoco.Renderer:
        renderer = self._renderers.get((height, width))
        if renderer is not None:
            return renderer
        try:
            renderer = mujoco.Renderer(self._model, height, width)
        except ValueError as e:  # larger than the model's offscreen framebuffer
            raise errors.RenderError(str(e)) from e
        except (ImportError, OSError, RuntimeError, AttributeError, mujoco.FatalError) as e:
            raise errors.RenderError(_no_backend_message(e)) from e
        self._renderers[(height, width)] = renderer
        return renderer

    def close(self) -> None:
        """Free the renderers' OpenGL resources; the physics itself stays usable."""
        renderers = self.__dict__.get("_renderers") or {}
        for renderer in renderers.values():
            renderer.close()
        renderers.clear()

    def __del__(self) -> None:
        self.close()


def _compile(loader: Any, source: str, assets: dict[str, bytes] | None) -> mujoco.MjModel:
    try:
        return loader(source) if assets is None else loader(source, assets)
    except ValueError as e:
        raise errors.CompileError(f"MuJoCo could not load the model: {e}") from e


def _did_you_mean(name: str, names: Sequence[str]) -> str:
    close = difflib.get_close_matches(name, list(names), n=3)
    return f" (did you mean {', '.join(map(repr, close))}?)" if close else ""


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
