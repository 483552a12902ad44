"""The convolutional encoder of the pixel recipes: frames in, a feature vector out, under
stable-baselines3's policy and value heads.

    policy_kwargs = encoder.policy_kwargs(recipe)      # for PPO('CnnPolicy', ...)
    PixelEncoder(space, conv=((16, 4, 4), (32, 3, 2), (32, 3, 1)), features=128)

Promise: the encoder's settings are kept as plain JSON (`SETTINGS_KEY`); settings that leave
nothing of a frame, or make too many values of one, raise ValueError. This module imports
stable-baselines3 and torch (the [train] extra).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn

from composer.cli import recipes

# The key of a model's .zip `data` (and the model attribute) holding the encoder's
# settings: {'conv': [[channels, kernel, stride], ...], 'features': n}. Plain JSON, so
# loading a policy file needs no pickled class (`composer.cli.engines.sb3.policy`).
SETTINGS_KEY = "pixel_encoder"
# The most values one conv layer may make of a frame (the default stack's first: 4,096).
MAX_LAYER_VALUES = 1 << 22


class PixelEncoder(BaseFeaturesExtractor):
    """Strided convolutions and a linear layer over channels-first frames scaled to [0, 1].

    stable-baselines3's `CnnPolicy` takes frames channels first (its `VecTransposeImage`
    turns Gymnasium's (height, width, channels) around) and scales them to [0, 1]; the
    encoder is then `conv` layers ((out channels, kernel, stride) each, no padding, ReLU
    after each) and a linear layer of `features` units with a ReLU. Its default, for 64x64
    frames with 3 stacked (9 channels): 16 4x4 filters at stride 4 (non-overlapping
    patches: 16x16x16), 32 3x3 at stride 2 (7x7x32), 32 3x3 (5x5x32), 128 features: smaller
    than stable-baselines3's NatureCNN (the Atari network: 32-64-64 filters, 512 features;
    docs/performance_profile.md compares their costs). Atari's and dm_control's pixel
    agents use such stacks of strided convolutions.
    """

    def __init__(
        self,
        observation_space: gymnasium.spaces.Box,
        conv: Sequence[Sequence[int]] = recipes.Recipe.conv,
        features: int = recipes.Recipe.features,
    ) -> None:
        """Encode observations of `observation_space` (channels, height, width). Raises
        ValueError when the layers leave nothing of a frame that size, or make more than
        MAX_LAYER_VALUES values of one frame (a policy file's settings could ask for
        gigabytes a frame)."""
        super().__init__(observation_space, features)
        channels, height, width = observation_space.shape
        layers: list[nn.Module] = []
        for out, kernel, stride in conv:
            height, width = (height - kernel) // stride + 1, (width - kernel) // stride + 1
            if height < 1 or width < 1:
                raise ValueError(
                    f"conv layers {list(conv)} do not fit frames of shape "
                    f"{observation_space.shape} (channels first)"
                )
            if out * height * width > MAX_LAYER_VALUES:
                raise ValueError(
                    f"conv layer {[out, kernel, stride]} makes {out * height * width:,} values "
                    f"of a frame, more than {MAX_LAYER_VALUES:,}"
                )
            layers += [nn.Conv2d(channels, out, kernel, stride), nn.ReLU()]
            channels = out
        self.conv = nn.Sequential(*layers, nn.Flatten())
        size = channels * height * width
        self.linear = nn.Sequential(nn.Linear(size, features), nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        """The features of a batch of frames."""
        return self.linear(self.conv(observations))


def settings(recipe: recipes.Recipe) -> dict[str, Any]:
    """The encoder's keywords for `recipe`, plain JSON (what SETTINGS_KEY keeps)."""
    return {"conv": [list(layer) for layer in recipe.conv], "features": recipe.features}


def policy_kwargs(recipe: recipes.Recipe) -> dict[str, Any]:
    """stable-baselines3's policy keywords of a pixel `recipe`: the encoder under the
    recipe's `net` heads."""
    return {
        "net_arch": list(recipe.net),
        "features_extractor_class": PixelEncoder,
        "features_extractor_kwargs": settings(recipe),
    }
