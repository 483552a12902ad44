"""Readers for the reStructuredText documentation shipped in the mujoco wheel.

Two shapes of text are read, and nothing else is interpreted:

* ``XMLschema.rst``: the element tree as nested ``.. dropdown::`` blocks whose
  titles are ``:ref:`tag<anchor>` ICON`` and whose ``grid-item`` entries are
  ``:ref:`attribute<anchor>``` (:func:`parse_schema_tree`).
* ``XMLreference.rst`` and ``modeling.rst``: anchors (``.. _body-geom-size:``)
  in front of an element heading, an attribute line
  ``:at:`size`: :at-val:`real(3), "0 0 0"```, or prose; and the attribute
  definitions found inside each labelled section (:func:`parse_reference`).

This is text processing only; ``generate.py`` turns the documented value text
into attribute specifications.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

_DROPDOWN = re.compile(r"^( *)\.\. dropdown:: :ref:`([^<`]+)<([^>]+)>`\s*(.*)$")
_GRID_REF = re.compile(r"^( *):ref:`([^<`]+)<([^>]+)>`\s*$")
_ICONS = {
    "|!|": "!",
    "|?|": "?",
    "|*|": "*",
    "|@|": "@",
    ":octicon:`dot`": "dot",
    ":octicon:`sync`": "sync",
    ":octicon:`star`": "star",
}

_ANCHOR = re.compile(r"^\.\. _([^:`]+):\s*$")
_DIRECTIVE = re.compile(r"^\.\. [\w-]+::")
_SUBSTITUTION = re.compile(r"^\.\. (\|[^|]+\|) replace::\s*(.*)$")
_AT_NAME = re.compile(r":at:`([^`]+)`")
_AT_VAL = re.compile(r":at-val:`([^`]*)`")
_BOLD_DEF = re.compile(r"^\*\*(\w+) :\*\* (.+)$")
_BOLD_TITLE = re.compile(r"\*\*([\w()]+)\*\*")
_HEADING_ICON = re.compile(r"\|([!?*@])\|\s*$")
_REF = re.compile(r":ref:`(?:[^<`]*<([^>`]+)>|([^<`]+))`")
_UNDERLINE = re.compile(r"^([=\-~^'\"`#*+])\1{3,}\s*$")


@dataclass
class SchemaNode:
    """One ``.. dropdown::`` of XMLschema.rst: an element with its attributes."""

    anchor: str
    label: str
    icon: str
    attributes: list[tuple[str, str]] = field(default_factory=list)  # (name, anchor)
    children: list[SchemaNode] = field(default_factory=list)


def parse_schema_tree(text: str) -> SchemaNode:
    """Parse XMLschema.rst into the tree rooted at the ``mujoco`` element."""
    root: SchemaNode | None = None
    stack: list[tuple[int, SchemaNode]] = []
    for line in text.splitlines():
        dropdown = _DROPDOWN.match(line)
        grid_ref = _GRID_REF.match(line)
        if dropdown:
            indent, label, anchor, rest = dropdown.groups()
            icon = _ICONS.get(rest.strip())
            if icon is None:
                raise ValueError(f"XMLschema.rst: unknown icon {rest!r} on {anchor!r}")
            node = SchemaNode(anchor=anchor, label=label, icon=icon)
            while stack and stack[-1][0] >= len(indent):
                stack.pop()
            if stack:
                stack[-1][1].children.append(node)
            elif root is None:
                root = node
            else:
                raise ValueError(f"XMLschema.rst: second root element {anchor!r}")
            stack.append((len(indent), node))
        elif grid_ref:
            indent, name, anchor = grid_ref.groups()
            while stack and stack[-1][0] >= len(indent):
                stack.pop()
            if not stack:
                raise ValueError(f"XMLschema.rst: attribute {anchor!r} outside an element")
            stack[-1][1].attributes.append((name, anchor))
    if root is None:
        raise ValueError("XMLschema.rst: no dropdown found")
    return root


@dataclass
class AttributeDoc:
    """The documentation block of one attribute anchor.

    ``value`` is the text that states type and default (the contents of
    ``:at-val:`...```), or ``None`` when the block only refers elsewhere ("See
    :ref:`CSensor`", "Same as in :ref:`connect <equality-connect>`").
    """

    names: tuple[str, ...]
    value: str | None
    description: str


@dataclass
class ElementDoc:
    """An element heading: its anchor, tag, introduction and attribute anchors."""

    anchor: str
    tag: str
    icon: str
    description: str
    attribute_anchors: list[str] = field(default_factory=list)


@dataclass
class Reference:
    """Everything read from the reference-style documents."""

    attributes: dict[str, AttributeDoc] = field(default_factory=dict)
    elements: dict[str, ElementDoc] = field(default_factory=dict)
    # section label -> {attribute name: definition} for definitions in that section
    sections: dict[str, dict[str, AttributeDoc]] = field(default_factory=dict)


def refs_in(text: str) -> list[str]:
    """The targets of all ``:ref:`` roles in ``text``, in order."""
    return [explicit or bare.strip() for explicit, bare in _REF.findall(text)]


def parse_reference(text: str, into: Reference | None = None) -> Reference:
    """Parse XMLreference.rst (or modeling.rst) anchors, headings and sections."""
    parser = _ReferenceParser(text.splitlines(), into if into is not None else Reference())
    parser.run()
    return parser.reference


class _ReferenceParser:
    """One pass over a document, collecting anchors until the block they label."""

    def __init__(self, lines: list[str], reference: Reference) -> None:
        self.lines = lines
        self.reference = reference
        self.substitutions: dict[str, str] = {}
        self.levels: list[str] = []  # heading underline characters, outermost first
        self.open_sections: list[tuple[str, int]] = []  # (label, heading level)
        self.pending: list[str] = []
        self.element: ElementDoc | None = None

    def run(self) -> None:
        lines = self.lines
        index = 0
        while index < len(lines):
            line = lines[index]
            anchor = _ANCHOR.match(line)
            substitution = _SUBSTITUTION.match(line)
            if anchor:
                self.pending.append(anchor.group(1))
                index += 1
            elif substitution:
                body, index = self._indented_block(index + 1)
                self.substitutions[substitution.group(1)] = f"{substitution.group(2)} {body}"
            elif _DIRECTIVE.match(line):
                _, index = self._indented_block(index + 1)
            elif not line.strip():
                index += 1
            elif self._heading_char(index) is not None:
                self._heading(index)
                index += 2
            else:
                index = self._block(index)

    def _heading(self, index: int) -> None:
        """Record a section title, and the element it introduces if it is one.

        Anchors stacked in front of an element heading are the element's own
        anchor plus attribute anchors documented only by the element's prose
        (``default/geom``: "the attributes of the dummy geom element").
        """
        char = self._heading_char(index)
        assert char is not None
        if char not in self.levels:
            self.levels.append(char)
        level = self.levels.index(char)
        self.open_sections = [(label, lv) for label, lv in self.open_sections if lv < level]
        self.open_sections.extend((label, level) for label in self.pending)
        title = _BOLD_TITLE.search(self.lines[index])
        self.element = None
        if title and self.pending:
            # The element's own anchor is the one the others extend
            # (default-camera, default-camera-fovy, ...), not always the first.
            anchor = min(self.pending, key=len)
            intro = self._intro(index + 2)
            others = [label for label in self.pending if label != anchor]
            icon = _HEADING_ICON.search(self.lines[index])
            self.element = ElementDoc(
                anchor, title.group(1), icon.group(1) if icon else "", intro, others
            )
            self.reference.elements[anchor] = self.element
            for label in others:
                self.reference.attributes[label] = AttributeDoc((), None, intro)
        self.pending = []

    def _block(self, index: int) -> int:
        """Record an attribute definition or anchored prose; return the next index."""
        first = self.lines[index].strip()
        first = self.substitutions.get(first, first)
        bold = _BOLD_DEF.match(first)
        if bold:
            names, value = [bold.group(1)], bold.group(2).strip()
            description, end = self._indented_block(index + 1)
        elif first.startswith(":at:"):
            names = _AT_NAME.findall(first.split(":at-val:")[0])
            value = _value_of(first, names)
            description, end = self._indented_block(index + 1)
        else:
            # Prose. Anchors in front of it ("Specifying them here is
            # deprecated") have that paragraph as their only documentation.
            names, value = [], None
            description, end = self._paragraph(index)
        doc = AttributeDoc(tuple(names), value, description)
        if value is not None:
            for label, _ in self.open_sections:
                section = self.reference.sections.setdefault(label, {})
                for name in names:
                    section.setdefault(name, doc)
        intro = self.element.description if self.element is not None else ""
        for label in self.pending:
            if names and label.rsplit("-", 1)[-1] not in names:
                # An anchor run into another attribute's block (the block
                # documents other names): only the links around it can tell.
                self.reference.attributes[label] = AttributeDoc((), None, f"{description}\n{intro}")
            else:
                self.reference.attributes[label] = doc
            if self.element is not None:
                self.element.attribute_anchors.append(label)
        self.pending = []
        return end

    def _indented_block(self, start: int) -> tuple[str, int]:
        """Join the indented (or blank) lines from ``start``; return text and end index."""
        index = start
        while index < len(self.lines) and (
            not self.lines[index].strip() or self.lines[index].startswith(" ")
        ):
            index += 1
        return _join(self.lines[start:index]), index

    def _paragraph(self, start: int) -> tuple[str, int]:
        """Join the lines from ``start`` to the next blank line; return text and end."""
        index = start
        while index < len(self.lines) and self.lines[index].strip():
            index += 1
        return _join(self.lines[start:index]), index

    def _intro(self, start: int) -> str:
        """The prose after a heading, up to the next anchor or heading."""
        index = start
        while index < len(self.lines):
            if _ANCHOR.match(self.lines[index]) or self._heading_char(index) is not None:
                break
            index += 1
        return _join(self.lines[start:index])

    def _heading_char(self, index: int) -> str | None:
        """The underline character if ``lines[index]`` is a section title."""
        lines = self.lines
        if index + 1 < len(lines) and lines[index].strip():
            underline = _UNDERLINE.match(lines[index + 1])
            if underline:
                return underline.group(1)
        return None


def _join(lines: list[str]) -> str:
    """Stripped non-blank lines, one per line (lists in descriptions keep their shape)."""
    return "\n".join(line.strip() for line in lines if line.strip())


def _value_of(line: str, names: list[str]) -> str | None:
    """The type/default text of an ``:at:`` line, in any of its documented spellings."""
    at_val = _AT_VAL.search(line)
    if at_val:
        return at_val.group(1).strip()
    # ":at:`a`, :at:`b` : string, optional" -- a value written without its role.
    tail = line[line.rfind("`") + 1 :].strip()
    if names and tail.startswith(":") and tail[1:].strip():
        return tail[1:].strip()
    return None
