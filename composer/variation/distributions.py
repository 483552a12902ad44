"""Distributions: variations that draw from a numpy random state.

    size = Uniform(0.05, 0.1)                      # shaped like the varied attribute
    count = UniformInteger(1, 5)                   # 1 to 4
    angle = Normal(0, 0.1, single_sample=True)     # one number, whatever the attribute
    value = size(initial_value=[0.1, 0.2], random_state=random_state)   # two draws

Promise: a seeded `numpy.random.RandomState` gives exactly dm_control's draws (`Distribution`
says how); parameters numpy refuses raise `composer.VariationError` naming them.
"""

from __future__ import annotations

import abc
import functools
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from composer import errors
from composer.variation import base
from composer.variation.variation_values import evaluate

_NEGATIVE_STDEV = "`stdev` must be >= 0, got {}."
_NEGATIVE_TIMESCALE = "`timescale` must be >= 0, got {}."


class Distribution(base.Variation, metaclass=abc.ABCMeta):
    """A parametrized distribution; parameters are constants or variations.

    A distribution called with an `initial_value` draws an array of its shape, unless
    `single_sample=True`; without one, it draws the broadcast shape of its parameters.
    Parameters may themselves be variations, evaluated first (keywords by sorted name, as
    dm_control does). Each draw is one call of the random state's method of the same name
    (`uniform`, `randint`, `choice`, `normal` ...), so a seeded `numpy.random.RandomState`
    gives exactly the values dm_control gives; a `numpy.random.Generator` works too. Called
    without a random state, a distribution draws from numpy's global one, as dm_control's do:
    the environment always passes its own (`composer.Environment.random_state`).
    Parameters numpy refuses raise `composer.VariationError` (a ValueError) naming them.

    Subclasses implement `_callable(random_state)`, returning the function called as
    `f(*args, size=size, **kwargs)` with the evaluated constructor parameters.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Keep the parameters (`single_sample=True` draws one value whatever the shape of
        the initial value)."""
        self._single_sample = bool(kwargs.pop("single_sample", False))
        self._args = args
        self._kwargs = kwargs

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """A draw (see the class docstring); raises VariationError for parameters numpy
        refuses."""
        size = None if self._single_sample or initial_value is None else np.shape(initial_value)
        args = evaluate(self._args, initial_value, current_value, random_state)
        kwargs = evaluate(self._kwargs, initial_value, current_value, random_state)
        try:
            return self._callable(base.random_state_or_global(random_state))(
                *args, size=size, **kwargs
            )
        except ValueError as e:
            raise errors.VariationError(
                f"{type(self).__name__}(args={args}, kwargs={kwargs}) cannot draw "
                f"{'one value' if size is None else f'shape {size}'}: {e}"
            ) from e

    @abc.abstractmethod
    def _callable(self, random_state: Any) -> Callable[..., Any]:
        """The function drawing from `random_state`, called with the parameters."""

    def __getattr__(self, name: str) -> Any:
        # Keyword parameters read as attributes (`Uniform(...).high`), as in dm_control.
        # Private names never reach the parameters: copy and pickle look for them on
        # instances whose parameters are not set yet.
        if not name.startswith("_") and name in self.__dict__.get("_kwargs", {}):
            return self._kwargs[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, type(self)):
            return False
        return (
            base.equal(self._args, other._args)
            and base.equal(self._kwargs, other._kwargs)
            and self._single_sample == other._single_sample
        )

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(args={self._args}, kwargs={self._kwargs}, "
            f"single_sample={self._single_sample})"
        )


class Uniform(Distribution):
    """Uniform on [low, high)."""

    def __init__(self, low: Any = 0.0, high: Any = 1.0, single_sample: bool = False) -> None:
        """Draw between `low` and `high` (broadcast)."""
        super().__init__(low=low, high=high, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.uniform


class UniformInteger(Distribution):
    """Integers uniform on [low, high), or on [0, low) without `high`."""

    def __init__(self, low: Any, high: Any = None, single_sample: bool = False) -> None:
        """Draw integers from `low` (inclusive) to `high` (exclusive)."""
        super().__init__(low, high=high, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        if isinstance(random_state, np.random.Generator):  # RandomState.randint's twin
            return random_state.integers
        return random_state.randint


class UniformChoice(Distribution):
    """One of `choices`, each equally likely (numpy's `choice`: numpy scalars)."""

    def __init__(self, choices: Any, single_sample: bool = False) -> None:
        """Pick among `choices` (a sequence or array)."""
        super().__init__(choices, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.choice


class _Choices:
    """Choices kept as given: `evaluate` treats this as one value, so a choice comes back
    itself, not a copy with its variations evaluated."""

    def __init__(self, choices: Sequence[Any]) -> None:
        self.choices = list(choices)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Choices) and base.equal(self.choices, other.choices)

    def __repr__(self) -> str:
        return repr(self.choices)


class Choice(Distribution):
    """One of `choices`, itself (not a numpy copy), uniformly or with probabilities `p`;
    one pick per call unless `single_sample=False` (then an array shaped like the initial
    value). Draws as `UniformChoice` does for the same random state when `p` is None."""

    def __init__(
        self, choices: Sequence[Any], p: Sequence[float] | None = None, single_sample: bool = True
    ) -> None:
        """Pick among `choices`; raises VariationError for no choices."""
        if len(choices) == 0:
            raise errors.VariationError("Choice needs at least one choice")
        super().__init__(_Choices(choices), p=p, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        def pick(kept: _Choices, size: Any = None, p: Any = None) -> Any:
            choices = kept.choices
            index = random_state.choice(len(choices), size=size, p=p)
            return choices[int(index)] if size is None else np.asarray(choices)[index]

        return pick


class UniformPointOnSphere(base.Variation):
    """Points on the unit sphere (3-vectors of norm 1), uniformly; one per element of the
    initial value (shape (*initial.shape, 3)) unless `single_sample`."""

    def __init__(self, single_sample: bool = False) -> None:
        """Draw one point, or one per element of the initial value."""
        self._single_sample = single_sample

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """Normalized standard normal 3-vectors."""
        if self._single_sample or initial_value is None:
            size: Any = 3
        else:
            size = np.append(np.shape(initial_value), 3)
        axis = base.random_state_or_global(random_state).normal(size=size)
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        return axis

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, UniformPointOnSphere):
            return False
        return self._single_sample == other._single_sample

    def __repr__(self) -> str:
        return f"{type(self).__name__}(single_sample={self._single_sample})"


class Normal(Distribution):
    """Normal of mean `loc` and standard deviation `scale`."""

    def __init__(self, loc: Any = 0.0, scale: Any = 1.0, single_sample: bool = False) -> None:
        """Draw from N(loc, scale**2)."""
        super().__init__(loc=loc, scale=scale, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.normal


class LogNormal(Distribution):
    """exp(N(mean, sigma**2)): positive, e.g. for masses and frictions."""

    def __init__(self, mean: Any = 0.0, sigma: Any = 1.0, single_sample: bool = False) -> None:
        """Draw exp of a normal of `mean` and standard deviation `sigma`."""
        super().__init__(mean=mean, sigma=sigma, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.lognormal


class Exponential(Distribution):
    """Exponential of mean `scale`."""

    def __init__(self, scale: Any = 1.0, single_sample: bool = False) -> None:
        """Draw from the exponential distribution of mean `scale`."""
        super().__init__(scale=scale, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.exponential


class Poisson(Distribution):
    """Poisson of rate `lam` (integers)."""

    def __init__(self, lam: Any = 1.0, single_sample: bool = False) -> None:
        """Draw counts of mean `lam`."""
        super().__init__(lam=lam, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return random_state.poisson


class Bernoulli(Distribution):
    """1 with probability `prob`, else 0 (integers, numpy's `binomial(1, prob)`)."""

    def __init__(self, prob: Any = 0.5, single_sample: bool = False) -> None:
        """Draw 1 with probability `prob`."""
        super().__init__(prob, single_sample=single_sample)

    def _callable(self, random_state: Any) -> Callable[..., Any]:
        return functools.partial(random_state.binomial, 1)


class BiasedRandomWalk(base.Variation):
    """Zero-mean Ornstein-Uhlenbeck noise: each call moves the last value by
    `x = retain * x + N(0, scale)`, with `retain = exp(-1 / timescale)` and
    `scale = stdev * sqrt(1 - retain**2)`, so the values have standard deviation `stdev`
    and lose correlation by exp(-1) every `timescale` calls (`timescale=0`: independent
    normal draws). It keeps state: one instance is one walk."""

    def __init__(self, stdev: float = 0.1, timescale: float = 10.0) -> None:
        """Raises VariationError (a ValueError) for a negative `stdev` or `timescale`."""
        if stdev < 0:
            raise errors.VariationError(_NEGATIVE_STDEV.format(stdev))
        if timescale < 0:
            raise errors.VariationError(_NEGATIVE_TIMESCALE.format(timescale))
        self._retain = 0.0 if timescale == 0 else float(np.exp(-1.0 / timescale))
        self._scale = stdev * np.sqrt(1 - self._retain * self._retain)
        self._value = 0.0

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The walk's next value."""
        step = base.random_state_or_global(random_state).normal(loc=0.0, scale=self._scale)
        self._value = self._retain * self._value + step
        return self._value

    def __eq__(self, other: object) -> bool:
        return self is other  # stateful: two walks are never the same

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(id={id(self)}, scale={self._scale}, "
            f"retain={self._retain}, value={self._value})"
        )
