"""Attachment's default classes, angle units, Euler sequences and converted compiler and
option settings: models composed as they compile alone, on gymnasium's models and the
real UR5e; irreconcilable settings refused, changing nothing."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import UR5E, gym_model
from tests.mjcf.attaching import differences_from_alone, top_bodies

Obj = mujoco.mjtObj


# -- default classes, angles and settings ----------------------------------------------------


def _parent(angle: str) -> mjcf.RootElement:
    degrees = angle == "degree"
    parent = mjcf.RootElement(model="parent")
    parent.compiler.angle = angle
    parent.default.geom.rgba = [1, 0, 0, 1]
    parent.default.joint.damping = 3
    body = parent.worldbody.add("body", name="pb", euler=[0, 90 if degrees else np.pi / 2, 0])
    body.add("joint", name="pj", type="hinge", range=[-45, 45] if degrees else [-0.7, 0.7])
    body.add("geom", name="pg", size=[0.1])
    parent.worldbody.add("site", name="mount", pos=[0.5, 0, 0])
    return parent


def _child(angle: str, eulerseq: str | None = None) -> mjcf.RootElement:
    degrees = angle == "degree"
    child = mjcf.RootElement(model="child")
    child.compiler.angle = angle
    if eulerseq is not None:
        child.compiler.eulerseq = eulerseq
    child.default.geom.set_attributes(rgba=[0, 1, 0, 1], friction=[0.5, 0.1, 0.1])
    child.default.joint.armature = 0.2
    child.default.add("default", dclass="thin").geom.size = [0.02]
    body = child.worldbody.add(
        "body", name="cb", pos=[1, 0, 0], euler=[30, 20, 10] if degrees else [0.5, 0.3, 0.2]
    )
    body.add("joint", name="hinge", type="hinge", range=[-30, 60] if degrees else [-0.5, 1],
             ref=10 if degrees else 0.2)  # fmt: skip
    body.add("joint", name="ball", type="ball", range=[0, 40] if degrees else [0, 0.7])
    body.add("geom", name="cg", size=[0.1], dclass="thin",
             axisangle=[0, 0, 1, 30] if degrees else [0, 0, 1, 0.5])  # fmt: skip
    body.add("site", name="cs", euler=[10, 20, 30] if degrees else [0.1, 0.2, 0.3])
    child.actuator.add("position", name="servo", joint="hinge", ctrlrange=[-1, 1], kp=10)
    return child


@pytest.mark.parametrize(
    ("parent_angle", "child_angle", "eulerseq"),
    [
        ("radian", "degree", None),
        ("degree", "radian", None),
        ("radian", "radian", "zyx"),
        ("degree", "degree", "XYZ"),
        ("radian", "degree", "ZYX"),
    ],
)
def test_defaults_angles_and_eulerseq_compile_as_alone(
    parent_angle: str, child_angle: str, eulerseq: str | None
) -> None:
    parent, child = _parent(parent_angle), _child(child_angle, eulerseq)
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    child_alone = mjcf.Physics.from_mjcf_model(child).model
    parent.find("site", "mount").attach(child)
    composed = mjcf.Physics.from_mjcf_model(parent).model
    assert differences_from_alone(child_alone, composed, "child/", placed={"cb"}) == []
    assert differences_from_alone(parent_alone, composed, "") == []
    green = composed.geom_rgba[mujoco.mj_name2id(composed, Obj.mjOBJ_GEOM, "child/cg")]
    assert np.array_equal(green, [0, 1, 0, 1])  # the child's defaults, not the parent's


@pytest.mark.parametrize("name", ["humanoid", "ant", "half_cheetah", "hopper", "walker2d"])
def test_gymnasium_settings_convert_into_a_radian_model(name: str) -> None:
    """Degrees, inertiafromgeom="true" and settotalmass (half_cheetah) of gymnasium's
    models, inside a radian model whose bodies have explicit inertias."""
    alone = mujoco.MjModel.from_xml_path(str(gym_model(name)))
    parent = _parent("radian")
    parent.find("body", "pb").add("inertial", pos=[0, 0, 0], mass=2, diaginertia=[0.1, 0.2, 0.3])
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    parent.find("site", "mount").attach(mjcf.from_path(gym_model(name)))
    composed = mjcf.Physics.from_mjcf_model(parent).model
    model_name = mjcf.from_path(gym_model(name)).model
    placed = top_bodies(alone)
    assert differences_from_alone(alone, composed, f"{model_name}/", placed) == []
    assert differences_from_alone(parent_alone, composed, "") == []


def test_a_radian_robot_inside_a_degree_model(menagerie) -> None:
    arm_alone = mjcf.Physics.from_mjcf_model(mjcf.from_path(UR5E)).model
    parent = _parent("degree")
    parent_alone = mjcf.Physics.from_mjcf_model(parent).model
    parent.find("site", "mount").attach(mjcf.from_path(UR5E))
    composed = mjcf.Physics.from_mjcf_model(parent).model
    assert differences_from_alone(arm_alone, composed, "ur5e/", placed={"base"}) == []
    assert differences_from_alone(parent_alone, composed, "") == []


@pytest.mark.parametrize(("angle", "quarter"), [("degree", 90.0), ("radian", np.pi / 2)])
def test_attachment_frames_inside_an_attached_model_keep_its_angle_units(
    angle: str, quarter: float
) -> None:
    """A frame belongs to the model it is in: its pose (set, or taken from the site it
    is attached at) is in that model's units, also when that model is attached."""
    base = mjcf.RootElement(model="base")
    base.compiler.angle = angle
    body = base.worldbody.add("body", name="bb")
    body.add("geom", size=[0.1])
    site = body.add("site", name="mount", euler=[0, 0, quarter])
    for name, place in (("at_site", site), ("at_body", body)):
        child = mjcf.RootElement(model=name)
        child.worldbody.add("body", name="cb").add("geom", size=[0.1])
        frame = place.attach(child)
        if place is body:
            frame.euler = [quarter, 0, 0]
    alone = mjcf.Physics.from_mjcf_model(base)
    root = mjcf.RootElement(model="root")
    root.compiler.angle = "radian" if angle == "degree" else "degree"
    root.attach(base)
    composed = mjcf.Physics.from_mjcf_model(root)
    for name in ("at_site", "at_body"):
        expected = alone.named.data.xquat[f"{name}/cb"]
        assert np.allclose(composed.named.data.xquat[f"base/{name}/cb"], expected)


def test_conflicting_options_are_refused_and_change_nothing() -> None:
    parent, child = _parent("radian"), _child("degree")
    parent.option.integrator = "RK4"
    child.option.integrator = "implicitfast"
    child.option.timestep = 0.005  # merges: the smaller step
    before, child_before = parent.to_xml_string(), child.to_xml_string()
    with pytest.raises(mjcf.AttachmentError, match=r"<option> integrator: 'RK4' in model"):
        parent.attach(child)
    assert parent.to_xml_string() == before and child.to_xml_string() == child_before
    assert child.parent_model is None
    child.option.integrator = "RK4"  # the same value on both is fine
    parent.attach(child)
    assert parent.option.timestep == 0.005
    child.option.integrator = "Euler"  # written later: the composed model's, as in dm_control
    assert mjcf.Physics.from_mjcf_model(parent).model.opt.integrator == 0  # Euler


def test_gymnasium_models_with_different_timesteps_compose_at_the_smaller_step() -> None:
    ant = mjcf.from_path(gym_model("ant"))  # timestep 0.01
    ant.attach(mjcf.from_path(gym_model("humanoid")))  # timestep 0.003, 50 PGS iterations
    model = mjcf.Physics.from_mjcf_model(ant).model
    assert model.opt.timestep == 0.003 and model.opt.iterations == 50
    assert model.opt.solver == mujoco.mjtSolver.mjSOL_PGS
    arena = mjcf.RootElement(model="arena")
    arena.attach(mjcf.from_path(gym_model("ant")))
    arena.attach(mjcf.from_path(gym_model("humanoid")))
    assert mjcf.Physics.from_mjcf_model(arena).model.opt.timestep == 0.003


def test_irreconcilable_inertia_settings_are_refused() -> None:
    parent = mjcf.RootElement(model="parent")
    parent.compiler.inertiafromgeom = "true"  # ignores the inertial below
    body = parent.worldbody.add("body", name="b")
    body.add("inertial", pos=[0, 0, 0], mass=5, diaginertia=[1, 1, 1])
    body.add("geom", size=[0.1])
    child = mjcf.RootElement(model="child")  # "auto": uses its inertial
    child_body = child.worldbody.add("body", name="c")
    child_body.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[1, 1, 1])
    child_body.add("geom", size=[0.1])
    before = parent.to_xml_string()
    with pytest.raises(mjcf.AttachmentError, match="inertiafromgeom"):
        parent.attach(child)
    assert parent.to_xml_string() == before


def _masses(model: mujoco.MjModel, prefix: str) -> dict[str, float]:
    """{body name without `prefix`: mass} of the bodies named `prefix` + a plain name (the
    world body left out)."""
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, i) or "" for i in range(model.nbody)
    ]
    return {
        name.removeprefix(prefix): float(model.body_mass[i])
        for i, name in enumerate(names)
        if i > 0
        and name.startswith(prefix)
        and name != prefix
        and "/" not in name.removeprefix(prefix)
    }


def _spec_attached(scene: mujoco.MjSpec, body: str, child: mujoco.MjSpec, prefix: str) -> None:
    """MuJoCo's own attachment: `child`'s top body on a frame of `scene`'s `body`."""
    frame = (scene.worldbody if not body else scene.body(body)).add_frame()
    frame.attach_body(child.worldbody.first_body(), prefix, "")


@pytest.mark.parametrize("order", ["cheetah first", "hopper first"])
def test_a_model_attached_inside_a_settotalmass_model_keeps_its_own_masses(order: str) -> None:
    """half_cheetah sets <compiler settotalmass="14">: attached into a scene its bodies weigh
    what they weigh alone (14 kg), and a hopper attached on its torso weighs what it weighs
    alone, in either order of attaching; the hopper was scaled with the cheetah (its 15.8 kg
    to 6.0). MuJoCo's own attach leaves the hopper's masses too (its compile here, with the
    same files, is the reference); dm_control scales every model of the scene to 14 kg."""
    hopper_alone = mujoco.MjModel.from_xml_path(str(gym_model("hopper")))
    cheetah_alone = mujoco.MjModel.from_xml_path(str(gym_model("half_cheetah")))
    scene = mjcf.RootElement(model="scene")
    cheetah, hopper = mjcf.from_path(gym_model("half_cheetah")), mjcf.from_path(gym_model("hopper"))
    hopper.option.timestep = cheetah.option.timestep  # one timestep for the composed model
    hopper.find("geom", "floor").remove()  # a plane is static: not on the cheetah's torso
    mount = cheetah.find("body", "torso").add("site", name="mount", pos=[0, 0, 0.5])
    if order == "cheetah first":
        scene.worldbody.attach(cheetah)
        mount.attach(hopper)
    else:
        mount.attach(hopper)
        scene.worldbody.attach(cheetah)
    composed = mjcf.Physics.from_mjcf_model(scene).model
    hopper_masses = _masses(composed, "cheetah/hopper/")
    assert hopper_masses == pytest.approx(_masses(hopper_alone, ""), rel=1e-12)
    assert _masses(composed, "cheetah/") == pytest.approx(_masses(cheetah_alone, ""), rel=1e-12)
    spec = mujoco.MjSpec.from_string("<mujoco/>")
    with warnings.catch_warnings():  # MuJoCo's "Attach conflict" of options, when compiling
        warnings.simplefilter("ignore", UserWarning)
        _spec_attached(spec, "", mujoco.MjSpec.from_file(str(gym_model("half_cheetah"))),
                       "cheetah/")  # fmt: skip
        _spec_attached(spec, "cheetah/torso", mujoco.MjSpec.from_file(str(gym_model("hopper"))),
                       "hopper/")  # fmt: skip
        theirs = spec.compile()
    assert hopper_masses == pytest.approx(_masses(theirs, "hopper/"), rel=1e-12)


def test_settotalmass_of_the_output_model_with_attachments_is_refused() -> None:
    """Written as the output model, half_cheetah's settotalmass would scale the hopper
    attached to it too (MuJoCo's and dm_control's do): refused when written or compiled,
    whenever the hopper was attached; attached into a scene, it is written."""
    cheetah, hopper = mjcf.from_path(gym_model("half_cheetah")), mjcf.from_path(gym_model("hopper"))
    hopper.option.timestep = cheetah.option.timestep
    cheetah.attach(hopper)
    for write in (cheetah.to_xml_string, lambda: mjcf.Physics.from_mjcf_model(cheetah)):
        with pytest.raises(
            mjcf.AttachmentError, match=r"settotalmass=14\.0> of model 'cheetah' would scale"
        ):
            write()
    scene = mjcf.RootElement(model="scene")
    scene.attach(cheetah)
    assert mjcf.Physics.from_mjcf_model(scene).model.nbody > 1


def test_sizes_merge_to_the_largest() -> None:
    parent, child = _parent("radian"), _child("radian")
    parent.size.nkey = 2
    child.size.nkey = 4
    parent.attach(child)
    assert mjcf.Physics.from_mjcf_model(parent).model.nkey == 4
