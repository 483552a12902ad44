"""`composer run`: roll out a random policy, print returns, record a video."""

from __future__ import annotations

import re

import imageio.v3 as iio
import numpy as np

from composer.cli import catalog, rollout, video
from tests.cli.helpers import composer

EPISODE = re.compile(r"^episode (\d): return (-?[\d.]+) over 75 steps, (?:no )?success$", re.M)


def test_run_prints_the_return_and_writes_a_video(tmp_path):
    result = composer("run", "Reach", "--seed", "7", "--video", "out/reach.mp4", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    (episode,) = EPISODE.findall(result.stdout)
    assert re.search(
        rf"^Reach, random policy: return {episode[1]} ± 0.00 over 1 episode, success rate "
        r"0.00$", result.stdout, re.M,
    )  # fmt: skip
    assert "video: out/reach.mp4 (3.0 s)" in result.stdout  # 75 steps + the last frame, 25 fps
    frames = iio.imread(tmp_path / "out" / "reach.mp4", plugin="FFMPEG")
    assert frames.shape == (76, 240, 320, 3)
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 0.1  # it moves


def test_the_same_seed_gives_the_same_episodes(tmp_path):
    first, second, other = (
        composer("run", "Reach", "--episodes", "2", "--seed", seed, cwd=tmp_path)
        for seed in ("3", "3", "4")
    )
    assert first.returncode == 0, first.stderr
    assert len(EPISODE.findall(first.stdout)) == 2
    assert first.stdout == second.stdout
    assert EPISODE.findall(other.stdout) != EPISODE.findall(first.stdout)


def test_a_video_is_a_gif_when_ffmpeg_is_missing(tmp_path, monkeypatch):
    monkeypatch.setattr(video, "ffmpeg_available", lambda: False)
    frames = [np.full((48, 64, 3), value, np.uint8) for value in (0, 120, 240)]
    written = video.write_video(frames, tmp_path / "clip.mp4", fps=10)
    assert written == tmp_path / "clip.gif"
    assert not (tmp_path / "clip.mp4").exists()
    read = iio.imread(written, index=None)
    assert read.shape[:3] == (3, 48, 64)
    assert [int(frame[..., :3].mean()) for frame in read] == [0, 120, 240]


def test_a_png_frame_round_trips(tmp_path):
    frame = np.random.default_rng(0).integers(0, 256, (5, 7, 3), dtype=np.uint8)
    path = video.write_png(frame, tmp_path / "f.png")
    np.testing.assert_array_equal(iio.imread(path), frame)


def test_runners_report_their_forward_speed(tmp_path):
    result = composer("run", "WalkerRun", "--episodes", "2", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    speeds = re.findall(r"^episode \d: return -?[\d.]+ over \d+ steps, (-?[\d.]+) m/s$",
                        result.stdout, re.M)  # fmt: skip
    assert len(speeds) == 2
    summary = re.search(r"forward speed (-?[\d.]+) m/s$", result.stdout, re.M)
    assert abs(float(summary[1]) - np.mean([float(s) for s in speeds])) <= 0.01


def test_forward_speed_is_the_mean_of_the_torso_s_forward_velocity_over_the_steps():
    env = catalog.make(catalog.find("WalkerRun"))
    (episode,) = rollout.run_episodes(env, rollout.random_policy(env, 5), 1, seed=5)
    env.reset(seed=5)
    policy, root_x = rollout.random_policy(env, 5), env.physics.bind(env.task.robot.root_x)
    velocities, finished = [], False
    while not finished:
        *_, terminated, truncated, _ = env.step(policy(None))
        velocities.append(float(root_x.qvel[0]))
        finished = terminated or truncated
    assert episode.length == len(velocities)
    assert episode.forward_speed == sum(velocities) / len(velocities)
