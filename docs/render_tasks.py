"""Render one picture per registered task into docs/images/<TaskName>.png (320x240).

    MUJOCO_GL=egl python docs/render_tasks.py              # every task
    MUJOCO_GL=egl python docs/render_tasks.py Reach        # some of them

Each task is reset with seed 0 and run for a few steps with zero action, so bodies have
settled, then rendered through its own camera. It also prints the README's task table
row for each task (id, observation and action sizes, description, picture).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported

import gymnasium as gym
import imageio.v3 as iio
import numpy as np

import tasks
from composer import registration
from entities import robots

IMAGES = Path(__file__).resolve().parent / "images"
SETTLE_STEPS = 10


def render(env_id: str, out_dir: Path) -> Path:
    """Write the picture of `env_id` into `out_dir` and return its path."""
    info = registration.registered()[env_id]
    env = gym.make(env_id, render_mode="rgb_array", flatten_observations=True)
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, env.action_space.dtype)
    for _ in range(SETTLE_STEPS):
        env.step(zero)
    path = out_dir / f"{info.name}.png"
    iio.imwrite(path, env.render())
    obs, action = env.observation_space.shape[0], env.action_space.shape[0]
    print(f"| `{env_id}` | {obs} | {action} | {info.description} | "
          f"![{info.name}](docs/images/{path.name}) |")  # fmt: skip
    env.close()
    return path


def main() -> None:
    """Render the tasks named on the command line, or all of them."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="task names (default: every task)")
    parser.add_argument("--out", type=Path, default=IMAGES, help="output folder")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    wanted = set(args.names)
    for env_id in tasks.IDS:
        if not wanted or registration.registered()[env_id].name in wanted:
            try:
                render(env_id, args.out)
            except robots.RobotNotFoundError as e:  # ArmPushBox without Menagerie files
                print(f"skipped {env_id}: {e}")


if __name__ == "__main__":
    main()
