"""Which MjModel / MjData arrays belong to which kind of object, read from the installed mujoco.

    JOINT = mujoco.mjtObj.mjOBJ_JOINT
    fields.kind_fields(JOINT)["range"]          # Field('jnt_range', 'model', JOINT, 'njnt')
    fields.kind_fields(JOINT)["qpos"].address   # Address(JOINT, 'nq', 'jnt_qposadr', ...)
    starts, counts = fields.rows(model, fields.indexed_field("qpos").address)
    fields.names(model, JOINT)                  # ('root', 'hip', ...)

No hand-kept list of fields: `mujoco.introspect` and the `name_<kind>adr` arrays give them
at import; only address schemes MuJoCo does not name systematically are a table (`_ADDRESSES`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Literal, TypeAlias

import mujoco
import numpy as np
from mujoco.introspect import structs

Obj: TypeAlias = mujoco.mjtObj
Struct = Literal["model", "data"]

# Rules for the row counts of an address scheme that has no count array of its own.
NEXT_START = "next start"  # an object's rows run up to the next object's start (packed buffers)
IF_PRESENT = "if present"  # one row where the start is >= 0, none where it is -1


@dataclasses.dataclass(frozen=True)
class Address:
    """How the objects of `kind` own rows of the buffer whose length is MjModel.`size`.

    Object i owns rows `starts[i] : starts[i] + counts[i]`, where `starts` is the MjModel array
    `start` and `counts` the MjModel array `count`, or the rule NEXT_START / IF_PRESENT.
    `one_each` marks schemes where an object normally owns exactly one row (a control, a force
    output, a mocap body): bound like one-row-per-object fields while every object has one row.
    """

    kind: Obj
    size: str
    start: str
    count: str
    one_each: bool = False


@dataclasses.dataclass(frozen=True)
class Field:
    """One MjModel ('model') or MjData ('data') array indexed by the objects of `kind`.

    `size` is the extent of its first axis. `address` is None when row i belongs to object i,
    else the scheme that maps objects to rows.
    """

    name: str
    struct: Struct
    kind: Obj
    size: str
    address: Address | None = None
    doc: str = dataclasses.field(default="", compare=False, repr=False)


# Address schemes that do not follow the `<p>_<x>adr` + `<p>_<x>num` -> `n<p><x>` convention.
_ADDRESSES = (
    # Joints own 7/4/1/1 qpos and 6/3/1/1 dofs (free/ball/slide/hinge), packed in joint order;
    # the widths follow from the addresses, so a new joint type needs no table here.
    Address(Obj.mjOBJ_JOINT, "nq", "jnt_qposadr", NEXT_START),
    Address(Obj.mjOBJ_JOINT, "nv", "jnt_dofadr", NEXT_START),
    Address(Obj.mjOBJ_SENSOR, "nsensordata", "sensor_adr", "sensor_dim"),
    Address(Obj.mjOBJ_ACTUATOR, "na", "actuator_actadr", "actuator_actnum"),
    # MuJoCo 4: an actuator takes ctrlnum controls and produces outnum force outputs.
    Address(Obj.mjOBJ_ACTUATOR, "nu", "actuator_ctrladr", "actuator_ctrlnum", one_each=True),
    Address(Obj.mjOBJ_ACTUATOR, "nout", "actuator_outadr", "actuator_outnum", one_each=True),
    Address(Obj.mjOBJ_BODY, "nmocap", "body_mocapid", IF_PRESENT, one_each=True),
    Address(Obj.mjOBJ_HFIELD, "nhfielddata", "hfield_adr", NEXT_START),
    Address(Obj.mjOBJ_TEXTURE, "ntexdata", "tex_adr", NEXT_START),
)

# Fields with one row per object in extent, whose row i is not object i: compacted lists of
# awake objects, an inverse permutation, and solver arrays indexed by a per-step id list.
_NOT_PER_OBJECT = frozenset(
    {
        "body_awake_ind",
        "parent_awake_ind",
        "dof_awake_ind",
        "map_idof2dof",
        "efm_aid",
        "efm_as",
        "efm_ak",
        "efm_tid",
        "efm_ts",
        "efm_tk",
    }
)

# Field-name prefixes meaning "of this kind" besides the kind's own abbreviation: MjData
# spells tendon fields `ten_`, and joints reach the `dof_` fields through jnt_dofadr.
_EXTRA_PREFIXES = {Obj.mjOBJ_TENDON: ("ten",), Obj.mjOBJ_JOINT: ("dof",)}


def kind_name(kind: Obj) -> str:
    """The kind's name in lower case: mjOBJ_JOINT -> 'joint'."""
    return Obj(kind).name[len("mjOBJ_") :].lower()


def kind_size(kind: Obj) -> str:
    """The MjModel attribute counting objects of `kind` ('njnt'); raises KeyError if none."""
    return _SIZE[Obj(kind)]


def count(model: mujoco.MjModel, kind: Obj) -> int:
    """How many objects of `kind` the model has; raises KeyError for a kind with no fields."""
    return int(getattr(model, kind_size(kind)))


def kind_fields(kind: Obj) -> Mapping[str, Field]:
    """{attribute name: Field} of every field indexed by `kind`; raises KeyError if none.

    Each field appears under its full name (`jnt_range`) and under its `short_name` (`range`).
    When two fields share a short name, one with a row per object wins over an addressed one
    (`solref` is `jnt_solref`, not `dof_solref`), and MjData wins over MjModel (`plugin` is
    MjData's copy of MjModel's); the other stays reachable by its full name.
    """
    return _ATTRIBUTES[Obj(kind)]


def indexed_field(name: str, struct: Struct | None = None) -> Field:
    """The indexing of field `name` that named access uses; raises KeyError if not indexed.

    `struct` picks MjModel or MjData; None means MjData if it has the field, else MjModel.
    A field indexed by two kinds (dof arrays: by joint through jnt_dofadr, and by dof) is
    named after the kind that has names (joint).
    """
    if struct is None:
        struct = "data" if name in _PRIMARY["data"] else "model"
    return _PRIMARY[struct][name]


def indexed_fields(struct: Struct) -> Mapping[str, Field]:
    """{full name: Field} of every MjModel ('model') or MjData ('data') field a kind indexes."""
    return _PRIMARY[struct]


def indexings(name: str, struct: Struct) -> tuple[Field, ...]:
    """Every kind's indexing of one field, `indexed_field`'s first ((): not indexed).

    Only dof arrays have two: by joint (through jnt_dofadr) and by dof.
    """
    return _INDEXINGS[struct].get(name, ())


def short_name(field: Field) -> str:
    """The name without a prefix meaning "of its kind": jnt_range -> range, ten_length -> length."""
    head, _, rest = field.name.partition("_")
    prefixes = {_PREFIX[field.kind], kind_name(field.kind), *_EXTRA_PREFIXES.get(field.kind, ())}
    return rest if rest and head in prefixes else field.name


def rows(model: mujoco.MjModel, address: Address) -> tuple[np.ndarray, np.ndarray]:
    """(starts, counts): object i of `address.kind` owns rows starts[i]:starts[i]+counts[i]."""
    starts = np.asarray(getattr(model, address.start), dtype=np.intp).reshape(-1)
    if address.count == IF_PRESENT:
        counts = (starts >= 0).astype(np.intp)
    elif address.count == NEXT_START:
        # Objects are packed in order, but sort anyway: the last one ends at the buffer's end.
        order = np.argsort(starts, kind="stable")
        ends = np.append(starts[order][1:], int(getattr(model, address.size)))
        counts = np.empty_like(starts)
        counts[order] = ends - starts[order]
    else:
        counts = np.asarray(getattr(model, address.count), dtype=np.intp).reshape(-1)
    return starts, counts


def row_index(
    model: mujoco.MjModel, address: Address | None, ids: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(rows, counts): the rows objects `ids` own under `address`, concatenated in id order.

    With `address` None (one row per object), rows is `ids` and every count is 1.
    """
    ids = np.asarray(ids, dtype=np.intp).reshape(-1)
    if address is None:
        return ids, np.ones_like(ids)
    starts, counts = rows(model, address)
    starts, counts = starts[ids], counts[ids]
    # Concatenated ranges without a Python loop: each block's offset, plus a 0..total-1 ramp.
    offsets = np.repeat(starts - np.cumsum(counts) + counts, counts)
    return offsets + np.arange(offsets.size, dtype=np.intp), counts


def names(model: mujoco.MjModel, kind: Obj) -> tuple[str, ...]:
    """The name of every object of `kind` in id order ('' for an unnamed object)."""
    kind = Obj(kind)
    return tuple(mujoco.mj_id2name(model, kind, i) or "" for i in range(count(model, kind)))


def column_names(name: str) -> tuple[str, ...] | None:
    """The names of the columns of MjModel/MjData field `name`, dm_control's convention: x y z
    for positions, directions, axes, sizes and inertias; qw qx qy qz for quaternions; xx xy
    xz yx ... zz for 3x3 matrices; r g b a for colors. None for fields without named columns."""
    return _COLUMNS.get(name)


_XYZ = ("x", "y", "z")
_QUAT = ("qw", "qx", "qy", "qz")
_MAT = ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")
_RGBA = ("r", "g", "b", "a")
# Ends of field names whose (n, 3) rows are Cartesian vectors.
_XYZ_ENDS = ("pos", "pos0", "poscom0", "dir", "dir0", "axis", "anchor", "inertia", "com",
             "vert", "normal", "linvel", "angmom", "size")  # fmt: skip


def _column_table() -> dict[str, tuple[str, ...]]:
    """{field: column names} by name and width, over every 2-D field of mjModel and mjData."""
    table: dict[str, tuple[str, ...]] = {}
    for struct_name in ("mjModel", "mjData"):
        for decl in structs.STRUCTS[struct_name].fields:
            extent = getattr(decl, "array_extent", None)
            if not extent or len(extent) != 2:
                continue
            name, width = decl.name, extent[1]
            if width == 3 and name.endswith(_XYZ_ENDS):
                table[name] = _XYZ
            elif width == 4 and name.endswith("quat"):
                table[name] = _QUAT
            elif width == 4 and name.endswith("rgba"):
                table[name] = _RGBA
            elif width == 9 and name.endswith(("mat", "mat0")):
                table[name] = _MAT
    return table


_COLUMNS = _column_table()


# -- derivation from the installed mujoco, once at import ------------------------------------


def _struct_extents(struct_name: str, live: object) -> dict[str, tuple[str, str]]:
    """{field: (first extent, doc)} of the fields of one struct that are numpy arrays: the
    array fields and the extent of their first axis come from `mujoco.introspect`, checked
    against a live MjModel/MjData `live` (only fields the Python bindings expose as numpy
    arrays count)."""
    out = {}
    for decl in structs.STRUCTS[struct_name].fields:
        extent = getattr(decl, "array_extent", None)
        if extent and isinstance(getattr(live, decl.name, None), np.ndarray):
            out[decl.name] = (str(extent[0]), decl.doc)
    return out


def _abbreviates(short: str, name: str) -> bool:
    """Whether `short` is `name` with letters left out ('jnt' of 'joint', 'eq' of 'equality')."""
    if not short or short[0] != name[0]:
        return False
    rest = iter(name)
    return all(letter in rest for letter in short)


def _derive_kinds(model_fields: Mapping[str, object]) -> tuple[dict[Obj, str], dict[Obj, str]]:
    """({kind: abbreviation}, {kind: size}) from the name_<abbr>adr arrays, plus dof rows."""
    abbrs = [n[len("name_") : -len("adr")] for n in model_fields if n.startswith("name_")
             and n.endswith("adr")]  # fmt: skip
    candidates = {
        kind: kind_name(kind) for kind in Obj.__members__.values()
        if kind.name.startswith("mjOBJ_")
    }  # fmt: skip
    prefix: dict[Obj, str] = {}
    # Exact spellings first ('text'), so that 'tex' then abbreviates only 'texture'.
    for abbr in sorted(abbrs, key=lambda a: a not in candidates.values()):
        free = {k: n for k, n in candidates.items() if k not in prefix}
        matches = [k for k, n in free.items() if n == abbr] or [
            k for k, n in free.items() if _abbreviates(abbr, n)
        ]
        if len(matches) == 1:
            prefix[matches[0]] = abbr
    sizes = {kind: f"n{abbr}" for kind, abbr in prefix.items()}
    # Degrees of freedom have no names but are a kind of their own, one row per dof.
    prefix[Obj.mjOBJ_DOF] = "dof"
    sizes[Obj.mjOBJ_DOF] = "nv"
    return prefix, sizes


def _derive_addresses(
    extents: Mapping[Struct, Mapping[str, tuple[str, str]]],
) -> tuple[Address, ...]:
    """The explicit schemes plus those that follow MuJoCo's adr/num naming convention
    (`mesh_vertadr` + `mesh_vertnum` address the `nmeshvert` rows)."""
    found = list(_ADDRESSES)
    taken = {a.size for a in found} | set(_SIZE.values())
    all_sizes = {extent for table in extents.values() for extent, _ in table.values()}
    model = extents["model"]
    for kind, abbr in _PREFIX.items():
        for name, (extent, _) in model.items():
            if extent != _SIZE[kind] or not name.startswith(f"{abbr}_"):
                continue
            stem = name[len(abbr) + 1 :]
            if len(stem) > 3 and stem.endswith("adr") and f"{abbr}_{stem[:-3]}num" in model:
                size, counter = f"n{abbr}{stem[:-3]}", f"{abbr}_{stem[:-3]}num"
            elif stem == "adr" and f"{abbr}_size" in model:
                size, counter = f"n{abbr}data", f"{abbr}_size"
            else:
                continue
            if size in all_sizes and size not in taken:
                found.append(Address(kind, size, name, counter))
                taken.add(size)
    return tuple(found)


def _derive_fields(
    extents: Mapping[Struct, Mapping[str, tuple[str, str]]],
) -> tuple[dict[Obj, dict[str, Field]], dict[Struct, dict[str, tuple[Field, ...]]]]:
    """({kind: {attribute: Field}}, {struct: {full name: Fields}}) over every indexed field."""
    by_size = {size: kind for kind, size in _SIZE.items()}
    by_address = {a.size: a for a in ADDRESSES}
    per_kind: dict[Obj, list[Field]] = {kind: [] for kind in KINDS}
    indexings: dict[Struct, dict[str, tuple[Field, ...]]] = {"model": {}, "data": {}}
    for struct, table in extents.items():
        for name, (extent, doc) in table.items():
            if name in _NOT_PER_OBJECT:
                continue
            found = []
            if extent in by_address:
                address = by_address[extent]
                found.append(Field(name, struct, address.kind, extent, address, doc))
            if extent in by_size:
                found.append(Field(name, struct, by_size[extent], extent, None, doc))
            for field in found:
                per_kind[field.kind].append(field)
            if found:
                # Addressed first: named access labels rows by the addressing kind's names.
                indexings[struct][name] = tuple(found)
    return {kind: _attribute_table(found) for kind, found in per_kind.items()}, indexings


def _attribute_table(found: list[Field]) -> dict[str, Field]:
    """{short and full name: Field} for one kind; see `kind_fields` for who wins a tie."""

    def rank(field: Field) -> tuple[bool, bool]:
        return (field.address is not None, field.struct == "model")

    table: dict[str, Field] = {}
    for field in sorted(found, key=rank, reverse=True):  # the best-ranked is written last
        table[short_name(field)] = field
    for field in found:  # full names win over short ones; MjData (listed last) over MjModel
        table[field.name] = field
    return table


_EMPTY_MODEL = mujoco.MjModel.from_xml_string("<mujoco/>")
_EXTENTS: dict[Struct, dict[str, tuple[str, str]]] = {
    "model": _struct_extents("mjModel", _EMPTY_MODEL),
    "data": _struct_extents("mjData", mujoco.MjData(_EMPTY_MODEL)),
}
_PREFIX, _SIZE = _derive_kinds(_EXTENTS["model"])

KINDS: tuple[Obj, ...] = tuple(sorted(_SIZE, key=int))
"""Every object kind that indexes at least one MjModel/MjData field."""

ADDRESSES: tuple[Address, ...] = _derive_addresses(_EXTENTS)
"""Every address scheme: buffers whose rows belong to objects through start/count arrays."""

_ATTRIBUTES, _INDEXINGS = _derive_fields(_EXTENTS)
_PRIMARY = {struct: {n: f[0] for n, f in table.items()} for struct, table in _INDEXINGS.items()}
