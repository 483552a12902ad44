"""Work on a whole tree at once, with Python's cyclic garbage collector paused.

    @bulk.whole_tree
    def serialize(root): ...

Reading, writing or copying a model makes many objects that live on and refer to each
other in cycles; nothing these functions make is garbage, so the collector waits until
they return (or raise), and stays off if it was off. Without this the work on a large
model grows faster than its size (docs/performance_profile.md, "Costs behind choices").
"""

from __future__ import annotations

import functools
import gc
from collections.abc import Callable
from typing import ParamSpec, TypeVar

_P = ParamSpec("_P")
_R = TypeVar("_R")


def whole_tree(function: Callable[_P, _R]) -> Callable[_P, _R]:
    """`function`, run with the garbage collector paused (see the module docstring)."""

    @functools.wraps(function)
    def paused(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        if not gc.isenabled():
            return function(*args, **kwargs)
        gc.disable()
        try:
            return function(*args, **kwargs)
        finally:
            gc.enable()

    return paused
