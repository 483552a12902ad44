"""Episodes of a policy in one environment: returns, lengths, success, optional frames.

    policy = rollout.random_policy(env, seed=0)    # or rollout.model_policy(trained)
    episodes = rollout.run_episodes(env, policy, episodes=5, seed=0, frames=[])
    rollout.summary(episodes)   # {'episodes': 5, 'mean_return': ..., 'success_rate': ...}

Episode i starts from `env.reset(seed=seed + i)`, so the same seed gives the same episodes;
success and forward speed are None for tasks that do not report them (`Episode`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any, Protocol, SupportsFloat, cast

import gymnasium
import numpy as np

Policy = Callable[[Any], np.ndarray]


class Predictor(Protocol):
    """A trained policy as every engine gives one: stable-baselines3's `predict`."""

    def predict(self, observation: Any, deterministic: bool = True) -> tuple[np.ndarray, Any]:
        """The action for one observation (and a recurrent state, None here)."""
        ...


# Frames kept per second of simulation in videos: enough to look smooth, few to render.
VIDEO_FPS = 30.0
# The seed of the first episode of training's evaluations (episode i: EVAL_SEED + i), apart
# from the seeds training draws, and `composer eval`'s default: eval repeats them exactly.
EVAL_SEED = 1_000_000


@dataclasses.dataclass(frozen=True)
class Episode:
    """One finished episode. It succeeded when the `info` of its last step says
    `is_success` (None: the task never reports it). Its forward speed is the mean of the
    `info['forward_velocity']` (m/s) of its steps, for the tasks that report one (the
    runners): their displacement over the time they ran; None for the others."""

    episode_return: float
    length: int
    success: bool | None
    forward_speed: float | None = None


class Tally:
    """One episode's running sums, step by step: `add` each step, `episode` at the end."""

    def __init__(self) -> None:
        self.total, self.distance, self.steps = 0.0, 0.0, 0

    def add(self, reward: SupportsFloat, info: dict[str, Any]) -> None:
        """Count a step's reward and forward velocity (NaN from then on if it has none)."""
        self.total += float(reward)
        self.distance += float(info.get("forward_velocity", math.nan))
        self.steps += 1

    def episode(self, last_info: dict[str, Any]) -> Episode:
        """The finished episode, its success read from the last step's `last_info`."""
        success = last_info.get("is_success")
        speed = None if math.isnan(self.distance) else self.distance / self.steps
        return Episode(self.total, self.steps, None if success is None else bool(success), speed)


def random_policy(env: gymnasium.Env, seed: int | None = None) -> Policy:
    """Uniform random actions from `env`'s action space, seeded."""
    space = env.action_space
    space.seed(seed)
    return lambda observation: space.sample()


def model_policy(model: Predictor) -> Policy:
    """The deterministic actions of a trained policy (what an engine loads or trains)."""
    return lambda observation: model.predict(observation, deterministic=True)[0]


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
        tally, finished = Tally(), False
        while not finished:
            if frames is not None and tally.steps % stride == 0:
                frames.append(render_frame(env))
            observation, reward, terminated, truncated, info = env.step(policy(observation))
            tally.add(reward, info)
            finished = terminated or truncated
        if frames is not None:
            frames.append(render_frame(env))
        episode = tally.episode(info)
        done.append(episode)
        if on_episode is not None:
            on_episode(index, episode)
    return done


def render_frame(env: gymnasium.Env) -> np.ndarray:
    """The frame `env` renders now: an array, as its render_mode is 'rgb_array'."""
    return cast(np.ndarray, env.render())


def summary(episodes: list[Episode]) -> dict[str, Any]:
    """Mean and std of returns, mean length, success rate and mean forward speed (m/s)
    (each None if the task never reports it)."""
    returns = np.array([e.episode_return for e in episodes], dtype=np.float64)
    successes = [e.success for e in episodes if e.success is not None]
    speeds = [e.forward_speed for e in episodes if e.forward_speed is not None]
    return {
        "episodes": len(episodes),
        "mean_return": float(returns.mean()) if len(returns) else math.nan,
        "std_return": float(returns.std()) if len(returns) else math.nan,
        "mean_length": float(np.mean([e.length for e in episodes])) if episodes else math.nan,
        "success_rate": float(np.mean(successes)) if successes else None,
        "forward_speed": float(np.mean(speeds)) if speeds else None,
    }
