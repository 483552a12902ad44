"""Decorators for entity classes: `observable` declares an observable, `cached_property` a
value computed once per object (dm_control's `composer.define`).

    class ArmObservables(composer.Observables):
        @composer.observable                      # also `define.observable`
        def joint_positions(self):
            return observation.MJCFFeature('qpos', self._entity.joints)

    class Arm(composer.Entity):
        @composer.cached_property                 # found once, then kept
        def joints(self):
            return self.mjcf_model.find_all('joint')

An `@observable` method is called once per `Observables` object, when the entity builds
its observables (an observable it reads through `self.other` is made first). On an
entity, `entity.name_of_method` and `entity.observables.name_of_method` are the same
object. `observable` is defined with the `Observables` it declares into
(`composer.observables`).
"""

from __future__ import annotations

import abc
import threading
from collections.abc import Callable
from typing import Any

from composer.observables import observable


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


# For abstract Observables classes: a subclass must define the observable.
abstract_observable = abc.abstractproperty

__all__ = ["abstract_observable", "cached_property", "observable"]
