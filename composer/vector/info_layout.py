"""Gymnasium's vector info layout: each key an array over environments, with a boolean
'_key' array saying which environments have it.

    put(info, 'discount', ids, values, num_envs)   # info['discount'][ids] = values
    add(info, {'angle': 0.3}, 2, num_envs)         # environment 2's entries
    kept, moved = split(info, mask)                # e.g. into info and info['final_info']
    replace_rows(info, newer, ids)                 # environments ids' entries: newer's

Promise: `add` makes each key's array as `gymnasium.vector.SyncVectorEnv` does.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def put(info: dict[str, Any], key: str, ids: np.ndarray, values: np.ndarray, n: int) -> None:
    """Set info[key][ids] = values (one row per id) and the mask info['_key'] for `n`
    environments."""
    array = info.get(key)
    if array is None:
        array = info[key] = np.zeros((n, *values.shape[1:]), dtype=values.dtype)
        info[f"_{key}"] = np.zeros(n, dtype=bool)
    array[ids] = values
    info[f"_{key}"][ids] = True


def add(info: dict[str, Any], entries: dict[str, Any], i: int, n: int) -> None:
    """Put environment i's info `entries` into the info of `n` environments, making each
    key's array as `gymnasium.vector.SyncVectorEnv` does for the same entries (of the
    entry's type for a Python or numpy number, of its shape and dtype for an array, of
    objects otherwise; a dict entry nests), so our info equals its info."""
    for key, value in entries.items():
        if isinstance(value, dict):
            nested = info.setdefault(key, {})
            add(nested, value, i, n)
        else:
            array = info.get(key)
            if array is None:
                array = info[key] = _array_for(value, n)
            array[i] = value
        mask = info.setdefault(f"_{key}", np.zeros(n, dtype=bool))
        mask[i] = True


def _array_for(value: Any, n: int) -> np.ndarray:
    """The array holding `value` for `n` environments, as Gymnasium's vector envs make it."""
    if type(value) in (int, float, bool) or isinstance(value, np.number):
        return np.zeros(n, dtype=type(value))
    if isinstance(value, np.ndarray):
        return np.zeros((n, *value.shape), dtype=value.dtype)
    return np.full(n, None, dtype=object)


def split(info: dict[str, Any], mask: np.ndarray) -> tuple[dict[str, Any], dict[str, Any]]:
    """(info without the environments of `mask`, info of only those), masks included."""
    kept: dict[str, Any] = {}
    moved: dict[str, Any] = {}
    for key, value in info.items():
        if key.startswith("_"):
            continue
        has = info[f"_{key}"]
        nested = split(value, mask) if isinstance(value, dict) else None
        for k, (part, rows) in enumerate(((kept, has & ~mask), (moved, has & mask))):
            if not rows.any():
                continue
            if nested is not None:
                part[key] = nested[k]
            else:
                array = _empty_like(value)
                array[rows] = value[rows]
                part[key] = array
            part[f"_{key}"] = rows
    return kept, moved


def replace_rows(info: dict[str, Any], newer: dict[str, Any], ids: np.ndarray) -> None:
    """Make the entries of environments `ids` in `info` those of `newer` (another info of
    the same environments), in place: keys `newer` has for them are copied, keys it lacks
    for them are removed for them (their rows zeroed, as Gymnasium leaves an absent key)."""
    for key in [k for k in info if not k.startswith("_")]:
        if key not in newer:
            _clear_rows(info, key, ids)
    for key, value in newer.items():
        if key.startswith("_"):
            continue
        rows = ids[newer[f"_{key}"][ids]]
        if isinstance(value, dict):
            replace_rows(info.setdefault(key, {}), value, ids)
        else:
            if key not in info:
                info[key] = _empty_like(value)
            _clear_rows(info, key, ids)
            info[key][rows] = value[rows]
        mask = info.setdefault(f"_{key}", np.zeros(len(newer[f"_{key}"]), dtype=bool))
        mask[ids] = newer[f"_{key}"][ids]


def _clear_rows(info: dict[str, Any], key: str, ids: np.ndarray) -> None:
    """Remove `key`'s entries of environments `ids` from `info`."""
    value = info[key]
    if isinstance(value, dict):
        for inner in [k for k in value if not k.startswith("_")]:
            _clear_rows(value, inner, ids)
    else:
        value[ids] = None if value.dtype == object else 0
    info[f"_{key}"][ids] = False


def _empty_like(value: np.ndarray) -> np.ndarray:
    """An info array like `value` holding no entry: None for objects, else zeros."""
    return np.full_like(value, None) if value.dtype == object else np.zeros_like(value)
