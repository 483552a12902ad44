"""dm_control's `composer.define`: the decorators `observable` and `cached_property`.

    class Reach(composer.Task):
        @composer.observable                      # a task's own: made once, then kept
        def goal(self):
            return observable.Generic(lambda physics: self._goal)

On an entity or its `Observables`, `@observable` declares one of the entity's observables
(`composer.observation.entity_observables`, where it is defined); a task lists its own in
`task_observables`. `cached_property` (`composer.caching`) computes a value once per object.
"""

from __future__ import annotations

import abc

from composer.caching import cached_property
from composer.observation.entity_observables import observable

# For abstract Observables classes: a subclass must define the observable.
abstract_observable = abc.abstractproperty

__all__ = ["abstract_observable", "cached_property", "observable"]
