"""A policy of the Ray engine: written from a training algorithm, and loaded for `composer
run`, `eval` and `view` without unpickling anything by default.

    policy = ray.policy.load_policy(folder, env)    # policy.predict(obs, deterministic=True)
    ray.policy.save_policy(algo, folder, info)      # policy.json, weights.npz, module/

Promise: without `--trust-policy` no pickle is read (`load_policy`); `predict` acts as
RLlib's env runners with exploration off, so `composer eval` repeats training's evaluations.
Ray and torch are imported only to load or save, so importing this module costs nothing.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from composer.cli.engines import base, untrusted
from composer.cli.engines.ray.files import (
    POLICY_FILE,
    POLICY_FORMAT,
    POLICY_VERSION,
    WEIGHTS_FILE,
    quiet_ray,
    require_ray,
)
from composer.cli.errors import PolicyError, UntrustedPolicyError

# RLlib's MeanStdFilter divides by std + this (ray.rllib.utils.filter.SMALL_NUMBER).
_FILTER_EPSILON = 1e-8


class RayPolicy:
    """An RLModule with the observation filter it was trained with: `predict` as a
    stable-baselines3 model's, for `composer.cli.rollout.model_policy`. It applies the filter,
    the module's deterministic action and RLlib's unsquashing to the action bounds, as RLlib's
    env runners do with exploration off, so `composer eval` repeats training's evaluations."""

    def __init__(self, module: Any, spec: dict[str, Any]) -> None:
        """Serve `module` (an RLlib RLModule) with `spec` (the contents of policy.json)."""
        import torch  # with Ray: checked by `files.require_ray`

        torch.set_num_threads(base.TORCH_THREADS)

        self.module = module
        self.spec = spec
        self.observation_space = gymnasium.spaces.Box(
            -np.inf, np.inf, tuple(spec["observation_shape"]), np.float32
        )
        self.action_space = gymnasium.spaces.Box(
            np.array(spec["action_low"], np.float32), np.array(spec["action_high"], np.float32)
        )
        stats = spec["observation_filter"]
        self._filter = None
        if stats is not None:
            self._filter = (
                np.array(stats["mean"], np.float64),
                np.array(stats["std"], np.float32),
                stats["clip"],
            )
        self._torch = torch

    def normalize(self, observation: np.ndarray) -> np.ndarray:
        """`observation` as the module saw it in training (RLlib's MeanStdFilter, frozen)."""
        x = np.asarray(observation)
        if self._filter is None:
            return x
        mean, std, clip = self._filter
        normalized = (x - mean) / (std + _FILTER_EPSILON)
        if clip:
            normalized = np.clip(normalized, -clip, clip)
        return normalized.astype(x.dtype)

    def predict(self, observation: Any, deterministic: bool = True) -> tuple[np.ndarray, None]:
        """The action for one observation (shape observation_shape): the distribution's
        mode when `deterministic`, else a sample, mapped into the action bounds."""
        from ray.rllib.core.columns import Columns  # Ray: only where a Ray policy is used
        from ray.rllib.utils.spaces.space_utils import unsquash_action

        torch = self._torch
        observations = torch.as_tensor(self.normalize(observation)[None], dtype=torch.float32)
        batch = {Columns.OBS: observations}
        with torch.no_grad():
            output = self.module.forward_inference(batch)
            actions = output.get(Columns.ACTIONS)
            if actions is None:
                distribution = self.module.get_inference_action_dist_cls().from_logits(
                    output[Columns.ACTION_DIST_INPUTS]
                )
                if deterministic:
                    distribution = distribution.to_deterministic()
                actions = distribution.sample()
        action = actions[0].numpy().astype(np.float32)
        return unsquash_action(action, self.action_space), None


def save_policy(algo: Any, folder: Path, info: dict[str, Any]) -> None:
    """Write `algo`'s current policy (see `current_policy`) to `folder`; `info` (task,
    env_id, algo) goes into policy.json."""
    write_module(algo.env_runner.module, folder)
    (folder / POLICY_FILE).write_text(json.dumps(policy_spec(algo, info), indent=1) + "\n")


def write_module(module: Any, folder: Path) -> None:
    """Write the RLModule `module` into `folder`: its weights as plain arrays (weights.npz),
    and RLlib's own checkpoint of it (`module/`)."""
    folder.mkdir(parents=True, exist_ok=True)
    module.save_to_path(uri(folder / "module"))
    weights: dict[str, Any] = {name: np.asarray(v) for name, v in module.get_state().items()}
    with (folder / WEIGHTS_FILE).open("wb") as file:
        np.savez(file, **weights)


def current_policy(algo: Any, info: dict[str, Any]) -> RayPolicy:
    """`algo`'s current policy: its local env runner's module and observation filter,
    which RLlib synchronizes with the learner and the sampling env runners after every
    training iteration."""
    spec = json.loads(json.dumps(policy_spec(algo, info)))  # the values a load would read
    return RayPolicy(algo.env_runner.module, spec)


def policy_spec(algo: Any, info: dict[str, Any]) -> dict[str, Any]:
    """The contents of policy.json for `algo`'s current policy."""
    module = algo.env_runner.module
    return {
        "format": POLICY_FORMAT,
        "version": POLICY_VERSION,
        **info,
        "model_config": dict(module.model_config),
        "observation_shape": list(module.observation_space.shape),
        "action_low": module.action_space.low.tolist(),
        "action_high": module.action_space.high.tolist(),
        "observation_filter": observation_filter(algo.env_runner),
    }


def observation_filter(runner: Any) -> dict[str, Any] | None:
    """The mean, std and clip of the MeanStdFilter in `runner`'s env-to-module pipeline,
    as plain lists, or None when it has none."""
    from ray.rllib.utils.filter import RunningStat  # Ray: only where a Ray policy is saved

    pipeline = runner.get_state(components="env_to_module_connector")["env_to_module_connector"]
    state = pipeline.get("MeanStdFilter")
    if state is None:
        return None
    (agent,) = state.values()
    (stats,) = agent["running_stats"]
    running = RunningStat.from_state(stats)
    return {
        "mean": np.asarray(running.mean, np.float64).tolist(),
        "std": np.asarray(running.std, np.float32).tolist(),
        "clip": agent["clip_by_value"],
    }


def load_policy(folder: Path, env: Any, trusted: bool = False) -> RayPolicy:
    """The policy saved in `folder`, checked to fit `env`'s spaces: its network built
    from policy.json and weights.npz (every part checked first, `untrusted`), or, when
    `trusted`, read by RLlib from `module/` (which unpickles). Raises PolicyError for a
    folder that cannot be read, a malformed policy or one of other spaces,
    UntrustedPolicyError for one that can only be read by unpickling, MissingExtraError
    without Ray.

    It builds the algorithm's default RLModule from policy.json and loads weights.npz into it,
    reading no pickle; RLlib's `module/` holds pickles (its class and constructor arguments, its
    state), which run code when loaded, so it is read only when the user trusts the file
    (`--trust-policy`), as are policies written before weights.npz existed.
    """
    path = folder / POLICY_FILE
    try:
        text = path.read_bytes()
    except OSError as e:
        raise PolicyError(f"cannot read {path}: {e}") from e
    spec = untrusted.json_data(text, str(path))
    if not isinstance(spec, dict) or spec.get("format") != POLICY_FORMAT:
        raise PolicyError(f"{path} is not a policy written by `composer train`")
    # Without Ray no folder of Ray's loads: say so first, whatever else the folder holds.
    require_ray(f"{folder} was trained with --engine ray: loading it needs")
    spec = _checked(path, spec)
    quiet_ray()
    module = _trusted_module(folder) if trusted else _module(folder, spec)
    module.eval()
    policy = RayPolicy(module, spec)
    base.check_spaces(folder, policy, env)
    return policy


def _checked(path: Path, spec: dict[str, Any]) -> dict[str, Any]:
    """policy.json's contents `spec` with the parts `RayPolicy` reads checked; raises
    PolicyError naming the part otherwise."""
    observation = untrusted.shape(spec.get("observation_shape"), f"{path}: observation_shape")
    low = untrusted.numbers(spec.get("action_low"), f"{path}: action_low", _size(spec, "low"))
    high = untrusted.numbers(spec.get("action_high"), f"{path}: action_high", low.shape)
    if not np.all(low < high):
        raise PolicyError(f"{path}: action_low must be below action_high")
    stats = spec.get("observation_filter")
    if stats is not None:
        where = f"{path}: observation_filter"
        stats = untrusted.mapping(stats, where)
        clip = stats.get("clip")
        stats = {
            "mean": untrusted.numbers(stats.get("mean"), f"{where}: mean", observation).tolist(),
            "std": untrusted.numbers(stats.get("std"), f"{where}: std", observation).tolist(),
            "clip": None if clip is None else untrusted.number(clip, f"{where}: clip", 0),
        }
    version = spec.get("version", 1)
    if isinstance(version, bool) or not isinstance(version, int):
        raise PolicyError(f"{path}: version must be an integer, got {version!r}")
    return {**spec, "observation_shape": list(observation), "action_low": low.tolist(),
            "action_high": high.tolist(), "observation_filter": stats}  # fmt: skip


def _size(spec: dict[str, Any], bound: str) -> tuple[int, ...]:
    """The shape of policy.json's action bounds, as written (a list of numbers)."""
    value = spec.get(f"action_{bound}")
    return (len(value),) if isinstance(value, list) else (-1,)


def _module(folder: Path, spec: dict[str, Any]) -> Any:
    """The RLModule of policy.json's algorithm and model config with weights.npz's
    weights, read without unpickling anything; the module built may hold no more numbers
    than the weights."""
    weights_path = folder / WEIGHTS_FILE
    if spec["version"] < POLICY_VERSION or not weights_path.is_file():
        raise UntrustedPolicyError(
            f"{folder} holds its network only as RLlib's pickles ({folder / 'module'}), "
            "which run code when loaded; load it only if you trust where it came from, with "
            "--trust-policy (see SECURITY.md)"
        )
    import torch  # with Ray: checked by load_policy
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.algorithms.sac import SACConfig
    from ray.rllib.core.rl_module.torch import TorchRLModule

    configs = {"ppo": PPOConfig, "sac": SACConfig}
    algo = spec.get("algo")
    if not isinstance(algo, str) or algo not in configs:
        raise PolicyError(f"{folder / POLICY_FILE}: algo must be one of {list(configs)}")
    if not isinstance(spec.get("model_config"), dict):
        raise PolicyError(f"{folder / POLICY_FILE} names no algorithm and network to build")
    arrays = untrusted.npz_arrays(weights_path, untrusted.unpacker())
    module_spec = configs[algo]().get_default_rl_module_spec()
    module_spec.observation_space = gymnasium.spaces.Box(
        -np.inf, np.inf, tuple(spec["observation_shape"]), np.float32
    )
    module_spec.action_space = gymnasium.spaces.Box(
        np.array(spec["action_low"], np.float32), np.array(spec["action_high"], np.float32)
    )
    module_spec.model_config = spec["model_config"]
    module_spec.inference_only = True
    capacity = untrusted.capacity(sum(array.size for array in arrays.values()))
    try:
        state = {name: torch.from_numpy(array) for name, array in arrays.items()}
        with untrusted.at_most(torch, capacity, folder):
            module = module_spec.build()
        if not isinstance(module, TorchRLModule):
            raise TypeError(f"RLlib built a {type(module).__name__}, not a PyTorch module")
        module.load_state_dict(state, strict=True)
    except PolicyError:
        raise
    # The model config is a stranger's keywords to RLlib's and torch's constructors,
    # which raise whatever they raise for a bad one.
    except Exception as e:
        raise PolicyError(f"cannot build the policy in {folder}: {type(e).__name__}: {e}") from e
    return module


def _trusted_module(folder: Path) -> Any:
    """RLlib's RLModule checkpoint in `folder`/module, read by RLlib (unpickling)."""
    from ray.rllib.core.rl_module.rl_module import RLModule  # Ray: checked by load_policy
    from ray.rllib.core.rl_module.torch import TorchRLModule

    try:
        module = RLModule.from_checkpoint(uri(folder / "module"))
    except (OSError, ValueError, KeyError) as e:
        raise PolicyError(f"cannot load the RLlib module in {folder / 'module'}: {e}") from e
    if not isinstance(module, TorchRLModule):
        raise PolicyError(f"{folder / 'module'} holds no PyTorch RLlib module")
    return module


def uri(path: Path) -> str:
    """`path` as RLlib takes it: absolute (a relative path is read as a URI)."""
    return str(path.resolve())
