"""Episodes of a policy in one environment: returns, lengths, success, optional frames.

    policy = rollout.random_policy(env, seed=0)          # or rollout.model_policy(sb3_model)
    episodes = rollout.run_episodes(env, policy, episodes=5, seed=0, frames=[])
    rollout.summary(episodes)   # {'episodes': 5, 'mean_return': ..., 'success_rate': ...}

Episode i starts from `env.reset(seed=seed + i)`, so the same seed gives the same episodes.
An episode succeeded when the `info` of its last step says `is_success`; tasks that never
report it have no success rate (None).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import gymnasium
import numpy as np

Policy = Callable[[Any], np.ndarray]

# Frames kept per second of simulation in videos: enough to look smooth, few to render.
VIDEO_FPS = 30.0


@dataclasses.dataclass(frozen=True)
class Episode:
    """One finished episode."""

    episode_return: float
    length: int
    success: bool | None


def random_policy(env: gymnasium.Env, seed: int | None = None) -> Policy:
    """Uniform random actions from `env`'s action space, seeded."""
    space = env.action_space
    space.seed(seed)
    return lambda observation: space.sample()


def model_policy(model: Any) -> Policy:
    """The deterministic actions of a stable-baselines3 model, its observations normalized
    first when it carries `observation_normalization` (see `composer.cli.training`)."""
    stats = getattr(model, "observation_normalization", None)
    if stats is None:
        return lambda observation: model.predict(observation, deterministic=True)[0]
    mean = np.asarray(stats["mean"])
    scale = np.sqrt(np.asarray(stats["var"]) + stats["epsilon"])
    clip = stats["clip"]

    def policy(observation: Any) -> np.ndarray:
        normalized = np.clip((observation - mean) / scale, -clip, clip)
        return model.predict(normalized, deterministic=True)[0]

    return policy


def frame_stride(env: gymnasium.Env) -> int:
    """Render every n-th control step so a video has about VIDEO_FPS frames a second."""
    fps = float(env.metadata.get("render_fps", VIDEO_FPS))
    return max(1, round(fps / VIDEO_FPS))


def video_fps(env: gymnasium.Env) -> float:
    """Frames per second of a video recorded with `frame_stride`: real time."""
    return float(env.metadata.get("render_fps", VIDEO_FPS)) / frame_stride(env)


def run_episodes(
    env: gymnasium.Env,
    policy: Policy,
    episodes: int,
    seed: int = 0,
    frames: list[np.ndarray] | None = None,
    on_episode: Callable[[int, Episode], None] | None = None,
) -> list[Episode]:
    """Run `episodes` episodes of `policy`; append rendered frames to `frames` when given
    (the env needs render_mode='rgb_array'); call `on_episode(index, episode)` after each."""
    stride = frame_stride(env) if frames is not None else 0
    done: list[Episode] = []
    for index in range(episodes):
        observation, info = env.reset(seed=seed + index)
        total, steps, finished = 0.0, 0, False
        while not finished:
            if frames is not None and steps % stride == 0:
                frames.append(env.render())
            observation, reward, terminated, truncated, info = env.step(policy(observation))
            total += float(reward)
            steps += 1
            finished = terminated or truncated
        if frames is not None:
            frames.append(env.render())
        success = info.get("is_success")
        episode = Episode(total, steps, None if success is None else bool(success))
        done.append(episode)
        if on_episode is not None:
            on_episode(index, episode)
    return done


def summary(episodes: list[Episode]) -> dict[str, Any]:
    """Mean and std of returns, mean length, and success rate (None if never reported)."""
    returns = np.array([e.episode_return for e in episodes], dtype=np.float64)
    successes = [e.success for e in episodes if e.success is not None]
    return {
        "episodes": len(episodes),
        "mean_return": float(returns.mean()) if len(returns) else math.nan,
        "std_return": float(returns.std()) if len(returns) else math.nan,
        "mean_length": float(np.mean([e.length for e in episodes])) if episodes else math.nan,
        "success_rate": float(np.mean(successes)) if successes else None,
    }


def describe(episode: Episode) -> str:
    """'return 12.3 over 250 steps, success' for a line of output."""
    text = f"return {episode.episode_return:.2f} over {episode.length} steps"
    if episode.success is not None:
        text += ", success" if episode.success else ", no success"
    return text


def describe_summary(stats: dict[str, Any]) -> str:
    """'return 12.3 ± 4.5 over 10 episodes, success rate 0.90' for a line of output."""
    text = (
        f"return {stats['mean_return']:.2f} ± {stats['std_return']:.2f} "
        f"over {stats['episodes']} episode{'s' if stats['episodes'] != 1 else ''}"
    )
    if stats["success_rate"] is not None:
        text += f", success rate {stats['success_rate']:.2f}"
    return text
