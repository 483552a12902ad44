"""examples/my_tasks.py as its docstring uses it, from the examples folder: `composer --import
my_tasks` lists, shows (its camera frames the arm) and trains its task, and `gym.make` of its
id is an environment Gymnasium's checker passes."""

from __future__ import annotations

import re
import subprocess
import sys

import imageio.v3 as iio

from tests.cli.helpers import composer, environment
from tests.conftest import REPO

EXAMPLES = REPO / "examples"


def test_composer_lists_shows_and_trains_the_example_task(tmp_path):
    listed = composer("--import", "my_tasks", "list", cwd=EXAMPLES)
    assert listed.returncode == 0, listed.stderr
    # 2 joint angles, 2 velocities, the fingertip (3), target minus fingertip (2); 2 motors.
    assert any(line.split()[:4] == ["Touch", "composer/Touch-v0", "9", "2"]
               for line in listed.stdout.splitlines())  # fmt: skip

    frame = tmp_path / "touch.png"
    shown = composer("--import", "my_tasks", "show", "Touch", "--out", str(frame), cwd=EXAMPLES)
    assert shown.returncode == 0, shown.stderr
    assert re.search(r"^  *to_target +\(2,\)", shown.stdout, re.M)
    assert "arm/tip" in shown.stdout and "arm/shoulder" in shown.stdout
    # The camera frames the arm: its orange links fill part of the middle of the picture.
    pixels = iio.imread(frame).astype(int)
    red, green, blue = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    orange = (red > 180) & (green > 60) & (green < 190) & (blue < 90)
    height, width = orange.shape
    middle = orange[height // 4 : 3 * height // 4, width // 4 : 3 * width // 4]
    assert middle.mean() > 0.01 and middle.sum() > 0.5 * orange.sum()

    trained = composer("--import", "my_tasks", "train", "Touch", "--timesteps", "512",
                       "--n-envs", "2", "--eval-episodes", "1", "--no-video",
                       "--out", str(tmp_path / "run"), cwd=EXAMPLES)  # fmt: skip
    assert trained.returncode == 0, trained.stderr
    assert "training Touch with PPO to 512 steps on 2 environments" in trained.stdout
    hyperparameters = next(line for line in trained.stdout.splitlines()
                           if line.startswith("hyperparameters:"))  # fmt: skip
    assert "gamma=0.95" in hyperparameters  # its recipe's (the generic one's is 0.99)
    assert (tmp_path / "run" / "policy.zip").is_file()


def test_the_example_id_is_a_checked_gymnasium_environment():
    code = (
        "import gymnasium as gym\n"
        "from gymnasium.utils.env_checker import check_env\n"
        "import my_tasks\n"
        "env = gym.make('composer/Touch-v0')\n"
        "check_env(env.unwrapped, skip_render_check=True)\n"
        "obs, info = env.reset(seed=0)\n"
        "print(' '.join(obs), env.unwrapped.task.render_camera)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=EXAMPLES, env=environment(),
                            capture_output=True, text=True, timeout=300)  # fmt: skip
    assert result.returncode == 0, result.stderr
    observed = "arm/joint_positions arm/joint_velocities arm/tip to_target"
    assert result.stdout.split() == [*observed.split(), "top"]
