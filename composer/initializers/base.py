"""The base of initializers: objects that set part of an episode's initial state (dm_control's
`composer.Initializer`); `composer.initializers` has the ones composer ships.

    class Raise(composer.Initializer):
        def __call__(self, physics, random_state):
            physics.bind(joint).qpos = random_state.uniform(0, 1)
"""

from __future__ import annotations

import abc

import numpy as np

import mjcf


class Initializer(metaclass=abc.ABCMeta):
    """Something that sets part of the initial state; call it in `initialize_episode`."""

    @abc.abstractmethod
    def __call__(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Set the state in `physics`, drawing from `random_state`; raise
        composer.EpisodeInitializationError when no valid state was found."""
