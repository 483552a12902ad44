"""Bad input raises one specific mjcf error that says where and what was expected, and
leaves the model as it was."""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest

import mjcf


@pytest.fixture
def model() -> mjcf.RootElement:
    root = mjcf.RootElement(model="robot")
    body = root.worldbody.add("body", name="arm")
    body.add("geom", name="tip", size=[0.1])
    body.add("joint", name="hinge")
    return root


def _unchanged(model: mjcf.RootElement, action, error: type[mjcf.Error], match: str) -> None:
    before = model.to_xml_string()
    with pytest.raises(error, match=match):
        action()
    assert model.to_xml_string() == before


def test_unknown_element_suggests(model: mjcf.RootElement) -> None:
    body = model.find("body", "arm")
    message = r"<body name=\"arm\">: <body> cannot have a <goem> child \(did you mean 'geom'\?\)"
    _unchanged(model, lambda: body.add("goem"), mjcf.SchemaError, message)


def test_unknown_attribute_suggests(model: mjcf.RootElement) -> None:
    tip = model.find("geom", "tip")
    message = r"<geom name=\"tip\">: can't set attribute 'rgab': <geom> has no such attribute \(did"
    _unchanged(
        model, lambda: setattr(tip, "rgab", [1, 0, 0, 1]), mjcf.UnknownAttributeError, message
    )
    _unchanged(
        model, lambda: model.worldbody.add("geom", sise=[1]), mjcf.UnknownAttributeError, "sise"
    )
    with pytest.raises(AttributeError):  # still the builtin meaning
        tip.rgab  # noqa: B018
    assert getattr(tip, "rgab", None) is None


@pytest.mark.parametrize(
    ("name", "value", "match"),
    [
        ("size", [1, 2, 3, 4], r"'size' takes 1 to 3 numbers, got 4"),
        ("quat", [1, 0, 0], r"'quat' takes 4 numbers, got 3"),
        ("size", "a b", r"'size' takes numbers"),
        ("condim", 1.5, r"'condim' takes integers"),
        ("type", "boxx", r"'type' takes one of \[.*\], got 'boxx' \(did you mean 'box'\?\)"),
        ("rgba", [[1, 2], [3, 4]], r"'rgba' takes a flat list"),
        ("name", 3, r"'name' takes a string"),
    ],
)
def test_wrong_values(model: mjcf.RootElement, name: str, value: object, match: str) -> None:
    tip = model.find("geom", "tip")
    where = r"model 'robot': <worldbody>/<body name=\"arm\">/<geom name=\"tip\">: "
    _unchanged(model, lambda: setattr(tip, name, value), mjcf.AttributeValueError, where + match)


def test_failed_add_adds_nothing(model: mjcf.RootElement) -> None:
    body = model.find("body", "arm")
    _unchanged(model, lambda: body.add("geom", name="new", size=[1, 2, 3, 4]),
               mjcf.AttributeValueError, "size")  # fmt: skip
    assert model.find("geom", "new") is None
    _unchanged(model, lambda: body.add("geom", name="tip"), mjcf.NameClashError, "already used")


def test_duplicate_names(model: mjcf.RootElement) -> None:
    other = model.worldbody.add("geom", name="other", size=[1])
    _unchanged(model, lambda: setattr(other, "name", "tip"), mjcf.NameClashError,
               r"'tip' is already used by another geom")  # fmt: skip
    model.worldbody.add("body", name="tip")  # another namespace: fine


def test_wrong_reference_kind(model: mjcf.RootElement) -> None:
    _unchanged(model, lambda: model.actuator.add("motor", joint=model.find("geom", "tip")),
               mjcf.InvalidReferenceError, "'joint' refers to a joint")  # fmt: skip


def test_dangling_reference_in_file() -> None:
    text = (
        '<mujoco><worldbody><body><joint name="j"/><geom size="1"/></body></worldbody>'
        '<actuator><motor joint="jj"/></actuator></mujoco>'
    )
    with pytest.raises(mjcf.InvalidReferenceError, match=r"joint='jj' \(no joint of that name\)"):
        mjcf.from_xml_string(text)
    model = mjcf.from_xml_string(text, resolve_references=False)
    assert model.actuator.motor[0].joint == "jj"


def test_dangling_reference_set_in_python_fails_on_compile(model: mjcf.RootElement) -> None:
    model.actuator.add("motor", joint="nonexistent")
    with pytest.raises(mjcf.CompileError, match="nonexistent"):
        mjcf.Physics.from_mjcf_model(model)


def test_missing_required_attribute_on_write(model: mjcf.RootElement) -> None:
    model.tendon.add("fixed").add("joint", coef=1)
    with pytest.raises(mjcf.AttributeValueError, match="<joint> requires the attribute 'joint'"):
        model.to_xml_string()


def test_malformed_xml_names_file_and_line(tmp_path: Path) -> None:
    path = tmp_path / "broken.xml"
    path.write_text("<mujoco>\n  <worldbody>\n    <geom size='1'>\n  </worldbody>\n</mujoco>\n")
    with pytest.raises(mjcf.ParseError, match=r"broken.xml:4: malformed XML"):
        mjcf.from_path(path)


def test_unknown_element_in_file_names_line(tmp_path: Path) -> None:
    path = tmp_path / "model.xml"
    path.write_text("<mujoco>\n<worldbody>\n<bdy/>\n</worldbody>\n</mujoco>\n")
    with pytest.raises(mjcf.SchemaError, match=r"model.xml:3: .*<bdy>.*did you mean 'body'"):
        mjcf.from_path(path)


def test_include_cycle_and_missing_include(tmp_path: Path) -> None:
    (tmp_path / "a.xml").write_text('<mujoco><include file="b.xml"/></mujoco>')
    (tmp_path / "b.xml").write_text('<mujoco><include file="a.xml"/></mujoco>')
    (tmp_path / "main.xml").write_text('<mujoco><include file="a.xml"/></mujoco>')
    with pytest.raises(mjcf.ParseError, match="included more than once"):
        mjcf.from_path(tmp_path / "main.xml")
    (tmp_path / "lost.xml").write_text('<mujoco><include file="nowhere.xml"/></mujoco>')
    with pytest.raises(mjcf.ParseError, match=r"'nowhere\.xml' not found"):
        mjcf.from_path(tmp_path / "lost.xml")


def test_children_of_an_include_are_refused_as_mujoco_refuses_them(tmp_path: Path) -> None:
    (tmp_path / "part.xml").write_text('<mujoco><body name="p"><geom size="1"/></body></mujoco>')
    path = tmp_path / "model.xml"
    path.write_text(
        '<mujoco><worldbody><include file="part.xml"><joint name="j"/></include></worldbody>'
        "</mujoco>"
    )
    with pytest.raises(ValueError, match="cannot have children"):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(mjcf.ParseError, match=r"model.xml:1: an <include> cannot have children"):
        mjcf.from_path(path)


def test_a_chain_of_a_thousand_nested_includes_reads_as_mujoco_compiles_it(
    tmp_path: Path,
) -> None:
    depth = 1000
    for i in range(depth):
        (tmp_path / f"f{i}.xml").write_text(f'<mujoco><include file="f{i + 1}.xml"/></mujoco>')
    (tmp_path / f"f{depth}.xml").write_text(
        '<mujoco><worldbody><geom name="deep" size="1"/></worldbody></mujoco>'
    )
    expected = mujoco.MjModel.from_xml_path(str(tmp_path / "f0.xml"))
    model = mjcf.from_path(tmp_path / "f0.xml")
    assert model.find("geom", "deep") is not None
    assert mjcf.Physics.from_mjcf_model(model).model.ngeom == expected.ngeom == 1


def test_root_must_be_mujoco_and_sections_known() -> None:
    with pytest.raises(mjcf.ParseError, match="root element of an MJCF model is <mujoco>"):
        mjcf.from_xml_string("<robot/>")
    with pytest.raises(mjcf.SchemaError, match="did you mean 'worldbody'"):
        mjcf.from_xml_string("<mujoco><wordlbody/></mujoco>")


def test_once_only_elements_and_sections() -> None:
    root = mjcf.RootElement()
    body = root.worldbody.add("body")
    body.add("inertial", pos=[0, 0, 0], mass=1)
    with pytest.raises(mjcf.SchemaError, match="only one <inertial>"):
        body.add("inertial", pos=[0, 0, 0], mass=2)
    worldbody = root.worldbody
    worldbody.remove()  # a section always exists: removing it empties it, as dm_control
    assert root.worldbody is worldbody and worldbody.all_children() == []
    assert not worldbody.is_removed and body.is_removed


@pytest.mark.parametrize("sections", ['<default class="a"/>', '<default/><default class="b"/>'])
def test_the_top_level_default_class_cannot_be_renamed_as_in_mujoco(sections: str) -> None:
    xml = f"<mujoco>{sections}</mujoco>"
    with pytest.raises(ValueError, match="top-level default class 'main' cannot be renamed"):
        mujoco.MjSpec.from_string(xml)
    with pytest.raises(mjcf.AttributeValueError, match="is 'main', which cannot be renamed"):
        mjcf.from_xml_string(xml)
    main = mjcf.from_xml_string('<mujoco><default class="main"><geom size="1"/></default></mujoco>')
    assert main.default.geom.size.tolist() == [1.0]


@pytest.mark.parametrize("text", [" none", "quat ", " expmap "])
def test_a_keyword_taken_only_alone_is_the_whole_text_as_in_mujoco(text: str) -> None:
    xml = f"""<mujoco><worldbody><body><joint name="j"/><geom size="1"/></body></worldbody>
      <actuator><general joint="j" input="{text}"/></actuator></mujoco>"""
    with pytest.raises(ValueError, match="invalid keyword"):
        mujoco.MjSpec.from_string(xml)
    with pytest.raises(mjcf.AttributeValueError, match="only alone, without spaces"):
        mjcf.from_xml_string(xml)
    assert mjcf.from_xml_string(xml.replace(text, " pos vel ")).actuator.general[0].input


def test_a_blank_connect_anchor_never_reaches_mujoco() -> None:
    """MuJoCo 4.0.0 fails on it inside its bindings ('Caught an unknown exception!'), and
    a later MuJoCo warning in the same process then never returns: refused first."""
    xml = """<mujoco><worldbody><body name="a"><geom size="1"/></body></worldbody>
      <equality><connect body1="a" anchor="{}"/></equality></mujoco>"""
    with pytest.raises(mjcf.AttributeValueError, match="anchor"):
        mjcf.from_xml_string(xml.format(" "))
    model = mjcf.from_xml_string(xml.format("0 0 1"))
    connect = model.equality.connect[0]
    with pytest.raises(mjcf.AttributeValueError, match="anchor"):
        connect.anchor = ""
    assert connect.anchor.tolist() == [0.0, 0.0, 1.0]


def test_counts_mujoco_refuses_inside_the_range() -> None:
    """A frame's scale takes one number or three, as MuJoCo's reader does: two is
    refused when parsing and when set, and the other counts compile."""
    text = '<mujoco><worldbody><frame scale="{}"><geom size="1"/></frame></worldbody></mujoco>'
    with pytest.raises(mjcf.AttributeValueError, match=r"'scale' takes 1 or 3 numbers, got 2"):
        mjcf.from_xml_string(text.format("1 2"))
    root = mjcf.from_xml_string(text.format("2"))
    frame = root.worldbody.frame[0]
    _unchanged(root, lambda: setattr(frame, "scale", [1, 2]), mjcf.AttributeValueError, "1 or 3")
    frame.scale = [3, 3, 3]
    assert mujoco.MjModel.from_xml_string(root.to_xml_string()).geom_size[0, 0] == 3


# -- mjcf errors, never raw ones ------------------------------------------------------------


def test_a_settotalmass_model_mujocos_reader_refuses_raises_a_compile_error() -> None:
    """MjSpec.from_string's ValueError, when the attached model is compiled alone to find
    the mass its settotalmass scales, is an mjcf.CompileError naming the model."""
    child = mjcf.RootElement(model="child")
    child.compiler.settotalmass = 5
    child.asset.add(  # MuJoCo's reader checks the layout against the grid
        "texture", name="t", type="cube", builtin="checker", width=8, height=8,
        gridsize=[2, 2], gridlayout="ABC",
    )  # fmt: skip
    child.worldbody.add("body", name="b").add("geom", size=[0.1])
    parent = mjcf.RootElement(model="parent")
    parent.attach(child)
    with pytest.raises(mjcf.CompileError, match=r"model 'child'.*settotalmass.*gridlayout"):
        parent.to_xml_string()
    with pytest.raises(mjcf.CompileError, match="gridlayout length must match gridsize"):
        mjcf.Physics.from_mjcf_model(parent)


@pytest.mark.parametrize("name", ["pos", "quat", "euler", "axisangle", "xyaxes", "zaxis"])
def test_a_blank_pose_of_an_attachment_site_reads_as_not_set(name: str) -> None:
    parent = mjcf.RootElement(model="parent")
    site = parent.worldbody.add("site", name="s", **{name: ""})
    child = mjcf.RootElement(model="child")
    child.worldbody.add("geom", name="g", size=[0.1])
    frame = site.attach(child)
    assert frame.get_attributes() == {}
    physics = mjcf.Physics.from_mjcf_model(parent)
    assert physics.bind(child.find("geom", "g")).xpos.tolist() == [0, 0, 0]


def test_repr_never_raises() -> None:
    model = mjcf.from_xml_string(
        '<mujoco><worldbody><body><joint name="j"/><geom size="1"/></body></worldbody>'
        '<actuator><motor name="m" joint="j"/></actuator></mujoco>'
    )
    motor = model.find("actuator", "m")
    model.find("joint", "j").remove()
    with pytest.raises(mjcf.InvalidReferenceError):
        motor.to_xml_string()
    assert repr(motor).startswith('MJCF Element: <actuator>/<motor name="m"> (not writable:')
    assert "removed" in repr(motor)
