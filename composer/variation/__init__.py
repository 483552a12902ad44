"""Variation: values drawn anew each episode, for MJCF attributes, physics fields,
initial poses and observation noise (dm_control's `composer.variation`, module for module).

    from composer import variation
    from composer.variation import distributions, noises, rotations, colors
    size = distributions.Uniform(0.05, 0.1)                  # shaped like the attribute
    variator = variation.MJCFVariator()
    hue = distributions.Uniform(0, 1, single_sample=True)     # one number, not one per rgba
    variator.bind_attributes(geom, size=size, rgba=colors.HsvVariation(h=hue, s=0.8, v=0.9))
    variator.apply_variations(random_state)                  # in initialize_episode_mjcf
    mass = noises.Multiplicative(distributions.LogNormal(0, 0.1))   # PhysicsVariator
    observable.corruptor = noises.Additive(distributions.Normal(0, 0.01))
    quat = rotations.UniformQuaternion()                     # e.g. for PropPlacer
    value = variation.evaluate((size, [1.0, quat]), random_state=random_state)

A variation is any callable `f(initial_value=None, current_value=None, random_state=None)`
(`base.Variation` gives arithmetic: `2 * Normal() + 1`, `-v`, `v[0]`); plain values stand
for themselves. Modules, as in dm_control:
- `base`: `Variation` and the operations combining variations.
- `distributions`: `Uniform`, `UniformInteger`, `UniformChoice`, `UniformPointOnSphere`,
  `Normal`, `LogNormal`, `Exponential`, `Poisson`, `Bernoulli`, `BiasedRandomWalk`, and
  our `Choice` (weighted, returns the choice itself); all take `single_sample`.
- `noises`: `Additive`, `Multiplicative` (of the initial or current value).
- `rotations`: `UniformQuaternion`, `QuaternionFromAxisAngle`, `QuaternionPreMultiply`,
  `QuaternionRotate`, `IDENTITY_QUATERNION`.
- `colors`: `RgbVariation`, `HsvVariation`, `GrayVariation` (RGBA arrays).
- `deterministic`: `Constant`, `Sequence`, `Identity`.
- `math`: `Log`, `Max`, `Min`, `Norm` of variations (`MathOp` to add one).
- `variation_values`: `evaluate` over nested lists, tuples and dicts.
- `variation_broadcaster`: `VariationBroadcaster`, one draw shared by many users.
- `variators`: `MJCFVariator` (before compiling) and `PhysicsVariator` (after).

Randomness: every draw comes from the `random_state` passed in. The environment passes its
own (seeded by `reset(seed=...)`) to hooks, variators, initializers and corruptors, the
last by keyword (`corruptor(value, random_state=...)`) as dm_control does; a variation
called without one draws from numpy's global state, as in dm_control. Bad parameters raise
`composer.VariationError` (a ValueError), an attribute an element lacks
`VariationAttributeError` (also an AttributeError).
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
