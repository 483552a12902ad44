"""Colors: a variation per channel of a color space, giving RGBA arrays.

    RgbVariation(r=Uniform(0, 1), g=0.2, b=0.2)          # alpha 1
    HsvVariation(h=Uniform(0, 1), s=0.8, v=0.9, alpha=0.5)
    GrayVariation(Uniform(0.2, 0.8))

Channels are evaluated in order (r, g, b, alpha or h, s, v, alpha); the value is a numpy
array [r, g, b, alpha]. Each channel gets the call's arguments: to vary an `rgba` that is
already set, give a channel's distribution `single_sample=True`, or it draws four numbers
(one per element of the initial value) for one channel.
"""

from __future__ import annotations

import colorsys
from typing import Any

import numpy as np

from composer.variation import base
from composer.variation.variation_values import evaluate


class RgbVariation(base.Variation):
    """An RGBA color from a variation (or constant) per channel."""

    def __init__(self, r: Any, g: Any, b: Any, alpha: Any = 1.0) -> None:
        """Vary red, green, blue and alpha independently, each in [0, 1]."""
        self._r, self._g, self._b = r, g, b
        self._alpha = alpha

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """An array [r, g, b, alpha]."""
        channels = [self._r, self._g, self._b, self._alpha]
        return np.asarray(evaluate(channels, initial_value, current_value, random_state))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RgbVariation):
            return False
        return base.equal(
            (self._r, self._g, self._b, self._alpha), (other._r, other._g, other._b, other._alpha)
        )


class HsvVariation(base.Variation):
    """An RGBA color from a variation (or constant) per channel of hue, saturation, value
    and alpha."""

    def __init__(self, h: Any, s: Any, v: Any, alpha: Any = 1.0) -> None:
        """Vary hue, saturation, value and alpha independently, each in [0, 1]."""
        self._h, self._s, self._v = h, s, v
        self._alpha = alpha

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """An array [r, g, b, alpha] of the drawn HSV color."""
        channels = (self._h, self._s, self._v, self._alpha)
        h, s, v, alpha = evaluate(channels, initial_value, current_value, random_state)
        return np.asarray([*colorsys.hsv_to_rgb(h, s, v), alpha])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, HsvVariation):
            return False
        return base.equal(
            (self._h, self._s, self._v, self._alpha), (other._h, other._s, other._v, other._alpha)
        )

    def __repr__(self) -> str:
        return f"HsvVariation(h={self._h}, s={self._s}, v={self._v}, alpha={self._alpha})"


class GrayVariation(HsvVariation):
    """A gray RGBA color from a variation (or constant) of its level and alpha."""

    def __init__(self, gray_level: Any, alpha: Any = 1.0) -> None:
        """Vary the gray level (0 black, 1 white) and alpha."""
        super().__init__(h=0.0, s=0.0, v=gray_level, alpha=alpha)

    def __repr__(self) -> str:
        return f"GrayVariation(gray_level={self._v}, alpha={self._alpha})"
