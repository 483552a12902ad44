"""The progress bar of `composer train`: the run's steps of its total, the same for both
engines, ending full at the true count after a resume that passes its total."""

from __future__ import annotations

import io
import json
import os
import re
import struct
import subprocess
import sys

import pytest

from composer.cli import progress
from tests.cli.helpers import environment


def frames(text: str) -> list[str]:
    """The bar's successive renderings in what tqdm wrote."""
    return [frame.strip() for frame in re.split(r"[\r\n]", text) if "steps" in frame]


def test_a_resumed_run_counts_its_earlier_steps_and_ends_at_its_true_count():
    out = io.StringIO()
    bar = progress.Bar(total=100_000, done=20_480, file=out)
    bar.advance_to(61_440)
    bar.advance_to(102_400)  # PPO's last rollout passed the total
    bar.close()
    shown = frames(out.getvalue())
    assert shown[0].startswith("20,480/100,000 steps  20% |")
    assert shown[-1].startswith("102,400/102,400 steps 100% |")


def test_without_a_terminal_there_is_no_bar_and_lines_go_to_stdout(capsys):
    assert progress.Bar.open(100, 0) is None  # pytest's stderr is no terminal
    progress.say(None, "   1,024 steps  3s  return 1.00")
    assert capsys.readouterr().out == "   1,024 steps  3s  return 1.00\n"


def test_train_draws_the_bar_on_a_terminal_and_ends_it_at_the_steps_done(tmp_path):
    fcntl = pytest.importorskip("fcntl", reason="a pseudo-terminal needs POSIX")
    termios = pytest.importorskip("termios", reason="a pseudo-terminal needs POSIX")
    common = ("--algo", "ppo", "--n-envs", "2", "--eval-episodes", "1", "--no-video",
              "--out", "run")  # fmt: skip
    first = subprocess.run([sys.executable, "-m", "composer", "train", "Reach", "--timesteps",
                            "1024", *common], cwd=tmp_path, env=environment(),
                           capture_output=True, text=True, timeout=300)  # fmt: skip
    assert first.returncode == 0, first.stderr
    terminal, bar_side = os.openpty()
    # A terminal 120 columns wide (a new one has none, and tqdm then draws nothing).
    fcntl.ioctl(bar_side, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 120, 0, 0))
    with subprocess.Popen(
        [sys.executable, "-m", "composer", "train", "Reach", "--timesteps", "1500", "--resume",
         *common], cwd=tmp_path, env=environment(), stdout=subprocess.PIPE, stderr=bar_side,
    ) as resumed:  # fmt: skip
        os.close(bar_side)
        drawn = b""
        while True:
            try:
                chunk = os.read(terminal, 65536)
            except OSError:  # the other side closed: Linux says EIO
                break
            if not chunk:
                break
            drawn += chunk
        assert resumed.wait(timeout=300) == 0, drawn.decode(errors="replace")
    os.close(terminal)
    done = json.loads((tmp_path / "run" / "metrics.json").read_text())["timesteps"]
    assert done > 1500  # whole rollouts: the run passed its total
    shown = frames(drawn.decode(errors="replace"))
    assert shown[0].startswith("1,024/1,500 steps")
    assert shown[-1].startswith(f"{done:,}/{done:,} steps 100% |")
