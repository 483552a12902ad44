"""The learning-curve PNG of a training run, drawn with matplotlib's Agg canvas (no display,
no pyplot global state).

    plot.learning_curve(metrics, 'runs/Reach-ppo/learning_curve.png')

`metrics` is what `composer train` writes to metrics.json: evaluation returns (mean ± std)
and success rate (or, for the runners, forward speed) against timesteps, the mean return
of training episodes, and the random policy's return as a dashed line.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from composer.cli.errors import MissingExtraError, OutputError

try:
    from matplotlib.figure import Figure
except ImportError as e:
    raise MissingExtraError(
        "plotting needs matplotlib, in the [train] and [ray] extras: pip install matplotlib"
    ) from e


def learning_curve(metrics: dict[str, Any], path: str | os.PathLike[str]) -> None:
    """Draw `metrics` into the PNG `path`; raises OutputError if it cannot be written."""
    figure = Figure(figsize=(8, 4.5), dpi=100, layout="constrained")
    axes = figure.add_subplot()
    curve = np.array([row[:2] for row in metrics["train_curve"]], dtype=float)
    if len(curve):
        axes.plot(curve[:, 0], curve[:, 1], color="tab:blue", lw=1, label="training episodes")
    evaluations = metrics["evaluations"]
    if evaluations:
        steps = np.array([e["timesteps"] for e in evaluations], dtype=float)
        mean = np.array([e["mean_return"] for e in evaluations])
        std = np.array([e["std_return"] for e in evaluations])
        axes.plot(steps, mean, "o-", color="tab:orange", lw=2, label="evaluation (mean ± std)")
        axes.fill_between(steps, mean - std, mean + std, color="tab:orange", alpha=0.2)
    random = metrics.get("random_policy")
    if random:
        axes.axhline(random["mean_return"], color="gray", ls="--", label="random policy")
    axes.set_xlabel("timesteps")
    axes.set_ylabel("episode return")
    axes.grid(alpha=0.3)
    for key, label in (("success_rate", "success rate"), ("forward_speed", "forward speed (m/s)")):
        points = [(e["timesteps"], e[key]) for e in evaluations if e.get(key) is not None]
        if points:
            right = axes.twinx()
            right.plot(*zip(*points, strict=True), "s:", color="tab:green", label=label)
            if key == "success_rate":
                right.set_ylim(-0.02, 1.02)
            else:  # from standing still, so the scale shows how far from it
                right.set_ylim(bottom=min(0.0, *(value for _, value in points)))
            right.set_ylabel(label)
            right.legend(loc="lower right")
            break
    axes.legend(loc="upper left")
    minutes = metrics["wall_time"] / 60
    axes.set_title(
        f"{metrics['task']} · {metrics['algo'].upper()} · {metrics['timesteps']:,} steps "
        f"in {minutes:.1f} min"
    )
    try:
        figure.savefig(path)
    except OSError as e:
        raise OutputError(f"cannot write {path}: {e.strerror or e}") from e
