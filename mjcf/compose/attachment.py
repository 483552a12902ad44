"""Attaching one model to another, at an `AttachmentFrame` of the parent.

    arm, gripper = mjcf.from_path('ur5e.xml'), mjcf.from_path('2f85.xml')
    frame = arm.find('site', 'attachment_site').attach(gripper)   # or body.attach, model.attach
    arm.find('actuator', '2f85/fingers_actuator')                 # scoped names
    scene.attach(arm).add('freejoint')                             # a free-floating model
    gripper.detach()                                               # or frame.detach()

The child keeps its own tree and name scope; it is attached in one place at a time (attach
a `copy.deepcopy` to use it twice), and a taken name becomes 'name_1', as in dm_control.
"""

from __future__ import annotations

from mjcf import errors, schema
from mjcf.compose import global_settings, settings
from mjcf.schema import AttributeSpec, ElementSpec
from mjcf.tree import builder
from mjcf.tree.element import Element, count_change, stored_attributes, tree_children, value_of
from mjcf.tree.element_list import attached_models
from mjcf.tree.root import RootElement, frame_of, section_of, set_frame

_ORIENTATION = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
_PLACES = frozenset({"body", "worldbody", "frame", "site"})


def _frame_spec() -> tuple[ElementSpec, frozenset[str], frozenset[str]]:
    """The schema of attachment frames: a `<frame>`'s attributes and a body's, with
    a body's joints, free joint and inertial as the only children."""
    body = schema.MUJOCO.child("worldbody").child("body")
    frame = body.child("frame")
    attributes: dict[str, AttributeSpec] = {}
    for source in (frame, body):
        for name, attribute in source.attributes.items():
            if name != "childclass":
                attributes.setdefault(name, attribute)
    children = {tag: body.child(tag) for tag in ("joint", "freejoint", "inertial")}
    spec = ElementSpec.synthesize(
        "attachment_frame", "attachment_frame", "attachment_frame", attributes, children
    )
    body_only = frozenset(body.attributes) - frozenset(frame.attributes)
    frame_only = frozenset(frame.attributes) - frozenset(body.attributes)
    return spec, body_only, frame_only


FRAME_SPEC, _BODY_ONLY, _FRAME_ONLY = _frame_spec()


class AttachmentFrame(Element):
    """Where an attached model sits in its parent: a frame with a pose, that may get
    joints (`frame.add('freejoint')`), an inertial and a name. It is written as a MuJoCo
    `<frame>` (so the child's free joints stay free), or as a `<body>` once joints or an
    inertial are added to it."""

    __slots__ = ("_attached",)

    _attached: RootElement
    # Its joints are named within the frame, scoped to the attached model as in
    # dm_control ('arm/root_x/'), so that two frames may each have a joint 'root_x'.
    _names_children_in_model = False

    @property
    def attached_model(self) -> RootElement:
        """The model attached here."""
        return self._attached

    def compiles_to_body(self) -> bool:
        """Whether this frame is written as a `<body>` (it has joints, an inertial or
        body-only attributes) rather than a `<frame>`."""
        if self._children or any(name in _BODY_ONLY for name in self._attrs):
            frame_only = [name for name in self._attrs if name in _FRAME_ONLY]
            if frame_only:
                raise errors.AttachmentError(
                    f"{self.path}: {frame_only} apply to frames only, and this attachment "
                    "frame is a body (it has joints, an inertial or body attributes)"
                )
            return True
        return False

    def detach(self) -> None:
        """Detach the attached model (see `RootElement.detach`)."""
        detach(self._attached)

    def remove(self, affect_attachments: bool = False) -> None:
        """Removing an attachment frame detaches its model."""
        detach(self._attached)

    def _describe(self) -> str:
        return f"<attachment_frame of {self._attached.model!r}>"


def attach(place: Element, child: RootElement) -> AttachmentFrame:
    """Attach model `child` at `place` (a site, body, frame or the world body) and
    return its attachment frame. Its global settings are merged into those of the
    outermost model it goes into, and shared with it from then on (see
    `mjcf.compose.global_settings`). Raises mjcf.AttachmentError for a model that is already
    attached, that would contain itself, or whose settings conflict with those of the
    models it goes into (naming every conflict); the tree is unchanged then. A child
    whose model name is taken by a model attached into the same model already is
    renamed 'name_1' (then 'name_2', ...), as dm_control does. Checks cost the same
    whatever is attached already."""
    if not isinstance(child, RootElement):
        raise errors.AttachmentError(
            f"Expected a mjcf.RootElement: only a model can be attached, got {child!r}"
        )
    if place.spec.tag not in _PLACES or isinstance(place, AttachmentFrame):
        raise errors.AttachmentError(
            f"{place.path}: models attach to a site, body, frame or worldbody, not <{place.tag}>"
        )
    if place.is_removed:
        raise errors.AttachmentError(f"{place.path}: cannot attach to a removed element")
    holder = child.parent_model
    if holder is not None:
        raise errors.AttachmentError(
            f"model {child.model!r} is already attached elsewhere (to model "
            f"{holder.model!r}); detach it first, or attach a copy "
            "(copy.deepcopy(model))"
        )
    model: RootElement | None = place.root
    while model is not None:
        if model is child:
            raise errors.AttachmentError(
                f"Cannot merge a model to itself: model {child.model!r} would be attached "
                f"inside itself ({place.path})"
            )
        model = model.parent_model
    top = place.root.root_model
    merge = global_settings.SettingsMerge(top)
    merge.add(child)
    for parent in dict.fromkeys((top, place.root)):
        merge.problems.extend(settings.compiler_problems(parent, child))
    merge.raise_problems(child, place.root)
    body = place.parent if place.spec.tag == "site" else place
    assert body is not None, "a site in the tree has a parent"
    frame = builder.new_element(AttachmentFrame, FRAME_SPEC, body, place.root)
    if place.spec.tag == "site":
        attrs = builder.attributes_to_fill(frame)
        for name in ("pos", *_ORIENTATION):
            if stored_attributes(place).get(name) is None:
                continue
            value = value_of(place, place.spec.attributes[name])
            if value is not None:  # None: blank text, which MuJoCo reads as not set
                attrs[name] = value.copy() if hasattr(value, "copy") else value
    free = place.root.namescope.free_child_name(child.model)
    if free != child.model:  # the same robot file attached twice: 'name_1', as dm_control
        child.model = free
    link(frame, child)
    builder.children_to_fill(body).append(frame)
    merge.apply()
    global_settings.share(child)
    count_change(place)
    return frame


def link(frame: AttachmentFrame, child: RootElement) -> None:
    """Make `frame` (new, of the parent model) hold model `child` (not attached): the
    one place the link between them (the frame's model, the model's frame, the parent's
    attachments and the child's scope in the parent's) is made, for `attach` and copies
    alike; `detach` undoes it, and nothing else writes it. Raises mjcf.NameClashError,
    changing nothing, if a model of `child`'s name is attached to the parent already."""
    frame.root.namescope.add_child(child.namescope)
    object.__setattr__(frame, "_attached", child)
    set_frame(child, frame)


def detach(child: RootElement) -> None:
    """Detach model `child` from the model it is attached to; raises
    mjcf.AttachmentError if it is not attached. The detached model keeps a copy of the
    global settings it shared (see `mjcf.compose.global_settings`)."""
    frame = frame_of(child)
    if frame is None:
        raise errors.AttachmentError(f"model {child.model!r} is not attached to any model")
    top = child.root_model
    builder.cut(frame)
    frame.root.namescope.remove_child(child.namescope)
    set_frame(child, None)
    global_settings.unshare(child, top)
    count_change(frame)


def remove(element: Element, affect_attachments: bool) -> None:
    """Remove `element` (and its subtree) from its model, or empty a top-level section
    (see `Element.remove`). Raises mjcf.AttachmentError if models are attached inside (or,
    for a section, into the model), unless `affect_attachments` (they are detached then),
    and mjcf.SchemaError for a model root or an element removed already. A once-only
    child of a settings section that models share (`<visual><headlight>`) is emptied in
    place, for every model sharing it, as dm_control empties it (see
    `mjcf.compose.global_settings`)."""
    parent = element.parent
    if parent is None:
        raise errors.SchemaError(
            f"{element.path}: a model root or removed element cannot be removed"
        )
    if parent.parent is None and parent is element.root:
        clear_section(element, affect_attachments)
        return
    if _shares_settings(element.root) and _is_settings_child(element):
        if element.root.namescope.children and not affect_attachments:
            _refuse_emptying(element)
        builder.attributes_to_fill(element).clear()
        count_change(element)
        return
    frames = [e for e in element.iter() if isinstance(e, AttachmentFrame)]
    if frames and not affect_attachments:
        models = ", ".join(repr(frame.attached_model.model) for frame in frames)
        raise errors.AttachmentError(
            f"{element.path}: models {models} are attached inside; detach them first, or "
            "call remove(affect_attachments=True)"
        )
    for frame in frames:
        frame.detach()
    count_change(builder.cut(element))


def clear_section(section: Element, affect_attachments: bool) -> None:
    """Empty the top-level section `section` (its attributes and children) of its model,
    and with `affect_attachments` the same section of every model attached into it
    (frames in an emptied world body are detached). Raises mjcf.AttachmentError if models
    are attached into the model and not `affect_attachments`; nothing changes then. The
    once-only children of a settings section that models share are emptied in place."""
    model = section.root
    attached = attached_models(model)
    if attached and not affect_attachments:
        _refuse_emptying(section)
    tag = section.spec.tag
    settings_children = tag in global_settings.SECTIONS and _shares_settings(model)
    for each in (*attached, model) if affect_attachments else (model,):
        emptied = section_of(each, tag)
        for frame in [c for c in emptied.iter() if isinstance(c, AttachmentFrame)]:
            if not frame.is_removed:
                detach(frame._attached)
        for child in list(tree_children(emptied)):
            if settings_children:
                builder.attributes_to_fill(child).clear()
            else:
                builder.cut(child)
        builder.attributes_to_fill(emptied).clear()
        count_change(emptied)


def _refuse_emptying(element: Element) -> None:
    attached = attached_models(element.root)
    raise errors.AttachmentError(
        f"{element.path}: models {', '.join(repr(m.model) for m in attached)} are attached "
        f"into this model, and each has its own <{element.tag}>: please use "
        "remove(affect_attachments=True) to empty it in every model"
    )


def _shares_settings(model: RootElement) -> bool:
    """Whether `model` shares its global settings with models it is attached into, or
    that are attached into it."""
    return frame_of(model) is not None or bool(model.namescope.children)


def _is_settings_child(element: Element) -> bool:
    """Whether `element` is a once-only child of a settings section (`<option><flag>`)."""
    section = element.parent
    return (
        section is not None
        and section.parent is element.root
        and section.spec.tag in global_settings.SECTIONS
        and not element.spec.repeated
    )


def frames(root: RootElement) -> list[AttachmentFrame]:
    """The frames of the models attached directly to `root`, in the order they were
    attached (a copy)."""
    found = [frame_of(scope.model) for scope in root.namescope.children.values()]
    return [frame for frame in found if frame is not None]


def find_frame(root: RootElement, identifier: str) -> AttachmentFrame | None:
    """The attachment frame of the model attached inside `root` under the scoped name
    `identifier` ('arm' or 'arm/gripper'), or the frame given that name."""
    scope = root.namescope.descendant(identifier)
    if scope is None:
        named = root.namescope.lookup("attachment_frame", identifier)
        return named if isinstance(named, AttachmentFrame) else None
    return frame_of(scope.model)
