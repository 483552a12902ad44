"""Writing a model as MJCF text, with its attached models composed in.

    xml = model.to_xml_string()                    # what a user saves or reads
    xml, assets = serializer.serialize(model)      # with the files it names (get_assets)
    xml, assets, composed, owners = serializer.serialize_for_compile(model)  # compiling

Text read from a file is written back unchanged, values set from Python with `precision`
significant digits (17: exactly); fewer digits or a `zero_threshold` rewrite every real
number, as dm_control does. Attached models are written where they are attached, their
other sections after the parent's, as `mjcf.compose.composition` says (names scoped ...).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol, cast

from mjcf import errors
from mjcf.compose import attachment, composition, defaults
from mjcf.io.attribute_text import AttributeWriter
from mjcf.io.file_names import FileNamer
from mjcf.io.parser import MAX_DEPTH
from mjcf.schema.values import escape
from mjcf.tree import assets as _assets
from mjcf.tree import bulk
from mjcf.tree.builder import cache_text
from mjcf.tree.element import stored_attributes, tree_children, written_empty
from mjcf.tree.root import own_version, section_of

if TYPE_CHECKING:
    from mjcf.compose import settings
    from mjcf.schema import AttributeSpec, ElementSpec
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement

# Sections in the order they are written: settings first, then what they affect.
_SECTION_ORDER = (
    "compiler", "option", "size", "statistic", "visual", "extension", "custom",
    "default", "asset", "worldbody", "deformable", "contact", "equality", "tendon",
    "actuator", "sensor", "keyframe",
)  # fmt: skip
_SETTINGS = frozenset({"compiler", "option", "size", "statistic", "visual"})
# One indent for each depth MuJoCo reads (mjcf.io.parser.MAX_DEPTH): a deeper element is
# refused (see `_Writer._element_writer`'s `write`).
_INDENTS = tuple("  " * depth for depth in range(MAX_DEPTH))
_NO_INDENTS = ("",) * MAX_DEPTH
_FRAME_SPEC = attachment.FRAME_SPEC


class _Write(Protocol):
    """Writes one element and its subtree (see `_Writer._element_writer`)."""

    def __call__(self, element: Element, depth: int, override: dict | None = None) -> None: ...


@bulk.whole_tree
def serialize(
    root: RootElement,
    precision: int = 17,
    pretty_print: bool = True,
    zero_threshold: float = 0.0,
    filename_with_hash: bool = False,
) -> tuple[str, dict[str, bytes]]:
    """The XML of a whole model and the `{file name: contents}` of the files it names,
    as `mujoco.MjModel.from_xml_string` takes them (see `mjcf.io.file_names.FileNamer`)."""
    files = FileNamer(root, hashed=filename_with_hash)
    writer = _Writer(root, precision, pretty_print, files, False, zero_threshold)
    writer.write_root()
    if not filename_with_hash:
        writer.composed.file_names = files
    return "".join(writer.parts), files.contents()


@bulk.whole_tree
def file_name_of(root: RootElement, asset: _assets.Asset) -> str | None:
    """The name `asset` is written under in the output of `root` (`to_xml_string`,
    `get_assets`, the exports), or None if that output does not write it or `root`
    cannot be written. The names of an output are found once while no model changes."""
    composed = composition.composition_of(root)
    if composed.file_names is None:
        files = FileNamer(root)
        writer = _Writer(root, 17, False, files, False)
        try:
            writer.write_root()
        except errors.Error:  # writing the model raises it, where it matters
            return None
        composed.file_names = files
    return composed.file_names.name_of(asset)


@bulk.whole_tree
def serialize_for_compile(
    root: RootElement, share_assets: bool = True
) -> tuple[str, dict[str, bytes], composition.Composition, list[Element | None]]:
    """What MuJoCo compiles: the XML with every element named, files on disk by their
    absolute path (MuJoCo reads them and caches their meshes) and other assets under a
    flat unique name, those assets, the composition (how elements are named), and the
    element written on each line. Written once for each composition: compiling a model
    again while no model changed writes nothing. Copies' meshes and textures are written
    once unless not `share_assets` (see `mjcf.compose.sharing`)."""
    composed = composition.composition_of(root, for_compile=True, share_assets=share_assets)
    if composed.compiled_text is None:
        files = FileNamer(root, by_path=True)
        writer = _Writer(root, 17, True, files, for_compile=True, share_assets=share_assets)
        writer.write_root()
        composed.compiled_text = ("".join(writer.parts), files.contents(), writer.owners)
    xml, assets, owners = composed.compiled_text
    return xml, dict(assets), composed, owners


@bulk.whole_tree
def to_xml_string(
    element: Element,
    prefix_root: RootElement | None,
    self_only: bool,
    pretty_print: bool,
    precision: int,
    zero_threshold: float = 0.0,
    filename_with_hash: bool = False,
) -> str:
    """XML text of `element` (see `Element.to_xml_string`)."""
    output_root = prefix_root or element.root
    files = FileNamer(output_root, hashed=filename_with_hash)
    writer = _Writer(output_root, precision, pretty_print, files, False, zero_threshold)
    if element is output_root and not self_only:
        writer.write_root()
    else:
        context = writer.context_of(element.root)
        if self_only:
            tag, text = writer.tag_of(element), writer.attributes(element, context)
            children = tree_children(element) or isinstance(element, attachment.AttachmentFrame)
            writer.parts.append(f"<{tag}{text}>...</{tag}>" if children else f"<{tag}{text}/>")
        else:
            writer.element(element, 0, context)
            if not writer.parts:  # an empty element left out of a model is still asked for
                writer.parts.append(f"<{writer.tag_of(element)}/>")
    return "".join(writer.parts)


def attribute_text(
    element: Element, attribute: AttributeSpec, prefix_root: RootElement | None
) -> str:
    """One attribute as it is written to XML."""
    output_root = prefix_root or element.root.namescope.root.model
    writer = _Writer(output_root, 17, False, FileNamer(output_root), False)
    return writer.value_text(
        element,
        attribute,
        stored_attributes(element)[attribute.name],
        writer.context_of(element.root),
    )


def _refers_out(element: Element) -> bool:
    """Whether a reference of `element` holds an element of another model, whose written
    name changes with that model (an element of its own model changes with it)."""
    model = element.root
    references = element.spec.references
    for name, value in stored_attributes(element).items():
        if type(value) is str or name not in references:
            continue  # names as text (all of them, in a model read from a file)
        for item in value if isinstance(value, list) else (value,):
            if type(item) is not str and item.root is not model:
                return True
    return False


class _Writer(AttributeWriter):
    """Accumulates XML fragments in `parts` (the attributes' text: `AttributeWriter`)."""

    def __init__(
        self,
        root: RootElement,
        precision: int,
        pretty_print: bool,
        files: FileNamer,
        for_compile: bool,
        zero_threshold: float = 0.0,
        share_assets: bool = True,
    ) -> None:
        composed = composition.composition_of(root, for_compile, share_assets)
        super().__init__(precision, zero_threshold, files, composed)
        self.root = root
        self.pretty = pretty_print
        self.for_compile = for_compile
        self.parts: list[str] = []
        self.owners: list[Element | None] = []  # the element each fragment (line) writes
        self._indents = _INDENTS if pretty_print else _NO_INDENTS
        self._newline_text = "\n" if pretty_print else ""
        self._writers: dict[composition.ModelContext, _Write] = {}

    def context_of(self, model: RootElement) -> composition.ModelContext:
        return self.composed.context(model)

    def tag_of(self, element: Element) -> str:
        if isinstance(element, attachment.AttachmentFrame):
            return "body" if element.compiles_to_body() else "frame"
        return element.spec.tag

    # -- whole model ------------------------------------------------------------------

    def write_root(self) -> None:
        root = self.root
        self.composed.check()
        newline = "\n" if self.pretty else ""
        name = stored_attributes(root).get("model")
        self._emit(f'<mujoco model="{escape(name)}">{newline}' if name else f"<mujoco>{newline}")
        sections = {s.spec.tag: s for s in tree_children(root)}
        for tag in _SECTION_ORDER:
            section = sections.pop(tag, None)
            if section is not None:
                self.section(section)
        for section in sections.values():  # sections of a newer MuJoCo, written last
            self.section(section)
        self._emit("</mujoco>" + newline)

    def section(self, section: Element) -> None:
        if not (
            tree_children(section) or stored_attributes(section) or self.composed.has_attachments
        ):
            return  # an empty section of a model written on its own: nothing to write
        tag = section.spec.tag
        root_context = self.context_of(self.root)
        if tag == "compiler" or (tag in _SETTINGS and self.composed.has_attachments):
            merged = self.composed.merged_settings(tag)
            self._write_merged(section.spec, merged, 1)
        elif tag == "default":
            mark = self._open(section, 1, root_context)
            for context, default in self.composed.default_roots():
                self._default_body(default, context)
            self._close(section, 1, mark)
        elif tag == "keyframe":
            keys = self.composed.keyframes()
            mark = self._open(section, 1, root_context)
            for key_element, context, override in keys:
                self.element(key_element, 2, context, override)
            self._close(section, 1, mark)
        else:
            mark = self._open(section, 1, root_context)
            self.children(tree_children(section), 2, root_context)
            if tag == "asset":
                for context in self.composed.attached_contexts():
                    self.children(self.composed.written_assets(context), 2, context)
            elif tag != "worldbody":
                for context in self.composed.attached_contexts():
                    self.children(tree_children(section_of(context.model, tag)), 2, context)
            self._close(section, 1, mark)

    def _default_body(self, default: Element, context: composition.ModelContext) -> None:
        """The contents of a model's global default class, inside a class named for its
        scope when it must be kept apart from the other models' defaults. Late settings
        (`defaults.LateDefault`) begin a new top-level `<default>` section, or, inside a
        named class, a class nested in the one before, which the model's elements use."""
        groups: list[list[Element]] = [[]]
        for child in tree_children(default):
            if type(child) is defaults.LateDefault:
                groups.append([])
            groups[-1].append(child)
        name = context.main_class_written
        if name is None:
            for number, group in enumerate(groups):
                if number:  # a later top-level section, as MuJoCo reads it
                    self._emit(f"{self._indent(1)}</default>{self._newline()}")
                    self._emit(f"{self._indent(1)}<default>{self._newline()}")
                self.children(group, 2, context)
            return
        if len(groups) == 1:
            opening = f'{self._indent(2)}<default class="{escape(name)}"'
            self._emit(opening + ">" + self._newline())
            start = len(self.parts)
            self.children(tree_children(default), 3, context)
            if len(self.parts) == start:
                self._unemit()
                self._emit(opening + "/>" + self._newline())
            else:
                self._emit(self._indent(2) + "</default>" + self._newline())
            return
        for number, group in enumerate(groups):
            written = name if number == 0 else defaults.late_class_name(name, number)
            indent = self._indent(2 + number)
            self._emit(f'{indent}<default class="{escape(written)}">{self._newline()}')
            self.children(group, 3 + number, context)
        for number in range(len(groups) - 1, -1, -1):
            self._emit(f"{self._indent(2 + number)}</default>{self._newline()}")

    def _write_merged(self, spec: ElementSpec, merged: settings.MergedSettings, depth: int) -> None:
        """A settings element merged over models, and its once-only children; left out
        when nothing in it is set."""
        tag = spec.tag
        text = "".join(
            f' {name}="{escape(self._number_text(spec.attributes[name], value))}"'
            if self.reformat and spec.attributes[name].converter.reals
            else f' {name}="{escape(value)}"'
            for name, value in merged.attributes.items()
        )
        self._emit(f"{self._indent(depth)}<{tag}{text}>{self._newline()}")
        start = len(self.parts)
        for child_tag, child in merged.children.items():
            self._write_merged(spec.children[child_tag], child, depth + 1)
        if len(self.parts) > start:
            self._emit(f"{self._indent(depth)}</{tag}>{self._newline()}")
            return
        self._unemit()
        if text:
            self._emit(f"{self._indent(depth)}<{tag}{text}/>{self._newline()}")

    # -- elements ------------------------------------------------------------------------

    def _emit(self, fragment: str, owner: Element | None = None) -> None:
        self.parts.append(fragment)
        self.owners.append(owner)

    def _unemit(self) -> None:
        self.parts.pop()
        self.owners.pop()

    def _indent(self, depth: int) -> str:
        return "  " * depth if self.pretty else ""

    def _newline(self) -> str:
        return "\n" if self.pretty else ""

    def _open(self, element: Element, depth: int, context: composition.ModelContext) -> int:
        """Write an opening tag; returns the mark `_close` needs."""
        self._emit(
            f"{self._indent(depth)}<{element.spec.tag}{self.attributes(element, context)}>"
            + self._newline(),
            element,
        )
        return len(self.parts)

    def _close(self, element: Element, depth: int, mark: int) -> None:
        if len(self.parts) == mark and not element.spec.repeated:
            opening = self.parts[-1]
            self._unemit()  # nothing inside: leave the section out, or close it at once
            if stored_attributes(element) or written_empty(element):
                self._emit(opening[: opening.rindex(">")] + "/>" + self._newline(), element)
            return
        self._emit(f"{self._indent(depth)}</{element.spec.tag}>{self._newline()}")

    def children(
        self, children: Sequence[Element], depth: int, context: composition.ModelContext
    ) -> None:
        """Write `children` of one model."""
        write = self._writer(context)
        for child in children:
            write(child, depth)

    def element(
        self,
        element: Element,
        depth: int,
        context: composition.ModelContext,
        override: dict | None = None,
    ) -> None:
        """Write `element` and its subtree (empty once-only elements are left out);
        `override` replaces attributes (see `attributes`)."""
        self._writer(context)(element, depth, override)

    def _writer(self, context: composition.ModelContext) -> _Write:
        write = self._writers.get(context)
        if write is None:
            write = self._writers[context] = self._element_writer(context)
        return write

    def _element_writer(self, context: composition.ModelContext) -> _Write:
        """The function that writes an element of `context`'s model with its subtree: one
        for every element, kept tight because it decides how close writing stays to lxml.

        An element's attribute text is cached on the element until its model changes,
        for outputs that write the model's elements alike (the context's token, the same
        number format), so writing an unchanged model again costs a lookup per element.
        Not cached: text given an override by the caller, and text that depends on more
        than the element's own model (file names, which depend on the output, and
        references to elements of other models, whose names change with those models).
        Where the context writes names and values as stored (a model written on its own:
        the common case) the text is built in one pass; elsewhere (scoped names,
        converted values) `attributes` builds it. Either way the tag is self-closing when
        nothing is inside, and an empty once-only element is left out where that changes
        nothing (`mjcf.tree.element.written_empty`)."""
        parts, owners = self.parts, self.owners
        indents, newline = self._indents, self._newline_text
        escaped_value, escaped_attributes = self._escaped_value, self._escaped_attributes
        attributes, frame, check_required = self.attributes, self._frame, self._check_required
        renamed, own_name = self.files.renamed, self._own_name
        frame_spec = _FRAME_SPEC
        generated_name, rewrite = self.composed.generated_name, context.rewrite
        as_stored = context.names_only and not self.reformat
        version = (own_version(context.model), context.token, self.precision, self.zero_threshold)

        def text_of(
            element: Element, spec: ElementSpec, depth: int, override: dict | None
        ) -> str | None:
            """The attribute text of `element` (of schema `spec`)'s tag; None for an
            attachment frame, which is written whole here."""
            # Its slot, not the reading function: a call per element costs a tenth of a write.
            attrs = element._attrs
            if spec is frame_spec:
                frame(cast(attachment.AttachmentFrame, element), depth, context)
                return None
            special = spec.file_attributes
            if as_stored and override is None and not spec.checked_on_write:
                if attrs:
                    text = "".join([
                        f' {name}="{value}"' if type(value) is str and name not in special
                        else f' {name}="{escaped_value(element, name, value, context)}"'
                        for name, value in attrs.items()
                    ])  # fmt: skip
                    # Stored text needs escaping only if it holds markup characters: rare.
                    if (
                        "&" in text
                        or "<" in text
                        or ">" in text
                        or text.count('"') != 2 * len(attrs)
                    ):
                        text = escaped_attributes(element, context, None)
                else:
                    text = ""
                identifier = spec.identifier
                if identifier is not None and identifier not in attrs:
                    name = generated_name(element, context)
                    if name is not None:  # a name that changes only with the model
                        text = f' {identifier}="{escape(name)}"' + text
                    elif element in renamed:  # named after a file written under another name
                        text += own_name(element, context)
                if not special and not (spec.references and _refers_out(element)):
                    cache_text(element, (version, text))
                return text
            if spec.checked_on_write and (
                attrs or tree_children(element) or written_empty(element)
            ):
                check_required(element)
            cacheable = override is None and not special
            if override is None:
                override = rewrite(element)
            text = attributes(element, context, override) if attrs or override else ""
            if element in renamed and not (override and spec.identifier in override):
                text += own_name(element, context)
            if cacheable and not (spec.references and _refers_out(element)):
                cache_text(element, (version, text))
            return text

        def write(element: Element, depth: int, override: dict | None = None) -> None:
            # The slots, not the reading functions: a call each per element would cost a
            # fifth of writing an unchanged model again (bench parse: write_ms).
            cached = element._text
            spec = element._spec
            if cached is not None and cached[0] == version and override is None:
                text: str | None = cached[1]
            else:
                text = text_of(element, spec, depth, override)
                if text is None:
                    return
            children = element._children
            try:
                indent = indents[depth]
            except IndexError:
                path = element.path
                if len(path) > 160:  # some 500 levels of it
                    path = f"{path[:70]} ... {path[-70:]}"
                raise errors.SchemaError(
                    f"{path}: is nested {depth + 1} elements deep when written; MuJoCo "
                    f"reads models nested at most {MAX_DEPTH} deep"
                ) from None
            if not children:
                if text or written_empty(element):
                    parts.append(f"{indent}<{spec.tag}{text}/>{newline}")
                    owners.append(element)
                return
            start = len(parts)
            parts.append(f"{indent}<{spec.tag}{text}>{newline}")
            owners.append(element)
            depth += 1
            for child in children:
                write(child, depth)
            if len(parts) == start + 1:
                parts.pop()
                owners.pop()
                if text or written_empty(element):
                    parts.append(f"{indent}<{spec.tag}{text}/>{newline}")
                    owners.append(element)
                return
            parts.append(f"{indent}</{spec.tag}>{newline}")
            owners.append(None)

        return write

    def _frame(
        self, frame: attachment.AttachmentFrame, depth: int, context: composition.ModelContext
    ) -> None:
        """An attachment frame: its own joints, then the attached model's world body."""
        child_context = self.context_of(frame.attached_model)
        tag = "body" if frame.compiles_to_body() else "frame"
        override = composition.frame_attributes(frame, child_context)
        text = self.attributes(frame, context, override)
        indent = self._indent(depth)
        newline = self._newline()
        self._emit(f"{indent}<{tag}{text}>{newline}", frame)
        for child in tree_children(frame):
            self.element(
                child, depth + 1, context, self.composed.frame_child_override(child, context)
            )
        self.children(tree_children(frame.attached_model.worldbody), depth + 1, child_context)
        self._emit(f"{indent}</{tag}>{newline}")

    def _check_required(self, element: Element) -> None:
        problem = element.spec.unmet(stored_attributes(element))
        if problem is not None:
            raise errors.AttributeValueError(f"{element.path}: {problem}")
