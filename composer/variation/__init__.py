"""Variation: values drawn anew each episode, for MJCF attributes, physics fields, initial
poses and observation noise (dm_control's `composer.variation`, module for module).

    variator = variation.MJCFVariator()                      # `variators` shows one in full
    variator.bind_attributes(geom, size=distributions.Uniform(0.05, 0.1))
    variator.apply_variations(random_state)                  # in initialize_episode_mjcf

Every draw comes from the `random_state` passed in (numpy's global one without, as in
dm_control). Bad parameters raise `composer.VariationError` (a ValueError), an attribute an
element lacks `VariationAttributeError` (an AttributeError too).
"""

from composer.variation import (
    base,
    colors,
    deterministic,
    distributions,
    math,
    noises,
    rotations,
    variation_broadcaster,
    variation_values,
)
from composer.variation.base import BinaryOperation, Variation
from composer.variation.distributions import (
    Bernoulli,
    Choice,
    Distribution,
    LogNormal,
    Normal,
    Uniform,
)
from composer.variation.variation_values import evaluate
from composer.variation.variators import MJCFVariator, PhysicsVariator, VariationAttributeError

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
    "VariationAttributeError",
    "base",
    "colors",
    "deterministic",
    "distributions",
    "evaluate",
    "math",
    "noises",
    "rotations",
    "variation_broadcaster",
    "variation_values",
]
