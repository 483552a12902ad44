"""Entities: robots and props that own an MJCF model, its observables and its hooks.

    arm = Arm(observable_options={'joint_positions': {'enabled': True}})  # `Entity`'s Arm
    arm.attach(gripper)                                    # at arm.attachment_site
    humanoid = composer.Entity.from_path('humanoid.xml')   # no class needed
    humanoid.set_pose(physics, position=[0, 0, 1])         # a free entity's world pose

Promises: an entity builds its model (`_build`), then its observables, then applies
`observable_options`; only the hooks it overrides run (`composer.hooks`); its poses are
dm_control's. A model it cannot own or pose raises EntityError.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import Any

import mujoco
import numpy as np

import mjcf
from composer import errors, hooks
from composer.define import observable
from composer.observation import MJCFFeature
from composer.observation.entity_observables import FreePropObservableMixin, Observables

__all__ = [
    "Entity",
    "FreePropObservableMixin",
    "ModelEntity",
    "ModelWrapperEntity",
    "Observables",
    "observable",
]


class Entity(hooks.EpisodeHooks):
    """A part of a scene that owns an MJCF model. Subclasses build it in `_build`.

        class Arm(composer.Entity):
            def _build(self, length=0.5):
                self._mjcf_root = mjcf.RootElement(model='arm')
                body = self._mjcf_root.worldbody.add('body', name='upper')
                self.joints = [body.add('joint', name='shoulder', axis=[0, 1, 0])]
                body.add('geom', type='capsule', fromto=[0, 0, 0, length, 0, 0], size=[0.05])
                self._mjcf_root.actuator.add('motor', joint=self.joints[0], ctrlrange=[-1, 1])
                self.wrist = body.add('site', name='wrist', pos=[length, 0, 0])

            @property
            def attachment_site(self):                   # where attach() mounts by default
                return self.wrist

            @composer.observable
            def joint_positions(self):
                return composer.observation.MJCFFeature('qpos', self.joints)

    An entity builds its model in `_build(*args, **kwargs)`, then its observables with
    `_build_observables()` (override it to return an `Observables` subclass, dm_control style;
    methods decorated with `@observable` on the entity or on that subclass become its
    observables), then applies `observable_options` (see `Observables.set_options`). Hooks (see
    `composer.hooks` for their order) are no-ops unless overridden; only overridden hooks run.

    Poses, as dm_control: `set_pose`/`get_pose` of an entity with a free joint are its world
    pose; of an entity attached without one, the pose of its attachment frame relative to the
    body it is attached in, read and written through `physics.bind(frame)`: a body's pos and
    quat when the frame has joints, else the frame's (a MuJoCo `<frame>`, moved with all it
    holds in the compiled simulation: `mjcf.sim.frame_binding`).
    """

    def __init__(self, *args: Any, observable_options: Any = None, **kwargs: Any) -> None:
        """Build the entity with `_build(*args, **kwargs)`, then its observables, configured
        by `observable_options` (see `Observables.set_options`)."""
        self._parent: Entity | None = None
        self._children: list[Entity] = []
        self._observables: Observables | None = None
        self._build(*args, **kwargs)
        self._observables = self._build_observables()
        self._observables.set_options(observable_options)

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
        """The entity's observables."""
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

    def iter_entities(self, exclude_self: bool = False) -> Iterator[Entity]:
        """This entity (unless `exclude_self`), then its attached entities depth first, in
        attachment order."""
        if not exclude_self:
            yield self
        for child in self._children:
            yield from child.iter_entities()

    @property
    def attachment_site(self) -> mjcf.Element:
        """Where `attach` mounts an entity when given no site: here the model's root (its
        world body); subclasses override it (an arm's wrist site)."""
        return self.mjcf_model

    def attach(self, entity: Entity, attach_site: mjcf.Element | None = None) -> mjcf.Element:
        """Attach `entity` at `attach_site` (a site, body or frame of this model; None:
        `self.attachment_site`) and return its attachment frame. Raises EntityError if
        `entity` is attached already, or if its model cannot be attached there."""
        if entity._parent is not None:
            raise errors.EntityError(
                f"entity {entity.name!r} is already attached to {entity._parent.name!r}; "
                "detach it first"
            )
        place = self.attachment_site if attach_site is None else attach_site
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
        """Detach this entity from its parent; raises EntityError (a RuntimeError) if it is
        not attached."""
        if self._parent is None:
            raise errors.EntityError(f"entity {self.name!r} is not attached to any entity")
        self.mjcf_model.detach()
        self._parent._children.remove(self)
        self._parent = None

    @property
    def attachment_frame(self) -> mjcf.Element | None:
        """The frame this entity's model is attached with, or None."""
        return mjcf.get_attachment_frame(self.mjcf_model)

    @property
    def root_body(self) -> mjcf.Element:
        """The entity's attachment frame when attached, else its model's world body."""
        if self._parent is not None:
            frame = self.attachment_frame
            if frame is not None:
                return frame
        return self.mjcf_model.worldbody

    # -- frames ----------------------------------------------------------------------------

    def _root_xmat(self, physics: mjcf.Physics) -> np.ndarray:
        """The world orientation (3, 3) of the entity's root body."""
        return np.reshape(physics.bind(self.root_body).xmat, (3, 3))

    def global_vector_to_local_frame(self, physics: mjcf.Physics, vec_in_world_frame: Any) -> Any:
        """A world-frame vector (last axis of size 3, or 2 for the xy plane) expressed in
        the axes of the entity's root body, same shape. Raises PoseError for another size."""
        vec = np.asarray(vec_in_world_frame)
        xmat = self._root_xmat(physics)
        if vec.shape[-1:] == (2,):
            return np.dot(vec, xmat[:2, :2])
        if vec.shape[-1:] == (3,):
            return np.dot(vec, xmat)
        raise errors.PoseError(
            f"`vec_in_world_frame` should have shape with final dimension 2 or 3: got {vec.shape}"
        )

    def global_xmat_to_local_frame(self, physics: mjcf.Physics, xmat: Any) -> np.ndarray:
        """Another frame's world orientation `xmat` ((3, 3) or (9,)) expressed relative to
        the entity's root body, same shape. Raises PoseError for another shape."""
        xmat = np.asarray(xmat)
        shape = xmat.shape
        if shape not in ((3, 3), (9,)):
            raise errors.PoseError(f"`xmat` should have shape (3, 3) or (9,): got {shape}")
        own = self._root_xmat(physics)
        return np.reshape(own.T @ xmat.reshape(3, 3), shape)

    # -- pose ------------------------------------------------------------------------------

    def _free_joint(self) -> mjcf.Element | None:
        """The free joint posing this entity: its attachment frame's, or its single top
        body's (a standalone robot file that floats already); None if it has none."""
        joint = mjcf.get_frame_freejoint(self.mjcf_model)
        if joint is None:
            bodies = self.mjcf_model.worldbody.get_children("body")
            if len(bodies) == 1:
                joint = mjcf.get_freejoint(bodies[0])
        return joint

    def _frame_binding(self, physics: mjcf.Physics) -> Any:
        """The binding of the attachment frame (a body's or a frame's, both with pos and
        quat); raises EntityError for an entity that is not attached."""
        frame = self.attachment_frame
        if frame is None:
            raise errors.EntityError(
                f"entity {self.name!r} has no free joint and is not attached: it has no pose "
                "(attach it, or add it with arena.add_free_entity(entity))"
            )
        return physics.bind(frame)

    def set_pose(self, physics: mjcf.Physics, position: Any = None, quaternion: Any = None) -> None:
        """Place the entity: with a free joint, its world `position` (3,) and/or
        `quaternion` (4,, w first, normalized here); else its attachment frame's, relative
        to the body it is attached in. Raises EntityError for an entity not attached."""
        if quaternion is not None:
            quaternion = np.asarray(quaternion, dtype=np.float64)
            quaternion = quaternion / np.linalg.norm(quaternion)
        joint = self._free_joint()
        if joint is None:
            frame = self._frame_binding(physics)
            if position is not None:
                frame.pos = position
            if quaternion is not None:
                frame.quat = quaternion
            return
        bound = physics.bind(joint)
        qpos = np.array(bound.qpos)
        if position is not None:
            qpos[:3] = position
        if quaternion is not None:
            qpos[3:] = quaternion
        bound.qpos = qpos

    def get_pose(self, physics: mjcf.Physics) -> tuple[np.ndarray, np.ndarray]:
        """(position, quaternion), copies: as `set_pose` sets them. Raises EntityError as
        set_pose."""
        joint = self._free_joint()
        if joint is None:
            frame = self._frame_binding(physics)
            return np.array(frame.pos), np.array(frame.quat)
        qpos = physics.bind(joint).qpos
        return np.array(qpos[:3]), np.array(qpos[3:])

    def shift_pose(
        self,
        physics: mjcf.Physics,
        position: Any = None,
        quaternion: Any = None,
        rotate_velocity: bool = False,
    ) -> None:
        """`set_pose` relative to the current pose: `position` added, `quaternion`
        premultiplied; with `rotate_velocity` a free entity's linear velocity turns with
        it (its angular velocity, in its own frame, already does)."""
        current_position, current_quaternion = self.get_pose(physics)
        new_position = new_quaternion = None
        if position is not None:
            new_position = current_position + np.asarray(position, dtype=np.float64)
        if quaternion is not None:
            quaternion = np.asarray(quaternion, dtype=np.float64)
            new_quaternion = np.empty(4)
            mujoco.mju_mulQuat(new_quaternion, quaternion, current_quaternion)
            joint = mjcf.get_frame_freejoint(self.mjcf_model)
            if joint is not None and rotate_velocity:
                velocity = np.array(physics.bind(joint).qvel[:3])
                rotated = np.empty(3)
                mujoco.mju_rotVecQuat(rotated, velocity, quaternion)
                self.set_velocity(physics, rotated)
        self.set_pose(physics, new_position, new_quaternion)

    def get_velocity(self, physics: mjcf.Physics) -> tuple[np.ndarray, np.ndarray]:
        """(linear velocity in the world frame, angular velocity in the entity's own
        frame), copies, of a free entity (its free joint's qvel). Raises PoseError (a
        ValueError) for an entity without a free joint."""
        joint = self._free_joint()
        if joint is None:
            raise errors.PoseError(
                f"get_velocity cannot be used on a non-free entity: {self.name!r} has no free joint"
            )
        qvel = physics.bind(joint).qvel
        return np.array(qvel[:3]), np.array(qvel[3:])

    def set_velocity(
        self, physics: mjcf.Physics, velocity: Any = None, angular_velocity: Any = None
    ) -> None:
        """Set a free entity's linear velocity (world frame) and/or angular velocity (in
        its own frame, as MuJoCo's free joint and dm_control take it). Raises PoseError
        for an entity without a free joint."""
        joint = self._free_joint()
        if joint is None:
            raise errors.PoseError(
                f"entity {self.name!r} has no free joint: its velocity cannot be set (add it "
                "with arena.add_free_entity(entity))"
            )
        bound = physics.bind(joint)
        qvel = np.array(bound.qvel)
        if velocity is not None:
            qvel[:3] = velocity
        if angular_velocity is not None:
            qvel[3:] = angular_velocity
        bound.qvel = qvel

    def configure_joints(self, physics: mjcf.Physics, position: Any) -> None:
        """Set the qpos of this entity's own joints (not of attached entities), in model
        order; subclasses with actuated joints may override it to keep their actuators'
        targets in step."""
        joints = self.mjcf_model.find_all("joint", exclude_attachments=True)
        physics.bind(joints).qpos = position

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


class ModelWrapperEntity(Entity):
    """An entity made from any MJCF model, with no observables of its own (dm_control's)."""

    def _build(self, mjcf_model: mjcf.RootElement) -> None:
        """Own `mjcf_model`; raises EntityError for anything else."""
        if not isinstance(mjcf_model, mjcf.RootElement):
            raise errors.EntityError(
                f"{type(self).__name__} needs an mjcf.RootElement, got {type(mjcf_model).__name__}"
            )
        self._mjcf_root = mjcf_model


class ModelEntity(ModelWrapperEntity):
    """An entity made from any MJCF model. Its observables, enabled, are those of its own
    elements that exist: `joint_positions` and `joint_velocities` (every joint, free joints
    included), `actuator_activations` (left out of observations when no actuator has an
    activation) and `sensors` (all sensor data). Its actuators are the action."""

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
