"""What a write through a binding or named access makes stale, and what a read needs fresh.

    staleness.write_effect(fields.indexed_field("qpos"))              # Effect.STATE
    staleness.write_effect(fields.indexed_field("geom_size", "model"))  # Effect.MODEL_CONSTANT
    staleness.read_stage("qacc")                                      # Stage.ACCELERATION
    staleness.sensor_stage(model, sensor_ids)                         # what those sensors need

These are the facts; the rules `mjcf.Physics` keeps with them are `mjcf.sim.binding.Binding`'s.
They are read from MuJoCo's headers (mjdata.h, mjxmacro.h); without the headers every derived
field counts as acceleration-dependent and every model field as an input of `mj_setConst`.
"""

from __future__ import annotations

import enum
import re
from pathlib import Path

import mujoco
import numpy as np

from mjcf.sim import fields

_HEADERS = Path(mujoco.__file__).parent / "include" / "mujoco"


class Effect(enum.IntEnum):
    """What writing a field changes, and so what must be recomputed before it is read."""

    DERIVED = 0  # an MjData output: the next forward pass overwrites it
    STEP_INPUT = 1  # ctrl, qfrc_applied, xfrc_applied: only the acceleration stage reads them
    STATE = 2  # the rest of the simulation state: every stage depends on it
    MODEL = 3  # a model parameter that mj_forward reads
    MODEL_CONSTANT = 4  # a model parameter mj_setConst derives other model fields from
    VISUAL = 5  # a model parameter only rendering reads


class Stage(enum.IntEnum):
    """The computation stage a derived MjData field comes from (MuJoCo's mjtStage order)."""

    NONE = 0  # not derived: state, inputs, model fields
    POSITION = 1  # position- and velocity-dependent (mj_step1 computes these)
    ACCELERATION = 2  # control/acceleration-dependent (mj_step2 or mj_forward's last stage)


# dm_control's list of model fields that do not make a physics dirty (they only change
# pictures), by name without the kind prefix; the material and texture kinds only render.
# The one hand-kept list of fields here: the others are read from MuJoCo (`mjtState`'s
# components, mjdata.h and mjxmacro.h).
VISUAL_SHORT_NAMES = frozenset({"rgba", "matid", "emission", "specular", "shininess",
                                "reflectance"})  # fmt: skip
_VISUAL_KINDS = frozenset({mujoco.mjtObj.mjOBJ_MATERIAL, mujoco.mjtObj.mjOBJ_TEXTURE})

# The state components mj_step2 reads after mj_step1 has run: MuJoCo's documented way to set
# controls and applied forces between the two halves of a step.
_STEP_INPUT_COMPONENTS = (
    mujoco.mjtState.mjSTATE_CTRL,
    mujoco.mjtState.mjSTATE_QFRC_APPLIED,
    mujoco.mjtState.mjSTATE_XFRC_APPLIED,
)
# mjtState components whose MjData field is not named after the component.
_COMPONENT_FIELDS = {"warmstart": "qacc_warmstart", "plugin": "plugin_state"}


def _state_fields() -> dict[str, mujoco.mjtState]:
    """{MjData field: mjtState component} of every single-component state bit."""
    out = {}
    for name, component in mujoco.mjtState.__members__.items():
        value = int(component)
        if not name.startswith("mjSTATE_") or value & (value - 1) or value == 0:
            continue  # combinations (PHYSICS, INTEGRATION ...) and the count
        short = name[len("mjSTATE_") :].lower()
        out[_COMPONENT_FIELDS.get(short, short)] = component
    return out


STATE_FIELDS: dict[str, mujoco.mjtState] = _state_fields()
"""{MjData field: mjtState component}: the simulation state, as MuJoCo defines it."""

STEP_INPUT_FIELDS = frozenset(f for f, c in STATE_FIELDS.items() if c in _STEP_INPUT_COMPONENTS)


def _data_stages(header: Path) -> tuple[dict[str, Stage], dict[str, tuple[str, str]]] | None:
    """({MjData field: Stage}, {field computed only on demand: (flag, function)}) from the
    section and group comments of mjdata.h ("POSITION dependent", "POSITION, VELOCITY,
    CONTROL/ACCELERATION dependent" ...); None without the file, and then every derived
    field counts as acceleration-dependent: slower, never stale."""
    try:
        text = header.read_text()
    except OSError:
        return None
    body = text.split("struct mjData_", 1)[-1]
    # "mjtBool flg_rnepost;  // has mj_rnePostConstraint been called"
    flags = {fn: flag for flag, fn in re.findall(r"(flg_\w+);\s*// has (mj_\w+) been called", body)}
    stages: dict[str, Stage] = {}
    lazy: dict[str, tuple[str, str]] = {}
    section, group = "", ""
    for line in body.splitlines():
        stripped = line.strip()
        if stripped.startswith("//--------------------"):
            section, group = stripped.strip("/- ").upper(), ""
        elif stripped.startswith("//"):
            group = stripped.strip("/ ")
        else:
            match = re.match(r"[\w\s]+?\**\s*(\w+)(\[\w*\])?;", stripped)
            if not match:
                continue
            name = match.group(1)
            if "ACCELERATION" in section or group == "dynamics":
                stages[name] = Stage.ACCELERATION
            elif "POSITION" in section or "VELOCITY" in section:
                stages[name] = Stage.POSITION
            elif section.startswith("MAIN INPUTS") and group != "sensors":
                stages[name] = Stage.NONE  # state, controls, plugin and sleep bookkeeping
            # "computed by mj_sensorVel/mj_subtreeVel if needed": only when a sensor asks
            on_demand = re.search(r"(mj_\w+) if needed", group)
            if on_demand and on_demand.group(1) in flags:
                lazy[name] = (flags[on_demand.group(1)], on_demand.group(1))
    return (stages, lazy) if stages else None


def _setconst_inputs(header: Path) -> frozenset[str] | None:
    """Model arrays some phase of mj_setConst reads (mjSC_IN or mjSC_INOUT in mjxmacro.h's
    MJSETCONST_ARRAYS); None without the file or the table."""
    try:
        text = header.read_text()
    except OSError:
        return None
    table = re.search(r"#define MJSETCONST_ARRAYS(.*?)\n\s*\n", text, re.S)
    if table is None:
        return None
    rows = re.findall(r"X\(\s*(\w+)\s*,([^)]*)\)", table.group(1))
    found = frozenset(name for name, phases in rows if "mjSC_IN" in phases)
    return found or None


_PARSED = _data_stages(_HEADERS / "mjdata.h")
_DATA_STAGES = None if _PARSED is None else _PARSED[0]
ON_DEMAND: dict[str, tuple[str, str]] = {} if _PARSED is None else _PARSED[1]
"""{MjData field: (flag, function)}: fields MuJoCo computes only when a sensor needs them
(cacc, cfrc_ext, subtree_linvel ...); a read runs `function` while `flag` is unset."""
SETCONST_INPUTS: frozenset[str] | None = _setconst_inputs(_HEADERS / "mjxmacro.h")
"""Model fields mj_setConst reads, from mjxmacro.h (None: unknown, treat every one so)."""


def read_stage(name: str) -> Stage:
    """The stage MjData field `name` comes from (Stage.NONE for state and inputs)."""
    if name in STATE_FIELDS:
        return Stage.NONE
    if _DATA_STAGES is None:
        return Stage.ACCELERATION
    return _DATA_STAGES.get(name, Stage.ACCELERATION)


def write_effect(field: fields.Field) -> Effect:
    """What writing `field` changes (see Effect)."""
    if field.struct == "data":
        if field.name in STEP_INPUT_FIELDS:
            return Effect.STEP_INPUT
        return Effect.STATE if field.name in STATE_FIELDS else Effect.DERIVED
    if field.kind in _VISUAL_KINDS or fields.short_name(field) in VISUAL_SHORT_NAMES:
        return Effect.VISUAL
    if SETCONST_INPUTS is None or field.name in SETCONST_INPUTS:
        return Effect.MODEL_CONSTANT
    return Effect.MODEL


def field_stage(field: fields.Field) -> Stage:
    """The stage a read of `field` needs fresh (Stage.NONE for model fields and state)."""
    if field.struct == "model":
        return Stage.NONE
    return read_stage(field.name)


def sensor_stage(model: mujoco.MjModel, ids: np.ndarray) -> Stage:
    """The latest stage sensors `ids` need: their sensordata rows are computed then."""
    ids = np.asarray(ids, dtype=np.intp).reshape(-1)
    if ids.size == 0:
        return Stage.NONE
    needed = int(np.max(model.sensor_needstage[ids]))
    return Stage.ACCELERATION if needed >= int(mujoco.mjtStage.mjSTAGE_ACC) else Stage.POSITION
