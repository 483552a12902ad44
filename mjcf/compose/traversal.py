"""Finding elements: by namespace and name (`find`), and all of a kind (`find_all`).

Namespaces are MuJoCo's kinds of named things ('body', 'joint' — which includes
`<freejoint>` —, 'geom', 'site', 'actuator' — every actuator tag —, 'sensor',
'default', 'mesh', ...); `find_all` also accepts a plain tag ('motor'). Order is the
order MuJoCo gives the compiled objects; attached models are searched too.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from mjcf import errors, schema
from mjcf.compose import attachment
from mjcf.schema.suggestions import suggest
from mjcf.tree import bulk
from mjcf.tree.element import tree_children
from mjcf.tree.element_list import attached_models
from mjcf.tree.root import frame_of

if TYPE_CHECKING:
    from mjcf.tree.element import Element

_TAGS = frozenset(spec.tag for spec in schema.all_specs())
ATTACHMENT_FRAME = "attachment_frame"


def find(element: Element, namespace: str, identifier: str) -> Element | None:
    """The element of `namespace` named `identifier` (scoped names reach into attached
    models) inside `element`, or None. Raises mjcf.NamespaceError for an unknown
    namespace and mjcf.NameClashError for an identifier that is not a string."""
    if not isinstance(identifier, str):
        raise errors.NameClashError(
            f"{element.path}: find({namespace!r}, ...) needs a name (str), got {identifier!r}"
        )
    found: Element | None
    if namespace == ATTACHMENT_FRAME:
        found = attachment.find_frame(element.root, identifier)
    else:
        _check_namespace(namespace, allow_tags=False)
        found = element.root.namescope.lookup(namespace, identifier)
    if found is None or element is element.root or _is_inside(found, element):
        return found
    return None


@bulk.whole_tree
def find_all(
    element: Element, namespace: str, immediate_children_only: bool, exclude_attachments: bool
) -> list[Element]:
    """Every element of `namespace` (or tag) inside `element`, in MuJoCo's order."""
    if namespace == ATTACHMENT_FRAME:
        return [
            e
            for e in walk(element, not exclude_attachments, immediate_children_only)
            if isinstance(e, attachment.AttachmentFrame)
        ]
    by_tag = _check_namespace(namespace, allow_tags=True)
    if by_tag:  # elements of that tag, but not the defaults of a class
        return [
            e
            for e in walk(element, not exclude_attachments, immediate_children_only)
            if e.spec.tag == namespace and not e.spec.key.startswith("default-")
        ]
    return [
        e
        for e in walk(element, not exclude_attachments, immediate_children_only)
        if e.spec.namespace == namespace
    ]


def walk(
    element: Element, into_attachments: bool = True, immediate_children_only: bool = False
) -> Iterator[Element]:
    """The descendants of `element` in the order MuJoCo compiles them: an attached
    model's world body contents where it is attached, and its other sections after
    those of the model it is attached to."""
    if immediate_children_only:
        yield from tree_children(element)
        return
    stack = list(reversed(tree_children(element)))
    while stack:
        current = stack.pop()
        yield current
        children = tree_children(current)
        if into_attachments and isinstance(current, attachment.AttachmentFrame):
            children = [*children, *tree_children(current.attached_model.worldbody)]
        stack.extend(reversed(children))
    if into_attachments and element is element.root:
        for child_model in attached_models(element):
            for section in tree_children(child_model):
                if section.spec.tag != "worldbody":
                    yield section
                    yield from walk(section, into_attachments=False)


def has_ancestor(element: Element, tag: str) -> bool:
    """Whether an ancestor of `element` (within its own model) has tag `tag`."""
    parent = element.parent
    while parent is not None:
        if parent.spec.tag == tag:
            return True
        parent = parent.parent
    return False


def _is_inside(element: Element, ancestor: Element) -> bool:
    current: Element | None = element
    while current is not None and current is not ancestor:
        parent = current.parent
        if parent is None and current is current.root:
            parent = frame_of(current)
        current = parent
    return current is not None


def _check_namespace(namespace: str, allow_tags: bool) -> bool:
    """Whether `namespace` is a tag rather than a namespace; raises
    mjcf.NamespaceError for neither."""
    if not isinstance(namespace, str):
        raise errors.NamespaceError(f"a namespace is a str, such as 'body', got {namespace!r}")
    if namespace in schema.NAMESPACES:
        return False
    if allow_tags and namespace in _TAGS:
        return True
    known = sorted(schema.NAMESPACES | {ATTACHMENT_FRAME})
    raise errors.NamespaceError(
        f"{namespace!r} is not a valid namespace"
        + suggest(namespace, known)
        + f"; namespaces: {', '.join(known)}"
    )
