"""`RootElement`: a whole MJCF model, the `<mujoco>` element.

    model = mjcf.RootElement(model='arm')
    model.worldbody.add('body', name='upper')      # every section exists, even empty
    model.compiler.angle = 'radian'
    model.default.geom.rgba = [1, 0, 0, 1]        # global defaults
    model.find('body', 'upper')

Every top-level section (`schema.ROOT_SECTIONS`: `worldbody`, `asset`, `default`, `option`,
`actuator` ...) is a property that always exists; empty sections are left out of the XML.
"""

from __future__ import annotations

import copy
from typing import TYPE_CHECKING, Any

from mjcf import errors, schema
from mjcf.tree import above, builder, references
from mjcf.tree.element import Element, built_from, count_change
from mjcf.tree.element_list import attached_models
from mjcf.tree.namescope import NameScope, check_model_name

if TYPE_CHECKING:
    from mjcf.compose.attachment import AttachmentFrame
    from mjcf.sim.physics import Physics

DEFAULT_MODEL_NAME = "unnamed_model"


class RootElement(Element):
    """A whole MJCF model. `model` is its name (the scope name of its elements when
    it is attached to another model); `model_dir` is where its relative file names
    are found; `assets` maps file names to contents for files that are not on disk.

    Reading, besides Element's: mjcf's modules read a model's sections with
    `section_of(model, tag)`, its own count of changes with `own_version(model)` and its
    attachment frame with `frame_of(model)`, functions of this module (a model's public
    names are its MJCF children's); the models attached to it are its name scope's
    children, in the order they were attached (`mjcf.tree.element_list.attached_models`).
    What other modules keep on a model is read and set through this module's functions
    (`set_frame`, `numbering_of`, `compositions_of`, `confine_files` ...); `_version` is
    counted by `mjcf.tree.element`, `_references` is `mjcf.tree.references`' state of the
    model's references, and `mjcf.tree.namescope` asks `_resolve(xml)` for an element not
    built yet (see `Element`).
    """

    __slots__ = (
        "_assets",
        "_composed",
        "_confine_to",
        "_frame",
        "_model_dir",
        "_namescope",
        "_numbering",
        "_references",
        "_version",
    )

    _namescope: NameScope
    _model_dir: str
    _assets: dict[str, bytes]
    _frame: AttachmentFrame | None
    _confine_to: str | None
    _numbering: tuple[tuple, dict[Element, int]] | None
    _composed: dict[tuple[bool, bool], Any] | None
    _references: references.ModelReferences
    _version: int

    def __init__(
        self, model: str | None = None, model_dir: str = "", assets: dict[str, bytes] | None = None
    ) -> None:
        setter = object.__setattr__
        setter(self, "_spec", schema.MUJOCO)
        setter(self, "_parent", None)
        setter(self, "_root", self)
        setter(self, "_attrs", {})
        setter(self, "_children", [])
        setter(self, "_source", None)
        setter(self, "_text", None)
        setter(self, "_xml", None)
        setter(self, "_namescope", NameScope(self))
        setter(self, "_model_dir", str(model_dir) if model_dir else "")
        setter(self, "_assets", dict(assets) if assets else {})
        setter(self, "_frame", None)
        # With strict_paths, the real folder that every file of the model must be in.
        setter(self, "_confine_to", None)
        # (versions, {unnamed element: number}) for generated names (see mjcf.compose.naming).
        setter(self, "_numbering", None)
        # {for compiling: the last composition of this model} (see mjcf.compose.composition).
        setter(self, "_composed", None)
        # How references are kept, and those naming no element yet (see mjcf.tree.references).
        setter(self, "_references", references.ModelReferences())
        setter(self, "_version", 0)
        if model is not None:  # an unnamed model is written without a name, as it was read
            self._attrs["model"] = check_model_name(model)
        for section in schema.MUJOCO.children.values():
            self._children.append(builder.new_element(Element, section, self, self))
        builder.register(self._section("default"))

    @property
    def model(self) -> str:
        """The model's name ('unnamed_model' if it was not given)."""
        return self._attrs.get("model", DEFAULT_MODEL_NAME)

    @model.setter
    def model(self, model: str) -> None:
        """Rename the model (and so its scope in the model it is attached to); raises
        mjcf.NameClashError if `model` cannot name a model, or a model attached next to
        this one has that name."""
        new = check_model_name(model)
        scope = self._namescope
        parent = scope.parent
        if parent is not None and new != self.model:
            parent.check_child_free(new)
            position = parent.remove_child(scope)
            self._attrs["model"] = new
            parent.add_child(scope, position)  # where it was: the attached models' order
            count_change(parent.model)
        else:
            self._attrs["model"] = new
        self._modified()

    @property
    def namescope(self) -> NameScope:
        """The names of this model's elements (see `mjcf.tree.namescope`)."""
        return self._namescope

    @property
    def model_dir(self) -> str:
        """Directory that relative file names of this model are read from."""
        return self._model_dir

    @property
    def assets(self) -> dict[str, bytes]:
        """File contents given at construction, by file name."""
        return self._assets

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "model":  # the property's setter (Element's would set an attribute)
            object.__setattr__(self, name, value)
            return
        super().__setattr__(name, value)

    def __delattr__(self, name: str) -> None:
        if name == "model":
            raise errors.AttributeValueError("a model always has a name")
        super().__delattr__(name)

    @property
    def version(self) -> int:
        """A number that grows with every change of this model or of a model attached to
        it (attributes set, deleted or edited in place, elements added or removed, models
        attached or detached): equal versions mean an unchanged model, so a compiled
        model can be reused."""
        return self._version + sum(m._version for m in attached_models(self))

    @property
    def parent_model(self) -> RootElement | None:
        """The model this model is attached to, or None."""
        return None if self._frame is None else self._frame.root

    @property
    def root_model(self) -> RootElement:
        """The outermost model this model is attached into (itself if not attached)."""
        return self if self._frame is None else self._frame.root.root_model

    def attach(self, child: RootElement) -> Element:
        """Attach `child` to this model's world body; see `Element.attach`."""
        return self._section("worldbody").attach(child)

    def detach(self) -> None:
        """Detach this model from the model it is attached to, taking out all it brought
        but the global settings merged at attach, which stay, as in dm_control; this model
        keeps a copy of the settings it shared (see `mjcf.compose.global_settings`). Raises
        mjcf.AttachmentError if it is not attached."""
        above.detach(self)

    def get_assets(self, filename_with_hash: bool = False) -> dict[str, bytes]:
        """`{file name: contents}` of every file `to_xml_string()` refers to (meshes,
        textures, ...), under the names it writes (unique as MuJoCo needs them), as
        `mujoco.MjModel.from_xml_string(xml, assets)` takes them; `filename_with_hash`
        as in `to_xml_string`. Raises mjcf.AssetError if a file cannot be read."""
        return above.serialize(self, filename_with_hash)[1]

    def compile_model(self) -> Physics:
        """Compile this model (with attached models) into a new `mjcf.Physics`."""
        return above.compile_model(self)

    def _resolve(self, xml: Any) -> Element | None:
        """The element built from lxml element `xml` of the file this model was read
        from, built now with the elements above it if they are not yet (see
        `Element._defer`); None if it is no longer in the model."""
        return built_from(self, xml)

    def __getstate__(self) -> tuple[None, dict[str, Any]]:
        """Pickled with every element built (see `Element._defer`)."""
        for _ in self.iter():
            pass
        return super().__getstate__()

    def _section(self, tag: str) -> Element:
        """The top-level section `tag`; raises mjcf.SchemaError for unknown sections."""
        section = self._single_child(tag)
        if section is None:  # every section exists: `tag` is none
            self._no_child(tag)
        return section

    def __copy__(self) -> RootElement:
        """`copy.copy(model)` is `copy.deepcopy(model)`, as in dm_control: an independent
        copy, detached, with copies of the models attached to it."""
        return copy.deepcopy(self)

    def __repr__(self) -> str:
        return f"MJCF RootElement: model {self.model!r}"


# -- reading a model: what mjcf's modules read of any model, besides an element's ----------


def section_of(model: RootElement, tag: str) -> Element:
    """The top-level section `tag` of `model` itself (not those of models attached to it);
    raises mjcf.SchemaError for a tag that names no section."""
    return model._section(tag)


def frame_of(model: RootElement) -> AttachmentFrame | None:
    """The attachment frame of `model`, or None if it is not attached."""
    return model._frame


def set_frame(model: RootElement, frame: AttachmentFrame | None) -> None:
    """Record that `model` is attached at `frame` (None: detached); for
    `mjcf.compose.attachment`, which alone links and unlinks models."""
    object.__setattr__(model, "_frame", frame)


def set_own_version(model: RootElement, version: int) -> None:
    """Set the count of changes of `model` itself: a copy's is its original's
    (`mjcf.compose.copying`)."""
    object.__setattr__(model, "_version", version)


def numbering_of(model: RootElement) -> tuple[tuple, dict[Element, int]] | None:
    """`mjcf.compose.naming`'s numbers of `model`'s unnamed elements, with the versions
    they were counted at (None until counted)."""
    return model._numbering


def set_numbering(model: RootElement, numbering: tuple[tuple, dict[Element, int]]) -> None:
    """Keep `mjcf.compose.naming`'s numbers of `model`'s unnamed elements."""
    object.__setattr__(model, "_numbering", numbering)


def compositions_of(model: RootElement) -> dict[tuple[bool, bool], Any] | None:
    """`mjcf.compose.composition`'s last composition of `model` for each kind of output
    (None until one is made)."""
    return model._composed


def set_compositions(model: RootElement, compositions: dict[tuple[bool, bool], Any]) -> None:
    """Keep `mjcf.compose.composition`'s last compositions of `model`."""
    object.__setattr__(model, "_composed", compositions)


def confine_files(model: RootElement, folder: str | None) -> None:
    """Make every file of `model` (read with `strict_paths`) have to be in the real folder
    `folder` (None: anywhere), as `mjcf.tree.assets` checks when it reads one."""
    object.__setattr__(model, "_confine_to", folder)


def own_version(model: RootElement) -> int:
    """The number of changes of `model` itself, not counting those of the models attached
    to it (see `RootElement.version`, which does)."""
    return model._version
