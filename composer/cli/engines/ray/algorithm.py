"""The RLlib side of `composer train --engine ray`: a task's recipe as an RLlib Algorithm.

    layout = algorithm.Layout(workers=2, envs_per_worker=16, address=None)
    recipe = recipes.for_task(info, 'ppo', engine='ray').replace(n_envs=layout.n_envs)
    algo = algorithm.build_algorithm(info, recipe, layout, seed=0)   # Ray is running
    algo.train()['env_runners'][algorithm.EPISODES]   # [(return, success), ...]

Promise: the recipe translated from stable-baselines3's terms (`algorithm_config` says how);
Ray is imported inside the functions, so importing this module costs nothing.
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import TYPE_CHECKING, Any

from composer.cli import catalog, recipes
from composer.cli.errors import CliError
from composer.registration import TaskInfo

if TYPE_CHECKING:
    from ray.rllib.algorithms.algorithm_config import AlgorithmConfig

# The key under which env runners report finished episodes: (return, success) each.
EPISODES = "composer_episodes"
# stable-baselines3's PPO defaults, so a recipe means the same on both engines.
SB3_PPO: dict[str, Any] = {
    "lambda_": 0.95,
    "clip_param": 0.2,
    "use_kl_loss": False,
    "vf_loss_coeff": 0.5,
    "grad_clip": 0.5,
    "vf_clip_param": math.inf,
}
SB3_SAC: dict[str, Any] = {"tau": 0.005, "twin_q": True, "n_step": 1}
# SAC's steps per environment per round trip to the env runners: updates keep their ratio
# to samples (training_intensity), and one step per trip left RLlib at ~300 steps/s.
SAC_FRAGMENT = 32


@dataclasses.dataclass(frozen=True)
class Layout:
    """Where a run samples: env runners, environments each, and the cluster's address
    (None: a local instance)."""

    workers: int
    envs_per_worker: int
    address: str | None

    @property
    def n_envs(self) -> int:
        """Environments in all."""
        return self.workers * self.envs_per_worker


def build_algorithm(info: TaskInfo, recipe: recipes.Recipe, layout: Layout, seed: int) -> Any:
    """The RLlib Algorithm of `recipe` on `info`'s task with `layout`'s env runners."""
    from composer import rllib  # imports Ray

    rllib.register_env(info.env_id)
    config = algorithm_config(info, recipe, layout, seed)
    try:
        return config.build_algo()
    except Exception as e:  # RLlib wraps env-runner failures in many types
        raise CliError(f"RLlib could not build {recipe.algo.upper()} on {info.name}: {e}") from e


def algorithm_config(info: TaskInfo, recipe: recipes.Recipe, layout: Layout, seed: int) -> Any:
    """The RLlib AlgorithmConfig of `recipe`.

    The recipe is the task's (`composer train --help`), with what the task's recipe changes for
    this engine where measured (`Recipe.engine_changes`), translated from stable-baselines3's
    terms: PPO collects `n_steps` per environment per update (a batch of n_steps x N x M), with
    stable-baselines3's clip 0.2, GAE lambda 0.95, gradient norm 0.5, value loss weight 0.5, no
    KL term, separate policy and value networks and a state-independent log std; `normalize`
    filters observations with RLlib's MeanStdFilter (rewards are not scaled). SAC maps its
    replay, warm-up and update ratio (training_intensity). Env runners (one CPU each) step their
    environments as one `composer.VectorEnvironment` (`composer.rllib`), the learner runs in
    this process, and a runner that dies is restarted by Ray (up to 1,000 times) while the
    others sample.
    """
    from ray.rllib.algorithms.ppo import PPOConfig  # Ray: see the module docstring
    from ray.rllib.algorithms.sac import SACConfig
    from ray.rllib.core.rl_module.default_model_config import DefaultModelConfig

    kwargs = catalog.environment_kwargs(info)
    env_config = {k: v for k, v in kwargs.items() if k not in info.default_kwargs}
    config: AlgorithmConfig
    if recipe.algo == "ppo":
        config = PPOConfig().training(
            lr=recipe.learning_rate,
            gamma=recipe.gamma,
            train_batch_size_per_learner=recipe.n_envs * recipe.n_steps,
            minibatch_size=recipe.batch_size,
            num_epochs=recipe.n_epochs,
            entropy_coeff=recipe.ent_coef,
            **SB3_PPO,
        )
        model = DefaultModelConfig(
            fcnet_hiddens=list(recipe.net), fcnet_activation="tanh",
            vf_share_layers=False, free_log_std=True,
        )  # fmt: skip
        fragment: int | str = "auto"
    else:
        config = SACConfig().training(
            actor_lr=recipe.learning_rate,
            critic_lr=recipe.learning_rate,
            alpha_lr=recipe.learning_rate,
            initial_alpha=recipe.initial_temperature,
            gamma=recipe.gamma,
            train_batch_size_per_learner=recipe.batch_size,
            replay_buffer_config={"type": "EpisodeReplayBuffer", "capacity": recipe.buffer_size},
            store_buffer_in_checkpoints=True,
            num_steps_sampled_before_learning_starts=recipe.learning_starts,
            training_intensity=_sac_intensity(recipe),
            **SB3_SAC,
        )
        model = DefaultModelConfig(fcnet_hiddens=list(recipe.net), fcnet_activation="relu")
        fragment = max(recipe.train_freq, SAC_FRAGMENT)
    return (
        config.environment(info.env_id, env_config=env_config)
        .framework("torch")
        .env_runners(
            num_env_runners=layout.workers,
            num_envs_per_env_runner=layout.envs_per_worker,
            num_cpus_per_env_runner=1,
            gym_env_vectorize_mode="vector_entry_point",
            rollout_fragment_length=fragment,
            env_to_module_connector=_observation_filter if recipe.normalize else None,
        )
        .learners(num_learners=0)
        .rl_module(model_config=model)
        .callbacks(on_episode_end=_record_episode)
        .fault_tolerance(
            restart_failed_env_runners=True,
            max_num_env_runner_restarts=1000,
            delay_between_env_runner_restarts_s=0.0,
        )
        .debugging(seed=seed, log_level="ERROR")
    )


def _sac_intensity(recipe: recipes.Recipe) -> float:
    """RLlib's trained-to-sampled ratio for stable-baselines3's `gradient_steps` updates of
    `batch_size` every `train_freq` steps of each of `n_envs` environments."""
    return recipe.gradient_steps * recipe.batch_size / (recipe.train_freq * recipe.n_envs)


def _observation_filter(env: Any = None, spaces: Any = None, device: Any = None) -> Any:
    """RLlib's env-to-module connector normalizing observations (picklable)."""
    from ray.rllib.connectors.env_to_module import MeanStdFilter  # in the env runner

    return MeanStdFilter()


def _record_episode(
    *, episode: Any, prev_episode_chunks: list[Any], metrics_logger: Any, **kwargs: Any
) -> None:
    """Env runners' callback: report a finished episode's return (over every chunk RLlib
    cut it into) and success (its last info's `is_success`, None if absent)."""
    total = float(episode.get_return()) + sum(float(c.get_return()) for c in prev_episode_chunks)
    success = episode.get_infos(-1).get("is_success")
    metrics_logger.log_value(
        EPISODES, (total, None if success is None else bool(success)), reduce="item_series"
    )


def describe_runners(algo: Any) -> str:
    """'2 on 192.0.2.2 (pids 123, 124)': the live env runners by machine."""
    places = algo.env_runner_group.foreach_env_runner(_whereabouts, local_env_runner=False)
    hosts: dict[str, list[int]] = {}
    for host, pid in places:
        hosts.setdefault(host, []).append(pid)
    return "; ".join(
        f"{len(pids)} on {host} (pid{'s' if len(pids) > 1 else ''} {', '.join(map(str, pids))})"
        for host, pids in hosts.items()
    )


def _whereabouts(runner: Any) -> tuple[str, int]:
    import ray  # in the env runner

    return ray.util.get_node_ip_address(), os.getpid()
