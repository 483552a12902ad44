"""Noises: variations that change the attribute's own value by another variation's.

    jitter = Additive(Normal(0, 0.01))                       # initial + noise
    drift = Additive(Normal(0, 0.01), cumulative=True)       # current + noise: a random walk
    heavier = Multiplicative(Uniform(0.9, 1.1))              # initial * factor
    obs.corruptor = Additive(Normal(0, 0.05))                # observation noise

The base is the initial value, or the current one with `cumulative=True`. As a corruptor
of an observable, the observation is the initial value and the environment passes its
random state by keyword (`corruptor(value, random_state=...)`), so the noise is seeded.
"""

from __future__ import annotations

from typing import Any

from composer.variation import base
from composer.variation.variation_values import evaluate


class _Noise(base.Variation):
    """The initial (or current) value combined, by the subclass's `_combine`, with what
    `variation` gives."""

    @staticmethod
    def _combine(base_value: Any, draw: Any) -> Any:
        raise NotImplementedError

    def __init__(self, variation: Any, cumulative: bool = False) -> None:
        self._variation = variation
        self._cumulative = cumulative

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """The base value combined with a new draw of the variation."""
        base_value = current_value if self._cumulative else initial_value
        draw = evaluate(self._variation, initial_value, current_value, random_state)
        return type(self)._combine(base_value, draw)

    def __eq__(self, other: object) -> bool:
        # Noises of one kind (one combination) are equal for equal variations and bases.
        if not isinstance(other, _Noise) or type(other)._combine is not type(self)._combine:
            return False
        return base.equal(self._variation, other._variation) and (
            self._cumulative == other._cumulative
        )

    def __repr__(self) -> str:
        return f"{type(self).__name__}(variation={self._variation}, cumulative={self._cumulative})"


class Additive(_Noise):
    """The initial (or current) value plus what `variation` gives."""

    @staticmethod
    def _combine(base_value: Any, draw: Any) -> Any:
        return base_value + draw

    def __init__(self, variation: Any, cumulative: bool = False) -> None:
        """Add `variation` (a variation or constant) to the initial value, or to the current
        one when `cumulative`."""
        super().__init__(variation, cumulative)


class Multiplicative(_Noise):
    """The initial (or current) value times what `variation` gives."""

    @staticmethod
    def _combine(base_value: Any, draw: Any) -> Any:
        return base_value * draw

    def __init__(self, variation: Any, cumulative: bool = False) -> None:
        """Multiply the initial value, or the current one when `cumulative`, by
        `variation` (a variation or constant)."""
        super().__init__(variation, cumulative)
