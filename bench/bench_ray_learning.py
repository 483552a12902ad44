"""Learning on Ray: CartpoleSwingup trained by `composer train --engine ray` against the
stable-baselines3 recipe, the time each takes to reach the same evaluation return.

    python bench/bench_ray_learning.py        # two full runs of the recipe, ~5 minutes
    python -m bench ray_learning

Both runs are the command line itself, one after the other, with the task's recipe
(PPO, 300k steps, 16 environments: 2 env runners x 8 on Ray), an evaluation (10 episodes,
fixed seeds) every EVAL_EVERY steps and no video. A run reaches the threshold at its
first evaluation whose mean return is at least THRESHOLD (SB3's recipe passes it about
halfway; a random policy scores about 18). Times are counted two ways: training time
(the run's own clock, metrics.json's evaluation wall_time: from the first step) and end
to end (from starting the command: Python, Ray and the env runners' start-up included).
Target: Ray within 2x SB3's time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
TASK = "CartpoleSwingup"
THRESHOLD = 150.0
EVAL_EVERY = 15_000
ENGINES = {"sb3": (), "ray": ("--engine", "ray", "--workers", "2")}


def train(engine: str, out: Path, quick: bool) -> dict[str, Any]:
    """Run `composer train` with `engine`; its metrics, with 'started' (seconds from the
    command's start to its first step) and 'elapsed' (to its end)."""
    budget = ("--timesteps", "8192", "--eval-every", "4096") if quick else (
        "--eval-every", str(EVAL_EVERY))  # fmt: skip
    command = [sys.executable, "-m", "composer", "train", TASK, *ENGINES[engine],
               "--out", str(out), "--no-video", *budget]  # fmt: skip
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO),
           os.environ.get("PYTHONPATH")])), "MUJOCO_GL": "egl"}  # fmt: skip
    start = time.perf_counter()
    started = None
    with subprocess.Popen(command, stdout=subprocess.PIPE, text=True, env=env) as process:
        for line in process.stdout:
            if started is None and line.startswith("Ctrl-C saves"):
                started = time.perf_counter() - start
    elapsed = time.perf_counter() - start
    if process.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited with {process.returncode}")
    metrics = json.loads((out / "metrics.json").read_text())
    return {**metrics, "started": started or 0.0, "elapsed": elapsed}


def reached(metrics: dict[str, Any], threshold: float) -> dict[str, Any] | None:
    """The first evaluation at or above `threshold`, or None."""
    return next((e for e in metrics["evaluations"] if e["mean_return"] >= threshold), None)


def main(quick: bool = False) -> dict[str, Any]:
    """Train with both engines and print when each reached the threshold."""
    try:
        import ray  # noqa: F401
    except ImportError:
        print("skipped: Ray is not installed (pip install -e '.[ray]')")
        return {}
    threshold = 0.0 if quick else THRESHOLD
    results: dict[str, Any] = {"threshold": threshold}
    with tempfile.TemporaryDirectory() as folder:
        for engine in ENGINES:
            metrics = train(engine, Path(folder) / engine, quick)
            first = reached(metrics, threshold)
            results[engine] = {
                "steps_to_threshold": first and first["timesteps"],
                "training_seconds_to_threshold": first and first["wall_time"],
                "seconds_to_threshold": first and metrics["started"] + first["wall_time"],
                "startup_seconds": metrics["started"],
                "final_return": metrics["final"]["mean_return"],
                "training_seconds": metrics["wall_time"],
                "steps_per_second": metrics["timesteps"] / metrics["wall_time"],
            }
    sb3, ray_ = results["sb3"], results["ray"]
    for engine in ENGINES:
        r = results[engine]
        at = (f"{r['steps_to_threshold']:,} steps, {r['training_seconds_to_threshold']:.0f} s "
              f"training, {r['seconds_to_threshold']:.0f} s end to end"
              if r["steps_to_threshold"] else "not reached")  # fmt: skip
        print(f"  {engine:4} return >= {threshold:g} at {at}; start-up {r['startup_seconds']:.0f}"
              f" s; final return {r['final_return']:.1f} after {r['training_seconds']:.0f} s "
              f"({r['steps_per_second']:.0f} steps/s)")  # fmt: skip
    if sb3["steps_to_threshold"] and ray_["steps_to_threshold"]:
        results["ray_vs_sb3_training_time"] = (
            ray_["training_seconds_to_threshold"] / sb3["training_seconds_to_threshold"]
        )
        results["ray_vs_sb3_end_to_end"] = (
            ray_["seconds_to_threshold"] / sb3["seconds_to_threshold"]
        )
        training, end_to_end = (results[f"ray_vs_sb3_{k}"] for k in ("training_time", "end_to_end"))
        print(f"  ray / sb3 time to the threshold: {training:.2f}x training, {end_to_end:.2f}x "
              "end to end (target <= 2)")  # fmt: skip
    return results


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
