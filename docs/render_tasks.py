"""Render one picture per registered task into docs/images/<TaskName>.png (320x240).

    python docs/render_tasks.py              # every task
    python docs/render_tasks.py Reach        # some of them

Each task is reset with seed 0 and run for a few steps with zero action, so bodies have
settled, then rendered through its own camera. It also prints the README's task table
row for each task (id, observation and action sizes, description, picture).

A picture already there is rewritten only when the new one looks different (`looks_same`):
renders differ in a few pixels between OpenGL drivers and after changes too small to see,
and a committed image should change only when the scene does.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import gymnasium as gym
import imageio.v3 as iio
import numpy as np

import tasks
from composer import registration
from entities import robots

IMAGES = Path(__file__).resolve().parent / "images"
SETTLE_STEPS = 10
# The mean difference of two pictures' channels (0 to 255) below which they look the same:
# a picture's edges moved by a pixel or lit a shade differently stay well under it (0.01
# to 0.6 measured), a body moved or recoloured, a camera turned, are far over it.
VISIBLE_DIFFERENCE = 1.0


def render(env_id: str, out_dir: Path) -> Path:
    """Write the picture of `env_id` into `out_dir` and return its path."""
    info = registration.registered()[env_id]
    env = gym.make(env_id, render_mode="rgb_array", flatten_observations=True)
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, env.action_space.dtype)
    for _ in range(SETTLE_STEPS):
        env.step(zero)
    path = out_dir / f"{info.name}.png"
    write_unless_same(path, env.render())
    obs, action = env.observation_space.shape[0], env.action_space.shape[0]
    print(f"| `{env_id}` | {obs} | {action} | {info.description} | "
          f"![{info.name}](docs/images/{path.name}) |")  # fmt: skip
    env.close()
    return path


def looks_same(first: np.ndarray, second: np.ndarray) -> bool:
    """Whether two (h, w, 3) uint8 pictures differ by less than VISIBLE_DIFFERENCE."""
    if first.shape != second.shape:
        return False
    difference = np.abs(first.astype(np.int16) - second.astype(np.int16))
    return float(difference.mean()) < VISIBLE_DIFFERENCE


def write_unless_same(path: Path, frame: np.ndarray) -> bool:
    """Write `frame` as the PNG `path` unless the picture there `looks_same`; whether it
    wrote."""
    if path.is_file() and looks_same(iio.imread(path)[..., :3], frame):
        return False
    iio.imwrite(path, frame)
    return True


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
