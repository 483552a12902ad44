"""Variation: per-episode randomization of MJCF attributes and physics fields.

    from composer import variation
    size = variation.Uniform(0.05, 0.1)
    variator = variation.MJCFVariator()
    variator.bind_attributes(geom, size=size)
    variator.apply_variations(random_state)      # in initialize_episode_mjcf

See `distributions` for the distributions and their arithmetic, `variators` for applying
them before (`MJCFVariator`) or after (`PhysicsVariator`) compiling.
"""

from composer.variation.distributions import (
    Bernoulli,
    BinaryOperation,
    Choice,
    Distribution,
    LogNormal,
    Normal,
    Uniform,
    Variation,
    evaluate,
)
from composer.variation.variators import MJCFVariator, PhysicsVariator

__all__ = [
    "Bernoulli",
    "BinaryOperation",
    "Choice",
    "Distribution",
    "LogNormal",
    "MJCFVariator",
    "Normal",
    "PhysicsVariator",
    "Uniform",
    "Variation",
    "evaluate",
]
