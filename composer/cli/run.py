"""`composer run TASK`: roll out a policy, print the returns, optionally record a video.

    $ composer run Reach --episodes 2 --video reach.mp4
    episode 1: return 16.15 over 75 steps, no success
    episode 2: return 21.36 over 75 steps, no success
    Reach, random policy: return 18.76 ± 2.61 over 2 episodes, success rate 0.00

`--policy random` (the default) needs no training extras; `--policy PATH` (a `composer train`
folder, policy or checkpoint) is loaded by the engine that wrote it, which needs its extra.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from composer.cli import catalog, describe, engines, output, rollout, video


def run(args: argparse.Namespace) -> int:
    """Roll out the policy; returns the exit status."""
    info = args.info
    path = output.file(video.target(args.video)) if args.video else None
    env = catalog.make(info, render_mode="rgb_array" if path else None)
    try:
        if args.policy == "random":
            policy, label = rollout.random_policy(env, args.seed), "random policy"
        else:
            policy = rollout.model_policy(engines.load_policy(args.policy, env, args.trust_policy))
            label = f"policy {args.policy}"
        frames: list[np.ndarray] | None = [] if path else None
        episodes = rollout.run_episodes(
            env, policy, args.episodes, args.seed, frames,
            on_episode=lambda i, e: print(f"episode {i + 1}: {describe.episode(e)}"),
        )  # fmt: skip
        fps = rollout.video_fps(env)
    finally:
        env.close()
    print(f"{info.name}, {label}: {describe.summary(rollout.summary(episodes))}")
    if path is not None and frames:
        written = video.write_video(frames, path, fps)
        note = "" if written.suffix == Path(args.video).suffix else " (ffmpeg not found: GIF)"
        print(f"video: {written} ({len(frames) / fps:.1f} s){note}")
    return 0
