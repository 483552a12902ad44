"""Any model MuJoCo loads, mjcf loads, writes, and MuJoCo compiles to the same model."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import GYM_ASSETS, MENAGERIE, MUJOCO_TESTDATA, ROBOTIQ, UR5E, gym_model
from tests.mjcf.attaching import differences_from_alone
from tests.mjcf.compare import model_differences, trajectories_match

SHIPPED = sorted(GYM_ASSETS.glob("*.xml")) + sorted(MUJOCO_TESTDATA.glob("*.xml"))
ROBOTS = sorted(MENAGERIE.glob("*/*.xml"))


def _assert_round_trip(path: Path, root: mjcf.RootElement) -> None:
    reference = mujoco.MjModel.from_xml_path(str(path))
    ours = mujoco.MjModel.from_xml_string(root.to_xml_string(), root.get_assets())
    assert model_differences(reference, ours) == []
    assert trajectories_match(reference, ours, steps=100)


@pytest.mark.parametrize("path", SHIPPED + ROBOTS, ids=lambda p: p.name)
def test_shipped_models_round_trip(path: Path, tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo writes deprecation warnings to MUJOCO_LOG.TXT
    _assert_round_trip(path, mjcf.from_path(path))


@pytest.mark.parametrize("path", SHIPPED + ROBOTS, ids=lambda p: p.name)
def test_round_trip_after_reading_every_attribute(path: Path, tmp_path, monkeypatch) -> None:
    """Values converted to Python on reading are written back exactly."""
    monkeypatch.chdir(tmp_path)
    root = mjcf.from_path(path)
    for element in root.iter():
        element.get_attributes()
    _assert_round_trip(path, root)


def test_physics_from_parsed_model_equals_mujoco(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    path = GYM_ASSETS / "humanoid.xml"
    physics = mjcf.Physics.from_mjcf_model(mjcf.from_path(path))
    reference = mujoco.MjModel.from_xml_path(str(path))
    assert physics.model.nq == reference.nq
    assert np.array_equal(physics.model.body_mass, reference.body_mass)


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text))
    return path


def test_includes_anywhere_with_relative_paths(tmp_path: Path) -> None:
    """<include> in worldbody, default, asset and a body; nested includes found next to
    the including file; meshes found through compiler meshdir."""
    mesh = (MUJOCO_TESTDATA / "abdomen_1_body.msh").read_bytes()
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "part.msh").write_bytes(mesh)
    _write(
        tmp_path,
        "parts/defaults.xml",
        """
        <mujoco>
          <geom rgba="0 1 0 1"/><default class="heavy"><geom density="5000"/></default>
        </mujoco>
    """,
    )
    _write(
        tmp_path,
        "parts/assets.xml",
        """
        <mujoco><mesh name="part" file="part.msh"/></mujoco>
    """,
    )
    _write(
        tmp_path,
        "parts/arm.xml",
        """
        <mujoco>
          <body name="arm" pos="0 0 1">
            <joint name="shoulder" axis="0 1 0"/>
            <geom type="capsule" size=".05" fromto="0 0 0 0 0 -.5" class="heavy"/>
            <include file="hand.xml"/>
          </body>
        </mujoco>
    """,
    )
    _write(
        tmp_path,
        "parts/hand.xml",
        """
        <mujoco><body name="hand" pos="0 0 -.5"><geom type="mesh" mesh="part"/></body></mujoco>
    """,
    )
    main = _write(
        tmp_path,
        "model.xml",
        """
        <mujoco model="included">
          <compiler meshdir="meshes"/>
          <default><include file="parts/defaults.xml"/></default>
          <asset><include file="parts/assets.xml"/></asset>
          <worldbody>
            <geom type="plane" size="1 1 .1"/>
            <include file="parts/arm.xml"/>
          </worldbody>
        </mujoco>
    """,
    )
    root = mjcf.from_path(main)
    assert root.find("body", "hand").parent is root.find("body", "arm")
    assert root.find("default", "heavy") is not None
    _assert_round_trip(main, root)


def test_meta_elements_frames_replicate_and_attach(tmp_path: Path) -> None:
    child = _write(
        tmp_path,
        "child.xml",
        """
        <mujoco><worldbody><body name="link"><joint/><geom size=".1"/></body></worldbody></mujoco>
    """,
    )
    main = _write(
        tmp_path,
        "model.xml",
        f"""
        <mujoco>
          <asset><model name="child" file="{child.name}"/></asset>
          <worldbody>
            <frame name="f" pos="0 0 1" euler="0 0 30">
              <body name="b"><freejoint/><geom size=".1"/></body>
            </frame>
            <replicate count="3" offset=".3 0 0">
              <body name="r"><joint type="slide"/><geom size=".05"/></body>
            </replicate>
            <body name="base"><attach model="child" body="link" prefix="c-"/></body>
          </worldbody>
        </mujoco>
    """,
    )
    root = mjcf.from_path(main)
    assert root.find("frame", "f").euler.tolist() == [0, 0, 30]
    _assert_round_trip(main, root)


def test_explicit_main_default_class_round_trips(tmp_path: Path) -> None:
    """dm_control re-emits <default class="main"> inside the top default, which MuJoCo
    rejects; a top-level class="main" must stay the global defaults."""
    main = _write(
        tmp_path,
        "model.xml",
        """
        <mujoco>
          <default class="main">
            <geom rgba="1 0 0 1"/>
            <default class="big"><geom size=".3"/></default>
          </default>
          <worldbody><geom class="big" type="sphere"/><geom size=".1"/></worldbody>
        </mujoco>
    """,
    )
    _assert_round_trip(main, mjcf.from_path(main))


def test_repeated_sections_merge(tmp_path: Path) -> None:
    main = _write(
        tmp_path,
        "model.xml",
        """
        <mujoco>
          <option timestep="0.005"/>
          <worldbody><body name="a"><joint/><geom size=".1"/></body></worldbody>
          <option gravity="0 0 -1"/>
          <worldbody><body name="b"><joint name="b"/><geom size=".1"/></body></worldbody>
          <actuator><motor joint="b"/></actuator>
        </mujoco>
    """,
    )
    root = mjcf.from_path(main)
    assert root.option.timestep == 0.005
    assert root.option.gravity.tolist() == [0, 0, -1]
    assert [b.name for b in root.worldbody.body] == ["a", "b"]
    _assert_round_trip(main, root)


def test_repeated_visual_sections_and_their_once_only_children_merge_as_mujoco(
    tmp_path: Path,
) -> None:
    """dm_control's suite models give <visual> (and its <map>, <quality>) more than once;
    MuJoCo merges them in order, a later value winning."""
    main = _write(
        tmp_path,
        "model.xml",
        """
        <mujoco>
          <visual><map znear="0.1" fogstart="2"/><quality shadowsize="1024"/></visual>
          <visual><map zfar="40" fogstart="3"/><headlight active="1"/></visual>
          <visual><quality offsamples="2"/></visual>
          <worldbody><geom size=".1"/></worldbody>
        </mujoco>
    """,
    )
    root = mjcf.from_path(main)
    assert (root.visual.map.znear, root.visual.map.zfar, root.visual.map.fogstart) == (0.1, 40, 3)
    assert (root.visual.quality.shadowsize, root.visual.quality.offsamples) == (1024, 2)
    _assert_round_trip(main, root)


def test_precision_controls_written_digits() -> None:
    root = mjcf.RootElement()
    root.worldbody.add("geom", size=[1 / 3])
    assert 'size="0.3333333333333333"' in root.to_xml_string()
    assert 'size="0.333"' in root.to_xml_string(precision=3)


def _real_numbers(xml: str) -> list[str]:
    """Every number written in an attribute of `xml` that has a fraction or exponent."""
    values = re.findall(r'="([-+0-9.eE ]+)"', xml)
    return [w for v in values for w in v.split() if "." in w or "e" in w.lower()]


def test_precision_applies_to_numbers_read_from_files_too(tmp_path, monkeypatch) -> None:
    """As in dm_control, `precision` below 17 rewrites every real number, those read
    from the file included; integers and keywords stay; MuJoCo compiles the result."""
    monkeypatch.chdir(tmp_path)
    path = GYM_ASSETS / "humanoid.xml"
    root = mjcf.from_path(path)
    xml = root.to_xml_string(precision=3)
    assert any(len(w.lstrip("-0.").replace(".", "")) > 3 for w in _real_numbers(path.read_text()))
    assert all(len(w.lstrip("-0.").replace(".", "").split("e")[0]) <= 3 for w in _real_numbers(xml))
    assert 'condim="3"' in xml and 'type="capsule"' in xml
    assert root.to_xml_string() == mjcf.from_path(path).to_xml_string()  # nothing changed
    reference = mujoco.MjModel.from_xml_path(str(path))
    rounded = mujoco.MjModel.from_xml_string(xml)
    assert np.allclose(rounded.body_pos, reference.body_pos, rtol=1e-2, atol=1e-3)
    assert np.allclose(rounded.body_mass, reference.body_mass, rtol=3e-2)


def test_zero_threshold_writes_small_numbers_as_zero() -> None:
    root = mjcf.from_xml_string(
        '<mujoco><option timestep="0.002"/><worldbody>'
        '<body name="b" pos="1e-12 -3e-10 0.5"><geom size="0.1"/></body></worldbody></mujoco>'
    )
    root.find("body", "b").quat = [1, 1e-17, 0, -2e-16]
    assert 'pos="1e-12 -3e-10 0.5"' in root.to_xml_string()  # by default, as read
    xml = root.to_xml_string(zero_threshold=1e-9)
    assert 'pos="0 0 0.5"' in xml and 'quat="1 0 0 0"' in xml
    assert 'timestep="0.002"' in xml and 'size="0.1"' in xml
    assert root.to_xml(zero_threshold=1e-9).find("worldbody/body").get("pos") == "0 0 0.5"


def test_precision_reaches_composed_values() -> None:
    """Values the composition computes (angles converted into the parent's units, merged
    settings, merged keyframes) are written with the precision asked for too."""
    parent = mjcf.RootElement(model="parent")
    parent.compiler.angle = "radian"
    parent.option.timestep = 1 / 300
    child = mjcf.RootElement(model="child")  # degrees
    body = child.worldbody.add("body", name="b", euler=[10, 20, 30])
    body.add("joint", name="j", range=[-10, 10])
    body.add("geom", size=[0.1])
    child.keyframe.add("key", name="k", qpos=[1 / 3])
    parent.attach(child)
    exact = parent.to_xml_string()
    assert 'range="-0.17453292519943295 0.17453292519943295"' in exact
    short = parent.to_xml_string(precision=3)
    assert 'range="-0.175 0.175"' in short and 'timestep="0.00333"' in short
    assert 'qpos="0.333"' in short
    assert all(len(w.lstrip("-0.").replace(".", "")) <= 3 for w in _real_numbers(short))


def test_to_xml_is_lxml_element() -> None:
    root = mjcf.from_path(GYM_ASSETS / "ant.xml")
    xml = root.to_xml()
    assert xml.tag == "mujoco"
    assert xml.find("worldbody/body").get("name") == "torso"


def test_repeated_top_level_default_compiles_as_mujoco_reads_it(tmp_path: Path) -> None:
    """The model's own classes first, then an included file that sets the global
    defaults: MuJoCo copied the classes before, so they keep the values they had."""
    _write(
        tmp_path,
        "scene_defaults.xml",
        """
        <mujoco>
          <default class="main">
            <geom friction="0.9 0.02 0.002" margin="0.002" solimp="0.8 0.9" material="grey"/>
            <joint armature="0.05" damping="0.3"/>
          </default>
        </mujoco>
    """,
    )
    main = _write(
        tmp_path,
        "model.xml",
        """
        <mujoco model="robot_on_scene">
          <default>
            <geom rgba="0.2 0.2 0.8 1" friction="0.6"/>
            <default class="link">
              <geom friction="0.4 0.01"/>
              <joint damping="1"/>
              <default class="pad"><geom margin="0.01"/></default>
            </default>
          </default>
          <include file="scene_defaults.xml"/>
          <default><default class="late"><geom condim="1"/></default></default>
          <asset><material name="grey" rgba=".5 .5 .5 1"/></asset>
          <worldbody>
            <geom name="floor" type="plane" size="2 2 .1"/>
            <body name="arm" pos="0 0 .5">
              <joint name="hinge" class="link"/>
              <geom name="upper" class="link" type="capsule" size=".05 .2"/>
              <geom name="pad" class="pad" type="sphere" size=".06" pos="0 0 -.2"/>
              <geom name="late" class="late" type="sphere" size=".05" pos="0 0 .2"/>
              <body name="free" pos=".3 0 0"><joint/><geom size=".05"/></body>
            </body>
          </worldbody>
        </mujoco>
    """,
    )
    root = mjcf.from_path(main)
    _assert_round_trip(main, root)
    reference = mujoco.MjModel.from_xml_path(str(main))
    assert model_differences(reference, mjcf.Physics.from_mjcf_model(root).model) == []
    upper = reference.geom("upper")
    assert upper.margin[0] == 0 and upper.matid[0] == -1  # what silently changed before
    reread = mjcf.from_xml_string(root.to_xml_string())
    _assert_round_trip(main, reread)


# The structure of Gymnasium-Robotics' adroit_hammer.xml (which MuJoCo compiles): a first
# <default> defines a class with actuator defaults; an included file, at the end of the
# model, sets the global actuator defaults in <default class="main"> and defines more
# classes. Classes defined before it keep the actuator defaults they copied.
_HAND = """
<mujoco model="hand">
  <default>
    <default class="board">
      <geom type="box" rgba=".6 .4 .2 1"/>
      <general user="0 1 0.03"/>
    </default>
  </default>
  <worldbody>
    <body name="finger" pos="0 0 .2">
      <joint name="knuckle" axis="0 1 0" range="-1 1"/>
      <geom name="bone" size=".02 .05" type="capsule"/>
      <body name="tip" pos="0 0 .1">
        <joint name="tip_joint" class="loose" axis="0 1 0"/>
        <geom name="pad" size=".02" class="soft"/>
      </body>
    </body>
    <body name="plank" pos=".3 0 0"><geom name="plank" class="board" size=".1 .1 .01"/></body>
  </worldbody>
  <actuator>
    <general name="plain" joint="knuckle" gainprm="10"/>
    <general name="boarded" class="board" joint="knuckle" gainprm="5"/>
    <position name="late_class" class="soft" joint="tip_joint" kp="2"/>
  </actuator>
  <include file="hand_defaults.xml"/>
</mujoco>
"""
_HAND_DEFAULTS = """
<mujocoinclude>
  <default class="main">
    <joint limited="true" damping="0.05"/>
    <geom friction="1 0.5 0.01" margin="0.0005"/>
    <general ctrllimited="true" ctrlrange="-1 1" user="0 1 0.05 0.09"/>
    <default class="soft">
      <geom rgba=".9 .7 .5 1"/>
      <general user="0 2 0.03" forcerange="-3 3" forcelimited="true"/>
    </default>
    <default class="loose"><joint damping="0" limited="false"/></default>
  </default>
</mujocoinclude>
"""


def _hand(folder: Path) -> Path:
    _write(folder, "hand_defaults.xml", _HAND_DEFAULTS)
    return _write(folder, "hand.xml", _HAND)


def test_late_actuator_defaults_are_written_as_sections_of_their_own(tmp_path: Path) -> None:
    path = _hand(tmp_path)
    reference = mujoco.MjModel.from_xml_path(str(path))
    boarded = reference.actuator("boarded")
    assert not boarded.ctrllimited and reference.actuator("plain").ctrllimited  # what differs
    root = mjcf.from_path(path)
    assert model_differences(reference, mjcf.Physics.from_mjcf_model(root).model) == []
    xml = root.to_xml_string()
    assert xml.count("<default>") == 2  # as many top-level sections as MuJoCo needs
    _assert_round_trip(path, root)
    _assert_round_trip(path, mjcf.from_xml_string(xml))  # and read back alike
    committed = mjcf.from_path(path)
    mjcf.commit_defaults(committed)
    assert committed.find("actuator", "boarded").ctrllimited is None  # the built-in 'auto'
    assert committed.find("actuator", "plain").ctrllimited == "true"
    _assert_round_trip(path, committed)


def test_a_model_with_late_actuator_defaults_attaches(tmp_path: Path) -> None:
    """Attached (twice), its global defaults become a class and the late section a class
    nested in it, which its elements use; every value compiles as in the model alone."""
    path = _hand(tmp_path)
    alone = mujoco.MjModel.from_xml_path(str(path))
    scene = mjcf.RootElement(model="scene")
    scene.default.general.ctrlrange = [-2, 2]  # the scene's own global defaults too
    scene.worldbody.add("geom", name="floor", type="plane", size=[1, 1, 0.1])
    left, right = mjcf.from_path(path), mjcf.from_path(path)
    scene.attach(left)
    scene.attach(right).pos = [0, 0.5, 0]
    composed = mjcf.Physics.from_mjcf_model(scene).model
    for prefix in ("hand/", "hand_1/"):
        assert differences_from_alone(alone, composed, prefix, placed={"finger", "plank"}) == []
    stock = mujoco.MjModel.from_xml_string(scene.to_xml_string(), scene.get_assets())
    assert model_differences(composed, stock) == []


def test_defaults_naming_assets_they_do_not_define_load() -> None:
    """A defaults-only file (included by models that define the materials) loads, as in
    MuJoCo; a dangling name is an error where an element uses it."""
    defaults = """<mujoco><default>
      <default class="red"><geom material="red_mat"/><site material="marker"/></default>
      <default class="textured"><material texture="wood"/></default>
    </default></mujoco>"""
    mujoco.MjModel.from_xml_string(defaults)
    root = mjcf.from_xml_string(defaults)
    assert root.find("default", "red").geom.material == "red_mat"
    mjcf.Physics.from_mjcf_model(root)
    root.worldbody.add("geom", dclass="red", size=[0.1])
    with pytest.raises(mjcf.CompileError, match="red_mat"):
        mjcf.Physics.from_mjcf_model(root)
    with pytest.raises(mjcf.InvalidReferenceError, match="red_mat"):
        mjcf.from_xml_string(defaults.replace("</default></mujoco>", "</default>"
            '<worldbody><geom material="red_mat" size=".1"/></worldbody></mujoco>'))  # fmt: skip


_LATE_DEFAULTS = [
    '<geom solref=".03 2" size=".2" priority="1" condim="4" fluidcoef=".3 .3"/>',
    '<joint range="-30 30" stiffness="2" springref="10" limited="true"/>',
    '<site size=".05" rgba="1 0 0 1"/>',
    '<camera fovy="60" ipd=".1"/>',
    '<light attenuation="1 .1 0" cutoff="30"/>',
    '<tendon stiffness="3" width=".01" limited="true" range="0 1"/>',
    '<equality solref=".05 1" active="false"/>',
    '<pair margin=".1"/>',
    '<mesh scale="2 2 2"/>',
    '<material specular=".1" rgba="1 0 0 1"/>',
]


@pytest.mark.parametrize("late", _LATE_DEFAULTS, ids=lambda text: text.split()[0][1:])
def test_classes_keep_built_in_values_of_late_global_defaults(late: str) -> None:
    """Every kind of default element: a class defined before the global defaults set a
    value keeps MuJoCo's built-in one."""
    xml = f"""<mujoco><default><default class="a"/></default><default>{late}</default>
      <asset><mesh name="m" class="a" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>
        <material name="mt" class="a"/></asset>
      <worldbody><camera class="a"/><light class="a"/>
        <body><joint name="j" class="a"/><joint name="j2" class="a" axis="1 0 0"/>
          <geom class="a" size=".1"/><geom size=".1" name="g2"/><site class="a"/></body>
      </worldbody>
      <tendon><fixed class="a"><joint joint="j" coef="1"/></fixed></tendon>
      <equality><joint joint1="j" joint2="j2" class="a"/></equality>
      <contact><pair geom1="g2" geom2="g2" class="a"/></contact>
    </mujoco>"""
    reference = mujoco.MjModel.from_xml_string(xml)
    root = mjcf.from_xml_string(xml)
    ours = mujoco.MjModel.from_xml_string(root.to_xml_string())
    assert model_differences(reference, ours) == []


@pytest.mark.parametrize("objtype", ["body", "geom", "Body", " body", "XBODY", "1", "0", "-1"])
def test_an_object_type_in_any_case_or_as_a_number_compiles_as_mujoco(objtype: str) -> None:
    """A <user> sensor's objtype names a kind of object in its exact word only: in
    another case, or as a number, it is an unknown object type to MuJoCo, which then
    ignores objname (here 'c', which names nothing)."""
    name = "b" if objtype in ("body", "geom") else "c"
    xml = f"""<mujoco><worldbody><body name="b"><geom name="b" size="1"/></body></worldbody>
      <sensor><user objtype="{objtype}" objname="{name}" dim="1" needstage="pos"/></sensor>
    </mujoco>"""
    stock = mujoco.MjModel.from_xml_string(xml)
    assert (
        model_differences(stock, mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(xml)).model)
        == []
    )


def test_write_read_write_is_a_fixed_point_with_attached_models() -> None:
    """Generated names of unnamed elements count the attached models' elements where
    they are written, so reading the text makes the same numbers (a scene body after an
    attached robot kept '//unnamed_body_1' but read back as '//unnamed_body_2')."""
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", type="plane", size=[5, 5, 0.1])
    ant = mjcf.from_path(gym_model("ant"))
    del ant.option.integrator  # the arms' integrator is another
    scene.worldbody.add("site").attach(ant)
    scene.worldbody.add("body").add("geom", size=[0.1])
    arm = mjcf.from_path(UR5E)
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    del arm.option.integrator
    scene.attach(arm).add("joint", type="slide")
    scene.worldbody.add("frame").add("body").add("geom", size=[0.1])
    scene.actuator.add("motor", joint=ant.find_all("joint")[1])
    written = scene.to_xml_string()
    assert '<body name="//unnamed_body_' in written.split('name="ur5e/"')[0]
    read = mjcf.from_xml_string(written, escape_separators=True, assets=scene.get_assets())
    assert read.to_xml_string() == written
    again = mjcf.from_xml_string(written, escape_separators=True, assets=scene.get_assets())
    assert mjcf.from_xml_string(again.to_xml_string(), escape_separators=True,
                                assets=scene.get_assets()).to_xml_string() == written  # fmt: skip
