"""Name scopes: the one owner of the rules for names (what a valid name is, that it is
unique in its namespace, how adding, renaming and removing one changes the scope).

    scope = model.namescope
    scope.lookup('joint', 'arm/shoulder')        # scoped names reach attached models; or None
    scope.get('joint', 'arm/shoulder')           # the same, a KeyError if none (dm_control)
    scope.check_free('geom', 'tip', geom)        # NameClashError if another geom has it
    scope.add('geom', 'tip', geom)               # what Element does when a name is set

Elements, the parser and copies ask it (`rename`, `remove` ...); nothing else edits it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lxml import etree

from mjcf import errors
from mjcf.tree import references

if TYPE_CHECKING:
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

PREFIX_SEPARATOR = "/"
WORLD = "world"  # MuJoCo's name of the world body, shared by every model
_ESCAPED_SEPARATOR = "\\" + PREFIX_SEPARATOR
# Asset elements that MuJoCo names after their file when they have no name.
NAMED_AFTER_FILE = frozenset({"mesh", "texture", "hfield", "skin"})


class NameScope:
    """The namespaces of one model, and the scopes of the models attached to it.

    Every `RootElement` owns one. Names are unique within a namespace of one scope ('body',
    'geom', 'actuator', ...); an attached model keeps its own scope, which is registered in
    its parent's under the child model's name. MuJoCo sees scoped names: `arm/gripper/pad`
    is the element named 'pad' in the scope 'gripper' attached into 'arm'. A name as an
    element stores it may hold an escaped separator ('a\\/b', read with
    `escape_separators`); the scope knows it as MuJoCo sees it ('a/b').

    A model read from a file holds, for the names of elements not built yet, the lxml
    elements they will be built from (`load`); asking for such a name builds its element
    (`RootElement._resolve`), which then takes its place (`adopt`)."""

    __slots__ = (
        "_children",
        "_namespaces",
        "built_early",
        "has_escaped_names",
        "model",
        "parent",
    )

    def __init__(self, model: RootElement) -> None:
        # An element, or the lxml element of one not built yet (see `load`).
        self._namespaces: dict[str, dict[str, Element | etree._Element]] = {}
        self._children: dict[str, NameScope] = {}
        self.parent: NameScope | None = None
        self.model = model
        # True once a name written differently from how it is stored ('a\\/b') was added.
        self.has_escaped_names = False
        # {lxml element: the element built from it before its siblings}, until they are
        # built (see `mjcf.tree.element.Element._defer`).
        self.built_early: dict[Any, Element] = {}

    @property
    def name(self) -> str:
        """The model name, which is this scope's name inside its parent scope."""
        return self.model.model

    # -- the names of this model's elements -----------------------------------------------

    def get(self, namespace: str, name: str) -> Element:
        """The element called `name` (possibly scoped 'child/name'), as dm_control's
        `NameScope.get`; raises mjcf.NotFoundError (a KeyError) if there is none."""
        found = self.lookup(namespace, name)
        if found is None:
            raise errors.NotFoundError(f"model {self.name!r} has no {namespace} named {name!r}")
        return found

    def lookup(self, namespace: str, name: str) -> Element | None:
        """The element called `name` (possibly scoped 'child/name') or None. The world
        body is the body called 'world'."""
        scope = self
        if PREFIX_SEPARATOR in name:
            *path, name = split_identifier(name)
            for part in path:
                child = scope._children.get(part)
                if child is None:
                    return None
                scope = child
        return scope._holder(namespace, name)

    def _holder(self, namespace: str, name: str) -> Element | None:
        if name == WORLD and namespace == "body":
            return self.model.worldbody
        names = self._namespaces.get(namespace)
        if names is None:
            return None
        found = names.get(name)
        if isinstance(found, etree._Element):
            found = self.model._resolve(found)  # built now; it takes the name (adopt)
        return found

    def load(self, names: dict[str, dict[str, etree._Element]]) -> None:
        """Hold the names of a model just read, whose elements are built when first used:
        {namespace: {name: the lxml element of the element that has it}}, checked unique
        by the parser."""
        for namespace, table in names.items():
            held = self._namespaces.get(namespace)
            if held is None:
                self._namespaces[namespace] = table  # the parser's own: taken, not copied
            else:
                held.update(table)

    def adopt(self, named: list[tuple[str, str, Element, Any]]) -> None:
        """Each element of (namespace, name, element, xml), just built from its lxml
        element `xml`, takes the name that lxml element held (if it held it)."""
        tables = self._namespaces
        for namespace, name, element, xml in named:
            names = tables.get(namespace)
            if names is not None and names.get(name) is xml:
                names[name] = element

    def check_free(
        self, namespace: str, name: str, claimant: Element, renaming: bool = False
    ) -> None:
        """Raise mjcf.NameClashError, naming `claimant`, if `name` (as an element stores
        it) is taken in `namespace`; when `renaming`, a name `claimant` holds already is
        free for it."""
        existing = self._holder(namespace, unescape(name))
        if existing is not None and not (renaming and existing is claimant):
            raise errors.NameClashError(
                f"{claimant.path}: the name {name!r} is already used by another {namespace} "
                f"in model {self.name!r}: {existing.path}"
            )

    def add(self, namespace: str, name: str, element: Element, implicit: bool = False) -> None:
        """Record `element` under `name` (as it stores it); raises mjcf.NameClashError
        if another element has it. An `implicit` name, which MuJoCo gives an unnamed
        asset after its file, never clashes: the first element keeps it (MuJoCo reports
        repeated file names itself)."""
        names = self._namespaces.get(namespace)
        if names is None:
            names = self._namespaces[namespace] = {}
        if implicit:
            names.setdefault(name, element)
            return
        key = name
        if _ESCAPED_SEPARATOR in name:
            key = unescape(name)
            self.has_escaped_names = True
        existing = names.get(key)
        if (existing is None and key == WORLD) or isinstance(existing, etree._Element):
            existing = self._holder(namespace, key)
        if existing is not None and existing is not element:
            self.check_free(namespace, name, element)  # raises, naming both
        names[key] = element

    def remove(self, namespace: str, name: str, element: Element) -> None:
        """Forget `name` if it still belongs to `element` (references naming it hold it
        from then on: see `mjcf.tree.references`)."""
        references.before_name_change(self.model, namespace, name)
        names = self._namespaces.get(namespace)
        key = unescape(name)
        if names is not None and names.get(key) is element:
            del names[key]

    def rename(self, namespace: str, old: str | None, new: str | None, element: Element) -> None:
        """Move `element` from name `old` to `new` (either may be None: no name); raises
        mjcf.NameClashError, changing nothing, if `new` is taken."""
        if new is not None:
            self.check_free(namespace, new, element, renaming=True)
        if old is not None:
            self.remove(namespace, old, element)
        if new is not None:
            self.add(namespace, new, element)

    # -- attached scopes ------------------------------------------------------------------

    def child(self, name: str) -> NameScope | None:
        """The scope of the attached model called `name`, or None."""
        return self._children.get(name)

    def descendant(self, identifier: str) -> NameScope | None:
        """The scope of the model attached inside this one under the scoped name
        `identifier` ('arm', or 'arm/gripper' for one attached inside it; a trailing '/'
        as in a prefix, 'arm/gripper/', is allowed), or None."""
        scope = self
        if identifier.endswith(PREFIX_SEPARATOR) and not identifier.endswith(_ESCAPED_SEPARATOR):
            identifier = identifier[: -len(PREFIX_SEPARATOR)]
        for part in split_identifier(identifier):
            child = scope._children.get(part)
            if child is None:
                return None
            scope = child
        return scope

    @property
    def children(self) -> dict[str, NameScope]:
        """Scopes of the models attached directly to this one, by model name, in the
        order they were attached."""
        return self._children

    def check_child_free(self, name: str) -> None:
        """Raise mjcf.NameClashError if a model called `name` is attached to this one."""
        if name in self._children:
            raise errors.NameClashError(
                f"a model named {name!r} is already attached to model {self.name!r}; "
                "give the child model a distinct name (RootElement(model=...))"
            )

    def free_child_name(self, name: str) -> str:
        """`name` if no model attached here has it, else the first free 'name_1',
        'name_2', ... (dm_control's names for the same model file attached twice)."""
        if name not in self._children:
            return name
        number = 1
        while f"{name}_{number}" in self._children:
            number += 1
        return f"{name}_{number}"

    def add_child(self, scope: NameScope, position: int | None = None) -> None:
        """Register an attached model's scope, last (the order models were attached in)
        or at `position` among them; raises mjcf.NameClashError on a name clash."""
        self.check_child_free(scope.name)
        if position is None or position >= len(self._children):
            self._children[scope.name] = scope
        else:
            entries = list(self._children.items())
            entries.insert(position, (scope.name, scope))
            self._children = dict(entries)
        scope.parent = self

    def remove_child(self, scope: NameScope) -> int | None:
        """Forget an attached model's scope (scoped references into it hold their
        elements from then on: see `mjcf.tree.references`); returns where it was among
        them (for `add_child`), None if it was not there."""
        references.before_name_change(self.model, None, None)
        position = None
        if self._children.get(scope.name) is scope:
            position = list(self._children).index(scope.name)
            del self._children[scope.name]
        scope.parent = None
        return position

    def prefix(self, relative_to: NameScope | None = None) -> str:
        """'a/b/' for a scope attached as b inside a, relative to `relative_to` (the
        outermost scope by default); '' for the scope itself."""
        parts = []
        scope = self
        while scope.parent is not None and scope is not relative_to:
            parts.append(scope.name)
            scope = scope.parent
        if relative_to is not None and scope is not relative_to:
            raise errors.InvalidReferenceError(
                f"model {self.name!r} is not attached inside model {relative_to.name!r}"
            )
        return "".join(part + PREFIX_SEPARATOR for part in reversed(parts))

    @property
    def root(self) -> NameScope:
        """The outermost scope this one is attached into (itself when not attached)."""
        scope = self
        while scope.parent is not None:
            scope = scope.parent
        return scope


def check_identifier(name: str, element: Element) -> None:
    """Raise mjcf.NameClashError if `name`, a name of `element`, holds the separator of
    scoped names unescaped."""
    if PREFIX_SEPARATOR in name.replace(_ESCAPED_SEPARATOR, ""):
        raise errors.NameClashError(
            f"{element.path}: name {name!r} contains {PREFIX_SEPARATOR!r}, which separates "
            "the names of attached models; write it as '\\/' (or parse with "
            "escape_separators=True)"
        )


def check_model_name(name: object) -> str:
    """`name` if it can name a model (a scope); raises mjcf.NameClashError otherwise."""
    if not isinstance(name, str) or not name:
        raise errors.NameClashError(f"a model name must be a non-empty string, got {name!r}")
    if PREFIX_SEPARATOR in name:
        raise errors.NameClashError(
            f"model name {name!r} contains '/', which separates the names of attached models"
        )
    return name


def name_from_file(value: object) -> str | None:
    """The name MuJoCo gives an unnamed mesh, texture, height field or skin: its file
    name without folder and extension; None without a file."""
    if value is None:
        return None
    path = value if isinstance(value, str) else getattr(value, "name", None)
    if not path:
        return None
    base = path.replace("\\", "/").rsplit("/", 1)[-1]
    return base.rsplit(".", 1)[0] if "." in base else base


def unescape(name: str) -> str:
    """The name MuJoCo sees: an escaped separator '\\/' is a plain '/'."""
    return name.replace(_ESCAPED_SEPARATOR, PREFIX_SEPARATOR)


def split_identifier(identifier: str) -> list[str]:
    """Split 'a/b/c' into scope names and the final name; '\\/' is an escaped '/' that
    stays inside a name."""
    if "\\" not in identifier:
        return identifier.split(PREFIX_SEPARATOR)
    parts, current, i = [], [], 0
    while i < len(identifier):
        char = identifier[i]
        if char == "\\" and identifier[i + 1 : i + 2] == PREFIX_SEPARATOR:
            current.append(PREFIX_SEPARATOR)
            i += 2
            continue
        if char == PREFIX_SEPARATOR:
            parts.append("".join(current))
            current = []
        else:
            current.append(char)
        i += 1
    parts.append("".join(current))
    return parts
