"""Decorators for entities and tasks: `observable` declares an observable, `cached_property` a
value computed once per object (dm_control's `composer.define`).

    class ArmObservables(composer.Observables):
        @composer.observable                      # also `define.observable`
        def joint_positions(self):
            return observation.MJCFFeature('qpos', self._entity.joints)

    class Arm(composer.Entity):
        @composer.cached_property                 # found once, then kept
        def joints(self):
            return self.mjcf_model.find_all('joint')

    class Reach(composer.Task):
        @composer.observable                      # a task's own: made once, then kept
        def goal(self):
            return observable.Generic(lambda physics: self._goal)

        @property
        def task_observables(self):
            return {'goal': self.goal}

An `@observable` method is called once per `Observables` object, when the entity builds
its observables (an observable it reads through `self.other` is made first). On an
entity, `entity.name_of_method` and `entity.observables.name_of_method` are the same
object. On any other object (a task) it is dm_control's: a `cached_property`, made at
first access and the same object after; a task lists it in its `task_observables`.
`observable` is defined with the `Observables` it declares into
(`composer.observation.entity_observables`), `cached_property` in `composer.caching`.
"""

from __future__ import annotations

import abc

from composer.caching import cached_property
from composer.observation.entity_observables import observable

# For abstract Observables classes: a subclass must define the observable.
abstract_observable = abc.abstractproperty

__all__ = ["abstract_observable", "cached_property", "observable"]
