"""Fresh values: what bindings and named access read after steps and tracked writes is what
MuJoCo's own mj_forward computes for the state (on a copy of the MjData), and model edits
give the model a recompiled spec gives (MjSpec as the oracle)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjcf
from mjcf.physics import Physics
from mjcf.sim import fields
from tests.conftest import MUJOCO_TESTDATA, gym_model

Obj = mujoco.mjtObj

# Derived fields compared with mj_forward: position/velocity stage, acceleration stage, and
# fields MuJoCo computes only when a sensor asks.
POSITION_FIELDS = ("xpos", "xquat", "xipos", "geom_xpos", "site_xpos", "subtree_com", "cvel",
                   "qfrc_bias", "ten_length", "actuator_length", "xanchor")  # fmt: skip
ACCELERATION_FIELDS = ("qacc", "actuator_force", "qfrc_constraint", "sensordata")
ON_DEMAND_FIELDS = ("cfrc_ext", "cacc", "subtree_linvel")


def forwarded_copy(physics: Physics) -> mujoco.MjData:
    """mj_forward of a copy of the physics' MjData: the oracle of fresh values."""
    data = mujoco.MjData(physics.model)
    mujoco.mj_copyData(data, physics.model, physics.data)
    mujoco.mj_forward(physics.model, data)
    mujoco.mj_rnePostConstraint(physics.model, data)
    mujoco.mj_subtreeVel(physics.model, data)
    return data


def read_all(physics: Physics, name: str) -> np.ndarray:
    """Field `name` of every object, read through a binding (the kind named access uses)."""
    field = fields.indexed_field(name)
    ids = np.arange(fields.count(physics.model, field.kind))
    if ids.size == 0:
        return np.zeros(getattr(physics.data, name).shape)
    return np.asarray(getattr(physics._binding(field.kind, ids), name))


def sensing_model(path, integrator: str | None = None) -> Physics:
    """The model at `path` with a touch sensor, an accelerometer and a frame sensor on its
    first body's first geom and a new site, as MuJoCo's own XML."""
    spec = mujoco.MjSpec.from_file(str(path))
    if integrator is not None:
        spec.option.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator}")
    body = spec.worldbody.bodies[0]
    while not body.geoms and body.bodies:
        body = body.bodies[0]
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_AUTO
    site = body.add_site(name="probe", size=[0.3, 0.3, 0.3], type=mujoco.mjtGeom.mjGEOM_BOX)
    for kind in ("TOUCH", "ACCELEROMETER", "FRAMEPOS", "VELOCIMETER"):
        sensor = spec.add_sensor(type=getattr(mujoco.mjtSensor, f"mjSENS_{kind}"))
        sensor.objtype, sensor.objname = mujoco.mjtObj.mjOBJ_SITE, site.name
    return Physics(spec.compile())


MODELS = {
    "humanoid, RK4": lambda: sensing_model(gym_model("humanoid")),
    "ant, Euler": lambda: sensing_model(gym_model("ant"), "EULER"),
    "ant, implicitfast": lambda: sensing_model(gym_model("ant"), "IMPLICITFAST"),
    "mujoco testdata": lambda: Physics.from_xml_path(MUJOCO_TESTDATA / "model.xml"),
}


@pytest.mark.parametrize("make", list(MODELS.values()), ids=list(MODELS))
def test_after_steps_every_read_is_what_mj_forward_computes(make) -> None:
    physics = make()
    plain = mujoco.MjData(physics.model)  # the same steps with bare mj_step: the state oracle
    mujoco.mj_copyData(plain, physics.model, physics.data)
    rng = np.random.default_rng(0)
    for _ in range(30):
        ctrl = rng.uniform(-1, 1, physics.model.nu)
        physics.set_control(ctrl)
        plain.ctrl[:] = ctrl
        physics.step(4)
        mujoco.mj_step(physics.model, plain, 4)
    assert np.array_equal(physics.get_state(), _state(physics.model, plain))  # bit for bit
    expected = forwarded_copy(physics)
    # Position/velocity fields are already current in the raw MjData after a step.
    for name in POSITION_FIELDS:
        assert np.array_equal(getattr(physics.data, name), getattr(expected, name)), name
    for name in POSITION_FIELDS + ACCELERATION_FIELDS + ON_DEMAND_FIELDS:
        got, want = read_all(physics, name), getattr(expected, name)
        assert np.array_equal(got.reshape(want.shape), want), name
    for name in ("sensordata", "qacc", "xpos"):
        assert np.array_equal(physics.named.data.__getattr__(name)[:], getattr(expected, name))


def _state(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    spec = mujoco.mjtState.mjSTATE_PHYSICS | mujoco.mjtState.mjSTATE_PLUGIN
    out = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, out, spec)
    return out


def test_a_touch_sensor_reads_the_contact_force_of_the_state_it_reports() -> None:
    physics = Physics.from_xml_string(
        """
        <mujoco><worldbody><geom type="plane" size="1 1 .1"/>
          <body pos="0 0 .2"><freejoint/><geom name="box" type="box" size=".1 .1 .1"/>
            <site name="pad" type="box" size=".11 .11 .11"/></body></worldbody>
          <sensor><touch name="touch" site="pad"/></sensor></mujoco>"""
    )
    touch = physics.bind_names(Obj.mjOBJ_SENSOR, "touch")
    for _ in range(200):
        physics.step()
        assert touch.sensordata[0] == forwarded_copy(physics).sensordata[0]
    assert touch.sensordata[0] > 0  # it came to rest on the floor


def test_legacy_step_false_is_a_plain_mj_step_whose_fields_lag() -> None:
    physics = Physics.from_xml_path(gym_model("ant"))
    physics.model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER  # RK4 ends mid-stage
    physics.legacy_step = False
    torso = physics.bind_names(Obj.mjOBJ_BODY, "torso")
    before = physics.data.qpos.copy()
    physics.step()
    lagging = mujoco.MjData(physics.model)
    lagging.qpos[:] = before
    mujoco.mj_forward(physics.model, lagging)
    assert np.array_equal(torso.xpos, lagging.xpos[1])  # the state before the step
    assert not physics.is_dirty
    copy = physics.copy()
    assert copy.legacy_step is False


def test_writing_joint_angles_moves_a_site_without_forward() -> None:
    model = mjcf.from_path(gym_model("ant"))
    tip = model.find("body", "aux_1").add("site", name="tip", pos=[0.2, 0.2, 0])
    physics = mjcf.Physics.from_mjcf_model(model)
    site = physics.bind(tip)
    before = site.xpos.copy()
    hip, ankle = model.find("joint", "hip_1"), model.find("joint", "ankle_1")
    physics.bind([hip, ankle]).qpos = [0.5, 1.0]
    assert physics.is_dirty
    assert np.array_equal(physics.data.site_xpos[0], before)  # raw data: not yet
    qpos = physics.bind(hip).qpos  # reading state (or a model field) runs nothing
    mass = physics.bind(model.find("body", "torso")).mass
    assert physics.is_dirty and qpos[0] == 0.5 and mass > 0
    moved = site.xpos  # a derived read forwards first
    assert not physics.is_dirty
    expected = forwarded_copy(physics)
    site_id = mujoco.mj_name2id(physics.model, Obj.mjOBJ_SITE, "tip")
    assert np.array_equal(moved, expected.site_xpos[site_id]) and not np.allclose(moved, before)
    # named access is tracked the same way, and so is item assignment into a list's copy
    physics.named.data.qpos["hip_1"] = -0.5
    assert physics.is_dirty
    assert np.array_equal(physics.named.data.site_xpos["tip"], forwarded_copy(physics).site_xpos[0])
    legs = physics.bind([ankle, hip])  # rows not a slice: a copy that writes back
    legs.qpos[1] = 0.25
    assert physics.is_dirty and physics.named.data.qpos["hip_1"] == 0.25
    assert np.array_equal(site.xpos, forwarded_copy(physics).site_xpos[site_id])


def test_controls_refresh_only_the_acceleration_stage() -> None:
    physics = sensing_model(gym_model("ant"), "EULER")
    physics.step()
    motors = physics._binding(Obj.mjOBJ_ACTUATOR, np.arange(physics.model.nu))
    motors.ctrl = 0.7
    assert physics.is_dirty
    xpos = physics.data.xpos.copy()
    physics._binding(Obj.mjOBJ_BODY, 1).xpos  # noqa: B018 - positions do not depend on ctrl
    assert physics.is_dirty and np.array_equal(physics.data.xpos, xpos)
    force = motors.force  # the acceleration stage is recomputed
    assert not physics.is_dirty
    assert np.array_equal(force, forwarded_copy(physics).actuator_force)
    assert np.all(force == 0.7)  # motors: force = ctrl in actuation space


def test_writing_a_derived_field_keeps_the_value_written() -> None:
    physics = sensing_model(gym_model("ant"), "EULER")
    sensors = physics._binding(Obj.mjOBJ_SENSOR, np.arange(physics.model.nsensor))
    physics.named.data.qpos[7] = 0.3  # dirty
    sensors.sensordata = 42.0  # forwards first, then writes
    assert not physics.is_dirty
    assert np.all(sensors.sensordata == 42.0)


def test_a_derived_write_after_a_step_keeps_its_value() -> None:
    """dm_control's flow: controls written, a step, then sensor data assigned (a test's
    fake reading): the derived write brings the acceleration stage up to date first and
    keeps the value written. (The step clears is_dirty, which dm_control keeps set: the
    step leaves every derived quantity fresh, so no read needs to forward.)"""
    physics = sensing_model(gym_model("ant"), "EULER")
    motors = physics._binding(Obj.mjOBJ_ACTUATOR, np.arange(physics.model.nu))
    motors.ctrl = 0.75
    assert physics.is_dirty
    physics.step()
    assert not physics.is_dirty
    sensors = physics._binding(Obj.mjOBJ_SENSOR, np.arange(physics.model.nsensor))
    sensors.sensordata = 12345.0
    assert not physics.is_dirty
    assert np.all(sensors.sensordata == 12345.0)
    physics.forward()
    assert np.array_equal(sensors.sensordata, forwarded_copy(physics).sensordata)


def test_step_after_a_tracked_write_starts_from_the_written_state() -> None:
    physics = Physics.from_xml_path(gym_model("ant"))
    twin = mujoco.MjData(physics.model)
    physics.step()
    physics.named.data.qvel["hip_1"] = 3.0
    mujoco.mj_copyData(twin, physics.model, physics.data)
    physics.step()
    mujoco.mj_step(physics.model, twin)
    assert np.array_equal(physics.data.qpos, twin.qpos)
    # Written into `data` directly: untracked, until mark_as_dirty() says so.
    physics.data.qvel[6] = -3.0
    physics.mark_as_dirty()
    mujoco.mj_copyData(twin, physics.model, physics.data)
    physics.step()
    mujoco.mj_step(physics.model, twin)
    assert np.array_equal(physics.data.qpos, twin.qpos)


# -- model edits: the model a recompiled spec gives ------------------------------------------

SCENE = """
<mujoco><worldbody><geom name="floor" type="plane" size="2 2 .1"/>
  <body name="arm" pos="0 0 1"><joint name="hinge" axis="0 1 0"/>
    <geom name="rod" type="capsule" fromto="0 0 0 0 0 -.4" size=".03"/>
    <geom name="knob" type="sphere" size=".05"/>
    <site name="mark" size=".01"/>
    <body name="hand" pos="0 0 -.4"><joint name="wrist" axis="0 1 0"/>
      <geom name="palm" type="box" size=".05 .05 .05"/></body></body>
  <body name="puck" pos="1 0 .05"><freejoint/><geom name="puck" type="sphere" size=".05"/></body>
  <body name="loose" pos="-1 0 .5" simple="false"><freejoint/>
    <geom name="loose" type="box" size=".1 .1 .1"/></body>
</worldbody></mujoco>"""


def recompiled(edit) -> mujoco.MjModel:
    """SCENE compiled after `edit(spec)`: MuJoCo's own answer."""
    spec = mujoco.MjSpec.from_string(SCENE)
    edit(spec)
    return spec.compile()


def scene() -> tuple[mjcf.RootElement, mjcf.Physics]:
    model = mjcf.from_xml_string(SCENE)
    return model, mjcf.Physics.from_mjcf_model(model)


@pytest.mark.parametrize("by", ["assignment", "item assignment", "named", "column"])
def test_moving_a_geom_at_its_body_origin_moves_it(by) -> None:
    model, physics = scene()
    knob = physics.bind(model.find("geom", "knob"))
    knob_id = mujoco.mj_name2id(physics.model, Obj.mjOBJ_GEOM, "knob")
    sameframe = physics.model.geom_sameframe.copy()
    assert sameframe[knob_id] == mujoco.mjtSameFrame.mjSAMEFRAME_BODY
    if by == "assignment":
        knob.pos = [0.1, 0, 0]
    elif by == "item assignment":
        knob.pos[0] = 0.1
    elif by == "named":
        physics.named.model.geom_pos["knob", "x"] = 0.1
    else:
        knob["pos", "x"] = 0.1
    oracle = recompiled(lambda spec: setattr(spec.geom("knob"), "pos", [0.1, 0, 0]))
    others = np.arange(physics.model.ngeom) != knob_id
    now = physics.model.geom_sameframe
    assert now[knob_id] == oracle.geom_sameframe[knob_id] != sameframe[knob_id]
    assert np.array_equal(physics.model.geom_sameframe[others], sameframe[others])  # only it
    assert np.array_equal(physics.model.geom_aabb, oracle.geom_aabb)
    physics.forward()
    expected = mujoco.MjData(oracle)
    mujoco.mj_forward(oracle, expected)
    assert np.allclose(physics.data.geom_xpos, expected.geom_xpos, atol=1e-12)
    assert np.allclose(knob.xpos, [0.1, 0, 1])


def test_moving_a_site_and_quaternions() -> None:
    model, physics = scene()
    mark = physics.bind(model.find("site", "mark"))
    quat = np.array([np.cos(0.3), 0, np.sin(0.3), 0])
    mark.quat = quat
    mark.pos += [0, 0, -0.2]
    oracle = recompiled(lambda spec: (setattr(spec.site("mark"), "quat", quat),
                                      setattr(spec.site("mark"), "pos", [0, 0, -0.2])))  # fmt: skip
    assert np.array_equal(physics.model.site_sameframe, oracle.site_sameframe)
    expected = mujoco.MjData(oracle)
    mujoco.mj_forward(oracle, expected)
    assert np.allclose(mark.xpos, expected.site_xpos[0], atol=1e-12)  # dirty: forwards first
    assert np.allclose(mark.xmat, expected.site_xmat[0], atol=1e-12)


def test_a_bigger_geom_collides_where_it_now_reaches() -> None:
    model, physics = scene()
    puck = physics.bind(model.find("geom", "puck"))
    puck.size = [0.3, 0, 0]  # bounding sphere and box follow, so contacts are not missed
    oracle = recompiled(lambda spec: setattr(spec.geom("puck"), "size", [0.3, 0, 0]))
    assert np.array_equal(physics.model.geom_rbound, oracle.geom_rbound)
    assert np.array_equal(physics.model.geom_aabb, oracle.geom_aabb)
    physics.forward()
    assert physics.data.ncon > 0  # the floor, 0.25 deep into the larger puck


def test_masses_and_inertial_frames_update_the_constants_mujoco_derives() -> None:
    model, physics = scene()
    hand = physics.bind(model.find("body", "hand"))
    hand.mass = 3.0
    arm = model.find("body", "arm")
    inertia = hand.inertia.copy()

    def heavier(spec: mujoco.MjSpec) -> None:
        body = spec.body("hand")
        body.explicitinertial, body.mass, body.inertia = True, 3.0, inertia
        body.ipos, body.iquat = [0, 0, 0], [1, 0, 0, 0]

    oracle = recompiled(heavier)
    assert np.array_equal(physics.model.body_subtreemass, oracle.body_subtreemass)
    assert np.allclose(physics.bind(arm).subtree_com, _forwarded(oracle).subtree_com[1])
    loose = physics.bind(model.find("body", "loose"))  # declared simple="false"
    loose.ipos = [0.05, 0, 0]
    assert loose.sameframe != mujoco.mjtSameFrame.mjSAMEFRAME_BODY
    physics.forward()
    assert np.allclose(loose.xipos, loose.xpos + np.array([0.05, 0, 0]))


def _forwarded(model: mujoco.MjModel) -> mujoco.MjData:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return data


def test_moving_the_inertial_frame_of_a_simple_body_as_a_recompile_gives_it() -> None:
    """Randomising a center of mass: a body MuJoCo compiled as "simple" (gymnasium's
    pusher object on two slides, its goal) takes a new ipos or iquat through a binding,
    and the model then equals the one compiled from the XML with those values (simple
    flags, dof_simplenum, sameframe) and simulates alike."""
    model = mjcf.from_path(gym_model("pusher"))
    physics = mjcf.Physics.from_mjcf_model(model)
    thing, goal = (physics.bind(model.find("body", name)) for name in ("object", "goal"))
    assert thing.simple and goal.simple
    turned = np.array([np.cos(0.2), 0, 0, np.sin(0.2)])
    new = {"object": ([0.02, -0.01, 0.0], [1.0, 0, 0, 0]), "goal": ([0.0, 0, 0], turned)}
    inertias = {name: (physics.bind(model.find("body", name)).mass.copy(),
                       physics.bind(model.find("body", name)).inertia.copy())
                for name in new}  # fmt: skip
    thing.ipos = new["object"][0]
    goal.iquat = turned

    spec = mujoco.MjSpec.from_file(str(gym_model("pusher")))
    # pusher.xml computes every inertia from geoms: "auto" keeps the other bodies' so
    # and takes the two written as explicit <inertial> elements.
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_AUTO
    for name, (ipos, iquat) in new.items():
        body = spec.body(name)
        body.explicitinertial, body.mass, body.inertia = True, *inertias[name]
        body.ipos, body.iquat = ipos, iquat
    oracle = spec.compile()
    assert not thing.simple and not goal.simple
    for field in ("body_simple", "dof_simplenum", "body_sameframe", "body_ipos", "body_iquat"):
        assert np.array_equal(getattr(physics.model, field), getattr(oracle, field)), field
    expected = mujoco.MjData(oracle)
    physics.data.ctrl[:] = expected.ctrl[:] = 0.5
    physics.data.qvel[-4:] = expected.qvel[-4:] = [0.3, -0.2, 0.1, 0.1]  # object and goal slide
    for _ in range(50):
        physics.step()
        mujoco.mj_step(oracle, expected)
    assert np.allclose(physics.data.qpos, expected.qpos, atol=1e-12)
    mujoco.mj_forward(oracle, expected)
    assert np.allclose(thing.xipos, expected.xipos[thing.element_id], atol=1e-12)
    assert np.allclose(goal.ximat, expected.ximat[goal.element_id], atol=1e-12)


def test_colors_do_not_make_the_physics_dirty() -> None:
    model, physics = scene()
    physics.bind(model.find("geom", "rod")).rgba = [1, 0, 0, 1]
    assert not physics.is_dirty
    physics.bind(model.find("geom", "rod")).friction = [0.5, 0.01, 0.001]
    assert physics.is_dirty


def _two_bodies() -> mjcf.RootElement:
    """dm_control's physics_test model: two bodies, each with an ellipsoid and a site
    (and an inertial, so that a recompile with a turned geom keeps the body's inertia,
    which a runtime write of a geom's pose does not change)."""
    root = mjcf.RootElement()
    for _ in range(2):
        body = root.worldbody.add("body")
        body.add("geom", type="ellipsoid", size=[0.1, 0.2, 0.3])
        body.add("site", type="sphere", size=[0.1])
        body.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[0.01, 0.02, 0.03])
    return root


_FRAME = {"body": ("body_sameframe", "xpos", "xmat"), "geom": ("geom_sameframe", "geom_xpos",
          "geom_xmat"), "site": ("site_sameframe", "site_xpos", "site_xmat")}  # fmt: skip


@pytest.mark.parametrize(
    ("kind", "field"),
    [(k, f) for k in ("body", "geom", "site") for f in ("pos", "quat")]
    + [("body", "ipos"), ("body", "iquat")],
)
def test_moved_frames_are_as_a_recompile_gives_them(kind: str, field: str) -> None:
    """dm_control zeroes the sameframe flag of a frame written through a binding; here
    MuJoCo recomputes it, so it and the poses after forward() equal those of the model
    compiled with the new values (the improvement shown, not assumed)."""
    root = _two_bodies()
    physics = mjcf.Physics.from_mjcf_model(root)
    first, second = (physics.bind(e) for e in root.find_all(kind))
    if field.endswith("pos"):
        setattr(first, field, [0.0, 0.0, 0.1])
        getattr(second, field)[0] = -0.1  # item assignment, as dm_control's test does
    else:
        setattr(first, field, [0.0, 0.0, 0.0, 1.0])
        setattr(second, field, [np.cos(0.3), 0.0, np.sin(0.3), 0.0])

    spec = mujoco.MjSpec.from_string(root.to_xml_string())
    elements = {"body": spec.bodies[1:], "geom": spec.geoms, "site": spec.sites}[kind]
    for element, written in zip(elements, (first, second), strict=True):
        if field in ("ipos", "iquat"):
            element.explicitinertial = True
            element.mass, element.inertia = written.mass, written.inertia
            element.ipos, element.iquat = written.ipos, written.iquat
        else:
            setattr(element, field, getattr(written, field))
    oracle = spec.compile()
    flag, xpos, xmat = _FRAME[kind]
    if field in ("ipos", "iquat"):
        flag, xpos, xmat = "body_sameframe", "xipos", "ximat"
    assert np.array_equal(getattr(physics.model, flag), getattr(oracle, flag))
    physics.forward()
    expected = _forwarded(oracle)
    assert np.allclose(getattr(physics.data, xpos), getattr(expected, xpos), atol=1e-12)
    assert np.allclose(getattr(physics.data, xmat), getattr(expected, xmat), atol=1e-12)
