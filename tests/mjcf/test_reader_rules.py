"""Rules MuJoCo 4's XML reader keeps between attributes, and values it reads in ways its
documentation does not say, kept by mjcf as the reader keeps them: each case is checked
against MuJoCo itself, then against mjcf when parsing and when editing."""

from __future__ import annotations

import mujoco
import pytest

import mjcf

_PLUGIN = (
    '<extension><plugin plugin="mujoco.pid"><instance name="pid">'
    '<config key="kp" value="1"/></instance></plugin></extension>'
)
_BODY = '<worldbody><body name="b"><geom size="1"/></body></worldbody>'


def _both_refuse(xml: str, mujoco_says: str, mjcf_says: str) -> None:
    with pytest.raises(ValueError, match=mujoco_says):
        mujoco.MjSpec.from_string(xml)
    with pytest.raises(mjcf.AttributeValueError, match=mjcf_says):
        mjcf.from_xml_string(xml)


def _both_read(xml: str) -> mjcf.RootElement:
    mujoco.MjSpec.from_string(xml)
    return mjcf.from_xml_string(xml)


@pytest.mark.parametrize("numeric", ['<numeric name="n"/>', '<numeric name="n" data=" "/>'])
def test_a_numeric_needs_its_size_or_data(numeric: str) -> None:
    """Blank data is no data to MuJoCo's reader: "custom field size must be positive"."""
    xml = "<mujoco><custom>{}</custom></mujoco>"
    message = "one of size / data must be set"
    _both_refuse(xml.format(numeric), "custom field size must be positive", message)
    assert _both_read(xml.format(numeric.replace("/>", ' size="2"/>'))).custom.numeric[0].size == 2
    data = _both_read(xml.format('<numeric name="n" data="1 2"/>')).custom.numeric[0]
    assert data.data.tolist() == [1, 2]
    with pytest.raises(mjcf.AttributeValueError, match=message):
        del data.data
        data.root.to_xml_string()


def test_a_numeric_size_has_the_readers_cap() -> None:
    xml = '<mujoco><custom><numeric name="n" size="{}"/></custom></mujoco>'
    _both_refuse(xml.format(10_000_001), "exceeds maximum", "at most 10000000")
    numeric = _both_read(xml.format(10_000_000)).custom.numeric[0]
    with pytest.raises(mjcf.AttributeValueError, match="at most 10000000"):
        numeric.size = 2**31 - 1
    assert numeric.size == 10_000_000


def test_a_plugin_sensor_names_its_reference_with_its_type() -> None:
    """'reftype is specified but refname is not', an empty refname counting as none;
    through the API the pair may be set one at a time, and is checked when written."""
    xml = f'<mujoco>{_PLUGIN}{_BODY}<sensor><plugin instance="pid" {{}}/></sensor></mujoco>'
    for attributes in ('reftype="body"', 'reftype="body" refname=""'):
        _both_refuse(xml.format(attributes), "reftype is specified", "'reftype' needs 'refname'")
    _both_refuse(xml.format('refname="b"'), "refname is specified", "'refname' needs 'reftype'")
    sensor = _both_read(xml.format("")).sensor.plugin[0]
    sensor.reftype = "body"
    with pytest.raises(mjcf.AttributeValueError, match="'reftype' needs 'refname'"):
        sensor.root.to_xml_string()
    sensor.refname = "b"
    spec = mujoco.MjSpec.from_string(sensor.root.to_xml_string())
    assert (spec.sensors[0].reftype, spec.sensors[0].refname) == (mujoco.mjtObj.mjOBJ_BODY, "b")


def test_a_frame_sensor_reference_type_and_name_come_together() -> None:
    """MuJoCo's schema counts an attribute there at all: an empty refname is one."""
    xml = f'<mujoco>{_BODY}<sensor><framepos objtype="body" objname="b" {{}}/></sensor></mujoco>'
    _both_refuse(xml.format('reftype="body"'), "must be specified together", "set together")
    _both_read(xml.format('reftype="body" refname=""'))


@pytest.mark.parametrize("params", ["", "  "])
def test_a_builtin_mesh_needs_its_params_not_blank(params: str) -> None:
    xml = f'<mujoco><asset><mesh name="m" builtin="sphere" params="{params}"/></asset></mujoco>'
    _both_refuse(xml, "required attribute missing: 'params'", "'builtin' needs 'params'")


def test_a_flexcomp_material_is_a_list_of_materials() -> None:
    """MuJoCo 4 gives a flex one material per element, or one for all."""
    xml = """<mujoco><asset><material name="red"/><material name="green"/></asset>
      <worldbody><flexcomp name="cloth" type="grid" count="2 2 1" spacing="1 1 1" dim="2"
        material="{}"/></worldbody></mujoco>"""
    root = _both_read(xml.format("red"))
    flexcomp = root.worldbody.flexcomp[0]
    flexcomp.material = list(reversed(root.asset.material))
    expected = mujoco.MjModel.from_xml_string(xml.format("green red")).flex_matid
    assert expected.tolist() == [1, 0]
    with pytest.warns(UserWarning, match="flex 'cloth' is not rigid"):  # MuJoCo's, passed on
        physics = mjcf.Physics.from_mjcf_model(root)
    assert physics.model.flex_matid.tolist() == expected.tolist()
    with pytest.raises(mjcf.Error, match="'blue'"):
        mjcf.from_xml_string(xml.format("red blue"))


@pytest.mark.parametrize("tag", ["body", "frame"])
def test_a_body_outside_worldbody_is_refused_where_mujoco_drops_it(tag: str) -> None:
    xml = f'<mujoco><{tag} name="lost"><geom size="1"/></{tag}></mujoco>'
    assert mujoco.MjModel.from_xml_string(xml).ngeom == 0  # read, and silently dropped
    with pytest.raises(mjcf.SchemaError, match=f"<mujoco> cannot have a <{tag}> child"):
        mjcf.from_xml_string(xml)


def test_a_flex_material_is_a_list_of_materials_too() -> None:
    xml = """<mujoco><asset><material name="red"/><material name="green"/></asset>
      <deformable><flex name="rope" dim="1" body="world world world"
        vertex="0 0 0 1 0 0 2 0 0" element="0 1 1 2" material="green red"/></deformable>
    </mujoco>"""
    root = _both_read(xml)
    expected = mujoco.MjModel.from_xml_string(xml).flex_matid
    assert mjcf.Physics.from_mjcf_model(root).model.flex_matid.tolist() == expected.tolist()
    assert expected.tolist() == [1, 0]
