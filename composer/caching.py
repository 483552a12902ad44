"""`cached_property`: a property computed once per object, then kept (dm_control's
`composer.define.cached_property`, exported there and as `composer.cached_property`).

    class Arm(composer.Entity):
        @composer.cached_property
        def joints(self):                          # found once, then kept
            return self.mjcf_model.find_all('joint')

Kept in the object's `__dict__` under the property's name; two threads reading it first
compute it once. `composer.observable` on a task is one too (`observation.entity_observables`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any


class cached_property(property):
    """A property computed on first access and then kept in the object's `__dict__`
    (thread safe: computed once even when first read from two threads)."""

    def __init__(self, function: Callable[[Any], Any], doc: str | None = None) -> None:
        """Wrap `function(obj)`; its docstring is the property's unless `doc` is given."""
        super().__init__(fget=function, doc=doc)
        self._lock = threading.RLock()
        self._name = function.__name__

    def __set_name__(self, owner: type, name: str) -> None:
        self._name = name

    def __get__(self, instance: Any, owner: type | None = None) -> Any:
        if instance is None:
            return self
        stored = instance.__dict__
        try:
            return stored[self._name]
        except KeyError:
            with self._lock:
                if self._name not in stored:
                    stored[self._name] = self.fget(instance)  # type: ignore[misc]
                return stored[self._name]


__all__ = ["cached_property"]
