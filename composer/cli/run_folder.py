"""What `composer train` keeps in its output folder, and what a new command may do there.

    run_folder.prepare(out, checkpoint, resume=False, fresh=False)   # raises or clears

A folder that holds a finished run (a checkpoint marked completed, or results with no
checkpoint) is never trained over silently: `prepare` raises CliError saying what is there
and what to do, unless `resume` (continue it, to a larger --timesteps) or `fresh` (remove
the earlier run's files first: only those `composer train` writes, nothing else). A run
that was stopped before it finished resumes without a flag.
"""

from __future__ import annotations

from pathlib import Path

from composer.cli import training
from composer.cli.errors import CliError, OutputError

# The files a finished run leaves beside its checkpoint.
RESULTS = ("policy.zip", "metrics.json", "learning_curve.png", "video.mp4", "video.gif")
CHOICES = "--resume continues it (to a larger --timesteps), --fresh replaces it, --out DIR "


def prepare(out: Path, checkpoint: training.Checkpoint, resume: bool, fresh: bool) -> None:
    """Check that training may go on in `out`, or with `fresh` clear it (saying what was
    removed). Raises CliError for a finished run or left-over results without a flag."""
    if fresh:
        removed = clear(out, checkpoint)
        if removed:
            print(f"--fresh: removed the earlier run in {out}: {', '.join(removed)}")
        return
    if resume:
        return
    if checkpoint.exists():
        progress = checkpoint.progress()
        if progress.completed:
            raise CliError(
                f"{out} holds a finished run: {describe(progress)}; {CHOICES}trains elsewhere"
            )
        return
    results = [name for name in RESULTS if (out / name).exists()]
    if results:
        raise CliError(
            f"{out} holds results of an earlier run ({', '.join(results)}) and no checkpoint "
            "to resume; --fresh replaces them, --out DIR trains elsewhere"
        )


def describe(progress: training.Progress) -> str:
    """'Reach with PPO, 800,768 steps in 4m13s, last evaluation: return 61.57, success
    1.00'."""
    text = (
        f"{progress.task} with {progress.algo.upper()}, {progress.timesteps:,} steps in "
        f"{training.duration(progress.wall_time)}"
    )
    if progress.evaluations:
        last = progress.evaluations[-1]
        text += f", last evaluation: return {last['mean_return']:.2f}"
        if last.get("success_rate") is not None:
            text += f", success {last['success_rate']:.2f}"
    return text


def clear(out: Path, checkpoint: training.Checkpoint) -> list[str]:
    """Remove the files `composer train` wrote in `out` (checkpoint and results); returns
    their names. Raises OutputError when one cannot be removed."""
    folder = checkpoint.folder
    saved = [checkpoint.model_path, checkpoint.buffer_path, checkpoint.normalization_path,
             checkpoint.state_path]  # fmt: skip
    partial = sorted(folder.glob(".*.partial*")) if folder.is_dir() else []
    files = [p for p in [*saved, *partial, *(out / n for n in RESULTS)] if p.is_file()]
    try:
        for path in files:
            path.unlink()
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    except OSError as e:
        raise OutputError(f"--fresh cannot remove the earlier run in {out}: {e}") from e
    return [str(p.relative_to(out)) for p in files]
