"""`Element`: one MJCF element, with its attributes as Python attributes.

    body = model.worldbody.add('body', name='arm', pos=[0, 0, 1])
    geom = body.add('geom', type='capsule', size=[0.05, 0.2])
    geom.rgba = [1, 0, 0, 1]          # validated now, against MuJoCo's schema
    body.geom[0] is geom             # repeated children by tag, indexable by name too
    del geom.rgba                    # or geom.rgba = None; `class` is `dclass` in Python

Every change is checked when made; one that fails raises an `mjcf.Error` naming the element
path and attribute, the tree unchanged. Defaults never change values (`commit_defaults`).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar, cast

from mjcf import errors
from mjcf.schema import ElementSpec
from mjcf.schema.suggestions import suggest, suggest_child
from mjcf.tree import debugging
from mjcf.tree.element_list import OWN_SECTIONS, ElementList, attached_models
from mjcf.tree.element_values import ALIASES, ElementValues, fill_new
from mjcf.tree.element_values import value_of as value_of  # one of the reading functions
from mjcf.tree.namescope import NAMED_AFTER_FILE, name_from_file

if TYPE_CHECKING:
    from mjcf.tree.namescope import NameScope
    from mjcf.tree.root import RootElement

_E = TypeVar("_E", bound="Element")


class Element(ElementValues):
    """An MJCF element. Create elements with `parent.add(tag, **attributes)`. One class in
    five files: this one (what an element is: its slots, its place in the tree, its
    children), `ElementValues` (its attributes), `ElementChecks` (the checks of names and
    rules), `ElementNames` (its name in its model's scope) and `ModelOperations` (finding,
    removing, attaching, copying, writing: done above the tree, see `mjcf.tree.above`).

    Reading: mjcf's modules read an element through `spec`, `parent`, `root` and
    `is_removed` and this module's functions `stored_attributes` (attribute name -> stored
    value: text as read, or the converted value), `tree_children`, `single_child`,
    `written_empty` and `created_at` (and `mjcf.tree.element_values.value_of`), read-only
    and typed so, and tell it of a change made in place with `count_change`; not through
    members, since an element's public names are its MJCF attributes'. Writing without
    the setters' checks (the reader, copies, defaults, attachment) goes through
    `mjcf.tree.builder`, the one other module that writes the slots; `_text` is the
    writer's cache there: ((model version, context token, number format), attribute text).

    Elements read from a file are built when first used: the reader gives a section the
    lxml element it was read from (`builder.defer`), and the section's children (and
    theirs, level by level) are made from it when `_children` is first read, each with
    its `_xml`, the lxml element it is made from (None for elements made otherwise). A
    model's name scope holds the lxml elements of names not built yet, which `built_from`
    builds (only the elements on the way). Reading `_children` (as every walk of the tree
    does) is all it takes: nothing else changes.
    """

    __slots__ = (
        "_attrs",
        "_children",
        "_parent",
        "_root",
        "_source",
        "_spec",
        "_text",
        "_xml",
    )

    _spec: ElementSpec
    _parent: Element | None
    _root: RootElement
    _attrs: dict[str, Any]
    _children: list[Element]
    _source: Any
    _text: tuple[tuple, str] | None
    _xml: Any

    def __init__(self, *args: object, **kwargs: object) -> None:
        raise TypeError("create elements with parent.add(tag, **attributes)")

    @classmethod
    def _make(cls: type[_E], spec: ElementSpec, parent: Element | None, root: RootElement) -> _E:
        if cls is Element:  # the common case, made the fast way (see _from_xml)
            fresh = _Fresh()
            fresh._spec = spec
            fresh._parent = parent
            fresh._root = root
            fresh._attrs = {}
            fresh._children = []
            fresh._source = debugging.creation_site()
            fresh._text = None
            fresh._xml = None
            fresh.__class__ = Element
            return cast(_E, fresh)  # cls is Element
        element = object.__new__(cls)
        setter = object.__setattr__
        setter(element, "_spec", spec)
        setter(element, "_parent", parent)
        setter(element, "_root", root)
        setter(element, "_attrs", {})
        setter(element, "_children", [])
        setter(element, "_source", debugging.creation_site())
        setter(element, "_text", None)
        setter(element, "_xml", None)
        return element

    # -- elements built when first used ----------------------------------------------------

    def _defer(self, xml: Any) -> None:
        """Make this element's children from lxml element `xml` (checked by the parser)
        when they are first used, instead of now."""
        object.__setattr__(self, "_xml", xml)
        object.__delattr__(self, "_children")

    def _build_children(self) -> list[Element]:
        """This element's children, made now from its lxml element (see `_defer`): each
        with its attributes as read, its own children deferred, its name's lxml element
        in the name scope replaced by it; children built early (`_child_built_from`)
        take their places."""
        early = self._root.namescope.built_early
        named: list[tuple[str, str, Element, Any]] = []
        if early:
            children = [
                early.pop(xml) if xml in early else _from_xml(self, xml, named) for xml in self._xml
            ]
        else:
            children = [_from_xml(self, xml, named) for xml in self._xml]
        object.__setattr__(self, "_children", children)
        if named:
            self._root.namescope.adopt(named)
        return children

    def _child_built_from(self, xml: Any) -> Element | None:
        """The child of this element built from lxml element `xml` (a child of its own
        lxml element), built now if it is not yet: alone, its siblings left for when
        `_children` is first read, so that finding one element deep in a model just
        read builds only the elements above it."""
        try:
            children = object.__getattribute__(self, "_children")
        except AttributeError:  # not built: build that one child early
            early = self._root.namescope.built_early
            child = early.get(xml)
            if child is None:
                named: list[tuple[str, str, Element, Any]] = []
                child = early[xml] = _from_xml(self, xml, named)
                if named:
                    self._root.namescope.adopt(named)
            return child
        for child in children:
            if child._xml is xml:
                return child
        return None

    def __getstate__(self) -> tuple[None, dict[str, Any]]:
        """Pickled: every slot, the children built first, without the lxml element."""
        self._children  # noqa: B018 - built, if they are not yet
        state = {}
        for cls in type(self).__mro__:
            for name in getattr(cls, "__slots__", ()):
                if name != "_xml" and name not in state:
                    with contextlib.suppress(AttributeError):  # a slot never set
                        state[name] = object.__getattribute__(self, name)
        return None, state

    # -- identity and place in the tree ---------------------------------------------------

    @property
    def tag(self) -> str:
        """The XML tag, e.g. 'geom'."""
        return self._spec.tag

    @property
    def spec(self) -> ElementSpec:
        """The schema of this element in its place of the tree."""
        return self._spec

    @property
    def parent(self) -> Element | None:
        """The parent element (None for a root, or after `remove()`)."""
        return self._parent

    @property
    def root(self) -> RootElement:
        """The model (`RootElement`) this element belongs to."""
        return self._root

    @property
    def namescope(self) -> NameScope:
        """The name scope of this element's model."""
        return self._root.namescope

    @property
    def is_removed(self) -> bool:
        """Whether this element was removed from its model (by `remove()` of itself or of
        an ancestor, or, for an attachment frame, by detaching its model)."""
        return self is not self._root and not self._is_registered()

    def _is_registered(self) -> bool:
        """Whether this element is part of its model's tree (not removed)."""
        element: Element = self
        while element._parent is not None:
            element = element._parent
        return element is self._root

    @property
    def identifier(self) -> str | None:
        """This element's name (its class for a default), or the name MuJoCo gives
        an unnamed mesh/texture/hfield/skin after its file; None if unnamed."""
        spec = self._spec
        if spec.identifier is None:
            return None
        value = self._attrs.get(spec.identifier)
        if value is None and spec.tag in NAMED_AFTER_FILE:
            return name_from_file(self._attrs.get("file"))
        return value

    @property
    def path(self) -> str:
        """Where this element is, for messages: '<worldbody>/<body name="arm">/<geom>'."""
        parts = []
        element: Element | None = self
        while element is not None and element._parent is not None:
            parts.append(element._describe())
            element = element._parent
        model = self._root._attrs.get("model")
        prefix = f"model {model!r}: " if model and element is self._root else ""
        if element is not self._root and element is not None:
            parts.append(element._describe())  # the top of the removed subtree
            prefix = "(removed) "
        return prefix + "/".join(reversed(parts)) if parts else prefix + "<mujoco>"

    def _describe(self) -> str:
        spec = self._spec
        ident = self._attrs.get(spec.identifier) if spec.identifier else None
        if isinstance(ident, str):
            return f'<{spec.tag} {spec.identifier}="{ident}">'
        return f"<{spec.tag}>"

    # -- attributes ----------------------------------------------------------------------

    def __getattr__(self, name: str) -> Any:
        if name[:1] == "_":  # private names never reach the schema
            if name == "_children":
                return self._build_children()
            if name == "_xml":  # unpickled: built already
                return None
            raise AttributeError(name)
        spec = self._spec
        attribute = spec.attributes.get(ALIASES.get(name, name))
        if attribute is not None:
            return self._get_value(attribute)
        child_spec = spec.children.get(name.rstrip("_"))
        if child_spec is not None:
            return self.get_children(child_spec.tag)
        known = list(spec.attributes) + list(spec.children)
        raise errors.UnknownAttributeError(
            f"{self.path}: <{spec.tag}> object has no attribute or child {name!r}"
            + suggest(name, known)
        )

    def __setattr__(self, name: str, value: Any) -> None:
        if name[:1] == "_":
            object.__setattr__(self, name, value)
            return
        self._set_attribute(self._attribute_spec(name), value)

    def __delattr__(self, name: str) -> None:
        """`del element.attribute` removes an attribute; `del element.child` removes a
        child that may appear once (`del body.inertial`), as `child.remove()`."""
        if name[:1] == "_":
            object.__delattr__(self, name)
            return
        spec = self._spec
        if name not in spec.attributes and name not in ALIASES and name in spec.children:
            if spec.children[name].repeated:
                raise errors.UnknownAttributeError(
                    f"{self.path}: `{name}` is a collection of child elements, which cannot "
                    f"be deleted; remove each (`for child in element.{name}: child.remove()`)"
                )
            child = self._single_child(name)
            if child is not None:
                child.remove()
            return
        self._set_attribute(self._attribute_spec(name, "read"), None)

    # -- children -------------------------------------------------------------------------

    def _child_spec(self, tag: str) -> ElementSpec:
        child = self._spec.children.get(tag)
        if child is None:
            self._no_child(tag)
        return child

    def _no_child(self, tag: str) -> NoReturn:
        """Raise mjcf.SchemaError: this element cannot have a `tag` child."""
        raise errors.SchemaError(
            f"{self.path}: <{self.tag}> cannot have a <{tag}> child"
            + suggest_child(tag, self._spec.children)
            + (f"; allowed: {', '.join(self._spec.children)}" if self._spec.children else "")
            + f" (<{tag}> is not a valid child of <{self.tag}>)"
        )

    def add(self, tag: str, **attributes: Any) -> Element:
        """Add a child element `tag` with `attributes`, and return it. Raises
        mjcf.SchemaError if MJCF does not allow it here, and the errors of setting
        each attribute; nothing is added then."""
        return self.insert(tag, len(self._children), **attributes)

    def insert(self, tag: str, position: int, **attributes: Any) -> Element:
        """Like `add`, at `position` among this element's children."""
        spec = self._child_spec(tag)
        if self._spec.crashing_children:
            self._check_child(
                tag, [ALIASES.get(n, n) for n, v in attributes.items() if v is not None]
            )
        if not spec.repeated:
            existing = self._single_child(tag)
            if existing is not None:
                # A model's sections may repeat in MJCF, and MuJoCo merges them: so do we.
                section = self._parent is None and self is self._root
                if (existing._attrs or existing._children) and not section:
                    raise errors.SchemaError(
                        f"{self.path}: <{tag}> child already exists: <{self.tag}> may have "
                        f"only one <{tag}>; set its attributes instead"
                    )
                existing.set_attributes(**attributes)
                existing._keep()
                return existing
        element = self._new_child(spec)
        fill_new(element, attributes)
        element._register()  # raises NameClashError while the tree is still unchanged
        self._children.insert(position, element)
        self._modified()
        return element

    def _new_child(self, spec: ElementSpec) -> Element:
        return Element._make(spec, self, self._root)

    def _written_empty(self) -> bool:
        """Whether this element is written when it has no attributes and no children:
        one that may repeat is, and one absent until added (a free joint); another
        once-only one only if being there changes the model (`ElementSpec.matters_empty`:
        an actuator shortcut in a default class) and it was put there (read, added), not
        made by reading `parent.<tag>`."""
        spec = self._spec
        return spec.repeated or spec.on_demand or spec.matters_empty

    def _keep(self) -> None:
        """Count this element as put there, even if it was made on first access."""
        if type(self) is _OnDemand:
            object.__setattr__(self, "__class__", Element)
            self._modified()  # it is written now

    def _modified(self) -> None:
        """Count a change of this element's model (see `RootElement.version`)."""
        root = self._root
        object.__setattr__(root, "_version", root._version + 1)

    def _single_child(self, tag: str) -> Element | None:
        for child in self._children:
            if child._spec.tag == tag:
                return child
        return None

    def get_children(self, tag: str) -> Any:
        """Children with `tag`: an `ElementList` for repeated elements (for a top-level
        section, with those of attached models: see `mjcf.tree.element_list`), or the single
        child for elements that may appear once: created empty on first access, but for
        those absent until added (a body's `inertial` and `freejoint`: None)."""
        spec = self._child_spec(tag)
        if spec.repeated:
            return ElementList(self._listed_children(tag), self._root)
        child = self._single_child(tag)
        if child is None and not spec.on_demand:
            if spec.matters_empty:  # not written while it stays empty (see _OnDemand)
                child = _OnDemand._make(spec, self, self._root)
            else:
                child = self._new_child(spec)
            self._children.append(child)
        return child

    def all_children(self) -> list[Element]:
        """The direct children of this element, in order (for a top-level section, then
        those of attached models: see `mjcf.tree.element_list`)."""
        return self._listed_children()

    def iter(self) -> Iterator[Element]:
        """This element and its descendants in document order (not into attached
        models)."""
        stack = [self]
        while stack:
            element = stack.pop()
            yield element
            stack.extend(reversed(element._children))

    def _cut(self) -> Element:
        """Take this element and its subtree out of the tree, forgetting their names;
        returns the parent it had."""
        parent = self._parent
        assert parent is not None, "only an element in a tree is cut"
        self._unregister_subtree()
        parent._children.remove(self)
        object.__setattr__(self, "_parent", None)
        return parent

    def _listed_children(self, tag: str | None = None) -> list[Element]:
        """This element's children (with `tag` if given), and for a top-level section
        those of the same section of every model attached inside its model (see
        `mjcf.tree.element_list`)."""
        found = [c for c in self._children if tag is None or c._spec.tag == tag]
        root = self._root
        if self._parent is not root or self._spec.tag in OWN_SECTIONS:
            return found
        for model in attached_models(root):
            section = model.get_children(self._spec.tag)
            found.extend(c for c in section._children if tag is None or c._spec.tag == tag)
        return found

    def _children_attributes(self) -> list[tuple[str, Mapping[str, Any]]]:
        """(tag, stored attributes) of each child in this element's own tree, for the
        checks of what crashes MuJoCo (`ElementChecks._check_crash`)."""
        return [(child._spec.tag, child._attrs) for child in self._children]

    def __dir__(self) -> list[str]:
        names = set(super().__dir__())
        names.update(ALIASES.get(n, n) for n in self._spec.attributes if n != "class")
        if "class" in self._spec.attributes:
            names.add("dclass")
        names.update(self._spec.children)
        return sorted(n for n in names if n.isidentifier())


class _OnDemand(Element):
    """A once-only element whose mere presence changes the model, made empty by reading
    `parent.<tag>` (`default.position`): it is written once it has attributes or
    children, or once `add` puts it there, not while it stays as it was made, so
    that reading a default never changes what compiles."""

    __slots__ = ()

    def _written_empty(self) -> bool:
        return False


# dm_control's name for the class of every element, which code uses as a type
# (`mjcf.tree.element._ElementImpl`, e.g. `MjcfElement = mjcf.tree.element._ElementImpl`).
_ElementImpl = Element


# -- reading the tree: what mjcf's modules read of any element ------------------------------
# With the properties `spec`, `parent` and `root`, these are how mjcf's other modules read an
# element; the element's attribute names are MJCF's, so they are functions, not members.
# Changing what they return is the tree builders' (see `Element`'s internal protocol).


def stored_attributes(element: Element) -> Mapping[str, Any]:
    """The attributes `element` has set, by MJCF name (`class`, not `dclass`), as it stores
    them: text as read from a file until first used, else the converted value (see
    `mjcf.schema.values`); a live view, not a copy."""
    return element._attrs


def tree_children(element: Element) -> Sequence[Element]:
    """The children of `element` in its own model's tree, in order (not those of models
    attached into it: see `Element.all_children`); a live view, not a copy."""
    return element._children


def single_child(element: Element, tag: str) -> Element | None:
    """The child of `element` with once-only `tag` in its own model's tree, or None if it
    has none (unlike `get_children`, never made here)."""
    return element._single_child(tag)


def written_empty(element: Element) -> bool:
    """Whether `element` is written even with no attributes and no children: one that
    may repeat is, and one absent until added; another once-only one only if its presence
    changes the model and it was put there, not made by reading `parent.<tag>` (see
    `ElementSpec.matters_empty`)."""
    return element._written_empty()


def created_at(element: Element) -> debugging.SourceLocation | None:
    """Where `element` was made (the Python line, or the file and line it was read from)
    if debug mode was on then, else None (see `mjcf.tree.debugging`)."""
    return element._source


# -- changing the tree: what mjcf's modules tell an element --------------------------------


def count_change(element: Element) -> None:
    """Count a change of `element`'s model made in place (not through the element's own
    setters, which count theirs), so that its version grows (see `RootElement.version`)."""
    element._modified()


def built_from(model: RootElement, xml: Any) -> Element | None:
    """The element of `model` built from lxml element `xml` of the file it was read from,
    built now with the elements above it if they are not yet (see `Element._defer`);
    None if it is no longer in the model."""
    path = [xml, *xml.iterancestors()]
    path.pop()  # the <mujoco> element
    element: Element = model
    for step in reversed(path):
        child = element._child_built_from(step)
        if child is None:
            return None
        element = child
    return element


def _from_xml(parent: Element, xml: Any, named: list[tuple[str, str, Element, Any]]) -> Element:
    """A new element, a child of `parent`, built from its lxml element `xml` (see
    `Element._defer`); (namespace, name, element, xml) appended to `named` if it has a
    name."""
    spec = parent._spec.children[xml.tag]
    # A _Fresh takes plain slot assignments (an Element's go through its __setattr__,
    # several times slower), then becomes the Element it is.
    child = _Fresh()
    child._spec = spec
    child._parent = parent
    child._root = parent._root
    child._attrs = attrs = dict(xml.items())
    child._source = None
    child._text = None
    child._xml = xml
    if not len(xml):
        child._children = []
    child.__class__ = Element
    namespace = spec.namespace
    if namespace is not None:
        name = attrs.get(spec.identifier) if spec.identifier else None
        if name is None and spec.tag in NAMED_AFTER_FILE:
            name = name_from_file(attrs.get("file"))
        if name is not None:
            named.append((namespace, name, child, xml))
    return child


if TYPE_CHECKING:
    # To the type checker a _Fresh is the Element it becomes: same slots, same types.
    _Fresh = Element
else:

    class _Fresh(ElementValues):
        """An element being built from its lxml element: the slots of `Element`, set as
        plain attributes (see `_from_xml`)."""

        __slots__ = Element.__slots__
