"""`composer train` and `composer eval` on a tiny budget: the files, resuming, and Ctrl-C."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys

import imageio.v3 as iio
import pytest

from tests.cli.helpers import (
    FINISHED_CHOICES,
    assert_one_line_error,
    composer,
    composer_without,
    environment,
)

EVALS = ("--eval-every", "1024", "--eval-episodes", "2")
TINY = ("--algo", "ppo", "--n-envs", "2", *EVALS)

# How long training took, as the progress line says it: 45s, 1m05s or 1h02m.
DURATION = r"(\d+h)?(\d+m)?\d*s?"


def saved_files(checkpoint) -> set[str]:
    """The files of the save a checkpoint folder's state.json names (the only save there)."""
    state = json.loads((checkpoint / "state.json").read_text())
    assert {p.name for p in checkpoint.iterdir()} == {"state.json", state["saved"]}
    return {p.name for p in (checkpoint / state["saved"]).iterdir()}


def test_train_writes_its_outputs_then_eval_and_run_use_them(tmp_path):
    temp = tmp_path / "temp"  # the system's temporary folder: left as it was
    temp.mkdir()
    # Without Ray installed: the stable-baselines3 engine does not need it.
    result = composer_without(("ray",), "train", "Reach", "--timesteps", "2000", "--out", "run",
                              *TINY, cwd=tmp_path, env=environment(TMPDIR=str(temp)))  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-1] == "imported: ['stable_baselines3', 'torch']"
    # Nothing per run (stable-baselines3 made an empty SB3-<date> folder); torch keeps one
    # cache folder per user there.
    assert [p.name for p in temp.iterdir() if not p.name.startswith("torchinductor_")] == []
    # PPO collects whole rollouts: the announcement says where the run ends, and why.
    assert (
        "training Reach with PPO to 2,048 steps on 2 environments -> run\n"
        "  2,000 steps rounded up to whole rollouts of 2 environments x 128 steps (256 steps "
        "each)\n"
        "  evaluating every 1,024 steps (2 times, 2 episodes each), then once more after "
        "training\n"
    ) in result.stdout
    assert re.search(rf"^ +2,048 steps +{DURATION}  return [\d.]+ ± [\d.]+  success [\d.]+$",
                     result.stdout, re.M)  # fmt: skip
    out = tmp_path / "run"
    metrics = json.loads((out / "metrics.json").read_text())
    assert (metrics["task"], metrics["algo"], metrics["timesteps"]) == ("Reach", "ppo", 2048)
    assert metrics["completed"] and metrics["wall_time"] > 0 and metrics["cpu_time"] > 0
    assert metrics["engine"] == "sb3" and metrics["env_steps_per_second"] > 0
    assert [e["timesteps"] for e in metrics["evaluations"]] == [1024, 2048]
    assert metrics["final"] == metrics["evaluations"][-1]
    assert metrics["final"]["success_rate"] is not None  # Reach reports is_success
    assert metrics["random_policy"]["episodes"] == 2
    curve = metrics["train_curve"]  # [timesteps, mean return, episodes, success rate]
    assert sum(row[2] for row in curve) == 2 * (1024 // 75)  # 75-step episodes, 2 envs
    assert all(0 <= row[3] <= 1 for row in curve)
    assert metrics["recipe"]["n_envs"] == 2 and "n_steps" in metrics["recipe"]
    assert iio.imread(out / "learning_curve.png").shape[:2] == (450, 800)
    assert iio.imread(out / "video.mp4", plugin="FFMPEG").shape == (76, 240, 320, 3)
    assert saved_files(out / "checkpoint") == {"model.zip", "vecnormalize.pkl"}  # PPO normalizes

    # policy.zip carries the observation statistics, and eval's seeds are those of training's
    # evaluations: with as many episodes, eval repeats training's final evaluation.
    evaluated = composer("eval", "Reach", "run", "--episodes", "2", cwd=tmp_path)
    assert evaluated.returncode == 0, evaluated.stderr
    final = metrics["final"]
    assert evaluated.stdout == (
        f"Reach, policy run: return {final['mean_return']:.2f} ± {final['std_return']:.2f} "
        f"over 2 episodes, success rate {final['success_rate']:.2f}\n"
    )
    ran = composer("run", "Reach", "--policy", "run/policy.zip", cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert "Reach, policy run/policy.zip: return" in ran.stdout
    elsewhere = composer("eval", "CartpoleSwingup", "run", cwd=tmp_path)
    assert_one_line_error(elsewhere, "observations of shape (10,)", "this task has (5,)")


def test_a_finished_run_is_kept_unless_resume_or_fresh_says_what_to_do(tmp_path):
    first = composer("train", "Reach", "--timesteps", "1024", "--out", "run", "--no-video",
                     *TINY, cwd=tmp_path)  # fmt: skip
    assert first.returncode == 0, first.stderr
    policy = (tmp_path / "run" / "policy.zip").read_bytes()
    again = composer("train", "Reach", "--timesteps", "2048", "--out", "run", cwd=tmp_path)
    line = assert_one_line_error(again, "run holds a finished run: Reach with PPO, 1,024 steps")
    assert line.endswith(FINISHED_CHOICES)
    smaller = composer("train", "Reach", "--timesteps", "512", "--resume", "run", cwd=tmp_path)
    assert_one_line_error(smaller, "has 1,024 steps already", "give --timesteps above that")
    # The Ray engine neither resumes nor replaces it (nor needs Ray to say so).
    for flag in ("--resume", "--fresh"):
        ray = composer("train", "Reach", "--engine", "ray", "--out", "run", flag, cwd=tmp_path)
        assert_one_line_error(ray, "run holds a run of --engine sb3 (Reach with PPO, 1,024 steps",
                              "--engine ray can neither resume nor replace it; give --engine "
                              "sb3, or --out DIR to train elsewhere")  # fmt: skip
    (tmp_path / "policy-only").mkdir()
    (tmp_path / "policy-only" / "policy.zip").write_bytes(policy)
    ray = composer("train", "Reach", "--engine", "ray", "--out", "policy-only", cwd=tmp_path)
    assert_one_line_error(ray, "policy-only holds a policy of --engine sb3 (policy.zip): "
                          "--engine ray can neither resume nor replace it")  # fmt: skip
    assert (tmp_path / "run" / "policy.zip").read_bytes() == policy  # nothing overwritten

    resumed = composer("train", "Reach", "--timesteps", "2048", "--out", "run", "--resume",
                       "--no-video", "--n-envs", "4", *EVALS, cwd=tmp_path)  # fmt: skip
    assert resumed.returncode == 0, resumed.stderr
    assert "note: resuming keeps the checkpoint's --n-envs 2" in resumed.stdout
    assert "resuming at 1,024 steps: Reach with PPO to 2,048 steps" in resumed.stdout
    assert "; wrote policy.zip, learning_curve.png, metrics.json in run" in resumed.stdout
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert metrics["timesteps"] == 2048 and metrics["completed"]
    assert [e["timesteps"] for e in metrics["evaluations"]] == [1024, 2048]
    # 512 steps per environment in each session; the episodes the resume cut are not counted.
    assert sum(row[2] for row in metrics["train_curve"]) == 2 * 2 * (512 // 75)

    fresh = composer("train", "Reach", "--timesteps", "1024", "--out", "run", "--fresh",
                     "--no-video", *TINY, cwd=tmp_path)  # fmt: skip
    assert fresh.returncode == 0, fresh.stderr
    assert re.match(
        r"--fresh: removed the earlier run in run: checkpoint/000000002048-[0-9a-f]{6}/, "
        r"checkpoint/state.json, policy.zip, metrics.json, learning_curve.png\n"
        r"training Reach with PPO to 1,024 steps",
        fresh.stdout,
    )
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert metrics["timesteps"] == 1024 and len(metrics["evaluations"]) == 1


@pytest.mark.parametrize("engine", ["sb3", "ray"])
def test_results_without_a_checkpoint_are_not_overwritten(tmp_path, engine):
    """The rules of the output folder, checked before the engine (or Ray) starts."""
    given = ("--engine", engine)
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "metrics.json").write_text("{}")
    result = composer("train", "Reach", *given, "--out", "run", cwd=tmp_path)
    assert_one_line_error(result, "run holds results of an earlier run (metrics.json) and no "
                          "checkpoint to resume; --fresh replaces them")  # fmt: skip
    both = composer("train", "Reach", *given, "--out", "run", "--fresh", "--resume",
                    cwd=tmp_path)  # fmt: skip
    assert_one_line_error(both, "--resume and --fresh contradict each other")
    elsewhere = composer("train", "Reach", *given, "--out", "run", "--resume", "other",
                         cwd=tmp_path)  # fmt: skip
    assert_one_line_error(elsewhere, "--resume other and --out run differ; give one of them")
    nothing = composer("train", "Reach", *given, "--resume", "run", cwd=tmp_path)
    assert_one_line_error(nothing, "no checkpoint to resume in run (expected "
                          "run/checkpoint/state.json)")  # fmt: skip


def test_tensorboard_gets_the_training_and_evaluation_scalars(tmp_path):
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    result = composer("train", "Reach", "--timesteps", "1024", "--out", "run", "--no-video",
                      "--tensorboard", "tb", *TINY, cwd=tmp_path)  # fmt: skip
    assert result.returncode == 0, result.stderr
    (log,) = (tmp_path / "tb").iterdir()
    assert log.name == "run_1"  # the output folder's name, numbered by stable-baselines3
    events = EventAccumulator(str(log))
    events.Reload()
    tags = set(events.Tags()["scalars"])
    assert {"eval/mean_return", "eval/success_rate", "train/value_loss"} <= tags
    assert [e.step for e in events.Scalars("eval/mean_return")] == [1024]


def test_tensorboard_without_the_package_says_how_to_install_it(tmp_path):
    result = composer_without(("tensorboard",), "train", "Reach", "--tensorboard", "tb",
                              cwd=tmp_path)  # fmt: skip
    assert_one_line_error(result, "--tensorboard needs the tensorboard package",
                          "pip install tensorboard")  # fmt: skip


def test_ctrl_c_saves_a_checkpoint_that_loads(tmp_path):
    """SIGINT to the whole process group, as a terminal's Ctrl-C, with worker processes."""
    process = subprocess.Popen(
        [sys.executable, "-m", "composer", "train", "Reach", "--algo", "sac", "--n-envs", "2",
         "--vec", "subproc", "--timesteps", "100000", "--out", "run"],
        cwd=tmp_path, env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, start_new_session=True,
    )  # fmt: skip
    try:
        for line in process.stdout:
            if line.startswith("Ctrl-C saves a checkpoint"):
                break
        os.killpg(process.pid, signal.SIGINT)
        stdout, stderr = process.communicate(timeout=120)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert re.search(r"stopped at [\d,]+ steps .*checkpoint saved in run/checkpoint", stdout)
    checkpoint = tmp_path / "run" / "checkpoint"
    assert saved_files(checkpoint) == {"model.zip", "replay_buffer.pkl"}
    state = json.loads((checkpoint / "state.json").read_text())
    assert state["algo"] == "sac" and not state["completed"] and state["timesteps"] > 0
    assert state["engine"] == "sb3"
    evaluated = composer("eval", "Reach", "run/checkpoint", "--episodes", "1", cwd=tmp_path)
    assert evaluated.returncode == 0, evaluated.stderr

    # A total below what the stopped run has is refused; above it, the run resumes with no
    # flag (here one step of each environment more) and finishes.
    done = state["timesteps"]
    smaller = composer("train", "Reach", "--timesteps", "1", "--out", "run", cwd=tmp_path)
    assert_one_line_error(smaller, f"the run in run has {done:,} steps already")
    resumed = composer("train", "Reach", "--timesteps", str(done + 1), "--out", "run",
                       "--no-video", "--eval-episodes", "1", cwd=tmp_path)  # fmt: skip
    assert resumed.returncode == 0, resumed.stderr
    assert (
        f"resuming at {done:,} steps: Reach with SAC to {done + 2:,} steps on 2 environments "
        f"-> run\n  {done + 1:,} steps rounded up to whole steps of its 2 environments (2 "
        "steps each)\n"
    ) in resumed.stdout
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert metrics["completed"] and metrics["timesteps"] == done + 2
