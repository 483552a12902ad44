"""`Element`: one MJCF element, with its attributes as Python attributes.

    body = model.worldbody.add('body', name='arm', pos=[0, 0, 1])
    geom = body.add('geom', type='capsule', size=[0.05, 0.2])
    geom.rgba = [1, 0, 0, 1]          # validated now, against MuJoCo's schema
    geom.size                        # array([0.05, 0.2])
    body.geom[0] is geom             # repeated children by tag, indexable by name too
    model.find('geom', ...)          # see RootElement
    del geom.rgba                    # or geom.rgba = None

Every change is checked when it is made and raises an `mjcf.Error` naming the element
path and the attribute; a change that raises leaves the tree as it was. Attribute
values are never affected by default classes (see `commit_defaults`). The `class`
attribute is `dclass` in Python.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar, cast

from mjcf import assets, debugging, element_list, errors, references
from mjcf import values as _values
from mjcf.element_list import ElementList
from mjcf.element_rules import ElementRules
from mjcf.namescope import NAMED_AFTER_FILE, name_from_file
from mjcf.schema import AttributeSpec, ElementSpec
from mjcf.upcalls import ABOVE

if TYPE_CHECKING:
    from mjcf.namescope import NameScope
    from mjcf.root import RootElement

_E = TypeVar("_E", bound="Element")

# Python spellings of MJCF attribute names that are Python keywords.
_ALIASES = {"dclass": "class", "class_": "class"}


class Element(ElementRules):
    """An MJCF element. Create elements with `parent.add(tag, **attributes)`; finding,
    removing, attaching, copying and writing are `ModelOperations`; its name in its
    model's scope is kept by `ElementNames`, the rules between its values by
    `ElementRules`.

    Reading protocol: mjcf's modules read an element through `spec`, `parent`, `root` and
    `is_removed` and this module's functions `stored_attributes` (attribute name -> stored
    value: text as read, or the converted value), `tree_children`,
    `value_of(element, attribute)`, `single_child(element, tag)`, `written_empty` and
    `created_at`, read-only and typed so, and tell it of a change made in place with
    `count_change`; not through members, since an element's public names are its MJCF
    attributes'.

    Internal protocol: what the other mjcf modules may use of an element's private
    members; everything else is this module's (tests/mjcf/test_architecture.py holds every
    module to it, and lists who may use each). `_spec`, `_parent`, `_attrs` and
    `_children` are what the reading functions return, for the modules this one imports
    (which cannot import them) and the writer's per-element loop; `_source` is where
    debug mode saw it made (`created_at`), set by the parser and copies. The tree
    builders count an element made by reading `parent.<tag>` as put there with `_keep()`.
    Only the modules that build or rewrite trees (parser, copying, default_sections,
    defaults, attachment, root, global_settings) make elements with `_make`, fill
    `_attrs` and `_children` of new elements or commit checked values into them, then
    record names with `_register()`; `_cut()` and `_unregister_subtree()` take elements
    out; `mjcf.references` replaces references held as text in `_attrs` by the elements
    they name; `mjcf.global_settings` gives the settings elements of attached models the
    `_attrs` of the outermost model's (one storage, shared), and makes them its
    `SharedSettings` and back (`change_class`). `_text` is the serializer's
    cache: ((model version, context token, number format), attribute text) of its last
    write.

    Elements read from a file are built when first used: the parser gives a section the
    lxml element it was read from with `_defer(xml)`, and the section's children (and
    theirs, level by level) are made from it when `_children` is first read, each with
    its `_xml`, the lxml element it is made from (None for elements made otherwise). A
    model's name scope holds the lxml elements of names not built yet, which
    `RootElement._resolve` builds (with `_child_built_from`, only the elements on the
    way). Reading `_children` (as every walk of the tree does) is all it takes: nothing
    else changes.
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
        early = self._root._early
        named: list[tuple[str, str, Element]] = []
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
            early = self._root._early
            child = early.get(xml)
            if child is None:
                named: list[tuple[str, str, Element]] = []
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

    def _attribute_spec(self, name: str, action: str = "set") -> AttributeSpec:
        """The schema of attribute `name`; raises mjcf.UnknownAttributeError (an
        AttributeError) saying what failed, in dm_control's words inside ours: `action`
        is 'set', 'read' (or delete) or 'give' (an attribute given to `add` or
        `set_attributes`)."""
        spec = self._spec
        attribute = spec.attributes.get(_ALIASES.get(name, name))
        if attribute is None:
            known = [*spec.attributes, "dclass" if "class" in spec.attributes else ""]
            suggestion = _values.suggest(name, [k for k in known if k])
            if action == "give":
                problem = f"{name!r} is not a valid attribute of <{spec.tag}>{suggestion}"
            elif action == "read":
                problem = f"<{spec.tag}> object has no attribute {name!r}{suggestion}"
            elif name in spec.children:
                problem = (
                    f"can't set attribute {name!r}: <{name}> is a child element of "
                    f"<{spec.tag}>; set its attributes instead"
                )
            else:
                problem = f"can't set attribute {name!r}: <{spec.tag}> has no such attribute"
                problem += suggestion
            raise errors.UnknownAttributeError(f"{self.path}: {problem}")
        return attribute

    def __getattr__(self, name: str) -> Any:
        if name[:1] == "_":  # private names never reach the schema
            if name == "_children":
                return self._build_children()
            if name == "_xml":  # unpickled: built already
                return None
            raise AttributeError(name)
        spec = self._spec
        attribute = spec.attributes.get(_ALIASES.get(name, name))
        if attribute is not None:
            return self._get_value(attribute)
        child_spec = spec.children.get(name.rstrip("_"))
        if child_spec is not None:
            return self.get_children(child_spec.tag)
        known = list(spec.attributes) + list(spec.children)
        raise errors.UnknownAttributeError(
            f"{self.path}: <{spec.tag}> object has no attribute or child {name!r}"
            + _values.suggest(name, known)
        )

    def _get_value(self, attribute: AttributeSpec) -> Any:
        value = self._attrs.get(attribute.name)
        if value is None or type(value) is not str:
            return value
        converter = attribute.converter
        if converter.lazy:
            converted = self._convert(attribute, value, from_text=True)
            if converted is None:  # blank text, which MuJoCo reads as not set
                return None
            value = _values.track(converted, self)
            self._attrs[attribute.name] = value
        elif converter.refers:
            value = references.read(self, attribute, value)
        elif converter.files and value:  # an empty one names no file, for MuJoCo
            self._attrs[attribute.name] = value = assets.resolve(self, attribute.name, value)
        return value

    def _convert(self, attribute: AttributeSpec, value: Any, from_text: bool = False) -> Any:
        try:
            if from_text:
                return attribute.converter.from_text(value)
            return attribute.converter.from_python(value)
        except _values.InvalidValue as error:
            raise errors.AttributeValueError(f"{self.path}: {attribute.name!r} {error}") from None

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
        if name not in spec.attributes and name not in _ALIASES and name in spec.children:
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

    def _set_attribute(self, attribute: AttributeSpec, value: Any) -> None:
        """Set one attribute from a Python value; None (or a text MuJoCo reads as not
        set, such as an empty name) removes it."""
        if value is not None:
            value = self._convert(attribute, value)
            if value is not None and attribute.name in self._spec.rule_names:
                self._check_rules({attribute.name}, ())
            if value is not None:
                self._check_crash([attribute.name])
        self._store(attribute, value)

    def _store(self, attribute: AttributeSpec, value: Any) -> None:
        """Store one converted value (None removes the attribute)."""
        name = attribute.name
        if value is None:
            if attribute.required and name in self._attrs:
                raise errors.AttributeValueError(
                    f"{self.path}: {name!r} is required by <{self.tag}> and cannot be removed"
                )
            if attribute.converter.names:
                self._rename(None)
            if self._attrs.pop(name, None) is not None:
                self._modified()
            return
        stored = _values.track(value, self)
        converter = attribute.converter
        if converter.names:
            self._check_name(stored)
            self._rename(stored)
        elif converter.refers:
            self._check_reference(attribute, stored)
            stored = references.stored(self, attribute, stored)
        elif converter.files:
            if isinstance(stored, assets.Asset):
                assets.claim(stored, self)
            if self._spec.tag in NAMED_AFTER_FILE:
                self._rename_after_file(stored)
        self._attrs[name] = stored
        self._modified()

    def get_attributes(self) -> dict[str, Any]:
        """The attributes that are set, as Python values (`class` under 'dclass')."""
        return {
            ("dclass" if name == "class" else name): self._get_value(self._spec.attributes[name])
            for name in self._attrs
        }

    def set_attributes(self, **attributes: Any) -> None:
        """Set several attributes at once; if any is invalid, none is set."""
        converted = self._prepare(attributes)
        self._apply(converted)

    def _prepare(self, attributes: dict[str, Any]) -> list[tuple[AttributeSpec, Any]]:
        """Convert and check every attribute without changing anything."""
        converted = []
        for name, value in attributes.items():
            attribute = self._attribute_spec(name, "give")
            if value is None:
                converted.append((attribute, None))
                continue
            stored = _values.track(self._convert(attribute, value), self)
            if stored is None:
                converted.append((attribute, None))
                continue
            if attribute.converter.names:
                self._check_name(stored)
                self._check_free(stored)
            elif attribute.converter.refers:
                self._check_reference(attribute, stored)
            converted.append((attribute, stored))
        if self._spec.rule_names:
            setting = {a.name for a, value in converted if value is not None}
            if not self._spec.rule_names.isdisjoint(setting):
                self._check_rules(setting, [a.name for a, value in converted if value is None])
        self._check_crash([a.name for a, value in converted if value is not None])
        return converted

    def _apply(self, converted: list[tuple[AttributeSpec, Any]]) -> None:
        # References last: a name is resolved in the namespace the new values select.
        for attribute, stored in sorted(converted, key=lambda item: item[0].converter.refers):
            self._store(attribute, stored)

    # -- references ------------------------------------------------------------------------

    def _check_reference(self, attribute: AttributeSpec, value: Any) -> None:
        items = value if isinstance(value, list) else [value]
        namespace = attribute.reference_namespace(self._attrs)
        for item in items:
            if (
                isinstance(item, Element)
                and namespace is not None
                and item._spec.namespace != namespace
            ):
                raise errors.InvalidReferenceError(
                    f"{self.path}: {attribute.name!r} refers to a {namespace}, got "
                    f"{item.path} (a {item._spec.namespace or item.tag})"
                )

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
            + _values.suggest_child(tag, self._spec.children)
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
                tag, [_ALIASES.get(n, n) for n, v in attributes.items() if v is not None]
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
        converted = element._prepare(attributes)
        element._apply_unregistered(converted)
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

    def _apply_unregistered(self, converted: list[tuple[AttributeSpec, Any]]) -> None:
        for attribute, stored in converted:
            if stored is not None:
                if isinstance(stored, assets.Asset):
                    assets.claim(stored, self)
                self._attrs[attribute.name] = stored
        for attribute, stored in converted:
            if stored is not None and attribute.converter.refers:
                self._attrs[attribute.name] = references.stored(self, attribute, stored)

    def _single_child(self, tag: str) -> Element | None:
        for child in self._children:
            if child._spec.tag == tag:
                return child
        return None

    def get_children(self, tag: str) -> Any:
        """Children with `tag`: an `ElementList` for repeated elements (for a top-level
        section, with those of attached models: see `mjcf.element_list`), or the single
        child for elements that may appear once: created empty on first access, but for
        those absent until added (a body's `inertial` and `freejoint`: None)."""
        spec = self._child_spec(tag)
        if spec.repeated:
            return ElementList(element_list.children(self, tag), self._root)
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
        those of attached models: see `mjcf.element_list`)."""
        return element_list.children(self)

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

    def __dir__(self) -> list[str]:
        names = set(super().__dir__())
        names.update(_ALIASES.get(n, n) for n in self._spec.attributes if n != "class")
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
# (`mjcf.element._ElementImpl`, e.g. `MjcfElement = mjcf.element._ElementImpl`).
_ElementImpl = Element


# -- reading the tree: what mjcf's modules read of any element ------------------------------
# With the properties `spec`, `parent` and `root`, these are how mjcf's other modules read an
# element; the element's attribute names are MJCF's, so they are functions, not members.
# Changing what they return is the tree builders' (see `Element`'s internal protocol).


def stored_attributes(element: Element) -> Mapping[str, Any]:
    """The attributes `element` has set, by MJCF name (`class`, not `dclass`), as it stores
    them: text as read from a file until first used, else the converted value (see
    `mjcf.values`); a live view, not a copy."""
    return element._attrs


def tree_children(element: Element) -> Sequence[Element]:
    """The children of `element` in its own model's tree, in order (not those of models
    attached into it: see `Element.all_children`); a live view, not a copy."""
    return element._children


def value_of(element: Element, attribute: AttributeSpec) -> Any:
    """The value of `element`'s attribute `attribute` as `getattr(element, name)` returns
    it (None if unset), converting and resolving text as read once (see `mjcf.values`)."""
    return element._get_value(attribute)


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
    if debug mode was on then, else None (see `mjcf.debugging`)."""
    return element._source


# -- changing the tree: what mjcf's modules tell an element --------------------------------


def count_change(element: Element) -> None:
    """Count a change of `element`'s model made in place (not through the element's own
    setters, which count theirs), so that its version grows (see `RootElement.version`)."""
    element._modified()


def change_class(element: Element, cls: type[Element]) -> None:
    """Make `element` an instance of `cls`: `Element`, or a subclass of it with no slots
    of its own (`mjcf.global_settings.SharedSettings`), keeping everything it holds."""
    element.__class__ = cls


def _from_xml(parent: Element, xml: Any, named: list[tuple[str, str, Element]]) -> Element:
    """A new element, a child of `parent`, built from its lxml element `xml` (see
    `Element._defer`); (namespace, name, element) appended to `named` if it has a name."""
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
            named.append((namespace, name, child))
    return child


if TYPE_CHECKING:
    # To the type checker a _Fresh is the Element it becomes: same slots, same types.
    _Fresh = Element
else:

    class _Fresh(ElementRules):
        """An element being built from its lxml element: the slots of `Element`, set as
        plain attributes (see `_from_xml`)."""

        __slots__ = Element.__slots__


def __getattr__(name: str) -> Any:
    """`mjcf.element.RootElement`, where dm_control code finds it (defined in `mjcf.root`)."""
    if name == "RootElement":
        return ABOVE.root_class
    raise AttributeError(f"module 'mjcf.element' has no attribute {name!r}")
