"""Variations: values drawn anew each episode, composable with arithmetic.

    mass = Uniform(0.5, 2.0)                    # one draw per call
    color = Uniform([0, 0, 0, 1], [1, 1, 1, 1])
    offset = Normal(0, 0.01) * 2 + 1            # Variation arithmetic makes a new Variation
    height = Choice([0.1, 0.2, 0.3])
    value = evaluate(offset, random_state=random_state)   # plain values pass through

A variation is called as `variation(initial_value, current_value, random_state)`; a
distribution draws with the shape of `initial_value` (unless `single_sample=True`), else
with the broadcast shape of its parameters, which may themselves be variations. Draws use
the given random state (a numpy RandomState or Generator), numpy's global one if None.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from composer import errors


def evaluate(
    value: Any, initial_value: Any = None, current_value: Any = None, random_state: Any = None
) -> Any:
    """`value(initial_value, current_value, random_state)` for a Variation, else `value`."""
    if isinstance(value, Variation):
        return value(initial_value, current_value, random_state)
    return value


class Variation:
    """A value that varies; `+ - * / **` and unary `-` combine variations and constants."""

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """A new value, given the attribute's value at binding (initial) and now (current)."""
        raise NotImplementedError

    def _combine(self, other: Any, op: Callable[[Any, Any], Any], reverse: bool) -> Variation:
        return BinaryOperation(op, other, self) if reverse else BinaryOperation(op, self, other)

    def __add__(self, other: Any) -> Variation:
        return self._combine(other, operator.add, False)

    def __radd__(self, other: Any) -> Variation:
        return self._combine(other, operator.add, True)

    def __sub__(self, other: Any) -> Variation:
        return self._combine(other, operator.sub, False)

    def __rsub__(self, other: Any) -> Variation:
        return self._combine(other, operator.sub, True)

    def __mul__(self, other: Any) -> Variation:
        return self._combine(other, operator.mul, False)

    def __rmul__(self, other: Any) -> Variation:
        return self._combine(other, operator.mul, True)

    def __truediv__(self, other: Any) -> Variation:
        return self._combine(other, operator.truediv, False)

    def __rtruediv__(self, other: Any) -> Variation:
        return self._combine(other, operator.truediv, True)

    def __pow__(self, other: Any) -> Variation:
        return self._combine(other, operator.pow, False)

    def __neg__(self) -> Variation:
        return BinaryOperation(operator.mul, -1, self)


class BinaryOperation(Variation):
    """`op(left, right)` of two variations or constants, evaluated left first."""

    def __init__(self, op: Callable[[Any, Any], Any], left: Any, right: Any) -> None:
        """Combine `left` and `right` with `op`."""
        self.op, self.left, self.right = op, left, right

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """Evaluate both sides with the same arguments, then apply the operation."""
        left = evaluate(self.left, initial_value, current_value, random_state)
        right = evaluate(self.right, initial_value, current_value, random_state)
        return self.op(np.asarray(left), np.asarray(right))


class Distribution(Variation):
    """A random variation; subclasses implement `_sample(random_state, size, *params)`."""

    def __init__(self, *params: Any, single_sample: bool = False) -> None:
        """Parameters (constants or variations); `single_sample` draws one value even when
        the initial value is an array."""
        self._params = params
        self._single_sample = single_sample

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """A draw shaped like `initial_value` (see the module docstring)."""
        if random_state is None:
            random_state = np.random.mtrand._rand
        params = [evaluate(p, initial_value, current_value, random_state) for p in self._params]
        size = None if self._single_sample or initial_value is None else np.shape(initial_value)
        try:
            return self._sample(random_state, size, *params)
        except ValueError as e:
            raise errors.VariationError(
                f"{type(self).__name__}{tuple(params)} cannot draw shape {size}: {e}"
            ) from e

    def _sample(self, random_state: Any, size: Any, *params: Any) -> Any:
        raise NotImplementedError


class Uniform(Distribution):
    """Uniform on [low, high)."""

    def __init__(self, low: Any = 0.0, high: Any = 1.0, single_sample: bool = False) -> None:
        """Draw uniformly between `low` and `high` (broadcast)."""
        super().__init__(low, high, single_sample=single_sample)

    def _sample(self, random_state: Any, size: Any, low: Any, high: Any) -> Any:
        return random_state.uniform(low, high, size=size)


class Normal(Distribution):
    """Normal of mean `loc` and standard deviation `scale`."""

    def __init__(self, loc: Any = 0.0, scale: Any = 1.0, single_sample: bool = False) -> None:
        """Draw from N(loc, scale**2)."""
        super().__init__(loc, scale, single_sample=single_sample)

    def _sample(self, random_state: Any, size: Any, loc: Any, scale: Any) -> Any:
        return random_state.normal(loc, scale, size=size)


class LogNormal(Distribution):
    """exp(N(mean, sigma**2)): positive, e.g. for masses and frictions."""

    def __init__(self, mean: Any = 0.0, sigma: Any = 1.0, single_sample: bool = False) -> None:
        """Draw exp of a normal of `mean` and standard deviation `sigma`."""
        super().__init__(mean, sigma, single_sample=single_sample)

    def _sample(self, random_state: Any, size: Any, mean: Any, sigma: Any) -> Any:
        return random_state.lognormal(mean, sigma, size=size)


class Bernoulli(Distribution):
    """True with probability `prob`, as bools."""

    def __init__(self, prob: Any = 0.5, single_sample: bool = False) -> None:
        """Draw True with probability `prob`."""
        super().__init__(prob, single_sample=single_sample)

    def _sample(self, random_state: Any, size: Any, prob: Any) -> Any:
        if size is None:
            size = np.shape(prob)
        return random_state.uniform(size=size) < prob


class Choice(Distribution):
    """One of `choices` (a sequence of values), uniformly or with probabilities `p`."""

    def __init__(
        self, choices: Sequence[Any], p: Sequence[float] | None = None, single_sample: bool = True
    ) -> None:
        """Pick among `choices`; one pick per call unless `single_sample=False`, which picks
        one per element of the initial value. Raises VariationError for no choices."""
        if len(choices) == 0:
            raise errors.VariationError("Choice needs at least one choice")
        super().__init__(single_sample=single_sample)
        self._choices = list(choices)
        self._p = p

    def _sample(self, random_state: Any, size: Any) -> Any:
        index = random_state.choice(len(self._choices), size=size, p=self._p)
        if size is None:
            return self._choices[int(index)]
        return np.asarray(self._choices)[index]
