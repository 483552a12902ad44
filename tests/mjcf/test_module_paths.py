"""dm_control's module paths that user code imports: `mjcf.traversal_utils` and
`mjcf.constants`, used on real models."""

from __future__ import annotations

import importlib

import pytest

import mjcf
from mjcf import constants, traversal_utils
from tests.conftest import ROBOTIQ, UR5E, gym_model


def test_traversal_utils_is_a_module_path_with_dm_controls_names() -> None:
    assert importlib.import_module("mjcf.traversal_utils") is traversal_utils
    assert mjcf.traversal_utils is traversal_utils
    for name in (
        "get_attachment_frame",
        "get_frame_freejoint",
        "get_frame_joints",
        "get_freejoint",
        "commit_defaults",
    ):
        assert getattr(traversal_utils, name) is getattr(mjcf, name)


def test_traversal_utils_on_composed_real_models(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    arm = mjcf.from_path(UR5E)
    gripper = mjcf.from_path(ROBOTIQ)
    arm.find("site", "attachment_site").attach(gripper)
    ant = mjcf.from_path(gym_model("ant"))
    del ant.option.integrator  # RK4, where the arm's is implicitfast: one model, one integrator
    arm_frame = scene.attach(arm)
    ant_frame = scene.attach(ant)
    ant_frame.add("joint", name="slide", type="slide", axis=[1, 0, 0])
    assert traversal_utils.get_attachment_frame(arm) is arm_frame
    assert traversal_utils.get_attachment_frame(gripper).parent is arm.find("body", "wrist_3_link")
    assert traversal_utils.get_frame_freejoint(arm) is None
    assert [j.name for j in traversal_utils.get_frame_joints(ant)] == ["slide"]
    torso = ant.find("body", "torso")
    assert traversal_utils.get_freejoint(torso) is ant.find("joint", "root")  # <joint type="free">
    pad = gripper.find("geom", "right_pad1")
    traversal_utils.commit_defaults(pad, attributes=["priority"])
    assert pad.priority == 1  # from the gripper's pad_box1 class


def test_constants_name_what_the_model_uses() -> None:
    model = mjcf.RootElement(model="m")
    assert constants.PREFIX_SEPARATOR == mjcf.PREFIX_SEPARATOR
    assert model.worldbody.tag == constants.WORLDBODY
    body = model.worldbody.add(constants.BODY, name="b", **{constants.CHILDCLASS: "main"})
    site = body.add(constants.SITE, **{constants.DCLASS: "main"})
    assert site.get_attribute_xml_string(constants.CLASS) == "main"
    model.asset.add(constants.MESH, name="tetra", vertex=[0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1])
    geom = body.add("geom", type="mesh", mesh="tetra", pos=[1 / 3, 0, 0])
    written = model.to_xml_string(precision=constants.XML_DEFAULT_PRECISION)
    assert written == model.to_xml_string()
    assert f'pos="{1 / 3!r} 0 0"' in written and geom.parent.tag == constants.BODY


def test_base_element_and_debug_mode_names(menagerie) -> None:
    from mjcf import base, debugging

    arm = mjcf.from_path(UR5E)
    frame = arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    assert all(isinstance(e, base.Element) for e in (arm, arm.worldbody, frame))
    assert not isinstance("body", base.Element)
    was = debugging.debug_mode()
    try:
        mjcf.enable_debug_mode()
        assert debugging.debug_mode() is True
        mjcf.disable_debug_mode()
        assert debugging.debug_mode() is False
    finally:
        (mjcf.enable_debug_mode if was else mjcf.disable_debug_mode)()


def test_parser_and_element_module_paths_as_dm_control_imports_them(menagerie, tmp_path) -> None:
    """`from dm_control.mjcf import parser, element` code: parser's readers (from_file
    also given a path, as lxml takes it), parser.from_zip, element.RootElement."""
    from mjcf import element, parser

    assert element.RootElement is mjcf.RootElement
    assert parser.from_path is mjcf.from_path and parser.from_zip is mjcf.from_zip
    by_path = parser.from_file(str(ROBOTIQ))
    with open(ROBOTIQ, "rb") as handle:
        by_handle = parser.from_file(handle)
    assert by_path.is_same_as(by_handle) and by_path.model_dir == str(ROBOTIQ.parent)
    zipped = mjcf.export_with_assets_as_zip(by_path, tmp_path / "gripper.zip")
    assert parser.from_zip(zipped).find("mesh", "pad") is not None
    with pytest.raises(mjcf.ParseError, match="cannot read MJCF file"):
        parser.from_file(str(tmp_path / "missing.xml"))


def test_element_impl_is_the_class_of_every_element(menagerie) -> None:
    """kevinzakka/mujoco_utils types elements as `mjcf.element._ElementImpl`, dm_control's
    class of every element: here `mjcf.Element`, whatever made the element."""
    from mjcf import element

    assert element._ElementImpl is mjcf.element._ElementImpl is mjcf.Element
    arm, gripper = mjcf.from_path(UR5E), mjcf.from_path(ROBOTIQ)  # read from files
    frame = arm.find("site", "attachment_site").attach(gripper)
    arm.worldbody.add("body", name="made").add("geom", size=[0.1])  # made in Python
    arm.default.add("default", dclass="extra").geom.rgba = [1, 0, 0, 1]
    everything = [*arm.iter(), *gripper.iter(), frame, *arm.worldbody.all_children()]
    kinds = {type(e).__name__ for e in everything}
    assert {"RootElement", "AttachmentFrame", "Element"} <= kinds
    assert len(everything) > 200
    assert all(isinstance(e, element._ElementImpl) for e in everything)
    assert not isinstance(arm.worldbody.body, element._ElementImpl)  # an ElementList
