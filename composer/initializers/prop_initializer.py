"""PropPlacer: props at random poses where they collide with nothing, optionally settled.

    placer = composer.initializers.PropPlacer(
        props=[box, ball],                                  # free entities (add_free_entity)
        position=variation.Uniform([-0.5, -0.5, 0.1], [0.5, 0.5, 0.3]),
        settle_physics=True)                                # let them come to rest
    placer(physics, random_state)                           # in a Task's initialize_episode

Promise: dm_control's rejection sampling (`PropPlacer` says how); no valid pose raises
PlacementError (an EpisodeInitializationError); every prop's contacts are back on return.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

import numpy as np

import mjcf
from composer import errors
from composer.entity import Entity
from composer.initializers.base import Initializer
from composer.variation import evaluate

_LOG = logging.getLogger(__name__)

IDENTITY_QUATERNION = np.array([1.0, 0.0, 0.0, 0.0])
_SETTLE_QVEL_TOL = 1e-3
_SETTLE_QACC_TOL = 1e-2

_REJECTION_SAMPLING_FAILED = (
    "PropPlacer found no pose for prop {model_name!r} without collisions in {max_attempts} "
    "attempts: widen the position or quaternion distribution, raise max_attempts_per_prop, "
    "or pass ignore_collisions=True"
)
_SETTLING_PHYSICS_FAILED = (
    "PropPlacer: the props did not settle within {max_time} s in {max_attempts} attempts "
    "(last largest |qvel| {max_qvel}, |qacc| {max_qacc}); raise max_settle_physics_attempts "
    "or max_settle_physics_time, or tune the contacts or the pose distributions"
)


class PropPlacer(Initializer):
    """Places props at random poses where they collide with nothing.

    Rejection sampling, as dm_control's: the props' contacts are switched off, then each prop
    in turn gets its contacts back and draws poses until, after `mj_forward`, no contact with a
    distance <= 0 involves it (contacts with props still to be placed, and with
    `ignore_contacts_with_entities`, cannot happen: theirs are off). After
    `max_attempts_per_prop` draws it raises PlacementError (an EpisodeInitializationError,
    so the environment retries the episode). Every prop's contacts are back when the call
    returns, whether it succeeded or not. With `settle_physics`, the simulation then runs (the
    other joints held still) until the props' joints move slower than the tolerances, up to
    `max_settle_physics_time` seconds, placing again up to `max_settle_physics_attempts`
    times; the physics time is restored afterwards.
    """

    def __init__(
        self,
        props: Sequence[Entity],
        position: Any,
        quaternion: Any = IDENTITY_QUATERNION,
        ignore_collisions: bool = False,
        max_qvel_tol: float = _SETTLE_QVEL_TOL,
        max_qacc_tol: float = _SETTLE_QACC_TOL,
        max_attempts_per_prop: int = 20,
        settle_physics: bool = False,
        min_settle_physics_time: float = 0.0,
        max_settle_physics_time: float = 2.0,
        max_settle_physics_attempts: int = 1,
        raise_exception_on_settle_failure: bool = False,
    ) -> None:
        """`position` and `quaternion` are constants or variations drawn per attempt
        (None keeps that part of the pose). Raises InitializerError (a ValueError) for no
        props, or attempts below 1."""
        if not props:
            raise errors.InitializerError("PropPlacer needs at least one prop")
        for label, value in (
            ("max_attempts_per_prop", max_attempts_per_prop),
            ("max_settle_physics_attempts", max_settle_physics_attempts),
        ):
            if value < 1:
                raise errors.InitializerError(f"{label} must be >= 1, got {value!r}")
        self._props = list(props)
        self._position = position
        self._quaternion = quaternion
        self._ignore_collisions = ignore_collisions
        self._max_attempts = max_attempts_per_prop
        self._settle_physics = settle_physics
        self._max_qvel_tol = max_qvel_tol
        self._max_qacc_tol = max_qacc_tol
        self._min_settle_time = min_settle_physics_time
        self._max_settle_time = max_settle_physics_time
        self._max_settle_attempts = max_settle_physics_attempts
        self._raise_on_settle_failure = raise_exception_on_settle_failure

    def __call__(
        self,
        physics: mjcf.Physics,
        random_state: np.random.RandomState,
        ignore_contacts_with_entities: Sequence[Entity] | None = None,
    ) -> None:
        """Place (and settle) the props. Raises PlacementError naming the prop when no pose
        is found, or when settling fails with `raise_exception_on_settle_failure`."""
        ignored = list(ignore_contacts_with_entities or [])
        switches = {id(e): _ContactSwitch(physics, e) for e in [*self._props, *ignored]}
        try:
            for switch in switches.values():
                switch.off()
            physics.forward()
            if self._settle_physics:
                self._place_and_settle(physics, random_state, switches)
            else:
                self._place(physics, random_state, switches)
        finally:
            for switch in switches.values():
                switch.on()

    def _place(
        self, physics: mjcf.Physics, random_state: np.random.RandomState, switches: dict
    ) -> None:
        for prop in self._props:
            switch = switches[id(prop)]
            switch.on()
            initial_position, initial_quaternion = prop.get_pose(physics)
            position, quaternion = initial_position, initial_quaternion
            for _ in range(self._max_attempts):
                position = evaluate(
                    self._position, initial_value=initial_position, current_value=position,
                    random_state=random_state,
                )  # fmt: skip
                quaternion = evaluate(
                    self._quaternion, initial_value=initial_quaternion,
                    current_value=quaternion, random_state=random_state,
                )  # fmt: skip
                prop.set_pose(physics, position, quaternion)
                physics.forward()
                if self._ignore_collisions or not switch.collides():
                    break
            else:
                raise errors.PlacementError(
                    _REJECTION_SAMPLING_FAILED.format(
                        model_name=prop.mjcf_model.model, max_attempts=self._max_attempts
                    )
                )

    def _place_and_settle(
        self, physics: mjcf.Physics, random_state: np.random.RandomState, switches: dict
    ) -> None:
        joints = _prop_joints(self._props)
        moving = physics.bind(joints)
        held = _HeldJoints(physics, self._props[0].mjcf_model.root_model, joints)
        max_qvel = max_qacc = np.inf
        for _ in range(self._max_settle_attempts):
            self._place(physics, random_state, switches)
            for switch in switches.values():
                switch.on()
            start = physics.data.time
            try:
                while physics.data.time - start < self._max_settle_time:
                    physics.step()
                    held.restore()
                    max_qvel = float(np.max(np.abs(moving.qvel), initial=0.0))
                    max_qacc = float(np.max(np.abs(moving.qacc), initial=0.0))
                    settled = max_qvel < self._max_qvel_tol and max_qacc < self._max_qacc_tol
                    if settled and physics.data.time - start > self._min_settle_time:
                        return
            finally:
                physics.data.time = start
        message = _SETTLING_PHYSICS_FAILED.format(
            max_attempts=self._max_settle_attempts, max_time=self._max_settle_time,
            max_qvel=max_qvel, max_qacc=max_qacc,
        )  # fmt: skip
        if self._raise_on_settle_failure:
            raise errors.PlacementError(message)
        _LOG.warning(message)


def _prop_joints(props: Sequence[Entity]) -> list[mjcf.Element]:
    """Every joint that moves the props: their free joints and their own joints."""
    found: list[mjcf.Element] = []
    for prop in props:
        free = mjcf.get_frame_freejoint(prop.mjcf_model)
        if free is not None:
            found.append(free)
        found.extend(prop.mjcf_model.find_all("joint"))
    return found


class _HeldJoints:
    """The joints of the scene other than `moving`, put back where they were when this
    was made after each physics step (dm_control's JointStaticIsolator)."""

    def __init__(
        self, physics: mjcf.Physics, scene: mjcf.RootElement, moving: list[mjcf.Element]
    ) -> None:
        kept = set(moving)
        others = [joint for joint in scene.find_all("joint") if joint not in kept]
        self._binding = physics.bind(others) if others else None
        if self._binding is not None:
            self._qpos = np.array(self._binding.qpos)
            self._qvel = np.array(self._binding.qvel)

    def restore(self) -> None:
        """Put the held joints back."""
        if self._binding is not None:
            self._binding.qpos = self._qpos
            self._binding.qvel = self._qvel


class _ContactSwitch:
    """One entity's geoms' contype and conaffinity: switched off and back on."""

    def __init__(self, physics: mjcf.Physics, entity: Entity) -> None:
        geoms = entity.mjcf_model.find_all("geom")
        self._physics = physics
        self._binding = physics.bind(geoms) if geoms else None
        self._ids = np.zeros(0, np.intp)
        if self._binding is not None:
            self._ids = np.atleast_1d(self._binding.element_id)
            self._contype = np.array(self._binding.contype)
            self._conaffinity = np.array(self._binding.conaffinity)
        self._off = False

    def off(self) -> None:
        """No contacts for the entity's geoms."""
        if self._binding is not None and not self._off:
            self._binding.contype = 0
            self._binding.conaffinity = 0
        self._off = True

    def on(self) -> None:
        """The entity's geoms' own contact settings back."""
        if self._binding is not None and self._off:
            self._binding.contype = self._contype
            self._binding.conaffinity = self._conaffinity
        self._off = False

    def collides(self) -> bool:
        """Whether a contact at distance <= 0 involves one of the entity's geoms."""
        data = self._physics.data
        if data.ncon == 0 or not self._ids.size:
            return False
        contact = data.contact
        touching = contact.dist <= 0
        involved = np.isin(contact.geom1, self._ids) | np.isin(contact.geom2, self._ids)
        return bool(np.any(touching & involved))
