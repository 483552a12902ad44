"""Physics: one MuJoCo simulation (MjModel + MjData) with bindings, named access and rendering.

    physics = Physics.from_xml_path("humanoid.xml")
    physics.named.data.qpos["root"][:3] = [0, 0, 1.4]   # or physics.bind(element).qpos = ...
    with physics.check_divergence():                    # PhysicsError if MuJoCo gave up
        physics.step(10)                                # positions, sensors: of the new state

Bindings and named access read what `mj_forward` would compute for the current state;
`model` and `data` stay the same objects for the physics' life; a pickled or copied physics
steps on as the original. Stepping never checks for divergence. The whole story: `Physics`.
"""

from __future__ import annotations

import contextlib
import copy as copy_module
import functools
import logging
import os
import weakref
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import binding as binding_module
from mjcf.sim import (
    budget,
    compiler,
    fields,
    frame_binding,
    frame_poses,
    mujoco_log,
    named,
    raw_access,
    tree_binding,
    validity,
)
from mjcf.sim.binding import ACC_BEHIND, POS_BEHIND
from mjcf.sim.physics_rendering import Rendering
from mjcf.sim.physics_state import ResetContext, StateAccess
from mjcf.sim.physics_stepping import Stepping
from mjcf.tree.element import Element as ElementType

if TYPE_CHECKING:
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

raw_access.install()
mujoco_log.install()  # MuJoCo's warnings to logging, not to MUJOCO_LOG.TXT

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
_LOG = logging.getLogger("mjcf.physics")  # its name before mjcf had layers

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
    "_stale",
    "_on_demand",
    "_scratch",
    "_opt",
    "_state_check",
    "_qacc_checked",
)
# Attributes made when first used (see Physics.__getattr__).
_MADE_ON_FIRST_USE = ("_data", "_warnings")
# Attributes a copy shares with its original instead of copying: the model tree a
# physics was compiled from (bind(element) needs the user's own element objects).
_SHARED = ("_compiled",)


class Physics(Stepping, StateAccess, Rendering):
    """A MuJoCo simulation: an MjModel, its MjData, and access to both by object and name.

        physics = Physics.from_xml_path("humanoid.xml")
        with physics.reset_context():                       # reset, then forward on exit
            physics.named.data.qpos["root"][:3] = [0, 0, 1.4]
        physics.named.model.geom_rgba["floor"] = [1, 0, 0, 1]
        hips = physics.bind_names(mujoco.mjtObj.mjOBJ_JOINT, ["right_hip_x", "right_hip_y"])
        hips.qpos = [0.1, 0.2]                              # live views; see mjcf.sim.binding
        physics.named.data.xpos["torso", "z"]               # forwards first: hips moved
        physics.set_control(u)
        with physics.check_divergence():                    # PhysicsError if MuJoCo gave up
            physics.step(10)                                # positions, sensors: of the new state
        state = physics.get_state()                         # qpos, qvel, act (+ plugin state)
        frame = physics.render(240, 320, camera_id=-1)      # headless too: mjcf.sim.rendering
        clone = pickle.loads(pickle.dumps(physics))         # same state, same next steps

    `model` and `data` are the raw `mujoco.MjModel` / `MjData` (with dm_control's `.ptr`,
    `name2id` and `id2name`, see `mjcf.sim.raw_access`); they stay the same objects for the
    life of the physics (reset works in place), so bindings and views stay valid. `copy()`
    and unpickling give a physics with its own MjData (and MjModel, unless shared).
    Subclasses (e.g. composer's) keep their extra attributes, bindings included, through
    `copy()` and pickling; they override nothing to get that, as long as their attributes
    are picklable.

    Fresh values: after `step()`, `forward()` and `reset()`, and after writes through
    bindings or `named` (tracked, see `mjcf.sim.binding.Binding`), what bindings and named
    access read is what `mj_forward` would compute for the current state. Writes straight
    into `data` or `model` are MuJoCo's own business: call `forward()` (or
    `mark_as_dirty()`) after them. Stepping does not check for divergence: call
    `check_invalid_state()` or step inside `check_divergence()` where it matters.

    `legacy_step` (dm_control's flag, True by default) picks how `step()` leaves MjData: True,
    consistent with the new state; False, as a plain `mj_step` leaves it (see `step`). The
    state accessors (`get_state`, `set_control`, `position` ...) are `StateAccess`'s; `step`,
    `forward`, `reset` and the freshness they keep are `Stepping`'s; `render` and `close` are
    `Rendering`'s.

    Bindings, named access and frame bindings use it through `BoundPhysics`, the protocol
    `mjcf.sim.binding` defines and this class implements; validity checks call
    `_raise_if_invalid()`. `_frame_poses` holds the current poses of the model's
    `<frame>`s, which `mjcf.sim.frame_poses` keeps (and replaces when the physics holds
    another model).
    """

    legacy_step: bool = True
    # dm_control's name: False while `suppress_physics_errors()` logs instead of raising.
    _warnings_cause_exception: bool = True
    _frame_poses: frame_poses.FramePoses | None = None
    _live_bindings: weakref.WeakSet[binding_module.Binding]

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        """Wrap `model` and `data` (a new MjData, forwarded, if None; a given MjData is
        forwarded before its derived fields are first read through bindings).

        A new MjData is made when the physics is first used, not here: making one costs
        mujoco's bindings about 0.3 ms whatever the model, as much as compiling a small
        model, and code that only inspects the compiled model never needs it."""
        self._attach(model, data, 0 if data is None else POS_BEHIND | ACC_BEHIND)

    def __getattr__(self, name: str) -> Any:
        # Only for attributes not set yet: the MjData that __init__ left to first use.
        if name in _MADE_ON_FIRST_USE and self.__dict__.get("_model") is not None:
            data = mujoco.MjData(self._model)
            mujoco.mj_forward(self._model, data)
            self._hold_data(data)
            return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _hold_data(self, data: mujoco.MjData) -> None:
        self._data = data
        self._warnings = data.warning.number  # a live view of MuJoCo's warning counters

    def _attach(self, model: mujoco.MjModel, data: mujoco.MjData | None, stale: int = 0) -> None:
        """Hold `model` and `data` (None: a new MjData, forwarded, made on first use),
        dropping every cache built for the previous ones; `stale` says what of `data` is not
        up to date (bits of `mjcf.sim.binding`).

        The one place a physics changes its MjModel/MjData. Bindings made before then read
        the new MjData if the model is the same, else raise BindingError; named views
        re-resolve their indices.
        """
        if self.__dict__.get("_live_bindings") is None:
            self._live_bindings = weakref.WeakSet()
        self._detach_bindings()
        self._model = model
        if data is None:
            for name in _MADE_ON_FIRST_USE:
                self.__dict__.pop(name, None)
        else:
            self._hold_data(data)
        self._opt = model.opt  # a live view; cached because each `model.opt` makes one
        self._stale = stale
        # The `_stale` a step left when MuJoCo checked the qacc it left (None: unchecked);
        # while `_stale` still holds it, nothing has recomputed or written since.
        self._qacc_checked: int | None = None
        self._on_demand: tuple[Any, ...] = ()  # mj_ functions bound fields need run
        self._scratch: mujoco.MjData | None = None  # for mj_setConst, which clobbers data
        self._bindings: dict[tuple, binding_module.Binding] = {}
        self._element_bindings: dict[
            object, binding_module.Binding | frame_binding.FrameBinding
        ] = {}
        self._named: named.NamedAccess | None = None
        # By size, and by (size, thread id) for a thread that drew while another held one.
        self._renderers: dict[tuple[Any, ...], mujoco.Renderer] = {}
        self._state_check = validity.StateCheck(self)

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
        """Compile the MJCF file at `path`; raises CompileError. MuJoCo reads the file
        unmeasured by `mjcf.sim.budget`: read a model you do not trust with
        `mjcf.from_path(path, strict_paths=True)` and compile that."""
        return cls(_compile(mujoco.MjModel.from_xml_path, os.fspath(path), None))

    @classmethod
    def from_binary_path(cls, path: str | os.PathLike[str]) -> Physics:
        """Load a compiled MJB file, unmeasured by `mjcf.sim.budget`; raises CompileError."""
        return cls(_compile(mujoco.MjModel.from_binary_path, os.fspath(path), None))

    @classmethod
    def from_mjcf_model(cls, mjcf_model: RootElement, share_assets: bool = True) -> Physics:
        """Compile an `mjcf.RootElement` (with its attached models); its elements can
        then be bound with `bind`. Copies of one model compile their meshes and textures
        once (`mjcf.compose.sharing`), which bindings can read but not write, unless not
        `share_assets`. Raises CompileError naming the offending element."""
        compiled = compiler.compile_composition(mjcf_model, share_assets)
        physics = cls(compiled.model)
        physics._compiled = compiled
        return physics

    def reload_from_mjcf_model(
        self, mjcf_model: RootElement, keep_state: bool = False, share_assets: bool = True
    ) -> None:
        """Recompile `mjcf_model` into this physics, with fresh data (time 0, the model's
        initial state), as `from_mjcf_model` would give (`share_assets` as there);
        `keep_state=True` keeps time and the state of the joints, actuators and mocap
        bodies that still exist instead. Bindings made before must be made again. Raises
        CompileError (and then changes nothing)."""
        compiled = compiler.compile_composition(mjcf_model, share_assets)
        data = mujoco.MjData(compiled.model)
        if keep_state:
            unnamed = compiler.unnamed_pairs(self.__dict__.get("_compiled"), compiled)
            tree_binding.transfer_state(self._model, self._data, compiled.model, data, unnamed)
        mujoco.mj_forward(compiled.model, data)
        self.close()
        self._attach(compiled.model, data)
        self._compiled = compiled

    def reload_from_xml_string(
        self, xml_string: str | bytes, assets: Mapping[str, bytes] | None = None
    ) -> None:
        """Recompile this physics from MJCF text, with fresh data, as `from_xml_string`
        would give (dm_control's method); bindings made before must be made again, and
        find elements by their full identifiers. Raises CompileError, changing nothing."""
        if isinstance(xml_string, bytes):
            xml_string = xml_string.decode("utf-8")
        self._reload(_compile(mujoco.MjModel.from_xml_string, xml_string, dict(assets or {})))

    def reload_from_xml_path(self, file_path: str | os.PathLike[str]) -> None:
        """`reload_from_xml_string` of the MJCF file at `file_path`."""
        self._reload(_compile(mujoco.MjModel.from_xml_path, os.fspath(file_path), None))

    def _reload(self, model: mujoco.MjModel) -> None:
        self.close()
        self._attach(model, None)
        self.__dict__.pop("_compiled", None)  # compiled from text: no composition to index

    # -- the raw model and data ----------------------------------------------------------

    @property
    def model(self) -> mujoco.MjModel:
        """The raw mujoco.MjModel (`.ptr` gives it too, as dm_control's wrapper does)."""
        return self._model

    @property
    def data(self) -> mujoco.MjData:
        """The raw mujoco.MjData (`.ptr` gives it too, as dm_control's wrapper does)."""
        return self._data

    # -- checked blocks ------------------------------------------------------------------

    def reset_context(
        self, keyframe: int | str | None = None
    ) -> contextlib.AbstractContextManager[Physics]:
        """Reset, let the block set up the state, then forward and check it is valid.

        One mj_forward in all, when the block ends: inside it, derived fields read through
        bindings or named access (xpos, contacts, sensors ...) are computed when first read,
        for the state as it is then (the reset state, until the block writes one), where
        `reset()` would forward at once; `data`'s own are computed when the block ends,
        or by `forward()`, as after any write.

        Raises PhysicsError if the state set in the block is invalid.
        """
        return ResetContext(self, functools.partial(self._reset_state, keyframe))

    def check_invalid_state(self) -> contextlib.AbstractContextManager[Physics]:
        """Raise PhysicsError if the state is invalid: MuJoCo flagged a bad qpos, qvel, qacc or
        ctrl since the last reset, or the last forward pass gave a non-finite qacc.

        Also a context manager, as in dm_control: `with physics.check_invalid_state(): ...`
        checks now and again when the block ends (like `check_divergence()`).

        For bad qpos/qvel/qacc MuJoCo has also reset the state itself, so the simulation did
        not continue from the bad values; the warning counters stay set until `reset()`.
        """
        self._raise_if_invalid()
        return self._state_check

    def _raise_if_invalid(self) -> None:
        checked = self._stale == self._qacc_checked  # as the step left it: MuJoCo saw qacc
        try:
            validity.raise_if_invalid(self._model, self._data, self._warnings, checked)
        except errors.PhysicsError as e:
            if self._warnings_cause_exception:
                raise
            _LOG.warning("%s", e)

    @contextlib.contextmanager
    def suppress_physics_errors(self) -> Iterator[Physics]:
        """Within the block, an invalid state is logged (the `mjcf.sim.physics` logger) instead
        of raising PhysicsError (dm_control's context manager, which its observation
        updater reads observables in)."""
        previous = self._warnings_cause_exception
        self._warnings_cause_exception = False
        try:
            yield self
        finally:
            self._warnings_cause_exception = previous

    @contextlib.contextmanager
    def check_divergence(self) -> Iterator[Physics]:
        """Run the block, then raise PhysicsError if the simulation became invalid in it."""
        yield self
        self._raise_if_invalid()

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
        new._attach(model, data, self._stale)
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

    def bind(self, elements: Element | Iterable[Element] | None) -> Any:
        """Live access to the simulation fields of model elements: `bind(joint).qpos`,
        `bind(bodies).xpos`, `bind(actuators).ctrl = u` (see `mjcf.sim.binding`).

        `elements` is one element (fields without the leading element axis), or a list,
        tuple, numpy object array or any iterable of elements of one kind. No elements give
        an empty binding whose fields read as empty arrays; None gives None. On a physics
        compiled from the elements' model they are found by their compiled index, unnamed
        ones too; otherwise (`from_xml_string(model.to_xml_string())`, `from_xml_path`,
        `from_model` ...) by their full identifiers, as dm_control does. The binding is
        made once and cached. Raises BindingError for elements the compiled model does not
        have (naming them), removed elements, or mixed kinds."""
        if elements is None:
            return None
        single = isinstance(elements, ElementType)
        try:
            key = elements if single else tuple(elements)
        except TypeError:
            raise errors.BindingError(
                f"bind() takes an element or an iterable of elements, got {type(elements).__name__}"
            ) from None
        cached = self._element_bindings.get(key)
        if cached is not None:
            return cached
        if not key:
            return binding_module.EMPTY
        items = [elements] if isinstance(elements, ElementType) else list(key)
        found: binding_module.Binding | frame_binding.FrameBinding
        frames = frame_binding.bind_frames(self, items, single)
        if frames is not None:
            found = frames
        else:
            compiled = self.__dict__.get("_compiled")
            kind, ids = tree_binding.element_ids(compiled, self._model, items)
            refusal = None if compiled is None else tree_binding.write_refusal(compiled, items)
            if refusal is None:
                found = self._binding(kind, int(ids[0]) if single else ids)
            else:  # read-only, and apart from the cached bindings of these objects
                found = binding_module.binding_class(kind)(
                    self, kind, int(ids[0]) if single else ids
                )
                binding_module.refuse_writes(found, refusal)
        self._element_bindings[key] = found
        return found

    def _binding(self, kind: mujoco.mjtObj, ids: int | np.ndarray) -> binding_module.Binding:
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
        wanted = [names] if isinstance(names, str) else list(names)
        ids = [mujoco.mj_name2id(self._model, kind, name) for name in wanted]
        if min(ids, default=0) < 0:
            missing = wanted[ids.index(-1)]
            known = [n for n in fields.names(self._model, kind) if n]
            hint = errors.did_you_mean(missing, known)
            raise errors.NotFoundError(f"no {fields.kind_name(kind)} named {missing!r}{hint}")
        return self._binding(kind, ids[0] if single else np.array(ids, dtype=np.intp))

    @property
    def named(self) -> named.NamedAccess:
        """Named indexing: `physics.named.data.qpos['hip']`, `.model.geom_rgba['floor']`,
        `.data.xpos['torso', 'z']`."""
        if self._named is None:
            self._named = named.NamedAccess(self)
        return self._named

    # -- release -------------------------------------------------------------------------

    def free(self) -> None:
        """Release the simulation: renderers, caches, and this physics' references to its
        MjModel/MjData (freed when nothing else holds them). The physics must not be used
        afterwards, as in dm_control."""
        self.close()
        self._detach_bindings()
        for name in ("_compiled", "_named", "_scratch", "_warnings"):
            self.__dict__.pop(name, None)
        self._bindings.clear()
        self._element_bindings.clear()
        self._model = self._data = self._opt = None

    def __del__(self) -> None:
        self.close()


def _compile(loader: Any, source: str, assets: dict[str, bytes] | None) -> mujoco.MjModel:
    """`loader(source, assets)`: MuJoCo's; MJCF text given (`assets` not None) is measured
    against `mjcf.budget` first. Raises CompileError (BudgetError past the budget)."""
    if assets is not None:
        budget.check(source, assets, "the model")
    try:
        return loader(source) if assets is None else loader(source, assets)
    except ValueError as e:
        raise errors.CompileError(f"MuJoCo could not load the model: {e}") from e
    except RuntimeError as e:  # MuJoCo's "Caught an unknown exception!": out of memory
        raise errors.CompileError(compiler.unknown_failure("the model", e)) from None
