"""Entities: robots and props that own an MJCF model, its observables and its hooks.

    class Arm(composer.Entity):
        def _build(self, length=0.5):
            self._mjcf_root = mjcf.RootElement(model='arm')
            body = self._mjcf_root.worldbody.add('body', name='upper')
            self.joints = [body.add('joint', name='shoulder', axis=[0, 1, 0])]
            body.add('geom', type='capsule', fromto=[0, 0, 0, length, 0, 0], size=[0.05])
            self._mjcf_root.actuator.add('motor', joint=self.joints[0], ctrlrange=[-1, 1])
            self.wrist = body.add('site', name='wrist', pos=[length, 0, 0])

        @composer.observable
        def joint_positions(self):
            return composer.observation.MJCFFeature('qpos', self.joints)

    arm = Arm()
    arm.attach(gripper, attach_site=arm.wrist)       # gripper: another entity
    arm.observables.joint_positions.enabled = True   # observables start disabled
    humanoid = composer.Entity.from_path('humanoid.xml')   # no class needed

An entity's observables are built on first access to `observables` by `_build_observables()`
(override it to return an `Observables` subclass, dm_control style); methods decorated with
`@observable` on the entity or on that subclass become its observables. Hooks (see
`composer.hooks` for their order) are no-ops unless overridden; only overridden hooks run.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Mapping
from typing import Any

import mujoco
import numpy as np

import mjcf
from composer import errors, hooks
from composer.observation import MJCFFeature, Observable


class observable:
    """Decorate a method returning an `Observable` to declare it as one, named after the
    method. On an entity, `entity.name_of_method` and `entity.observables.name_of_method`
    are the same object."""

    def __init__(self, function: Callable[[Any], Observable]) -> None:
        """Wrap `function(owner) -> Observable` (owner: the entity or its Observables)."""
        self.function = function
        self.name = function.__name__
        self.__doc__ = function.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, instance: Any, owner: type | None = None) -> Any:
        if instance is None:
            return self
        observables = instance if isinstance(instance, Observables) else instance.observables
        return observables[self.name]


def _declared(cls: type) -> dict[str, observable]:
    found: dict[str, observable] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if isinstance(value, observable):
                found[name] = value
    return found


class Observables(Mapping[str, Observable]):
    """The named observables of one entity, a read-only mapping: `obs['name']`,
    `obs.name`, `obs.items()`. Subclass it with `@observable` methods that use
    `self._entity`."""

    def __init__(self, entity: Entity) -> None:
        """Create every `@observable` of `entity`'s class and of this class."""
        self._entity = entity
        self._items: dict[str, Observable] = {}
        for owner in (entity, self):
            for name, declared in _declared(type(owner)).items():
                made = declared.function(owner)
                if not isinstance(made, Observable):
                    raise errors.ObservableError(
                        f"entity {entity.name!r}: @observable {name!r} returned "
                        f"{type(made).__name__}, expected an Observable"
                    )
                self._items[name] = made

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


class Entity(hooks.EpisodeHooks):
    """A part of a scene that owns an MJCF model. Subclasses build it in `_build`."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Build the entity with `_build(*args, **kwargs)`."""
        self._parent: Entity | None = None
        self._children: list[Entity] = []
        self._observables: Observables | None = None
        self._build(*args, **kwargs)

    def _build(self, *args: Any, **kwargs: Any) -> None:
        """Make the MJCF model: set `self._mjcf_root` (or override `mjcf_model`)."""
        raise NotImplementedError(f"{type(self).__name__} must implement _build()")

    def _build_observables(self) -> Observables:
        """The entity's observables; override to return an `Observables` subclass."""
        return Observables(self)

    # -- model and tree --------------------------------------------------------------------

    @property
    def mjcf_model(self) -> mjcf.RootElement:
        """The entity's MJCF model; raises EntityError if `_build` made none."""
        root = self.__dict__.get("_mjcf_root")
        if root is None:
            raise errors.EntityError(
                f"{type(self).__name__}._build() must set self._mjcf_root to an "
                "mjcf.RootElement (or the class must override mjcf_model)"
            )
        return root

    @property
    def name(self) -> str:
        """The entity's name: its model's name, the scope of its elements when attached."""
        return self.mjcf_model.model

    @property
    def actuators(self) -> list[mjcf.Element]:
        """The actuators of this entity's own model (not of attached entities)."""
        return self.mjcf_model.find_all("actuator", exclude_attachments=True)

    @property
    def observables(self) -> Observables:
        """The entity's observables, built on first access."""
        if self._observables is None:
            self._observables = self._build_observables()
        return self._observables

    @property
    def parent(self) -> Entity | None:
        """The entity this one is attached to, or None."""
        return self._parent

    def scope_in(self, ancestor: Entity) -> str:
        """The scope of this entity's names in `ancestor`'s model: '' for `ancestor`
        itself, 'arm' for an entity attached to it, 'arm/gripper' below that. Raises
        EntityError if this entity is not `ancestor` or attached under it."""
        parts = []
        current: Entity | None = self
        while current is not ancestor:
            if current is None:
                raise errors.EntityError(
                    f"entity {self.name!r} is not attached under entity {ancestor.name!r}"
                )
            parts.append(current.name)
            current = current._parent
        return "/".join(reversed(parts))

    def iter_entities(self) -> Iterator[Entity]:
        """This entity, then its attached entities depth first, in attachment order."""
        yield self
        for child in self._children:
            yield from child.iter_entities()

    def attach(self, entity: Entity, attach_site: mjcf.Element | None = None) -> mjcf.Element:
        """Attach `entity` at `attach_site` (a site, body or frame of this model; the world
        body if None) and return its attachment frame. Raises EntityError if `entity` is
        attached already, or if its model cannot be attached there."""
        if entity._parent is not None:
            raise errors.EntityError(
                f"entity {entity.name!r} is already attached to {entity._parent.name!r}; "
                "detach it first"
            )
        place = self.mjcf_model.worldbody if attach_site is None else attach_site
        try:
            frame = place.attach(entity.mjcf_model)
        except mjcf.Error as e:
            raise errors.EntityError(
                f"cannot attach entity {entity.name!r} to entity {self.name!r}: {e}"
            ) from e
        entity._parent = self
        self._children.append(entity)
        return frame

    def detach(self) -> None:
        """Detach this entity from its parent; raises EntityError if it is not attached."""
        if self._parent is None:
            raise errors.EntityError(f"entity {self.name!r} is not attached to any entity")
        self.mjcf_model.detach()
        self._parent._children.remove(self)
        self._parent = None

    @property
    def attachment_frame(self) -> mjcf.Element | None:
        """The frame this entity's model is attached with, or None."""
        return mjcf.get_attachment_frame(self.mjcf_model)

    # -- pose ------------------------------------------------------------------------------

    def _free_joint(self) -> mjcf.Element:
        joint = mjcf.get_frame_freejoint(self.mjcf_model)
        if joint is None:
            bodies = self.mjcf_model.worldbody.get_children("body")
            if len(bodies) == 1:
                joint = mjcf.get_freejoint(bodies[0])
        if joint is None:
            raise errors.EntityError(
                f"entity {self.name!r} has no free joint to pose: attach it with "
                "arena.add_free_entity(entity), or give its single top body a free joint"
            )
        return joint

    def set_pose(self, physics: mjcf.Physics, position: Any = None, quaternion: Any = None) -> None:
        """Place a free entity: world `position` (3,) and/or `quaternion` (4,, w first).
        Raises EntityError for an entity without a free joint."""
        qpos = physics.bind(self._free_joint()).qpos
        if position is not None:
            qpos[:3] = position
        if quaternion is not None:
            qpos[3:] = quaternion

    def get_pose(self, physics: mjcf.Physics) -> tuple[np.ndarray, np.ndarray]:
        """(position, quaternion) of a free entity, copies. Raises EntityError as set_pose."""
        qpos = physics.bind(self._free_joint()).qpos
        return qpos[:3].copy(), qpos[3:].copy()

    def set_velocity(
        self, physics: mjcf.Physics, velocity: Any = None, angular_velocity: Any = None
    ) -> None:
        """Set a free entity's linear and/or angular velocity, both in the world frame
        (MuJoCo keeps the angular one in the body frame: converted here). Raises
        EntityError for an entity without a free joint."""
        joint = physics.bind(self._free_joint())
        qvel = joint.qvel
        if velocity is not None:
            qvel[:3] = velocity
        if angular_velocity is not None:
            inverse = np.empty(4)
            mujoco.mju_negQuat(inverse, joint.qpos[3:])
            local = np.empty(3)
            mujoco.mju_rotVecQuat(local, np.asarray(angular_velocity, np.float64), inverse)
            qvel[3:] = local

    # -- hooks (see composer.hooks for the order; the others are in hooks.EpisodeHooks) --

    @hooks.noop
    def before_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Each control step, after the task's before_step applied the action."""

    @hooks.noop
    def before_substep(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Before each physics step."""

    # -- generic entities ----------------------------------------------------------------

    @classmethod
    def from_path(cls, path: str | os.PathLike[str], name: str | None = None) -> ModelEntity:
        """An entity of the MJCF file at `path` (renamed `name` if given), with default
        observables enabled; raises mjcf.Error subclasses when the file does not parse."""
        model = mjcf.from_path(os.fspath(path))
        if name is not None:
            model.model = name
        return ModelEntity(model)

    @classmethod
    def from_mjcf_model(cls, mjcf_model: mjcf.RootElement) -> ModelEntity:
        """An entity owning `mjcf_model`, with default observables enabled."""
        return ModelEntity(mjcf_model)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r}>"


class ModelEntity(Entity):
    """An entity made from any MJCF model. Its observables, enabled, are those of its own
    elements that exist: `joint_positions` and `joint_velocities` (every joint, free joints
    included), `actuator_activations` (left out of observations when no actuator has an
    activation) and `sensors` (all sensor data). Its actuators are the action."""

    def _build(self, mjcf_model: mjcf.RootElement) -> None:
        """Own `mjcf_model`; raises EntityError for anything else."""
        if not isinstance(mjcf_model, mjcf.RootElement):
            raise errors.EntityError(
                f"ModelEntity needs an mjcf.RootElement, got {type(mjcf_model).__name__}"
            )
        self._mjcf_root = mjcf_model

    def _build_observables(self) -> Observables:
        observables = Observables(self)
        model = self.mjcf_model
        joints = model.find_all("joint", exclude_attachments=True)
        if joints:
            observables.add_observable("joint_positions", MJCFFeature("qpos", joints))
            observables.add_observable("joint_velocities", MJCFFeature("qvel", joints))
        if self.actuators:
            observables.add_observable("actuator_activations", MJCFFeature("act", self.actuators))
        sensors = model.find_all("sensor", exclude_attachments=True)
        if sensors:
            observables.add_observable("sensors", MJCFFeature("sensordata", sensors))
        return observables
