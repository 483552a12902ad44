"""`composer train --engine ray`: RLlib on a real two-worker local Ray instance, the files
of the stable-baselines3 engine, eval and run of the result, resuming, Ctrl-C, and an env
runner killed mid-training. One command starts its own local instance; the others join the
session's cluster (tests/ray_cluster.py), to pay Ray's start once."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import imageio.v3 as iio
import pytest

from composer.cli.engines.ray import instance as ray_instance
from composer.cli.engines.ray.algorithm import Layout
from composer.cli.engines.ray.instance import LOOPBACK_ONLY
from tests.cli.helpers import (
    FINISHED_CHOICES,
    assert_one_line_error,
    composer,
    composer_without,
    environment,
)
from tests.ray_cluster import free_port, start_node, stop_node, wait_started

try:
    import ray.rllib  # noqa: F401

    RAY_MISSING = None
except ImportError as e:
    RAY_MISSING = f"Ray's RLlib is not installed ({e}): pip install -e '.[ray]'"
needs_ray = pytest.mark.skipif(RAY_MISSING is not None, reason=RAY_MISSING or "")

RAY = ("--engine", "ray")
# Ray starts, trains and stops in each command: far slower than a plain command.
TIMEOUT = 600

# How long training took, as the progress line says it: 45s, 1m05s or 1h02m.
DURATION = r"(\d+h)?(\d+m)?\d*s?"


def processes_started_with(marker: str) -> list[int]:
    """The live processes whose environment holds `marker` (Linux; elsewhere none)."""
    found = []
    for environ in Path("/proc").glob("[0-9]*/environ"):
        try:
            if marker.encode() in environ.read_bytes().split(b"\0"):
                found.append(int(environ.parent.name))
        except OSError:
            continue
    return found


@needs_ray
def test_ray_train_on_a_local_instance_writes_what_eval_and_run_read(tmp_path):
    # A local instance, started and stopped by the command: nothing of it is left.
    # Nor does it need stable-baselines3.
    with tempfile.TemporaryDirectory(dir="/tmp") as short:  # Ray's socket paths go in it
        result = composer_without(("stable_baselines3",), "train", "CartpoleSwingup", *RAY,
                                  "--workers", "2", "--timesteps", "8000", "--eval-episodes",
                                  "2", "--out", "run", cwd=tmp_path,
                                  env=environment(TMPDIR=short), timeout=TIMEOUT)  # fmt: skip
        assert result.returncode == 0, result.stderr
        assert result.stdout.splitlines()[-1] == "imported: ['ray', 'torch']"
        assert processes_started_with(f"TMPDIR={short}") == []
        left = [p.name for p in Path(short).iterdir() if not p.name.startswith("torchinductor_")]
        assert left == []
    assert result.stderr == ""  # no notice of Ray's that asks nothing of the user
    # 4,096 steps per iteration (32 environments x 128): the run ends at the second, and an
    # evaluation every 800 steps is due after each.
    assert (
        "training CartpoleSwingup with RLlib PPO to 8,192 steps on 2 env runners x 16 "
        "environments -> run\n  8,000 steps rounded up to whole iterations of RLlib's train "
        "batch (4,096 steps each)\n  evaluating every 800 steps (2 times, 2 episodes each), "
        "then once more after training\n"
    ) in result.stdout
    local = r"a local Ray instance, on 127\.0\.0\.1 only"  # listening on the loopback only
    runners = rf"^env runners: 2 on 127\.0\.0\.1 \(pids \d+, \d+\): {local}$"
    assert re.search(runners, result.stdout, re.M)
    progress = rf"^ +8,192 steps +{DURATION}  return [\d.]+ ± [\d.]+$"
    assert re.search(progress, result.stdout, re.M)
    out = tmp_path / "run"
    metrics = json.loads((out / "metrics.json").read_text())
    assert (metrics["engine"], metrics["workers"], metrics["envs_per_worker"]) == ("ray", 2, 16)
    assert (metrics["task"], metrics["algo"], metrics["timesteps"]) == ("CartpoleSwingup", "ppo",
                                                                        8192)  # fmt: skip
    assert metrics["completed"] and metrics["env_steps_per_second"] > 0
    assert metrics["env_runner_restarts"] == 0 and metrics["ray"]["cluster"] == "local"
    assert [e["timesteps"] for e in metrics["evaluations"]] == [4096, 8192]
    assert metrics["final"] == metrics["evaluations"][-1]
    assert metrics["recipe"]["n_envs"] == 32 and metrics["recipe"]["n_steps"] == 128
    assert sum(row[2] for row in metrics["train_curve"]) == 32 * (8192 // 32 // 200)
    assert metrics["random_policy"]["episodes"] == 2
    assert iio.imread(out / "learning_curve.png").shape[:2] == (450, 800)
    assert iio.imread(out / "video.mp4", plugin="FFMPEG").shape[1:] == (240, 320, 3)
    assert {p.name for p in (out / "policy").iterdir()} == {"module", "policy.json", "weights.npz"}

    # The policy carries its observation filter, and eval's default seeds are those of
    # training's evaluations: eval of as many episodes repeats training's final evaluation.
    evaluated = composer("eval", "CartpoleSwingup", "run", "--episodes", "2", cwd=tmp_path)
    assert evaluated.returncode == 0, evaluated.stderr
    final = metrics["final"]
    assert evaluated.stdout == (
        f"CartpoleSwingup, policy run: return {final['mean_return']:.2f} ± "
        f"{final['std_return']:.2f} over 2 episodes\n"
    )
    # Read from weights.npz (the default) or by RLlib from module/: the same policy.
    trusted = composer("eval", "CartpoleSwingup", "run", "--episodes", "2", "--trust-policy",
                       cwd=tmp_path)  # fmt: skip
    assert trusted.stdout == evaluated.stdout
    ran = composer("run", "CartpoleSwingup", "--policy", "run/policy", cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert "CartpoleSwingup, policy run/policy: return" in ran.stdout
    elsewhere = composer("eval", "Reach", "run", cwd=tmp_path)
    assert_one_line_error(elsewhere, "observations of shape (5,)", "this task has (10,)")


@needs_ray
def test_a_ray_run_keeps_the_folder_rules_resumes_on_other_workers_and_is_replaced(
    tmp_path, ray_cluster
):
    """On the session's cluster: a finished run of two env runners, the output folder's
    rules, resuming it on one runner, and replacing it with --fresh."""
    cluster = ("--address", ray_cluster.address)
    first = composer("train", "CartpoleSwingup", *RAY, *cluster, "--workers", "2",
                     "--envs-per-worker", "4", "--timesteps", "2000", "--eval-episodes", "1",
                     "--out", "run", "--no-video", cwd=tmp_path, env=ray_cluster.environment(),
                     timeout=TIMEOUT)  # fmt: skip
    assert first.returncode == 0, first.stderr
    assert "to 2,048 steps on 2 env runners x 4 environments -> run\n" in first.stdout
    assert re.search(r"^env runners: 2 on 127\.0\.0\.1 \(pids \d+, \d+\)$", first.stdout, re.M)
    out = tmp_path / "run"

    # The rules of the output folder are the stable-baselines3 engine's, checked before
    # Ray starts: a finished run is kept unless --resume or --fresh says what to do, ...
    files = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    again = composer("train", "CartpoleSwingup", *RAY, "--timesteps", "3000", "--out", "run",
                     cwd=tmp_path)  # fmt: skip
    line = assert_one_line_error(again, "run holds a finished run: CartpoleSwingup with PPO, "
                                 "2,048 steps")  # fmt: skip
    assert line.endswith(FINISHED_CHOICES)
    smaller = composer("train", "CartpoleSwingup", *RAY, "--timesteps", "2048", "--resume",
                       "run", cwd=tmp_path)  # fmt: skip
    assert_one_line_error(smaller, "the run in run has 2,048 steps already",
                          "give --timesteps above that")  # fmt: skip
    # ... the stable-baselines3 engine neither resumes nor replaces it ...
    for flag in ("--resume", "--fresh"):
        sb3 = composer("train", "CartpoleSwingup", "--out", "run", flag, cwd=tmp_path)
        assert_one_line_error(sb3, "run holds a run of --engine ray (CartpoleSwingup with PPO, "
                              "2,048 steps", "--engine sb3 can neither resume nor replace it; "
                              "give --engine ray, or --out DIR")  # fmt: skip
    shutil.copytree(out / "policy", tmp_path / "policy-only" / "policy")
    sb3 = composer("train", "CartpoleSwingup", "--out", "policy-only", cwd=tmp_path)
    assert_one_line_error(sb3, "policy-only holds a policy of --engine ray (policy): --engine "
                          "sb3 can neither resume nor replace it")  # fmt: skip
    # ... and --fresh removes the earlier run only once the new one can train.
    port = free_port()
    unreachable = composer("train", "CartpoleSwingup", *RAY, "--out", "run", "--fresh",
                           "--address", f"127.0.0.1:{port}", cwd=tmp_path)  # fmt: skip
    assert_one_line_error(unreachable, f"cannot reach the Ray cluster at 127.0.0.1:{port}")
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == files

    # Resumed on one env runner, the run keeps its recipe: its batch stays 1,024 (2 x 4 x 128).
    resumed = composer("train", "CartpoleSwingup", *RAY, *cluster, "--workers", "1",
                       "--timesteps", "3000", "--resume", "--out", "run", "--no-video",
                       cwd=tmp_path, env=ray_cluster.environment(), timeout=TIMEOUT)  # fmt: skip
    assert resumed.returncode == 0, resumed.stderr
    assert (
        "resuming at 2,048 steps: CartpoleSwingup with RLlib PPO to 3,072 steps on 1 env "
        "runner x 4 environments -> run\n  3,000 steps rounded up to whole iterations of "
        "RLlib's train batch (1,024 steps each)\n"
    ) in resumed.stdout
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["timesteps"] == 3072 and metrics["workers"] == 1
    assert [e["timesteps"] for e in metrics["evaluations"]] == [1024, 2048, 3072]
    # Resumed environments start new episodes: 4 of 256 steps each, 1 episode each (and 8
    # of the first session's).
    assert sum(row[2] for row in metrics["train_curve"]) == 8 + 4
    (saved,) = (p.name for p in (out / "checkpoint").iterdir() if p.is_dir())

    # --fresh replaces the run with a new one (one iteration: 2 environments x 128 steps,
    # PPO's minibatch of 256), and leaves nothing in ~/ray_results.
    home = tmp_path / "home"
    fresh = composer("train", "CartpoleSwingup", *RAY, *cluster, "--workers", "1",
                     "--envs-per-worker", "2", "--timesteps", "256", "--eval-episodes", "1",
                     "--out", "run", "--fresh", "--no-video", cwd=tmp_path,
                     env=ray_cluster.environment(HOME=str(home)), timeout=TIMEOUT)  # fmt: skip
    assert fresh.returncode == 0, fresh.stderr
    assert fresh.stdout.startswith(
        f"--fresh: removed the earlier run in run: checkpoint/{saved}/, checkpoint/state.json, "
        "policy/, metrics.json, learning_curve.png\ntraining CartpoleSwingup with RLlib PPO to "
        "256 steps on 1 env runner x 2 environments -> run\n"
    )
    metrics = json.loads((out / "metrics.json").read_text())
    assert (metrics["timesteps"], len(metrics["evaluations"])) == (256, 1)
    assert not (out / "video.mp4").exists()
    assert (home / "ray_results").is_dir() and not any((home / "ray_results").iterdir())


@needs_ray
def test_killing_an_env_runner_does_not_end_training_and_ctrl_c_saves(tmp_path, ray_cluster):
    """SIGKILL one env runner's process, as a crash or a lost machine would; later SIGINT
    to the whole process group, as a terminal's Ctrl-C."""
    command = ["train", "CartpoleSwingup", *RAY, "--address", ray_cluster.address, "--workers",
               "2", "--envs-per-worker", "2", "--timesteps", "10000000", "--eval-every", "1024",
               "--eval-episodes", "1", "--out", "run", "--no-video"]  # fmt: skip
    process = subprocess.Popen(
        [sys.executable, "-m", "composer", *command], cwd=tmp_path, env=ray_cluster.environment(),
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip
    # A restart that never comes must not hang the suite.
    watchdog = threading.Timer(TIMEOUT, os.killpg, (process.pid, signal.SIGKILL))
    watchdog.start()
    seen: list[str] = []
    try:
        pids, killed, evaluations_after = [], None, 0
        for line in process.stdout:
            seen.append(line)
            if line.startswith("env runners:") and not pids:
                pids = [int(pid) for pid in re.findall(r"\d+", line.partition("pids")[2])]
            elif re.match(r" +[\d,]+ steps +\S+  return ", line):  # an evaluation
                if killed is None:
                    killed = int(line.split()[0].replace(",", ""))
                    os.kill(pids[0], signal.SIGKILL)
                elif any(s.startswith("env runner restarted") for s in seen):
                    evaluations_after += 1
                    if evaluations_after == 2:
                        break
        os.killpg(process.pid, signal.SIGINT)
        stdout, stderr = process.communicate(timeout=TIMEOUT)
    finally:
        watchdog.cancel()
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    text = "".join(seen) + stdout
    assert process.returncode == 130, (text, stderr)
    assert "Traceback" not in stderr
    restarted = re.search(r"^env runner restarted \(1 restart in this run\); env runners: "
                          r"2 on [\d.]+ \(pids (\d+), (\d+)\)$", text, re.M)  # fmt: skip
    assert restarted and pids[0] not in map(int, restarted.groups()), text
    assert re.search(r"stopped at [\d,]+ steps .*checkpoint saved in run/checkpoint", text)

    state = json.loads((tmp_path / "run" / "checkpoint" / "state.json").read_text())
    assert state["engine"] == "ray" and not state["completed"]
    assert state["env_runner_restarts"] == 1
    # No lost progress: every 1,024-step iteration was sampled and evaluated, before,
    # during and after the restart.
    steps = [e["timesteps"] for e in state["evaluations"]]
    assert steps == [1024 * i for i in range(1, len(steps) + 1)] and steps[-1] > killed
    assert state["timesteps"] >= steps[-1]

    evaluated = composer("eval", "CartpoleSwingup", "run/checkpoint", "--episodes", "1",
                         cwd=tmp_path)  # fmt: skip
    assert evaluated.returncode == 0, evaluated.stderr
    # A total below what the stopped run has is refused; above it, the run resumes with no
    # flag (here for one more iteration) and finishes, its evaluations and restarts kept.
    done = state["timesteps"]
    smaller = [("1024" if word == "10000000" else word) for word in command]
    assert_one_line_error(composer(*smaller, cwd=tmp_path, env=ray_cluster.environment()),
                          f"the run in run has {done:,} steps already")  # fmt: skip
    more = [(str(done + 1) if word == "10000000" else word) for word in command]
    finished = composer(*more, cwd=tmp_path, env=ray_cluster.environment(), timeout=TIMEOUT)
    assert finished.returncode == 0, finished.stderr
    assert f"resuming at {done:,} steps: CartpoleSwingup with RLlib PPO" in finished.stdout
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert metrics["completed"] and metrics["env_runner_restarts"] == 1
    assert metrics["evaluations"][: len(steps)] == state["evaluations"]
    # One iteration: 2 runners x 2 environments x 128 steps.
    assert metrics["timesteps"] == metrics["evaluations"][-1]["timesteps"] == done + 512


@needs_ray
def test_joins_a_cluster_of_two_nodes_started_with_ray_start(tmp_path):
    """`ray start --head` and `ray start --address=...` (two nodes of one CPU, here on one
    machine, with a token of their own), then training with --address spreads the env
    runners over both."""
    port = free_port()
    token = os.urandom(16).hex()
    # Two nodes make a cluster of machines, which Ray's switch for one machine refuses: its
    # nodes listen on this machine's interface address, as on a real cluster.
    several = {LOOPBACK_ONLY: "1"}
    env = environment(RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=token, **several)
    temp = tempfile.mkdtemp(prefix="ray", dir="/tmp")  # Ray's socket paths must be short
    head, worker = tmp_path / "head.log", tmp_path / "worker.log"
    nodes = [start_node("--head", "--port", str(port), "--include-dashboard", "false",
                        "--temp-dir", temp, env=env, log=head, cpus=1)]  # fmt: skip
    try:
        wait_started(nodes[0], head)
        nodes.append(start_node("--address", f"127.0.0.1:{port}", env=env, log=worker, cpus=1))
        wait_started(nodes[1], worker)
        # The token alone, as a user copies it: the command joins in token mode itself.
        result = composer("train", "CartpoleSwingup", *RAY, "--address", f"127.0.0.1:{port}",
                          "--envs-per-worker", "2", "--timesteps", "2048", "--eval-episodes",
                          "1", "--out", "run", "--no-video", cwd=tmp_path,
                          env=environment(RAY_AUTH_TOKEN=token, **several),
                          timeout=TIMEOUT)  # fmt: skip
    finally:
        for node in reversed(nodes):
            stop_node(node.pid)
        shutil.rmtree(temp, ignore_errors=True)
    assert result.returncode == 0, result.stderr
    assert "on 2 env runners x 2 environments" in result.stdout  # the cluster's two CPUs
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert metrics["ray"]["cluster"] == f"127.0.0.1:{port}"
    assert (metrics["ray"]["nodes"], metrics["ray"]["cpus"], metrics["workers"]) == (2, 2, 2)
    assert metrics["timesteps"] == 2048 and metrics["completed"]


def test_more_env_runners_than_cpus_on_this_machine_is_said():
    cpus = ray_instance.machine_cpus()
    note = ray_instance.oversubscribed(Layout(cpus + 1, 2, None))
    assert note == (
        f"note: {cpus + 1} env runners on this machine's {cpus} CPUs take turns on them: "
        f"sampling is no faster than with --workers {cpus} (see docs/ray.md)"
    )
    assert ray_instance.oversubscribed(Layout(cpus, 2, None)) is None
    assert ray_instance.oversubscribed(Layout(cpus + 1, 2, "10.0.0.1:6379")) is None  # a cluster's


def test_a_long_temporary_folder_puts_ray_s_session_in_tmp(monkeypatch, tmp_path):
    # Ray's socket paths inside the session folder must fit in 107 bytes (macOS's TMPDIR).
    long = tmp_path / ("x" * 60)
    long.mkdir()
    monkeypatch.delenv("RAY_TMPDIR", raising=False)
    monkeypatch.setenv("TMPDIR", str(long))
    monkeypatch.setattr(tempfile, "tempdir", None)  # tempfile caches what it found
    assert ray_instance._temp_root() == "/tmp"
    monkeypatch.setenv("RAY_TMPDIR", str(long))  # asked for: Ray's own variable
    assert ray_instance._temp_root() == str(long)


def test_options_of_the_other_engine_are_refused(tmp_path):
    mixed = composer("train", "Reach", *RAY, "--n-envs", "4", cwd=tmp_path)
    assert_one_line_error(mixed, "--n-envs belongs to the stable-baselines3 engine; with "
                          "--engine ray give --workers and --envs-per-worker")  # fmt: skip
    # RLlib writes TensorBoard files only under Ray Tune, which the engine does not run.
    logged = composer("train", "Reach", *RAY, "--vec", "dummy", "--tensorboard", "tb",
                      cwd=tmp_path)  # fmt: skip
    assert_one_line_error(logged, "--vec and --tensorboard belong to the stable-baselines3 "
                          "engine", "--engine ray logs no TensorBoard scalars")  # fmt: skip
    assert not (tmp_path / "tb").exists()
    sb3 = composer("train", "Reach", "--workers", "2", "--address", "auto", cwd=tmp_path)
    assert_one_line_error(sb3, "--workers and --address need --engine ray")


@needs_ray
def test_an_unreachable_cluster_fails_at_once(tmp_path):
    port = free_port()
    result = composer("train", "Reach", *RAY, "--address", f"127.0.0.1:{port}", cwd=tmp_path)
    assert_one_line_error(result, f"cannot reach the Ray cluster at 127.0.0.1:{port}",
                          "ray start --head")  # fmt: skip
    malformed = composer("train", "Reach", *RAY, "--address", "headnode", cwd=tmp_path)
    assert_one_line_error(malformed, "--address 'headnode': expected HOST:PORT")


def test_without_ray_the_engine_names_the_extra_to_install(tmp_path):
    result = composer_without(("ray",), "train", "Reach", *RAY, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    assert "--engine ray needs the [ray] extra" in result.stderr
    assert result.stderr.rstrip().endswith("pip install -e '.[ray]'")


def test_without_ray_a_ray_policy_names_the_extra_to_install(tmp_path):
    policy = tmp_path / "run" / "policy"
    policy.mkdir(parents=True)
    (policy / "policy.json").write_text(json.dumps({"format": "composer-rllib-policy"}))
    result = composer_without(("ray",), "eval", "Reach", "run", cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    assert "run/policy was trained with --engine ray: loading it needs the [ray] extra" in (
        result.stderr
    )
