"""What mjcf refuses though MuJoCo's reader accepts it (mjcf/schema/_refusals.py): each
entry is shown true of the installed MuJoCo (a crash, or an empty name bound to an
unnamed element), and refused by both readers and the Python API, naming why."""

from __future__ import annotations

import signal
import subprocess
import sys

import mujoco
import pytest

import mjcf
from mjcf.io import fast_reader
from mjcf.schema import _refusals
from tests.conftest import MENAGERIE

PAD = MENAGERIE / "robotiq_2f85" / "assets" / "pad.stl"
_PID = (
    '<extension><plugin plugin="mujoco.pid"><instance name="p"><config key="kp" value="1"/>'
    "</instance></plugin></extension>"
)
CRASHES = {
    "mesh file with plugin": f'<mujoco><asset><mesh name="m" file="{PAD}"><plugin/></mesh></asset>'
    "</mujoco>",
    "mesh file with named plugin": f'<mujoco><asset><mesh name="m" file="{PAD}">'
    '<plugin plugin="mujoco.sdf.torus"/></mesh></asset></mujoco>',
    "plugin without plugin or instance in flexcomp": '<mujoco><worldbody><flexcomp name="f" '
    'type="grid" count="2 2 1" spacing="1 1 1" dim="2"><plugin/></flexcomp></worldbody></mujoco>',
    "two plugins in a replicate": f"<mujoco>{_PID}<worldbody><replicate count='1'>"
    '<plugin plugin="mujoco.pid"/><plugin plugin="mujoco.pid"/></replicate></worldbody></mujoco>',
    "frame as a tuple's object type": '<mujoco><keyframe><key name="p"/></keyframe><custom>'
    '<tuple name="t"><element objtype="frame" objname="p"/></tuple></custom></mujoco>',
    "frame as a user sensor's object type": '<mujoco><keyframe><key name="p"/></keyframe>'
    '<sensor><user objtype="frame" objname="p" dim="1"/></sensor></mujoco>',
}


def _mujoco_compiles(xml: str) -> int:
    """The exit status of a fresh process that compiles `xml` with MuJoCo alone."""
    code = (
        "import sys, mujoco\n"
        "try:\n    mujoco.MjModel.from_xml_string(sys.stdin.read())\n"
        "except ValueError:\n    pass\n"
    )
    return subprocess.run(
        [sys.executable, "-c", code], input=xml, text=True, check=False
    ).returncode


@pytest.mark.parametrize("case", sorted(CRASHES))
def test_what_crashes_mujoco_is_refused(case: str, monkeypatch) -> None:
    xml = CRASHES[case]
    assert _mujoco_compiles(xml) == -signal.SIGSEGV  # the entry is still needed
    with pytest.raises(mjcf.Error, match="crashes on it"):
        mjcf.from_xml_string(xml)
    monkeypatch.setattr(fast_reader, "read", lambda *args: False)
    with pytest.raises(mjcf.Error, match="crashes on it"):
        mjcf.from_xml_string(xml)


def test_what_crashes_mujoco_cannot_be_built_through_the_api() -> None:
    model = mjcf.RootElement()
    mesh = model.asset.add("mesh", name="m", file=str(PAD))
    with pytest.raises(mjcf.SchemaError, match="crashes on it"):
        mesh.add("plugin", plugin="mujoco.sdf.torus")
    sdf = model.asset.add("mesh", name="sdf")
    sdf.add("plugin", instance="t")
    with pytest.raises(mjcf.SchemaError, match="crashes on it"):
        sdf.file = str(PAD)
    replicate = model.worldbody.add("replicate", count=2)
    plugin = replicate.add("plugin", instance="t")
    with pytest.raises(mjcf.SchemaError, match="crashes on it"):
        plugin.plugin = "mujoco.pid"
    model.worldbody.add("body").add("plugin")
    with pytest.raises(mjcf.AttributeValueError, match="one of plugin / instance"):
        model.to_xml_string()
    tuple_ = model.custom.add("tuple", name="t")
    with pytest.raises(mjcf.AttributeValueError, match="takes no 'frame'"):
        tuple_.add("element", objtype="frame", objname="p")
    assert model.find("mesh", "m").plugin == [] and sdf.file is None


def test_a_gear_or_armature_that_is_not_finite_is_refused() -> None:
    """MuJoCo 4.0.0's compile never ends computing a muscle's length range with such a
    gear or armature (found by the full sweep of the differential check; not run here,
    as it would hang)."""
    body = '<worldbody><body><joint name="j" {}/><geom size="1"/></body></worldbody>'
    for joint, muscle in (("", 'gear="inf"'), ("", 'gear="1 0 0 0 0 -inf"'),
                          ("", 'armature="nan"'), ('armature="nan"', "")):  # fmt: skip
        actuator = f'<actuator><muscle joint="j" {muscle}/></actuator>'
        xml = f"<mujoco>{body.format(joint)}{actuator}</mujoco>"
        with pytest.raises(mjcf.AttributeValueError, match="takes finite numbers"):
            mjcf.from_xml_string(xml)
    with pytest.raises(mjcf.AttributeValueError, match="takes finite numbers"):
        mjcf.RootElement().default.muscle.gear = [float("inf")]
    with pytest.raises(mjcf.AttributeValueError, match="takes finite numbers"):
        mjcf.RootElement().default.joint.armature = float("nan")


# Each refused empty name: MuJoCo compiles the document with the first unnamed element
# of its kind, and fails once that element has a name too.
_UNNAMED = (
    '<worldbody><body pos="0 0 1"><joint/><geom size="0.1"/><site/></body>'
    '<body name="p" pos="1 0 1"><joint name="p"/><geom name="p" size="0.1"/><site name="p"/>'
    '</body></worldbody><tendon><fixed><joint joint="p" coef="1"/></fixed>'
    '<fixed name="p"><joint joint="p" coef="1"/></fixed></tendon>'
)
_EMPTY = {
    ("contact-pair", "geom1"): '<contact><pair geom1="" geom2="p"/></contact>',
    ("contact-pair", "geom2"): '<contact><pair geom1="p" geom2=""/></contact>',
    ("contact-exclude", "body1"): '<contact><exclude body1="" body2="p"/></contact>',
    ("contact-exclude", "body2"): '<contact><exclude body1="p" body2=""/></contact>',
    ("equality-connect", "body1"): '<equality><connect body1="" body2="p" anchor="0 0 0"/>'
    "</equality>",
    ("equality-connect", "site1"): '<equality><connect site1="" site2="p"/></equality>',
    ("equality-weld", "body1"): '<equality><weld body1="" body2="p"/></equality>',
    ("equality-weld", "site1"): '<equality><weld site1="" site2="p"/></equality>',
    ("equality-joint", "joint1"): '<equality><joint joint1="" joint2="p"/></equality>',
    ("equality-tendon", "tendon1"): '<equality><tendon tendon1="" tendon2="p"/></equality>',
    ("fixed-joint", "joint"): '<tendon><fixed name="q"><joint joint="" coef="1"/></fixed></tendon>',
    ("spatial-site", "site"): '<tendon><spatial><site site=""/><site site="p"/></spatial></tendon>',
    ("spatial-geom", "geom"): '<tendon><spatial><site site="p"/><geom geom=""/><site site="p"/>'
    "</spatial></tendon>",
}


def _named(prelude: str) -> str:
    """The prelude with its unnamed elements named 'u'."""
    return (
        prelude.replace('<body pos="0 0 1">', '<body name="u" pos="0 0 1">')
        .replace("<joint/>", '<joint name="u"/>')
        .replace('<geom size="0.1"/>', '<geom name="u" size="0.1"/>')
        .replace("<site/>", '<site name="u"/>')
        .replace("<fixed>", '<fixed name="u">')
    )


def _compiled_by_mujoco(xml: str) -> bool:
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError:
        return False
    return True


def test_every_refused_empty_name_is_listed_and_shown() -> None:
    listed = {(key, name) for key, names in _refusals.EMPTY_NAME_IS_FIRST_UNNAMED.items()
              for name in names}  # fmt: skip
    assert listed == set(_EMPTY)


@pytest.mark.parametrize("key", sorted(_EMPTY), ids="/".join)
def test_an_empty_name_mujoco_binds_to_an_unnamed_element_is_refused(key: tuple) -> None:
    document = f"<mujoco>{_UNNAMED}{_EMPTY[key]}</mujoco>"
    assert _compiled_by_mujoco(document)
    assert not _compiled_by_mujoco(f"<mujoco>{_named(_UNNAMED)}{_EMPTY[key]}</mujoco>")
    with pytest.raises(mjcf.AttributeValueError, match=f"'{key[1]}' is empty, which MuJoCo"):
        mjcf.from_xml_string(document)
    with pytest.raises(mjcf.AttributeValueError, match="is empty, which MuJoCo"):
        mjcf.from_xml_string(document, resolve_references=False)


def test_a_pair_without_geoms_is_refused_and_so_is_an_empty_name_set_in_python() -> None:
    document = f'<mujoco>{_UNNAMED}<contact><pair geom2="p"/></contact></mujoco>'
    assert _compiled_by_mujoco(document)  # the first unnamed geom, for MuJoCo
    with pytest.raises(mjcf.AttributeValueError, match="requires the attribute 'geom1'"):
        mjcf.from_xml_string(document)
    model = mjcf.from_xml_string(f"<mujoco>{_UNNAMED}</mujoco>")
    with pytest.raises(mjcf.AttributeValueError, match="'geom1' is empty"):
        model.contact.add("pair", geom1="", geom2="p")
    exclude = model.contact.add("exclude", body1="p", body2="world")
    with pytest.raises(mjcf.AttributeValueError, match="'body1' is empty"):
        exclude.body1 = ""
    model.contact.add("pair", geom2="p")
    with pytest.raises(mjcf.AttributeValueError, match="requires the attribute 'geom1'"):
        model.to_xml_string()
