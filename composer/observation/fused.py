"""FusedRead: one environment's observables that are rows of bound MjData fields, read
together, one gather per field, into their outputs.

    plan = FusedRead.plan(observable, value, physics)   # None: read it with its reader
    fused = FusedRead(physics, [(plan, column), ...], row, readers)  # row: float64 outputs
    fused.read()                                        # writes every one's current value

Promise: the values are the readers', bit for bit; each plan is checked against its reader's
value at the compile, and an observable that reads otherwise is read its own way.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

import mjcf
from composer.batch import protocol
from composer.observation.observable import FieldRows, Observable
from mjcf.sim import fields, staleness

# What a value is made of: the field's value, or the cos or sin of it, or another ufunc of
# it (`FieldRows.function`), each by its index here.
_RAW, _COS, _SIN = 0, 1, 2
_OPERATIONS: list[np.ufunc | None] = [None, np.cos, np.sin]


def _operation(function: np.ufunc) -> int:
    """The index of elementwise `function` in _OPERATIONS (added the first time)."""
    if function not in _OPERATIONS:
        _OPERATIONS.append(function)
    return _OPERATIONS.index(function)


_READERS = ("reader", "batch_reader", "_callable")


class Plan(NamedTuple):
    """One observable's value as a gather: for each value element (in C order) its MjData
    field and flat index into it, its operation (_RAW, _COS, _SIN ...), its clip bounds
    (None: none), and the binding and field whose read brings them up to date at `stage`."""

    fields: tuple[str, ...]
    sources: np.ndarray
    operations: np.ndarray
    bounds: tuple[np.ndarray, np.ndarray] | None
    probe: tuple[Any, str]
    stage: staleness.Stage


def _declares_its_reader(observable: Observable) -> bool:
    """Whether `observable`'s `field_rows` is defined where every reading method it
    overrides is, or on a subclass: then it describes what that reader reads."""
    cls = type(observable)
    rows_owner = protocol.defining_class(cls, "field_rows")
    if rows_owner is None or rows_owner is Observable:
        return False
    for name in _READERS:
        owner = protocol.defining_class(cls, name)
        if owner is not None and owner is not Observable and not issubclass(rows_owner, owner):
            return False
    return True


def _stage(physics: Any, spec: fields.Field, ids: np.ndarray) -> staleness.Stage:
    """The stage a read of `spec` for objects `ids` needs fresh, as bindings decide it."""
    if spec.name == "sensordata":
        return staleness.sensor_stage(physics.model, ids)
    if spec.name in staleness.ON_DEMAND:
        return staleness.Stage.ACCELERATION
    return staleness.field_stage(spec)


class FusedRead:
    """Reads observables planned by `plan` into their columns of one float64 row.

    An observable saying what its value is (`Observable.field_rows`: rows of one MjData field
    of bound elements, maybe as (cos, sin), maybe clipped) costs a single environment a chain
    of closures and a one-row copy when read with its reader; here it is a column of index
    arrays resolved at compile, and all of them together cost a few numpy calls: a `take`
    per MjData field, cos and sin, one clip, one scatter into the outputs. The values are the
    reader's, bit for bit: the same elementwise operations on the same numbers. Each plan is
    checked against the value its reader gave at the compile (`plan` returns None if they
    differ), and only for an observable whose `field_rows` is defined on the class defining
    its reader or a subclass of it, so a subclass that reads otherwise is read its own way.
    Derived fields are brought up to date as bindings do it, by reading the field of the
    latest stage through its binding first.
    """

    @staticmethod
    def plan(observable: Observable, value: Any, physics: Any) -> Plan | None:
        """How to gather `observable` in `physics` (an mjcf.Physics), or None when it
        cannot be: it says nothing of its rows, its reader is another class's, its field
        is not an mjtNum MjData field, or the gather does not give `value` (what its reader
        read just now), bit for bit."""
        if not _declares_its_reader(observable):
            return None
        rows = observable.field_rows()
        if rows is None:
            return None
        try:
            return _checked_plan(rows, np.asarray(value), physics)
        except (mjcf.Error, KeyError, IndexError, ValueError, TypeError):
            return None  # a declaration the physics cannot serve: read the reader's way

    def __init__(
        self,
        physics: Any,
        plans: Sequence[tuple[Plan, int]],
        row: np.ndarray,
        readers: Sequence[Callable[[], Any]],
    ) -> None:
        """Read each plan's value into `row` (a 1-D float64 view of the outputs) from its
        column on. `readers` are the plans' observables' own: they run instead (and raise
        what they raise) if the physics holds another model than the one planned."""
        self._physics = physics
        self._model = physics.model
        self._row = row
        self._readers = list(readers)
        # Every element of every value, as (field, operation, flat source index, output
        # column, low, high), in runs of one field and operation: a `take` (and cos, sin
        # or another ufunc) per run, then one clip and one scatter for all.
        rows = []
        for plan, column in plans:
            low, high = plan.bounds or (np.full(plan.sources.size, -np.inf),
                                        np.full(plan.sources.size, np.inf))  # fmt: skip
            for j in range(plan.sources.size):
                operation = int(plan.operations[j])
                rows.append((plan.fields[j], operation, int(plan.sources[j]), column + j,
                             float(low[j]), float(high[j])))  # fmt: skip
        rows.sort(key=lambda item: (item[0], item[1]))
        self._targets = np.array([item[3] for item in rows], dtype=np.intp)
        # Unclipped elements are within (-inf, inf): max and min leave them as they are.
        bounds = np.array([item[4] for item in rows]), np.array([item[5] for item in rows])
        self._bounds = bounds if any(plan.bounds is not None for plan, _ in plans) else None
        self._fields = sorted({item[0] for item in rows})
        # (which field, its flat indices, None or the ufunc applied) of each run
        self._runs: list[tuple[int, np.ndarray, Any]] = []
        for (field, operation), run in itertools.groupby(rows, lambda item: item[:2]):
            indices = np.array([item[2] for item in run], dtype=np.intp)
            turn = _OPERATIONS[operation]
            self._runs.append((self._fields.index(field), indices, turn))
        stage, latest = max((plan.stage, i) for i, (plan, _) in enumerate(plans))
        self._probe = plans[latest][0].probe if stage else None
        self._data: Any = None
        self._views: list[np.ndarray] = []

    def _hold(self, data: Any) -> None:
        """Flat views of the fields in `data` (the physics' MjData since the last read)."""
        if self._physics.model is not self._model:
            for read in self._readers:  # their bindings raise: the model was replaced
                read()
        self._data = data
        views = [getattr(data, name).reshape(-1) for name in self._fields]
        self._gathers = [(views[field], indices, turn) for field, indices, turn in self._runs]

    def read(self) -> None:
        """Write every planned observable's current value into its columns of the row."""
        data = self._physics.data
        if data is not self._data:
            self._hold(data)
        probe = self._probe
        if probe is not None:
            getattr(*probe)  # derived fields up to date, as that binding's read does it
        # No `out=` arguments: numpy's small-array calls take twice as long with them.
        parts = [
            view[indices] if turn is None else turn(view[indices])
            for view, indices, turn in self._gathers
        ]
        values = parts[0] if len(parts) == 1 else np.concatenate(parts)
        if self._bounds is not None:
            low, high = self._bounds
            values = np.minimum(np.maximum(values, low), high)
        self._row[self._targets] = values


class _Part(NamedTuple):
    """One FieldRows' elements: their field, flat indices, operations and clip bounds
    (shaped as the value they make), and the read bringing them up to date at `stage`."""

    field: str
    grid: np.ndarray
    operations: np.ndarray
    bounds: tuple[np.ndarray, np.ndarray] | None
    probe: tuple[Any, str]
    stage: staleness.Stage


def _part(rows: FieldRows, physics: Any) -> _Part | None:
    """What `rows` gathers in `physics`; None when it is not an mjtNum MjData field, or
    asks for a function that is not one elementwise ufunc (or one with angles)."""
    elements = rows.elements
    binding = physics.bind(list(elements) if isinstance(elements, tuple) else elements)
    bound = np.asarray(getattr(binding, rows.field))
    spec = fields.kind_fields(binding.kind)[rows.field]
    if spec.struct != "data":
        return None
    array = getattr(physics.data, spec.name)
    if array.dtype != np.float64:
        return None
    ids = np.atleast_1d(np.asarray(binding.ids))
    starts, _ = fields.row_index(physics.model, spec.address, ids)
    width = int(np.prod(array.shape[1:], dtype=np.intp))
    # The flat index in the field of each element of the bound value, indexed as it is.
    grid: np.ndarray = (starts[:, None] * width + np.arange(width)).reshape(bound.shape)
    if rows.index is not None:
        grid = np.asarray(grid[rows.index])
    function = rows.function
    if function is not None and (
        rows.angles or not isinstance(function, np.ufunc) or (function.nin, function.nout) != (1, 1)
    ):
        return None  # read by the reader: not a gather and one elementwise function
    operations: np.ndarray = np.full(grid.shape, _RAW if function is None else _operation(function))
    if rows.angles:  # (cos, sin) of each value, concatenated along the last axis
        operations = np.concatenate([operations + _COS, operations + _SIN], axis=-1)
        grid = np.concatenate([grid, grid], axis=-1)
    if rows.flat:
        grid, operations = grid.reshape(-1), operations.reshape(-1)
    bounds = None
    if rows.bounds is not None:
        bounds = tuple(np.broadcast_to(np.asarray(b, np.float64), grid.shape) for b in rows.bounds)
    return _Part(spec.name, grid, operations, bounds, (binding, rows.field),  # type: ignore[arg-type]
                 _stage(physics, spec, ids))  # fmt: skip


def _checked_plan(
    declared: FieldRows | Sequence[FieldRows], value: np.ndarray, physics: Any
) -> Plan | None:
    """The plan of `declared` (one FieldRows, or several whose values are concatenated
    along the last axis), if it gives `value` in `physics` now; else None."""
    if value.dtype != np.float64:
        return None
    parts = []
    for rows in [declared] if isinstance(declared, FieldRows) else declared:
        part = _part(rows, physics)
        if part is None:
            return None
        parts.append(part)
    if len(parts) == 1:
        grid, operations = parts[0].grid, parts[0].operations
        each = np.zeros(grid.shape, dtype=np.intp)  # the part of each element
    else:
        grid = np.concatenate([part.grid for part in parts], axis=-1)
        operations = np.concatenate([part.operations for part in parts], axis=-1)
        each = np.concatenate([np.full(part.grid.shape, k) for k, part in enumerate(parts)], -1)
    if grid.shape != value.shape:
        return None
    bounds = None
    if any(part.bounds is not None for part in parts):  # (unclipped parts: +-inf)
        lows, highs = zip(*(part.bounds or (np.full(part.grid.shape, -np.inf),
                                            np.full(part.grid.shape, np.inf))
                            for part in parts), strict=True)  # fmt: skip
        bounds = (np.concatenate(lows, axis=-1).ravel(), np.concatenate(highs, axis=-1).ravel())
    stage, latest = max((part.stage, k) for k, part in enumerate(parts))
    plan = Plan(tuple(parts[k].field for k in each.ravel()), grid.ravel(), operations.ravel(),
                bounds, parts[latest].probe, stage)  # fmt: skip
    gathered = np.zeros(value.size)
    FusedRead(physics, [(plan, 0)], gathered, []).read()
    return plan if gathered.tobytes() == value.ravel().tobytes() else None
