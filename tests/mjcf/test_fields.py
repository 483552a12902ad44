"""mjcf.sim.fields covers every indexed MjModel/MjData field of the installed mujoco, correctly.

The model below has at least one object of every kind, so that iterating the installed
fields exercises every kind and every address scheme; the checks compare against MuJoCo's own
per-object views (`model.joint(i)`, `data.sensor(i)` ...) and name lookups, not against our
tables.
"""

from __future__ import annotations

import re
from pathlib import Path

import mujoco
import numpy as np
import pytest
from mujoco.introspect import structs

from mjcf import errors
from mjcf.physics import Physics
from mjcf.sim import fields, staleness
from tests.conftest import MUJOCO_TESTDATA

Obj = mujoco.mjtObj

EVERY_KIND = """
<mujoco model="every kind">
  <extension>
    <plugin plugin="mujoco.pid">
      <instance name="pid"><config key="kp" value="10"/><config key="ki" value="1"/></instance>
    </plugin>
  </extension>
  <custom>
    <numeric name="gains" data="1 2 3"/>
    <text name="note" data="hello"/>
    <tuple name="bodies">
      <element objtype="body" objname="arm" prm="1"/>
      <element objtype="body" objname="target" prm="2"/>
    </tuple>
  </custom>
  <asset>
    <texture name="grid" type="2d" builtin="checker" width="8" height="8"/>
    <texture name="sky" type="skybox" builtin="gradient" width="8" height="8"/>
    <material name="grid" texture="grid"/>
    <hfield name="bumps" nrow="2" ncol="3" size="1 1 0.1 0.1" elevation="0 1 0 1 0 1"/>
    <mesh name="tet" vertex="0 0 0  1 0 0  0 1 0  0 0 1" scale="0.1 0.1 0.1"/>
  </asset>
  <worldbody>
    <light name="sun" pos="0 0 3"/>
    <camera name="front" pos="0 -3 1" xyaxes="1 0 0 0 0.3 1"/>
    <geom name="floor" type="plane" size="3 3 0.1" material="grid"/>
    <geom name="terrain" type="hfield" hfield="bumps" pos="2 2 0"/>
    <body name="target" mocap="true" pos="0.5 0 1">
      <geom name="marker" type="sphere" size="0.05" contype="0" conaffinity="0"/>
    </body>
    <body name="arm" pos="0 0 1">
      <joint name="slide" type="slide" axis="1 0 0"/>
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom name="upper" type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
      <site name="elbow" pos="0.3 0 0"/>
      <body name="forearm" pos="0.3 0 0">
        <joint name="wrist" type="ball"/>
        <geom name="lower" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <geom name="tip" type="mesh" mesh="tet" pos="0.3 0 0"/>
        <site name="hand" pos="0.3 0 0"/>
      </body>
    </body>
    <body name="ball" pos="1 0 0.5">
      <freejoint name="free"/>
      <geom name="ball" type="sphere" size="0.1"/>
    </body>
    <body name="rope_base" pos="-1 0 1">
      <flexcomp name="rope" type="grid" count="3 1 1" spacing="0.1 0.1 0.1" dim="1"
                radius="0.01">
        <edge equality="true"/>
      </flexcomp>
    </body>
  </worldbody>
  <deformable>
    <skin name="hull" vertex="0 0 0  0.1 0 0  0 0.1 0" face="0 1 2">
      <bone body="arm" bindpos="0 0 0" bindquat="1 0 0 0" vertid="0 1 2" vertweight="1 1 1"/>
    </skin>
  </deformable>
  <contact>
    <pair name="ball_floor" geom1="ball" geom2="floor"/>
    <exclude name="no_self" body1="arm" body2="forearm"/>
  </contact>
  <equality>
    <joint name="couple" joint1="slide" joint2="hinge" active="false"/>
  </equality>
  <tendon>
    <fixed name="sum"><joint joint="slide" coef="1"/><joint joint="hinge" coef="0.5"/></fixed>
    <spatial name="span"><site site="elbow"/><site site="hand"/></spatial>
  </tendon>
  <actuator>
    <motor name="push" joint="slide" gear="2"/>
    <general name="filtered" joint="hinge" dyntype="filter" dynprm="0.1"/>
    <orientation name="aim" joint="wrist" kp="5"/>
    <plugin name="pid_slide" joint="slide" plugin="mujoco.pid" instance="pid" actdim="1"/>
    <motor name="pull" tendon="sum"/>
  </actuator>
  <sensor>
    <jointpos name="slide_pos" joint="slide"/>
    <framepos name="hand_pos" objtype="site" objname="hand"/>
    <ballquat name="wrist_quat" joint="wrist"/>
    <tendonpos name="sum_len" tendon="sum"/>
    <actuatorfrc name="aim_force" actuator="aim"/>
  </sensor>
  <keyframe>
    <key name="start" time="0.5"/>
  </keyframe>
</mujoco>
"""

# Extents of the first axis of installed array fields that no object kind indexes, and why.
# A new MuJoCo extent fails test_every_first_extent_is_classified until it is added here or
# gets indexed: the runtime never depends on this table.
UNINDEXED_EXTENTS = {
    # per-step constraints and islands: rows are not objects (contacts, names, paths and
    # text are not numpy arrays in the Python bindings, so they never show up here)
    "nefc", "nJ", "nA", "nY", "nisland", "nidof",
    # sparse matrix storage
    "nC", "nD", "nB", "nJten", "nJfe", "nJmom",
    # bounding volume hierarchies and octrees
    "nbvh", "nbvhstatic", "nbvhdynamic", "noct",
    # kinematic trees are not an mjtObj kind
    "ntree",
    # buffers shared by several kinds (actuator and sensor history; joint, tendon and flex
    # plasticity) or addressed differently in MjModel and MjData (tendon wrap paths)
    "nhistory", "nplastic", "nwrap",
    # second-level data of flexes, meshes and skins, addressed per element, vertex or bone
    "nflexelemdata", "nflexelemedge", "nflexshelldata", "nflexstiffness", "nflexbending",
    "nflextexcoord", "nmeshgraph", "nmeshpolyvert", "nmeshpolymap", "nskinbonevert",
    "nskintexvert",
    # the implicit-flex solver's factorizations
    "nefm0dof", "nefm0L", "nefmCvert", "nefmK", "nefmcon", "nefmdof", "nefmL",
    # user scratch, the name hash map and the plugin-attribute characters
    "nuserdata", "nnames_map", "npluginattr",
}  # fmt: skip

# Attributes of MuJoCo's per-object views that live in a buffer we leave unindexed (above):
# the tendon's sparse Jacobian columns (nJten). Joint/tendon `plastic`, actuator `moment` and
# mesh `graph` are in unindexed buffers too, but empty or computed in the model below.
UNBOUND_VIEW_ATTRIBUTES = {("tendon", "J_colind")}


@pytest.fixture(scope="module")
def every_kind() -> Physics:
    physics = Physics.from_xml_string(EVERY_KIND)
    physics.data.ctrl[:] = np.linspace(-0.5, 0.5, physics.model.nu)
    physics.step(5)
    return physics


def installed_array_fields(model: mujoco.MjModel, data: mujoco.MjData):
    """(struct, name, first extent) of every numpy array field the bindings expose."""
    for struct, live in (("mjModel", model), ("mjData", data)):
        for decl in structs.STRUCTS[struct].fields:
            extent = getattr(decl, "array_extent", None)
            if extent and isinstance(getattr(live, decl.name, None), np.ndarray):
                yield ("model" if live is model else "data"), decl.name, str(extent[0])


def test_every_kind_model_has_every_kind(every_kind):
    missing = [fields.kind_name(k) for k in fields.KINDS if fields.count(every_kind.model, k) == 0]
    assert not missing, f"add objects of {missing} to EVERY_KIND so their fields get tested"


def test_kinds_are_derived_from_name_arrays(every_kind):
    model = every_kind.model
    abbrs = [
        f.name[5:-3]
        for f in structs.STRUCTS["mjModel"].fields
        if re.fullmatch(r"name_\w+adr", f.name)
    ]
    by_size = {fields.kind_size(k): k for k in fields.KINDS}
    for abbr in abbrs:
        kind = by_size.get(f"n{abbr}")
        assert kind is not None, f"name_{abbr}adr names objects of no kind"
        # The abbreviation picked the right mjtObj if MuJoCo's own id->name lookup agrees
        # with the names stored at name_<abbr>adr.
        stored = tuple(
            model.names[adr:].split(b"\0", 1)[0].decode()
            for adr in getattr(model, f"name_{abbr}adr")
        )
        assert fields.names(model, kind) == stored, abbr
    assert {fields.kind_name(k) for k in fields.KINDS} >= {
        "body", "joint", "dof", "geom", "site", "camera", "light", "flex", "mesh", "skin",
        "hfield", "texture", "material", "pair", "exclude", "equality", "tendon",
        "actuator", "sensor", "numeric", "text", "tuple", "key", "plugin",
    }  # fmt: skip


def test_every_first_extent_is_classified(every_kind):
    kind_sizes = {fields.kind_size(k) for k in fields.KINDS}
    addressed = {a.size for a in fields.ADDRESSES}
    seen = set()
    for _, name, extent in installed_array_fields(every_kind.model, every_kind.data):
        seen.add(extent)
        assert extent in kind_sizes | addressed | UNINDEXED_EXTENTS, (
            f"{name} has first axis {extent}: index it in mjcf/sim/fields.py or list it in "
            "UNINDEXED_EXTENTS with the reason"
        )
    assert not UNINDEXED_EXTENTS - seen, "stale UNINDEXED_EXTENTS entries"
    assert not (UNINDEXED_EXTENTS & (kind_sizes | addressed))


def test_every_kind_indexed_field_is_known(every_kind):
    """Any installed field whose first axis counts objects or is addressed has an indexing."""
    kind_sizes = {fields.kind_size(k) for k in fields.KINDS}
    addressed = {a.size for a in fields.ADDRESSES}
    for struct, name, extent in installed_array_fields(every_kind.model, every_kind.data):
        if extent not in kind_sizes | addressed or name in fields._NOT_PER_OBJECT:
            continue
        field = fields.indexed_fields(struct).get(name)
        assert field is not None and field.struct == struct, name
        bound = fields.kind_fields(field.kind)[name]
        # A binding attribute names one field: where MjData has a same-named copy of an
        # MjModel field (`plugin`), the MjData one is bound; named access reaches both.
        assert bound is field or (struct == "model" and bound.struct == "data"), name


JOINT_WIDTHS = {  # documented in mjmodel.h (mjtJoint): qpos and dof widths
    mujoco.mjtJoint.mjJNT_FREE: (7, 6),
    mujoco.mjtJoint.mjJNT_BALL: (4, 3),
    mujoco.mjtJoint.mjJNT_SLIDE: (1, 1),
    mujoco.mjtJoint.mjJNT_HINGE: (1, 1),
}


def test_addresses_partition_their_buffers(every_kind):
    model = every_kind.model
    for address in fields.ADDRESSES:
        starts, counts = fields.rows(model, address)
        assert starts.shape == counts.shape == (fields.count(model, address.kind),)
        rows, _ = fields.row_index(model, address, np.arange(starts.size))
        size = int(getattr(model, address.size))
        # Every row of the buffer belongs to exactly one object.
        assert np.array_equal(np.sort(rows), np.arange(size)), address


def test_joint_widths_follow_joint_types(every_kind):
    model = every_kind.model
    qpos = fields.indexed_field("qpos").address
    qvel = fields.indexed_field("qvel").address
    _, qpos_counts = fields.rows(model, qpos)
    _, dof_counts = fields.rows(model, qvel)
    expected = np.array([JOINT_WIDTHS[mujoco.mjtJoint(t)] for t in model.jnt_type])
    assert set(model.jnt_type) == {int(t) for t in JOINT_WIDTHS}
    assert np.array_equal(qpos_counts, expected[:, 0])
    assert np.array_equal(dof_counts, expected[:, 1])


def test_packed_asset_buffers_have_documented_sizes(every_kind):
    model = every_kind.model
    _, hfield = fields.rows(model, fields.indexed_field("hfield_data").address)
    assert np.array_equal(hfield, model.hfield_nrow * model.hfield_ncol)
    _, tex = fields.rows(model, fields.indexed_field("tex_data").address)
    assert np.array_equal(tex, model.tex_height * model.tex_width * model.tex_nchannel)


def test_mujoco4_multi_control_actuator_is_addressed(every_kind):
    model = every_kind.model
    aim = mujoco.mj_name2id(model, Obj.mjOBJ_ACTUATOR, "aim")
    assert model.actuator_ctrlnum[aim] == 3
    assert fields.indexed_field("ctrl").address.start == "actuator_ctrladr"
    assert fields.indexed_field("actuator_force").address.start == "actuator_outadr"
    assert fields.indexed_field("actuator_gear").size == "nout"


def _view_kind(view: object) -> Obj:
    word = re.fullmatch(r"_Mj(?:Model|Data)(\w+)Views", type(view).__name__).group(1).lower()
    return {"keyframe": Obj.mjOBJ_KEY}.get(word) or Obj.__members__[f"mjOBJ_{word.upper()}"]


def _containing_field(raw: object, part: np.ndarray) -> str | None:
    """The array field of `raw` whose memory holds `part` (how MuJoCo's views are laid out)."""
    for name in dir(raw):
        full = getattr(raw, name, None)
        if not isinstance(full, np.ndarray) or full.dtype != part.dtype or not part.size:
            continue
        offset = part.ctypes.data - full.ctypes.data
        if offset >= 0 and offset + part.nbytes <= full.nbytes:
            return name
    return None


def test_bindings_match_mujoco_per_object_views(every_kind):
    """Every array of MuJoCo's model.<kind>(i) / data.<kind>(i) views is our binding's field."""
    physics = every_kind
    skipped, checked = set(), 0
    for raw in (physics.model, physics.data):
        accessors = {"actuator", "body", "cam", "eq", "exclude", "geom", "hfield", "jnt", "key",
                     "light", "mat", "mesh", "numeric", "pair", "sensor", "site", "skin",
                     "tendon", "tex", "tuple"}  # fmt: skip
        for accessor in sorted(a for a in accessors if hasattr(raw, a)):
            kind = _view_kind(getattr(raw, accessor)(0))
            for i in range(fields.count(physics.model, kind)):
                view = getattr(raw, accessor)(i)
                bound = physics._binding(kind, i)
                for attribute in dir(view):
                    value = getattr(view, attribute)
                    if attribute.startswith("_") or not isinstance(value, np.ndarray):
                        continue
                    name = _containing_field(raw, value)
                    if value.size == 0 or name is None:
                        continue
                    if name not in fields.kind_fields(kind):
                        skipped.add((fields.kind_name(kind), attribute))
                        continue
                    ours = getattr(bound, name)
                    assert np.array_equal(np.ravel(ours), np.ravel(value)), (kind, i, name)
                    assert np.shares_memory(ours, value), (kind, i, name)
                    checked += 1
    assert skipped == UNBOUND_VIEW_ATTRIBUTES, skipped ^ UNBOUND_VIEW_ATTRIBUTES
    assert checked > 500


def test_every_indexed_field_is_bindable_and_named(every_kind):
    """Iterate the installed fields: each one binds and name-indexes for every object."""
    physics = every_kind
    model = physics.model
    kind_sizes = {fields.kind_size(k) for k in fields.KINDS}
    addressed = {a.size for a in fields.ADDRESSES}
    tested = set()
    for struct, name, extent in installed_array_fields(model, physics.data):
        if extent not in kind_sizes | addressed or name in fields._NOT_PER_OBJECT:
            continue
        raw = getattr(physics.model if struct == "model" else physics.data, name)
        indexer = getattr(getattr(physics.named, struct), name)
        for field in fields.indexings(name, struct):
            ids = np.arange(fields.count(model, field.kind))
            starts, counts = (
                (ids, np.ones_like(ids)) if field.address is None
                else fields.rows(model, field.address)
            )  # fmt: skip
            expected = [raw[s : s + c] for s, c in zip(starts, counts, strict=True)]
            if field.address is not None and field.address.one_each and not counts.all():
                with pytest.raises(errors.BindingError, match="own no rows"):
                    getattr(physics._binding(field.kind, ids), name)
                ids = ids[counts > 0]
                expected = [e for e, c in zip(expected, counts, strict=True) if c]
            object_names = fields.names(model, field.kind)
            if field is fields.indexed_field(name, struct):
                for i, rows in zip(ids, expected, strict=True):
                    if object_names[i]:
                        assert np.array_equal(np.ravel(indexer[object_names[i]]), np.ravel(rows))
            if fields.kind_fields(field.kind)[name] is not field:
                # MjData's same-named copy is the one bound (`plugin`); named access has both.
                assert struct == "model" and fields.kind_fields(field.kind)[name].struct == "data"
                continue
            together = getattr(physics._binding(field.kind, ids), name)
            assert np.array_equal(together.reshape(-1), np.concatenate(expected).reshape(-1))
            for i, rows in zip(ids, expected, strict=True):
                single = getattr(physics._binding(field.kind, int(i)), name)
                assert np.array_equal(np.ravel(single), np.ravel(rows)), (name, i)
            tested.add((struct, name))
    every = {(s, n) for s in ("model", "data") for n in fields.indexed_fields(s)}
    shadowed = {("model", n) for n in fields.indexed_fields("model") if n in physics.data.__dir__()}
    assert tested == every - shadowed


def test_short_names_strip_the_kind_prefix():
    joint = fields.kind_fields(Obj.mjOBJ_JOINT)
    assert joint["range"].name == "jnt_range"
    assert joint["damping"].name == "dof_damping"
    assert joint["solref"].name == "jnt_solref"  # own rows win over dof_solref
    assert joint["qpos"].name == "qpos" and joint["qpos"].struct == "data"
    assert fields.kind_fields(Obj.mjOBJ_GEOM)["xpos"].name == "geom_xpos"
    assert fields.kind_fields(Obj.mjOBJ_TENDON)["length"].name == "ten_length"
    assert fields.kind_fields(Obj.mjOBJ_ACTUATOR)["force"].name == "actuator_force"
    assert fields.kind_fields(Obj.mjOBJ_BODY)["mass"].name == "body_mass"
    assert fields.kind_fields(Obj.mjOBJ_BODY)["mocap_pos"].address.start == "body_mocapid"


def test_names_of_unnamed_objects_are_empty():
    physics = Physics.from_xml_path(Path(mujoco.__file__).parent / "testdata" / "model.xml")
    names = fields.names(physics.model, Obj.mjOBJ_GEOM)
    assert len(names) == physics.model.ngeom
    assert names[0] == "floor" and "" in names


# -- what writes make stale (mjcf.sim.staleness), and column names -------------------------


def test_state_fields_are_mujocos_state_components() -> None:
    model = mujoco.MjModel.from_xml_path(str(MUJOCO_TESTDATA / "model.xml"))
    data = mujoco.MjData(model)
    for name, component in staleness.STATE_FIELDS.items():
        size = mujoco.mj_stateSize(model, component)
        assert np.size(getattr(data, name)) == size, name
    singles = [c for c in mujoco.mjtState.__members__.values() if bin(int(c)).count("1") == 1]
    assert sorted(staleness.STATE_FIELDS.values(), key=int) == sorted(singles, key=int)
    assert {"ctrl", "qfrc_applied", "xfrc_applied"} == staleness.STEP_INPUT_FIELDS


def test_every_derived_field_has_a_stage_from_mjdata_h() -> None:
    assert staleness.read_stage("xpos") == staleness.Stage.POSITION
    assert staleness.read_stage("cvel") == staleness.Stage.POSITION  # velocity: same half-step
    assert staleness.read_stage("qacc") == staleness.Stage.ACCELERATION
    assert staleness.read_stage("actuator_force") == staleness.Stage.ACCELERATION
    assert staleness.read_stage("qpos") == staleness.Stage.NONE
    unparsed = [
        name for name in fields.indexed_fields("data")
        if name not in staleness.STATE_FIELDS and name not in staleness._DATA_STAGES
    ]  # fmt: skip
    assert unparsed == ["sensordata"]  # a stage per sensor: staleness.sensor_stage
    assert staleness.ON_DEMAND["cfrc_ext"] == ("flg_rnepost", "mj_rnePostConstraint")
    assert staleness.ON_DEMAND["subtree_linvel"] == ("flg_subtreevel", "mj_subtreeVel")


def test_model_write_effects_follow_mj_setconst_inputs() -> None:
    effect = {name: staleness.write_effect(f) for name, f in fields.indexed_fields("model").items()}
    constant = staleness.Effect.MODEL_CONSTANT
    for name in ("body_pos", "body_ipos", "body_mass", "geom_pos", "geom_quat", "geom_size",
                 "site_pos", "jnt_axis", "qpos0"):  # fmt: skip
        assert effect[name] == constant, name
    assert effect["geom_friction"] == effect["dof_damping"] == staleness.Effect.MODEL
    assert effect["geom_rgba"] == effect["mat_rgba"] == staleness.Effect.VISUAL
    assert len(staleness.SETCONST_INPUTS) > 50


def test_column_names_cover_dm_controls() -> None:
    dm_control = {
        ("x", "y", "z"): ["body_pos", "body_ipos", "body_inertia", "jnt_pos", "jnt_axis",
                          "geom_size", "geom_pos", "site_size", "site_pos", "cam_pos",
                          "cam_poscom0", "cam_pos0", "light_pos", "light_dir", "light_poscom0",
                          "light_pos0", "light_dir0", "mesh_vert", "mesh_normal", "mocap_pos",
                          "xpos", "xipos", "xanchor", "xaxis", "geom_xpos", "site_xpos",
                          "cam_xpos", "light_xpos", "light_xdir", "subtree_com",
                          "subtree_linvel", "subtree_angmom"],
        ("qw", "qx", "qy", "qz"): ["body_quat", "body_iquat", "geom_quat", "site_quat",
                                   "cam_quat", "mocap_quat", "xquat"],
        ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"): ["cam_mat0", "xmat", "ximat",
                                                                 "geom_xmat", "site_xmat",
                                                                 "cam_xmat"],
        ("r", "g", "b", "a"): ["geom_rgba", "site_rgba", "skin_rgba", "mat_rgba", "tendon_rgba"],
    }  # fmt: skip
    for columns, names in dm_control.items():
        for name in names:
            assert fields.column_names(name) == columns, name
    assert fields.column_names("geom_friction") is None and fields.column_names("qpos") is None
