"""Name scopes: the names of one model's elements, by namespace, and the scopes of the
models attached to it.

Every `RootElement` owns one `NameScope`. Names are unique within a namespace of one
scope ('body', 'geom', 'actuator', ...); an attached model keeps its own scope, which is
registered in its parent's under the child model's name. MuJoCo sees scoped names:
`arm/gripper/pad` is the element named 'pad' in the scope 'gripper' attached into 'arm'.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from mjcf import errors

if TYPE_CHECKING:
    from mjcf.element import Element

PREFIX_SEPARATOR = "/"
WORLD = "world"  # MuJoCo's name of the world body, shared by every model


class NameScope:
    """The namespaces of one model, and the scopes of the models attached to it."""

    __slots__ = ("_children", "_namespaces", "model", "parent")

    def __init__(self, model: Element) -> None:
        self._namespaces: dict[str, dict[str, Element]] = {}
        self._children: dict[str, NameScope] = {}
        self.parent: NameScope | None = None
        self.model = model

    @property
    def name(self) -> str:
        """The model name, which is this scope's name inside its parent scope."""
        return self.model.model

    def namespace(self, namespace: str) -> dict[str, Element]:
        """The live `{name: element}` dict of one namespace (created empty on demand)."""
        names = self._namespaces.get(namespace)
        if names is None:
            names = self._namespaces[namespace] = {}
        return names

    def get(self, namespace: str, name: str) -> Element | None:
        """The element called `name` (possibly scoped 'child/name') or None. The world
        body is the body called 'world'."""
        if name == WORLD and namespace == "body":
            return self.model.worldbody
        scope = self
        if PREFIX_SEPARATOR in name:
            *path, name = split_identifier(name)
            for part in path:
                scope = scope._children.get(part)
                if scope is None:
                    return None
        names = scope._namespaces.get(namespace)
        return None if names is None else names.get(name)

    def register(self, namespace: str, name: str, element: Element) -> None:
        """Record `element` under `name`; raises mjcf.NameClashError if the name is taken."""
        names = self.namespace(namespace)
        existing = names.get(name)
        if existing is not None and existing is not element:
            raise errors.NameClashError(
                f"{element.path}: the name {name!r} is already used by another "
                f"{namespace} in model {self.name!r}: {existing.path}"
            )
        names[name] = element

    def unregister(self, namespace: str, name: str, element: Element) -> None:
        """Forget `name` if it still belongs to `element`."""
        names = self._namespaces.get(namespace)
        if names is not None and names.get(name) is element:
            del names[name]

    # -- attached scopes ------------------------------------------------------------------

    def child(self, name: str) -> NameScope | None:
        """The scope of the attached model called `name`, or None."""
        return self._children.get(name)

    @property
    def children(self) -> dict[str, NameScope]:
        """Scopes of the models attached directly to this one, by model name."""
        return self._children

    def add_child(self, scope: NameScope) -> None:
        """Register an attached model's scope; raises mjcf.NameClashError on a name clash."""
        name = scope.name
        if name in self._children:
            raise errors.NameClashError(
                f"a model named {name!r} is already attached to model {self.name!r}; "
                "give the child model a distinct name (RootElement(model=...))"
            )
        self._children[name] = scope
        scope.parent = self

    def remove_child(self, scope: NameScope) -> None:
        """Forget an attached model's scope."""
        if self._children.get(scope.name) is scope:
            del self._children[scope.name]
        scope.parent = None

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


def unescape(name: str) -> str:
    """The name MuJoCo sees: an escaped separator '\\/' is a plain '/'."""
    return name.replace("\\" + PREFIX_SEPARATOR, PREFIX_SEPARATOR)


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
