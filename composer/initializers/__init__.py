"""Initializers: set entities' initial state each episode (dm_control's `composer.initializers`).

    placer = composer.initializers.PropPlacer(props=[box], position=variation.Uniform(...))
    tcp = composer.initializers.ToolCenterPointInitializer(hand=hand, arm=arm, position=...)
    def initialize_episode(self, physics, random_state):    # in a Task
        placer(physics, random_state)

`PropPlacer` and `ToolCenterPointInitializer` state their promises. An initializer finding
no valid state raises `composer.EpisodeInitializationError`, which the environment answers
by retrying the episode (up to its `max_reset_attempts`).
"""

import importlib
from typing import TYPE_CHECKING

from composer.initializers.base import Initializer

if TYPE_CHECKING:
    from composer.initializers import prop_initializer, tcp_initializer
    from composer.initializers.prop_initializer import PropPlacer
    from composer.initializers.tcp_initializer import ToolCenterPointInitializer

# The initializers composer ships, imported when first used (they need `composer.variation`).
_ON_DEMAND = {
    "prop_initializer": ("composer.initializers.prop_initializer", None),
    "PropPlacer": ("composer.initializers.prop_initializer", "PropPlacer"),
    "tcp_initializer": ("composer.initializers.tcp_initializer", None),
    "ToolCenterPointInitializer": (
        "composer.initializers.tcp_initializer",
        "ToolCenterPointInitializer",
    ),
}

__all__ = [
    "Initializer",
    "PropPlacer",
    "ToolCenterPointInitializer",
    "prop_initializer",
    "tcp_initializer",
]


def __getattr__(name: str) -> object:
    """The names of `_ON_DEMAND`, importing their module when first asked for."""
    found = _ON_DEMAND.get(name)
    if found is None:
        raise AttributeError(f"module 'composer.initializers' has no attribute {name!r}")
    module = importlib.import_module(found[0])
    return module if found[1] is None else getattr(module, found[1])


def __dir__() -> list[str]:
    return sorted({*globals(), *_ON_DEMAND})
