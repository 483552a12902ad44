"""`evaluate`: a nested structure of variations (or any callables) and constants, with
every callable replaced by what it returns.

    evaluate(Uniform(0, 1), random_state=random_state)            # one draw
    evaluate((Uniform(0, 1), [2.0, Normal()]), random_state=rs)   # (draw, [2.0, draw])
    evaluate(3.0)                                                 # 3.0

Promise: callables are called in dm_control's order, so a seeded random state gives its draws.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Mapping
from typing import Any


def evaluate(structure: Any, *args: Any, **kwargs: Any) -> Any:
    """`structure` with each callable in it replaced by `callable(*args, **kwargs)`; the
    arguments are usually `initial_value, current_value, random_state` (see `base`).

    Lists, tuples, named tuples and mappings are traversed (numpy arrays, strings and sets are
    values); the result has the structure's types. Callables are called in dm_control's
    order (dm-tree's): depth first, a mapping's entries by sorted key, so a seeded random
    state gives the same draws as there.
    """
    if callable(structure):
        return structure(*args, **kwargs)
    if isinstance(structure, list):
        return [evaluate(item, *args, **kwargs) for item in structure]
    if isinstance(structure, tuple):
        items = [evaluate(item, *args, **kwargs) for item in structure]
        return type(structure)(*items) if hasattr(structure, "_fields") else tuple(items)
    if isinstance(structure, Mapping):
        values = {key: evaluate(structure[key], *args, **kwargs) for key in _sorted(structure)}
        ordered = [(key, values[key]) for key in structure]
        if isinstance(structure, defaultdict):
            return type(structure)(structure.default_factory, ordered)
        return type(structure)(ordered) if isinstance(structure, dict) else dict(ordered)
    return structure


def _sorted(mapping: Mapping[Any, Any]) -> list[Any]:
    try:
        return sorted(mapping)
    except TypeError:  # keys that do not order: as they come
        return list(mapping)
