"""Batched over n environments: dm_control's `Physics` helpers of manipulator and stacker.

    bounded_joint_positions(physics, arm.joints)     # (n, 8, 2): sin, cos of each angle
    observed_2d_pose(hand)                           # observable (n, 4): x, z, qw, qy
    site_distances(physics, ball_site, target_site)  # (n,): the distance between two sites
    SiteDistances([(a, b), (c, d)])(physics)         # (n, 2): several pairs' at once
    randomize_arm(physics, arm, random_state)        # a random pose, the hand symmetric

The scene lies in the x-z plane. Distances are `np.linalg.norm` of the difference, as
dm_control's (`tasks.rewards.squared_norms` sums the squares as its dot does).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import composer
import mjcf
from entities.suite.planar_arm import ARM_JOINTS, PlanarArm
from tasks.rewards import squared_norms
from tasks.suite.observables import BoundField, Concatenated


def bounded_joint_positions(
    physics: composer.BatchPhysics, joints: Sequence[mjcf.Element]
) -> np.ndarray:
    """The sine and cosine of each hinge's angle: (n, joints, 2)."""
    angles = physics.bind(joints).qpos
    bounded = np.empty((*angles.shape, 2))
    np.sin(angles, out=bounded[..., 0])
    np.cos(angles, out=bounded[..., 1])
    return bounded


def observed_2d_pose(
    bodies: mjcf.Element | Sequence[mjcf.Element], orientation: bool = True
) -> Concatenated | BoundField:
    """Each body's x and z, then (with `orientation`) its quaternion's w and y, as an
    observable read together with the task's other bound fields by one environment: (n, 4)
    for one body, (n, bodies, 4) for a sequence; x and z alone without `orientation`."""
    one = isinstance(bodies, mjcf.Element)
    every_other = slice(None, None, 2) if one else (slice(None), slice(None, None, 2))
    positions = BoundField("xpos", bodies, index=every_other)  # x and z
    if not orientation:
        return positions
    return Concatenated([positions, BoundField("xquat", bodies, index=every_other)])  # w, y


def site_distances(
    physics: composer.BatchPhysics, first: mjcf.Element, second: mjcf.Element
) -> np.ndarray:
    """The distance between two sites in each environment: (n,)."""
    positions = physics.bind([second, first]).xpos  # (n, 2, 3)
    return np.sqrt(squared_norms(positions[:, 1] - positions[:, 0]))


class SiteDistances:
    """The distances of several pairs of sites, read and computed together (a reward's
    four distances cost what one does apart): each column `site_distances` of its pair,
    to the last bit."""

    def __init__(self, pairs: Sequence[tuple[mjcf.Element, mjcf.Element]]) -> None:
        """Measure each (first, second) of `pairs`."""
        sites = list(dict.fromkeys(site for pair in pairs for site in pair))
        self._sites = tuple(sites)
        self._firsts = np.array([sites.index(first) for first, _ in pairs])
        self._seconds = np.array([sites.index(second) for _, second in pairs])

    def __call__(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The distance of each pair in each environment: (n, pairs)."""
        positions = physics.bind(self._sites).xpos  # (n, sites, 3)
        offsets = positions.take(self._firsts, axis=1) - positions.take(self._seconds, axis=1)
        return np.sqrt(squared_norms(offsets))


def randomize_arm(
    physics: mjcf.Physics, arm: PlanarArm, random_state: np.random.RandomState
) -> None:
    """dm_control's draw of the arm's pose (one `uniform` of the eight angles, within each
    joint's range, [-pi, pi] where unlimited), the finger then set to the thumb's angle
    so that the hand opens symmetrically."""
    joints = physics.bind(arm.joints)
    limited = joints.limited.astype(bool)
    ranges = joints.range
    lower = np.where(limited, ranges[:, 0], -np.pi)
    upper = np.where(limited, ranges[:, 1], np.pi)
    joints.qpos = random_state.uniform(lower, upper)
    finger = physics.bind(arm.joints[ARM_JOINTS.index("finger")])
    finger.qpos = physics.bind(arm.joints[ARM_JOINTS.index("thumb")]).qpos
