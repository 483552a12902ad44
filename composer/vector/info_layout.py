"""Gymnasium's vector info layout: each key an array over environments, with a boolean
'_key' array saying which environments have it.

    put(info, 'discount', ids, values, num_envs)   # info['discount'][ids] = values
    kept, moved = split(info, mask)                # e.g. into info and info['final_info']
"""

from __future__ import annotations

from typing import Any

import numpy as np

from composer.vector.protocol import BatchError


def put(info: dict[str, Any], key: str, ids: np.ndarray, values: np.ndarray, n: int) -> None:
    """Set info[key][ids] = values (one row per id) and the mask info['_key'] for `n`
    environments; raises BatchError when `values` has not one row per id."""
    if values.shape[:1] != (len(ids),):
        raise BatchError(
            f"get_info_batch entry {key!r} has shape {values.shape}; expected ({len(ids)}, ...)"
        )
    array = info.get(key)
    if array is None:
        array = info[key] = np.zeros((n, *values.shape[1:]), dtype=values.dtype)
        info[f"_{key}"] = np.zeros(n, dtype=bool)
    array[ids] = values
    info[f"_{key}"][ids] = True


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
                array = np.full_like(value, None) if value.dtype == object else np.zeros_like(value)
                array[rows] = value[rows]
                part[key] = array
            part[f"_{key}"] = rows
    return kept, moved
