"""Named indexing on real models equals indexing through mujoco.mj_name2id and address arrays."""

from __future__ import annotations

from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

from mjcf import errors
from mjcf.physics import Physics
from tests.conftest import UR5E

Obj = mujoco.mjtObj
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata" / "model.xml"


def load(path: Path) -> Physics:
    physics = Physics.from_xml_path(path)
    rng = np.random.default_rng(1)
    physics.data.qvel[:] = rng.normal(scale=0.1, size=physics.model.nv)
    physics.data.ctrl[:] = rng.uniform(-0.3, 0.3, size=physics.model.nu)
    physics.step(10)
    return physics


@pytest.fixture(
    params=[
        GYM_ASSETS / "humanoid.xml",
        MUJOCO_TESTDATA,
        UR5E,
    ],
    ids=["humanoid", "mujoco testdata", "ur5e"],
)
def physics(request) -> Physics:
    return load(request.param)


# (field, object kind, how mj_name2id's id finds the rows: one row, or adr/width arrays)
ROW_FIELDS = [
    ("model", "body_mass", Obj.mjOBJ_BODY),
    ("model", "body_pos", Obj.mjOBJ_BODY),
    ("data", "xpos", Obj.mjOBJ_BODY),
    ("data", "xquat", Obj.mjOBJ_BODY),
    ("data", "cvel", Obj.mjOBJ_BODY),
    ("model", "geom_rgba", Obj.mjOBJ_GEOM),
    ("model", "geom_size", Obj.mjOBJ_GEOM),
    ("data", "geom_xpos", Obj.mjOBJ_GEOM),
    ("model", "jnt_range", Obj.mjOBJ_JOINT),
    ("data", "xanchor", Obj.mjOBJ_JOINT),
    ("data", "site_xpos", Obj.mjOBJ_SITE),
    ("model", "actuator_gainprm", Obj.mjOBJ_ACTUATOR),
    ("model", "actuator_ctrlrange", Obj.mjOBJ_ACTUATOR),
    ("data", "ctrl", Obj.mjOBJ_ACTUATOR),
    ("data", "actuator_force", Obj.mjOBJ_ACTUATOR),
    ("data", "ten_length", Obj.mjOBJ_TENDON),
    ("data", "light_xpos", Obj.mjOBJ_LIGHT),
    ("model", "key_qpos", Obj.mjOBJ_KEY),
]


def named_objects(model: mujoco.MjModel, kind: Obj) -> list[tuple[str, int]]:
    found = []
    for i in range(model.nbody + model.njnt + model.ngeom + model.nsite + model.nu + 64):
        name = mujoco.mj_id2name(model, kind, i)
        if name:
            found.append((name, mujoco.mj_name2id(model, kind, name)))
    return found


def test_names_index_the_rows_mj_name2id_gives(physics):
    model, data = physics.model, physics.data
    compared = 0
    for struct, field, kind in ROW_FIELDS:
        raw = getattr(model if struct == "model" else data, field)
        indexer = getattr(getattr(physics.named, struct), field)
        objects = named_objects(model, kind)
        for name, i in objects:
            assert np.array_equal(indexer[name], raw[i]), (field, name)
            compared += 1
        if len(objects) >= 2:
            (a, i), (b, j) = objects[0], objects[-1]
            assert np.array_equal(indexer[[b, a]], raw[[j, i]])
    assert compared > 20


def test_joint_names_index_qpos_and_dof_blocks(physics):
    model, data = physics.model, physics.data
    qpos_width = {0: 7, 1: 4, 2: 1, 3: 1}
    for name, j in named_objects(model, Obj.mjOBJ_JOINT):
        qadr, vadr = model.jnt_qposadr[j], model.jnt_dofadr[j]
        nq = qpos_width[int(model.jnt_type[j])]
        nv = {7: 6, 4: 3}.get(nq, 1)
        assert np.array_equal(physics.named.data.qpos[name], data.qpos[qadr : qadr + nq])
        assert np.array_equal(physics.named.data.qvel[name], data.qvel[vadr : vadr + nv])
        assert np.array_equal(physics.named.data.qfrc_bias[name], data.qfrc_bias[vadr:][:nv])
        assert np.array_equal(physics.named.model.dof_damping[name], model.dof_damping[vadr:][:nv])
        assert np.array_equal(physics.named.model.qpos0[name], model.qpos0[qadr : qadr + nq])


def test_sensor_names_index_sensordata():
    physics = load(MUJOCO_TESTDATA)
    model = physics.model
    for name, s in named_objects(model, Obj.mjOBJ_SENSOR):
        adr, dim = model.sensor_adr[s], model.sensor_dim[s]
        assert np.array_equal(
            physics.named.data.sensordata[name], physics.data.sensordata[adr : adr + dim]
        )


def test_numpy_keys_pass_through():
    physics = load(GYM_ASSETS / "humanoid.xml")
    named, data = physics.named.data, physics.data
    assert np.array_equal(named.qpos[3:7], data.qpos[3:7])
    assert named.qpos[2] == data.qpos[2]
    mask = data.qpos > 0
    assert np.array_equal(named.qpos[mask], data.qpos[mask])
    assert np.array_equal(named.xpos[[1, 2]], data.xpos[[1, 2]])
    assert named.xpos["torso", 2] == data.xpos[1, 2]
    assert np.array_equal(named.xpos[["torso", 3]], data.xpos[[1, 3]])
    assert np.array_equal(np.asarray(named.xpos), data.xpos)
    assert np.array_equal(named.xpos[np.array(["torso", "pelvis"])], data.xpos[[1, 3]])
    assert named.xpos.shape == data.xpos.shape and len(named.qpos) == physics.model.nq


def test_assignment_writes_through_every_kind_of_key():
    physics = load(GYM_ASSETS / "humanoid.xml")
    model, data = physics.model, physics.data
    physics.named.data.qpos["right_knee"] = -0.5
    assert data.qpos[model.jnt_qposadr[model.joint("right_knee").id]] == -0.5
    physics.named.data.qpos["root"][:3] = [1.0, 2.0, 3.0]  # a name's block is a view
    assert np.array_equal(data.qpos[:3], [1, 2, 3])
    physics.named.model.geom_rgba["floor"] = [1, 0, 0, 1]
    assert np.array_equal(model.geom_rgba[0], [1, 0, 0, 1])
    physics.named.data.qvel[["abdomen_z", "root"]] = np.arange(7.0)
    assert data.qvel[model.jnt_dofadr[1]] == 0 and np.array_equal(data.qvel[:6], np.arange(1, 7))
    mass = model.body_mass[1]
    physics.named.model.body_mass["torso"] += 1.0
    assert model.body_mass[1] == mass + 1.0
    physics.named.data.xfrc_applied["torso", 2] = 5.0
    assert data.xfrc_applied[1, 2] == 5.0
    physics.named.data.ctrl = 0.1  # attribute assignment writes every row
    assert np.all(data.ctrl == 0.1)
    with pytest.raises(errors.BindingError, match=r"cannot write \(2,\)-shaped values to qpos"):
        physics.named.data.qpos["root"] = [1.0, 2.0]


def test_axes_name_the_owner_of_every_row():
    physics = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    names = physics.named.data.qpos.axes.row.names
    assert names[:8] == ("root",) * 7 + ("abdomen_z",)
    assert len(names) == physics.model.nq
    assert physics.named.model.body_mass.axes.row.names[:2] == ("world", "torso")
    assert physics.named.model.geom_rgba.axes.row.kind == Obj.mjOBJ_GEOM


def test_repr_is_a_table_of_names_and_values():
    physics = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    text = repr(physics.named.data.xpos)
    lines = text.splitlines()
    assert lines[0].startswith("data.xpos: 14 rows of body")
    assert "torso" in lines[2] and "1.4" in lines[2]
    qpos = repr(physics.named.data.qpos).splitlines()
    assert "root" in qpos[1] and "root" not in qpos[2]  # the owner labels its first row
    assert "via jnt_qposadr" in qpos[0]


def test_unknown_names_and_fields_are_clear_errors():
    physics = Physics.from_xml_path(GYM_ASSETS / "humanoid.xml")
    with pytest.raises(errors.NotFoundError, match=r"no row named 'torsoo' \(did you mean"):
        physics.named.data.xpos["torsoo"]
    with pytest.raises(KeyError):  # NotFoundError is a KeyError too
        physics.named.data.qpos[["root", "nope"]]
    with pytest.raises(errors.BindingError, match="not indexed by any kind of object"):
        physics.named.data.qLD  # noqa: B018
    with pytest.raises(errors.BindingError, match="did you mean 'xpos'"):
        physics.named.data.xpso  # noqa: B018
    with pytest.raises(errors.BindingError, match="index"):
        physics.named.data.qpos[999]
    assert "qpos" in dir(physics.named.data) and "geom_rgba" in dir(physics.named.model)


def test_named_views_survive_reset_copy_and_model_change():
    physics = load(GYM_ASSETS / "humanoid.xml")
    qpos = physics.named.data.qpos
    physics.reset()
    assert np.array_equal(qpos["right_knee"], physics.data.qpos[[physics.model.jnt_qposadr[7]]])
    clone = physics.copy()
    clone.named.data.qpos["right_knee"] = 1.0
    assert qpos["right_knee"][0] != 1.0
    other = Physics.from_xml_path(GYM_ASSETS / "ant.xml")
    physics._attach(other.model, other.data)
    assert np.array_equal(qpos["hip_1"], other.data.qpos[[other.model.jnt_qposadr[1]]])
