"""Robots: entities with actuators (dm_control's `composer.Robot`).

class Arm(composer.Robot):
    def _build(self):
        self._mjcf_root = mjcf.from_path('arm.xml')

    @property
    def actuators(self):
        return self._mjcf_root.find_all('actuator')
"""

from __future__ import annotations

import abc

import numpy as np

import mjcf
from composer.entity import Entity

# A quaternion (w, x, y, z) pointing a tool's z axis down, as dm_control names it.
DOWN_QUATERNION = np.array([0.0, 0.70710678118, 0.70710678118, 0.0])


class Robot(Entity, metaclass=abc.ABCMeta):
    """An entity that must say which actuators are its own."""

    @property
    @abc.abstractmethod
    def actuators(self) -> list[mjcf.Element]:
        """The actuator elements of the robot."""
