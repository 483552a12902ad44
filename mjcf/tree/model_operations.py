"""The methods of `Element` that the layers above the tree carry out, through
`mjcf.tree.above`: finding (`mjcf.compose.traversal`), comparing (`sameness`), removing,
attaching, copying (`attachment`, `copying`), naming (`naming`) and writing (`mjcf.io`).

    model.find('joint', 'arm/shoulder'); model.find_all('geom')
    body.remove(); site.attach(gripper); scene.include_copy(floor)
    geom.full_identifier                 # 'arm/tip'
    geom.to_xml_string(); body.is_same_as(other)

`Element` inherits them from `ModelOperations`: `mjcf.tree.element` holds what it is.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

from lxml import etree

from mjcf.schema.values import ElementBase
from mjcf.tree import above, references
from mjcf.tree.namescope import NameScope

if TYPE_CHECKING:
    from mjcf.schema import AttributeSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement


def _model_of(prefix_root: RootElement | NameScope | None) -> RootElement | None:
    """The model a `prefix_root` argument names: a model, or (as dm_control passes it)
    a model's name scope."""
    return prefix_root.model if isinstance(prefix_root, NameScope) else prefix_root


def _element(operations: ModelOperations) -> Element:
    """`operations` as the `Element` it is (ModelOperations is only a base of Element)."""
    return cast("Element", operations)


class ModelOperations(ElementBase):
    """Operations of an element on its model and the models attached to it (see the
    module docstring); a base of `Element`, not used alone."""

    __slots__ = ()

    if TYPE_CHECKING:  # the members of Element the operations use on `self`
        _attrs: dict[str, Any]

        def _attribute_spec(self, name: str, action: str = "set") -> AttributeSpec: ...

    # -- names in an output -----------------------------------------------------------------

    @property
    def full_identifier(self) -> str | None:
        """The name MuJoCo sees for this element in the outermost model it is attached
        into ('arm/gripper/pad'): generated for an unnamed element ('//unnamed_geom_0',
        'arm//unnamed_geom_0'), 'world' for the world body, and as in dm_control its
        attachment frame's ('arm/') for the world body of an attached model. None for elements that
        cannot carry a name, and unnamed ones that are removed or replicated (see
        `mjcf.compose.naming`)."""
        return self.prefixed_identifier(None)

    def prefixed_identifier(self, prefix_root: RootElement | NameScope | None = None) -> str | None:
        """This element's name as model `prefix_root` (default: the outermost model it is
        attached into) writes it; see `full_identifier`. Raises mjcf.InvalidReferenceError
        if this element's model is not attached inside `prefix_root`."""

        return above.identifier(_element(self), _model_of(prefix_root))

    # -- finding and comparing --------------------------------------------------------------

    def find(self, namespace: str, identifier: str) -> Element | None:
        """The element of `namespace` ('body', 'joint', 'geom', 'actuator', 'default',
        'attachment_frame' ...) called `identifier` ('arm/shoulder' for attached models)
        inside this element, or None. Raises mjcf.NamespaceError (a ValueError) for an
        unknown namespace."""

        return above.find(_element(self), namespace, identifier)

    def find_all(
        self,
        namespace: str,
        immediate_children_only: bool = False,
        exclude_attachments: bool = False,
    ) -> list[Element]:
        """Every element of `namespace` (or with tag `namespace`) inside this element,
        in the order MuJoCo will see them, including attached models' unless excluded.
        Raises mjcf.NamespaceError (a ValueError) for an unknown namespace."""

        return above.find_all(
            _element(self), namespace, immediate_children_only, exclude_attachments
        )

    def resolve_references(self) -> None:
        """Replace every reference held as text in this element's subtree by the element
        it names (names that match none stay text), as dm_control does after
        `from_path(..., resolve_references=False)`; called on a model, its attached
        models too, and the model resolves the names it is given from then on (see
        `mjcf.tree.references`)."""
        references.resolve_all(_element(self))

    def enter_scope(self, scope_identifier: str) -> RootElement | None:
        """The model attached into this element's model under the scoped name
        `scope_identifier` ('arm', or 'arm/gripper' for one attached inside it), or None
        if there is none."""
        scope = _element(self).root.namescope.descendant(scope_identifier)
        return None if scope is None else scope.model

    def is_same_as(self, other: object) -> bool:
        """Whether `other` is structurally the same element: same schema, attribute
        values (references by what they point to) and children (see `mjcf.compose.sameness`)."""

        return above.is_same_as(_element(self), other)

    # -- removing, attaching, copying -------------------------------------------------------

    def remove(self, affect_attachments: bool = False) -> None:
        """Remove this element (and its subtree) from the model; a model's top-level
        section, which always exists, is emptied instead (`del model.option` too), and
        with `affect_attachments` that section of every model attached into this one
        too, as in dm_control. Raises mjcf.AttachmentError (a ValueError) if models are
        attached inside (or, for a section, into the model), unless `affect_attachments`
        (they are detached then), and mjcf.SchemaError for a model root or an element
        removed already."""

        above.remove(_element(self), affect_attachments)

    def attach(self, child: RootElement) -> Element:
        """Attach model `child` here (a site, body, frame or the world body) and return
        its attachment frame; its names become scoped ('child_model/name'). Raises
        mjcf.AttachmentError (see `mjcf.compose.attachment.attach`)."""

        return above.attach(_element(self), child)

    def include_copy(self, other: Element, override_attributes: bool = False) -> None:
        """Merge a copy of `other` (an element of the same tag, or another model into
        this model) into this element, without a name scope, as `<include>` would; see
        `mjcf.compose.copying`. Nothing changes if it raises."""

        above.include_copy(_element(self), other, override_attributes)

    def __copy__(self) -> Element:
        raise TypeError(
            f"{_element(self).path}: an element belongs to its model and cannot be copied "
            "alone; copy the model with copy.copy(root) or copy.deepcopy(root), or merge a copy "
            "into another element with include_copy"
        )

    def __deepcopy__(self, memo: dict[int, Any]) -> Element:
        """A copy of the whole model (detached, with its attached models), sharing the
        schema; returns this element's copy (see `mjcf.compose.copying`)."""

        return above.deepcopy_element(_element(self), memo)

    # -- XML --------------------------------------------------------------------------------

    def get_attribute_xml_string(
        self, name: str, prefix_root: RootElement | NameScope | None = None
    ) -> str | None:
        """The attribute as it would be written to XML (scoped names for references)."""

        attribute = self._attribute_spec(name, "read")
        if attribute.name not in self._attrs:
            return None
        return above.attribute_text(_element(self), attribute, _model_of(prefix_root))

    def to_xml(
        self,
        prefix_root: RootElement | NameScope | None = None,
        *,
        precision: int = 17,
        zero_threshold: float = 0.0,
        filename_with_hash: bool = False,
    ) -> etree._Element:
        """This element (and its subtree, with attached models) as an lxml element;
        the keywords are `to_xml_string`'s."""
        return etree.fromstring(
            self.to_xml_string(
                prefix_root,
                pretty_print=False,
                precision=precision,
                zero_threshold=zero_threshold,
                filename_with_hash=filename_with_hash,
            )
        )

    def to_xml_string(
        self,
        prefix_root: RootElement | NameScope | None = None,
        self_only: bool = False,
        pretty_print: bool = True,
        *,
        precision: int = 17,
        zero_threshold: float = 0.0,
        filename_with_hash: bool = False,
    ) -> str:
        """XML text of this element (with its subtree and attached models unless
        `self_only`: then its tag and attributes alone, '...' standing for its
        children). Numbers keep their source text, or are written with `precision`
        significant digits (17: exact); with `precision` below 17 or a `zero_threshold`
        every real number is rewritten, those smaller in magnitude than `zero_threshold`
        as 0 (as in dm_control). Files are named as `get_assets()` names them: plain
        names, or dm_control's '<name>-<sha1>.ext' with `filename_with_hash`. Raises
        mjcf errors for missing required attributes and dangling references."""

        return above.to_xml_string(
            _element(self),
            _model_of(prefix_root),
            self_only,
            pretty_print,
            precision,
            zero_threshold=zero_threshold,
            filename_with_hash=filename_with_hash,
        )

    def __str__(self) -> str:
        """The element alone, as dm_control shows it: '<body name="arm">...</body>' (the
        dots standing for its children), '<geom size="0.1"/>'."""
        return self.to_xml_string(self_only=True, pretty_print=False)

    def __repr__(self) -> str:
        """The element's start tag as written, or where it is when it cannot be written
        (a reference to a removed element ...): a repr never raises."""
        try:
            return f"MJCF Element: {self.to_xml_string(self_only=True, pretty_print=False)}"
        except Exception as error:  # a repr must not raise, whatever failed
            reason = (
                str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
            )
            return f"MJCF Element: {_element(self).path} (not writable: {reason})"
