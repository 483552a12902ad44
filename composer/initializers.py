"""Initializers: set entities' initial state each episode, e.g. random prop poses.

    placer = composer.PropPlacer(
        props=[box, ball],                                  # free entities (add_free_entity)
        position=variation.Uniform([-0.5, -0.5, 0.1], [0.5, 0.5, 0.3]),
        quaternion=None,                                    # keep the orientation
        max_attempts_per_prop=50,
    )

    def initialize_episode(self, physics, random_state):    # in a Task
        placer(physics, random_state)

`PropPlacer` draws poses by rejection sampling: a pose is kept when, after `mj_forward`,
MuJoCo reports no penetrating contact between the prop and anything but the props still
to be placed. After `max_attempts_per_prop` rejected poses it raises PlacementError naming
the prop.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

import mjcf
from composer import errors
from composer.entity import Entity
from composer.variation import evaluate


class Initializer:
    """Something that sets part of the initial state; call it in `initialize_episode`."""

    def __call__(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Set the state in `physics`, drawing from `random_state`."""
        raise NotImplementedError


class PropPlacer(Initializer):
    """Places free props at random poses where they do not penetrate anything."""

    def __init__(
        self,
        props: Sequence[Entity],
        position: Any,
        quaternion: Any = None,
        ignore_collisions: bool = False,
        max_attempts_per_prop: int = 20,
    ) -> None:
        """`position` and `quaternion` are constants or variations drawn per attempt, called
        with the prop's pose before placing as initial value (None keeps the orientation).
        Raises PlacementError for no props or attempts < 1."""
        if not props:
            raise errors.PlacementError("PropPlacer needs at least one prop")
        if max_attempts_per_prop < 1:
            raise errors.PlacementError(
                f"max_attempts_per_prop must be >= 1, got {max_attempts_per_prop!r}"
            )
        self._props = list(props)
        self._position = position
        self._quaternion = quaternion
        self._ignore_collisions = ignore_collisions
        self._max_attempts = max_attempts_per_prop

    def __call__(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Place each prop in turn. Raises PlacementError naming the prop when no pose is
        found, and EntityError for a prop without a free joint."""
        geoms = [_geom_ids(physics, prop) for prop in self._props]
        for index, prop in enumerate(self._props):
            unplaced = np.concatenate([np.zeros(0, np.intp), *geoms[index + 1 :]])
            # As dm_control: a variation gets the prop's pose before placing (a distribution
            # draws in its shape, a noise adds to it) and the last attempt's.
            initial_position, initial_quaternion = position, quaternion = prop.get_pose(physics)
            for _ in range(self._max_attempts):
                position = evaluate(self._position, initial_position, position, random_state)
                quaternion = evaluate(
                    self._quaternion, initial_quaternion, quaternion, random_state
                )
                prop.set_pose(physics, position, quaternion)
                physics.forward()
                if self._ignore_collisions or not _penetrates(physics, geoms[index], unplaced):
                    break
            else:
                raise errors.PlacementError(
                    f"PropPlacer found no pose for prop {prop.name!r} without penetration in "
                    f"{self._max_attempts} attempts (position {self._position!r}); widen the "
                    "region, or raise max_attempts_per_prop"
                )


def _geom_ids(physics: mjcf.Physics, prop: Entity) -> np.ndarray:
    found = prop.mjcf_model.find_all("geom")
    if not found:
        return np.zeros(0, np.intp)
    return np.atleast_1d(physics.bind(found).ids)


def _penetrates(physics: mjcf.Physics, own: np.ndarray, ignored: np.ndarray) -> bool:
    """Whether a contact with negative distance joins one of `own` geoms to a geom that
    is neither `own` nor `ignored`."""
    data = physics.data
    if data.ncon == 0:
        return False
    contact = data.contact
    pairs = contact.geom[contact.dist < 0]
    mine = np.isin(pairs, own)
    other = pairs[:, ::-1]
    counted = mine & ~np.isin(other, own) & ~np.isin(other, ignored)
    return bool(counted.any())
