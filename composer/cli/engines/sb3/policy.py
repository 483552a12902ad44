"""A stable-baselines3 policy file loaded for `composer run`, `eval` and `view`, by default
without running code from it.

    policy = sb3.policy.load_policy(Path('runs/Reach-ppo/policy.zip'), env)
    action, _ = policy.predict(observation, deterministic=True)   # a files.NormalizedPolicy

Promise: without `--trust-policy` only plain data and tensors are read (`plain_policy`), and
`predict` gives the model's own actions; a file whose needed parts are pickles raises
UntrustedPolicyError. This module imports stable-baselines3 and torch (the [train] extra).
"""

from __future__ import annotations

import io
import pickle
import types
import warnings
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import stable_baselines3
import torch
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.vec_env import VecTransposeImage

from composer.cli.engines import base, untrusted
from composer.cli.engines.sb3 import encoder, files
from composer.cli.engines.sb3.files import NORMALIZATION, NormalizedPolicy
from composer.cli.errors import PolicyError, UntrustedPolicyError

ALGORITHMS: dict[str, type[BaseAlgorithm]] = {
    "ppo": stable_baselines3.PPO,
    "sac": stable_baselines3.SAC,
}
# How stable-baselines3 marks a value of `data` that it pickled.
_PICKLED = ":serialized:"
# What of a pixel policy's `policy_kwargs` is pickled: the encoder's class, and the whole
# dict (beside its JSON-readable items) because of it.
_ENCODER_PICKLES = (_PICKLED, ":type:", "features_extractor_class")

torch.set_num_threads(base.TORCH_THREADS)


def load_policy(file: Path, env: gymnasium.Env, trusted: bool = False) -> NormalizedPolicy:
    """The policy in the stable-baselines3 .zip `file`, checked to fit `env`'s spaces,
    served with its observation statistics. Only its weights and plain settings are read
    (`plain_policy`), unless `trusted`: then the library's own loader reads it whole,
    unpickling and so running code from the file. Raises PolicyError, and
    UntrustedPolicyError when the file can only be read whole."""
    algorithm = ALGORITHMS[files.algo_of(file)]
    if not trusted:
        return plain_policy(file, algorithm, env)
    model = algorithm.load(file, device="cpu")
    base.check_spaces(file, model, env)
    return NormalizedPolicy(model, getattr(model, NORMALIZATION, None))


def plain_policy(
    file: Path, algorithm: type[BaseAlgorithm], env: gymnasium.Env
) -> NormalizedPolicy:
    """The policy saved in the stable-baselines3 .zip `file` by `algorithm`, for `env`:
    built from the file's plain settings and its weights, served with its observation
    statistics when it has them. Every part is checked before use (`untrusted`): the file
    is unpacked within mjcf.archives' limits, and the network built may hold no more
    numbers than its weights. Raises PolicyError for a file that cannot be read, is
    malformed or does not fit `env`, UntrustedPolicyError when what it needs is pickled.

    A stable-baselines3 .zip holds `data` (JSON, where every value that is not plain JSON is a
    pickled Python object: classes, schedules, spaces, buffers), `policy.pth` (the network's
    weights) and the optimizer's state. `stable_baselines3.PPO.load` unpickles all of it, and
    unpickling runs whatever code the file's author put there. Here only plain data is read:
    the network's settings (`policy_kwargs`, which `composer train` writes as plain JSON; a pixel
    recipe's encoder by its plain settings, `encoder.SETTINGS_KEY`, its class being ours), the
    shapes of the spaces, the observation statistics (`observation_normalization`), and the
    weights through `torch.load(weights_only=True)`, which loads tensors and refuses anything
    else. The policy is built on the environment's own spaces, so `predict` is the model's: the
    same network, weights and action scaling, the same actions (tested against
    `PPO.load`). A file whose needed parts are pickles raises UntrustedPolicyError, which names
    `--trust-policy`, for files from a source the user trusts; with it, the library's own
    loader reads the file whole.
    """
    unpacker = untrusted.unpacker()
    with untrusted.archive(file, f"the policy in {file}") as archive:
        data_bytes = untrusted.entry(unpacker, archive, "data", file)
        weight_bytes = untrusted.entry(unpacker, archive, "policy.pth", file)
    data = untrusted.mapping(untrusted.json_data(data_bytes, f"{file}: data"), f"{file}: data")
    untrusted.inner_archive(unpacker, weight_bytes, f"{file}: policy.pth")
    weights = _weights(file, weight_bytes)
    saved = types.SimpleNamespace(**{
        key: gymnasium.spaces.Box(-np.inf, np.inf, _saved_shape(file, data, key))
        for key in ("observation_space", "action_space")
    })  # fmt: skip
    base.check_spaces(file, saved, env)
    pixel_encoder = _plain(file, data, encoder.SETTINGS_KEY, None)
    kwargs = data.get("policy_kwargs", {})
    if pixel_encoder is not None and isinstance(kwargs, dict):
        # stable-baselines3 pickles the whole dict for its class (ours, which the plain
        # settings name) and writes the rest beside it as JSON: that is read, not unpickled.
        kwargs = {k: v for k, v in kwargs.items() if k not in _ENCODER_PICKLES}
    settings = untrusted.mapping(
        _plain(file, {"policy_kwargs": kwargs}, "policy_kwargs", {}), f"{file}: policy_kwargs"
    )
    observation_space = env.observation_space
    if pixel_encoder is not None:
        if (
            not isinstance(observation_space, gymnasium.spaces.Box)
            or len(observation_space.shape) != 3
        ):
            raise PolicyError(f"{file} was trained from pixels: give --pixels")
        # Trained on VecTransposeImage's channels-first frames; `predict` transposes.
        observation_space = VecTransposeImage.transpose_space(observation_space)
        settings.update(
            features_extractor_class=encoder.PixelEncoder,
            features_extractor_kwargs=_encoder_settings(file, pixel_encoder),
        )
        alias = "CnnPolicy"
    elif isinstance(observation_space, gymnasium.spaces.Dict):
        alias = "MultiInputPolicy"
    else:
        alias = "MlpPolicy"
    policy_class = algorithm.policy_aliases[alias]
    use_sde = _plain(file, data, "use_sde", False)
    if not isinstance(use_sde, bool):
        raise PolicyError(f"{file}: use_sde must be true or false, got {use_sde!r}")
    settings.setdefault("use_sde", use_sde)
    capacity = untrusted.capacity(sum(int(tensor.numel()) for tensor in weights.values()))
    try:
        with untrusted.at_most(torch, capacity, file):
            policy = policy_class(observation_space, env.action_space, _no_learning, **settings)
        policy.load_state_dict(weights)
    except PolicyError:
        raise
    # The settings are a stranger's keywords to stable-baselines3's and torch's
    # constructors, which raise whatever they raise for a bad one.
    except Exception as e:
        raise PolicyError(f"cannot build the policy in {file}: {type(e).__name__}: {e}") from e
    policy.set_training_mode(False)
    statistics = _statistics(file, data, env.observation_space)
    return NormalizedPolicy(policy, statistics)


def _weights(file: Path, data: bytes) -> dict[str, torch.Tensor]:
    """The tensors of policy.pth's bytes `data`, by name; raises UntrustedPolicyError
    when it holds more than tensors, PolicyError when it is not a torch file of them."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # torch's notes on a file not its own
            weights = torch.load(io.BytesIO(data), map_location="cpu", weights_only=True)
    except pickle.UnpicklingError as e:  # torch refused: not only tensors
        reason = "its policy.pth holds more than tensors"
        raise UntrustedPolicyError(_untrusted(file, reason)) from e
    # torch's reader raises what its parts raise on a corrupt file.
    except Exception as e:
        raise PolicyError(f"cannot read the weights in {file}: {type(e).__name__}: {e}") from e
    if not isinstance(weights, dict) or not all(
        isinstance(name, str) and isinstance(value, torch.Tensor) for name, value in weights.items()
    ):
        raise PolicyError(f"{file}: policy.pth must hold tensors by name (a state dict)")
    return weights


def _saved_shape(file: Path, data: dict[str, Any], key: str) -> tuple[int, ...]:
    """The shape of the space `key` that `data` says, checked (`untrusted.shape`)."""
    space = data.get(key)
    what = key.replace("_", " ")
    if not isinstance(space, dict) or "_shape" not in space:
        raise PolicyError(f"{file} does not say the shape of its {what}")
    return untrusted.shape(space["_shape"], f"{file}: the shape of its {what}")


def _encoder_settings(file: Path, settings: Any) -> dict[str, Any]:
    """The pixel encoder's settings `settings`, checked to be `encoder.settings`' kind."""
    where = f"{file}: {encoder.SETTINGS_KEY}"
    settings = untrusted.mapping(settings, where)
    conv, features = settings.get("conv"), settings.get("features")
    triples = isinstance(conv, list) and conv and all(
        isinstance(layer, list) and len(layer) == 3
        and all(isinstance(n, int) and not isinstance(n, bool) and n > 0 for n in layer)
        for layer in conv
    )  # fmt: skip
    if not triples or isinstance(features, bool) or not isinstance(features, int) or features < 1:
        raise PolicyError(
            f"{where} must be {{'conv': [[channels, kernel, stride], ...], 'features': "
            f"units}} of positive integers, got {settings}"
        )
    return {"conv": conv, "features": features}


def _statistics(file: Path, data: dict[str, Any], space: gymnasium.Space) -> dict[str, Any] | None:
    """The observation statistics in `data` (None if absent), checked to fit `space`."""
    statistics = _plain(file, data, NORMALIZATION, None)
    if statistics is None:
        return None
    where = f"{file}: {NORMALIZATION}"
    statistics = untrusted.mapping(statistics, where)
    size = tuple(space.shape or ())
    return {
        "mean": untrusted.numbers(statistics.get("mean"), f"{where}: mean", size),
        "var": untrusted.numbers(statistics.get("var"), f"{where}: var", size).clip(0),
        "epsilon": untrusted.number(statistics.get("epsilon"), f"{where}: epsilon", 0),
        "clip": untrusted.number(statistics.get("clip"), f"{where}: clip", 0),
    }


def _no_learning(progress: float) -> float:
    """The learning rate schedule a policy is built with: it only predicts."""
    return 0.0


def _plain(file: Path, data: dict[str, Any], key: str, default: Any) -> Any:
    """`data[key]` (`default` if absent); raises UntrustedPolicyError if any part of it
    is pickled."""
    value = data.get(key, default)
    if _holds_pickles(value):
        raise UntrustedPolicyError(_untrusted(file, f"its {key!r} holds pickled Python objects"))
    return value


def _holds_pickles(value: Any) -> bool:
    if isinstance(value, dict):
        return _PICKLED in value or any(_holds_pickles(v) for v in value.values())
    if isinstance(value, list):
        return any(_holds_pickles(v) for v in value)
    return False


def _untrusted(file: Path, reason: str) -> str:
    return (
        f"{file} cannot be loaded without running code from it: {reason}. Load it only if "
        "you trust where it came from, with --trust-policy (see SECURITY.md)"
    )
