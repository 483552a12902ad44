"""Initializers: set entities' initial state each episode (dm_control's
`composer.initializers`).

    placer = composer.initializers.PropPlacer(props=[box], position=variation.Uniform(...))
    tcp = composer.initializers.ToolCenterPointInitializer(hand=hand, arm=arm, position=...)

    def initialize_episode(self, physics, random_state):    # in a Task
        placer(physics, random_state)

`prop_initializer` and `tcp_initializer` say what each promises. An initializer that finds
no valid state raises `composer.EpisodeInitializationError`, which the environment answers
by retrying the episode (up to its `max_reset_attempts`).
"""

from composer.initializer import Initializer
from composer.initializers import prop_initializer, tcp_initializer
from composer.initializers.prop_initializer import PropPlacer
from composer.initializers.tcp_initializer import ToolCenterPointInitializer

__all__ = [
    "Initializer",
    "PropPlacer",
    "ToolCenterPointInitializer",
    "prop_initializer",
    "tcp_initializer",
]
