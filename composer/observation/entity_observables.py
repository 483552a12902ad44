"""The observables of one entity: `entity.observables` (dm_control's `composer.Observables`).

    class ArmObservables(composer.Observables):
        @composer.observable                         # on a task: a cached property
        def joint_positions(self):
            return observation.MJCFFeature('qpos', self._entity.joints)
    arm.observables.set_options({'joint_positions': {'enabled': True, 'buffer_size': 2}})
    arm.observables.dict_keys.joint_positions        # 'arm/joint_positions' once attached

An unknown name raises ObservableNotFoundError (a KeyError), a name taken ObservableError.
"""

from __future__ import annotations

import abc
from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any

from composer import errors
from composer.caching import cached_property
from composer.observation.observable import Observable

if TYPE_CHECKING:
    from composer.entity import Entity

# The options `set_options` can give every observable at once (dm_control's set).
OPTION_KEYS = frozenset(
    {"update_interval", "buffer_size", "delay", "aggregator", "corruptor", "enabled"}
)


class observable(cached_property):
    """Declare a method returning an `Observable` as one, named after the method
    (dm_control's `composer.define.observable`, re-exported there). On an `Observables`
    subclass and on an entity it is one of the entity's observables (`entity.name` and
    `entity.observables.name` are then the same object); on any other object (a task, which
    lists it in its own `task_observables`) it is dm_control's, a `cached_property`: made at
    first access, then the same object. The method is `function(owner) -> Observable`
    (owner: the entity, its Observables, or the task)."""

    def __get__(self, instance: Any, owner: type | None = None) -> Any:
        if instance is None:
            return self
        if isinstance(instance, Observables):
            return instance._declared_item(self._name)
        # An entity (what has `_build_observables`): its Observables made the observable.
        if hasattr(instance, "_build_observables"):
            return instance.observables[self._name]
        return super().__get__(instance, owner)


def _declared(cls: type) -> dict[str, observable]:
    found: dict[str, observable] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if isinstance(value, observable):
                found[name] = value
    return found


def scope_prefix(entity: Entity) -> str:
    """The prefix of `entity`'s names in the outermost model it is attached into: '' for
    that model, 'arm/' for a model attached to it, 'arm/gripper/' below that (dm_control's
    `mjcf_model.full_identifier`)."""
    parts = []
    model = entity.mjcf_model
    while model.parent_model is not None:
        parts.append(model.model)
        model = model.parent_model
    return "".join(f"{name}/" for name in reversed(parts))


class _ObservableKeys:
    """`observables.dict_keys.name`: the key of observable `name` in `as_dict()`."""

    def __init__(self, observables: Observables) -> None:
        self._observables = observables

    def __getattr__(self, name: str) -> str:
        if name.startswith("_"):
            raise AttributeError(name)
        self._observables[name]  # raises ObservableNotFoundError for an unknown name
        return scope_prefix(self._observables._entity) + name

    def __dir__(self) -> list[str]:
        return sorted({*self._observables, *super().__dir__()})


class Observables(Mapping[str, Observable]):
    """The named observables of one entity, a read-only mapping: `obs['name']`,
    `obs.name`, `obs.items()`. Subclass it with `@observable` methods that use
    `self._entity`."""

    def __init__(self, entity: Entity) -> None:
        """Make every `@observable` of `entity`'s class and of this class, in name order
        (one that reads another through `self.name` gets it made first). Raises
        ObservableError for one that returns something else than an Observable."""
        self._entity = entity
        self._items: dict[str, Observable] = {}
        self._declarations = {
            name: (declared, owner)
            for owner in (entity, self)
            for name, declared in _declared(type(owner)).items()
        }
        for name in sorted(self._declarations):
            self._declared_item(name)
        self._items = {name: self._items[name] for name in sorted(self._items)}
        self._keys = _ObservableKeys(self)

    def _declared_item(self, name: str) -> Observable:
        """Observable `name`, made now if it is declared and not made yet."""
        found = self._items.get(name)
        if found is not None or name not in self._declarations:
            return self[name]
        declared, owner = self._declarations[name]
        made = declared.fget(owner)  # type: ignore[misc]
        if not isinstance(made, Observable):
            raise errors.ObservableError(
                f"entity {self._entity.name!r}: @observable {name!r} returned "
                f"{type(made).__name__}, expected an Observable"
            )
        self._items[name] = made
        return made

    # -- dm_control's methods ------------------------------------------------------------

    @property
    def dict_keys(self) -> Any:
        """`dict_keys.name` is observable `name`'s key in `as_dict()` ('arm/name')."""
        return self._keys

    def as_dict(self, fully_qualified: bool = True) -> dict[str, Observable]:
        """A new dict of the observables by name, prefixed by the entity's scope in the
        outermost model it is attached into ('arm/name'; none for that model) when
        `fully_qualified`."""
        prefix = scope_prefix(self._entity) if fully_qualified else ""
        return {prefix + name: item for name, item in self._items.items()}

    def get_observable(self, name: str, name_fully_qualified: bool = False) -> Observable:
        """The observable `name` (with the entity's scope prefix if `name_fully_qualified`).
        Raises ObservableNotFoundError (a KeyError and an AttributeError)."""
        if name_fully_qualified:
            prefix = scope_prefix(self._entity)
            if not name.startswith(prefix):
                raise errors.ObservableNotFoundError(
                    f"entity {self._entity.name!r}: {name!r} is not under its scope {prefix!r}"
                )
            name = name[len(prefix) :]
        return self[name]

    def set_options(self, options: Mapping[str, Any] | None) -> None:
        """Configure observables: `{name: {option: value}}`, or `{option: value}` (keys
        among OPTION_KEYS) for every observable; None does nothing. Raises
        ObservableNotFoundError for an unknown name and ObservableOptionError for an
        unknown option, before anything changes."""
        if not options:
            return
        if set(options) <= OPTION_KEYS:
            options = {name: options for name in self._items}
        for name, item_options in options.items():
            if name not in self._items:
                raise errors.ObservableNotFoundError(
                    f"No observable with name {name!r} in entity {self._entity.name!r}; it "
                    f"has {sorted(self._items)}"
                )
            for key in item_options:
                if key.startswith("_") or not hasattr(self._items[name], key):
                    raise errors.ObservableOptionError(
                        f"Cannot add attribute {key} in configure: observable {name!r} has "
                        f"no option {key!r}"
                    )
        for name, item_options in options.items():
            self._items[name].configure(**item_options)

    def add_observable(self, name: str, observable: Observable, enabled: bool = True) -> None:
        """Add `observable` under `name`; raises ObservableError if the name is taken."""
        if name in self._items:
            raise errors.ObservableError(
                f"entity {self._entity.name!r} already has an observable {name!r}"
            )
        if not isinstance(observable, Observable):
            raise errors.ObservableError(
                f"entity {self._entity.name!r}: {name!r} must be an Observable, "
                f"got {type(observable).__name__}"
            )
        observable.enabled = enabled
        self._items[name] = observable

    def enable_all(self) -> None:
        """Enable every observable of this entity."""
        for item in self._items.values():
            item.enabled = True

    def disable_all(self) -> None:
        """Disable every observable of this entity."""
        for item in self._items.values():
            item.enabled = False

    # -- the mapping ---------------------------------------------------------------------

    def __getitem__(self, name: str) -> Observable:
        found = self._items.get(name)
        if found is None:
            raise errors.ObservableNotFoundError(
                f"entity {self._entity.name!r} has no observable {name!r}; "
                f"it has {sorted(self._items)}"
            )
        return found

    def __getattr__(self, name: str) -> Observable:
        if name.startswith("_"):
            raise AttributeError(name)
        return self[name]

    def get(self, name: str, default: Any = None) -> Any:
        """The observable `name`, or `default`."""
        return self._items.get(name, default)

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)


class FreePropObservableMixin(metaclass=abc.ABCMeta):
    """For the Observables of a free prop: it must declare `position`, `orientation`,
    `linear_velocity` and `angular_velocity` (dm_control's mixin)."""

    @property
    @abc.abstractmethod
    def position(self) -> Observable:
        """The prop's world position."""

    @property
    @abc.abstractmethod
    def orientation(self) -> Observable:
        """The prop's world orientation."""

    @property
    @abc.abstractmethod
    def linear_velocity(self) -> Observable:
        """The prop's linear velocity."""

    @property
    @abc.abstractmethod
    def angular_velocity(self) -> Observable:
        """The prop's angular velocity."""
