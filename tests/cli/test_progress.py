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
from composer.cli.engines.base import Collection, Progress, Session
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


def test_the_time_left_counts_the_evaluations_still_due():
    estimate = progress.Estimate(total=10_000, done=0, evaluations=3)
    assert estimate.text() == "?"
    estimate.trained(1_000, 10.0)  # 100 steps/s
    assert estimate.text() == "01:30 + 3 evaluations"  # not yet timed: said, not guessed
    estimate.evaluated(20.0)
    assert estimate.text() == "02:10"  # 9,000 steps at 100/s, then 2 evaluations of 20 s
    estimate.trained(10_000, 90.0)
    assert estimate.text() == "00:40"  # the last 2 evaluations: they come before the end


def test_an_evaluation_is_timed_apart_and_leaves_the_speed_as_it_was():
    """tqdm's own rate and time left swung with each evaluation (7, 24, then 3 minutes): the
    evaluation's seconds counted as training's."""
    now = [0.0]
    out = io.StringIO()
    bar = progress.Bar(total=10_000, done=0, evaluations=3, file=out, clock=lambda: now[0])
    now[0] = 10.0
    bar.advance_to(1_000)
    with progress.evaluating(bar):
        now[0] = 30.0
    now[0] = 40.0
    bar.advance_to(2_000)
    assert bar.estimate.speed() == 100.0  # 2,000 steps in 20 s of training, not 40 s
    assert bar.estimate.text() == "02:00"  # 8,000 steps at 100/s, 2 evaluations of 20 s
    bar.close()
    assert frames(out.getvalue())[-1].endswith("<02:00, 100 steps/s")


def run_session(eval_every: int, evaluated_at: int | None) -> Session:
    """A session evaluating every `eval_every` steps, after an earlier one at
    `evaluated_at` (None: a new run)."""
    run = Progress("Reach", "composer/Reach-v0", "ppo", 0, {})
    if evaluated_at is not None:
        run.evaluations.append({"timesteps": evaluated_at})
    return Session(run, eval_env=None, eval_every=eval_every, eval_episodes=1)


@pytest.mark.parametrize(
    ("done", "end", "every", "check", "evaluated_at"),
    [
        (0, 6_144, 500, 8, None),  # PPO on 8 environments, --timesteps 5000
        (0, 20_480, 1_000, 4_096, None),  # RLlib's iterations: several due at one check
        (1_024, 1_536, 150, 2, 1_024),  # a resumed run
        (3_000, 4_096, 5_000, 4, 0),  # none due before the end
    ],
)
def test_the_evaluations_counted_ahead_are_those_the_session_asks_for(
    done, end, every, check, evaluated_at
):
    counted = run_session(every, evaluated_at).evaluations_until(end, done, check)
    session = run_session(every, evaluated_at)
    asked = sum(session.due(steps) for steps in range(done + check, end + 1, check))
    assert counted == asked


def test_a_run_ends_at_the_first_whole_batch_past_its_total():
    rollouts = Collection(2_048, "rollouts of 8 environments x 256 steps", 8)
    assert rollouts.end(0, 5_000) == 6_144
    assert rollouts.end(1_000, 5_000) == 5_096  # a run stopped mid-rollout starts a new one
    assert rollouts.end(6_144, 5_000) == 6_144  # nothing left to train
    assert Collection(None, "RLlib's SAC samples in iterations", 64).end(0, 5_000) == 5_000


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
    assert done == 1536  # whole rollouts of 2 x 128 steps: the run passed its total
    shown = frames(drawn.decode(errors="replace"))
    assert shown[0].startswith("1,024/1,536 steps")  # the end, known from the start
    assert re.match(r"1,536/1,536 steps 100% \|.*\| [\d:]+<00:00, [\d,]+ steps/s$", shown[-1])
