"""Mistakes a user makes: one line on stderr, exit status 2, no traceback; and the commands
that need no training extras work without them."""

from __future__ import annotations

import sys

import pytest

from composer.cli import video
from tests.cli.helpers import assert_one_line_error, composer, composer_without

INSTALL = "pip install torch==2.13.0 && pip install -e '.[train]'"


@pytest.mark.parametrize("command", [["show", "Reech"], ["run", "reech"], ["train", "Reech"]])
def test_an_unknown_task_names_the_closest_and_the_known_ones(tmp_path, command):
    # The closest name first (the Control Suite's ids may follow it).
    line = assert_one_line_error(composer(*command, cwd=tmp_path), "did you mean 'Reach'")
    assert line.startswith("composer: error: unknown task")
    for name in ("AntRun", "CartpoleSwingup", "Reach", "WalkerRun"):
        assert name in line.partition("Known tasks:")[2]


@pytest.mark.parametrize(
    ("command", "needs"),
    [
        (["train", "Reach", "--out", "run"], "training with stable-baselines3 needs"),
        (["eval", "Reach", "policy.zip"], "policy.zip was trained with --engine sb3: loading "
         "it needs"),
    ],
)  # fmt: skip
def test_training_without_the_extra_prints_the_install_command(tmp_path, command, needs):
    (tmp_path / "policy.zip").write_bytes(b"")  # a policy file: its engine needs its library
    result = composer_without(("stable_baselines3",), *command, cwd=tmp_path)
    missing = "the [train] extra (stable_baselines3 is missing)"
    line = assert_one_line_error(result, f"{needs} {missing}")
    assert line.endswith(INSTALL)


@pytest.mark.parametrize(
    "command",
    [["list"], ["show", "Reach", "--out", "f.png"], ["run", "Reach", "--video", "v.mp4"]],
)
def test_list_show_and_run_need_no_training_library(tmp_path, command):
    result = composer_without(("torch", "stable_baselines3", "ray"), *command, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.rstrip().endswith("imported: []")


@pytest.mark.parametrize(
    "command",
    [
        ["train", "Reach", "--out", "file/run"],
        ["show", "Reach", "--out", "file/f.png"],
        ["run", "Reach", "--video", "file/v.mp4"],
    ],
)
def test_an_unwritable_output_fails_before_any_work(tmp_path, command):
    (tmp_path / "file").write_text("not a folder")
    assert_one_line_error(composer(*command, cwd=tmp_path), "cannot write", "file")


@pytest.mark.parametrize(
    ("command", "line"),
    [
        (["train", "--timestep", "100"], "composer train: error: unknown option --timestep; "
         "did you mean --timesteps? (see: composer train --help)"),
        (["train", "--time", "100"], "composer train: error: unknown option --time; did you "
         "mean --timesteps? (see: composer train --help)"),
        (["run", "Reach", "--episode=3"], "composer run: error: unknown option --episode=3; "
         "did you mean --episodes? (see: composer run --help)"),
        (["--imprt", "x", "list"], "composer: error: unknown option --imprt; did you mean "
         "--import? (see: composer --help)"),
        (["trian"], "composer: error: argument COMMAND: invalid choice: 'trian' (choose from "
         "'list', 'show', 'run', 'view', 'train', 'eval'); did you mean 'train'? (see: "
         "composer --help)"),
        (["train", "--algo", "ppo2"], "composer train: error: argument --algo: invalid "
         "choice: 'ppo2' (choose from 'ppo', 'sac'); did you mean 'ppo'? (see: composer "
         "train --help)"),
        (["show", "Reach", "extra"], "composer show: error: unexpected argument 'extra' "
         "(see: composer show --help)"),
        (["run", "Reach", "--episodes", "0"], "composer run: error: argument --episodes: must "
         "be at least 1, got 0 (see: composer run --help)"),
    ],
)  # fmt: skip
def test_options_are_matched_exactly_and_mistakes_are_one_line(tmp_path, command, line):
    assert assert_one_line_error(composer(*command, cwd=tmp_path)) == line


def test_a_video_that_cannot_be_written_is_named_before_the_episodes_run(tmp_path):
    if not sys.platform.startswith("linux"):
        pytest.skip("/proc refuses new files on Linux, even to root")
    result = composer("run", "Reach", "--video", "/proc/reach.mp4", cwd=tmp_path)
    assert_one_line_error(result, "cannot write /proc/reach.mp4")
    assert "episode 1" not in result.stdout
    (tmp_path / "taken.mp4").mkdir()
    result = composer("run", "Reach", "--video", "taken.mp4", cwd=tmp_path)
    assert_one_line_error(result, "cannot write taken.mp4: it is a directory")


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (["run", "Reach", "--video", "x.txt"], "cannot write x.txt: a video is written as "
         ".mp4 or .gif, not .txt"),
        (["run", "Reach", "--video", "x.avi"], "cannot write x.avi: a video is written as "
         ".mp4 or .gif, not .avi"),
        (["run", "Reach", "--video", "clip"], "cannot write clip: a video is written as .mp4 "
         "or .gif, not a file without an extension"),
        (["show", "Reach", "--out", "frame.jpg"], "cannot write frame.jpg: a frame is written "
         "as .png, not .jpg"),
    ],
)  # fmt: skip
def test_an_output_format_we_cannot_write_is_refused_before_any_work(tmp_path, command, message):
    result = composer(*command, cwd=tmp_path)
    assert assert_one_line_error(result) == f"composer: error: {message}"
    assert result.stdout == ""  # no episode played, no scene printed
    assert list(tmp_path.iterdir()) == []


def test_the_help_names_the_video_formats_the_check_accepts(tmp_path):
    text = " ".join(composer("run", "--help", cwd=tmp_path).stdout.split())
    assert "write the episodes to this .mp4 or .gif file" in text
    for suffix in (".mp4", ".gif", ".MP4"):
        assert video.target(tmp_path / f"v{suffix}").suffix.lower() in (".mp4", ".gif")


def test_missing_policies_and_checkpoints_are_named(tmp_path):
    assert_one_line_error(
        composer("eval", "Reach", "nothing", cwd=tmp_path), "no policy at nothing"
    )
    (tmp_path / "empty").mkdir()
    assert_one_line_error(
        composer("train", "Reach", "--resume", "empty", cwd=tmp_path), "no checkpoint to resume"
    )
