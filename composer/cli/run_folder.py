"""What `composer train` keeps in its output folder, and what a new command may do there,
the same for every engine.

    folder = run_folder.prepare(args, engines.get('sb3'))    # raises CliError, or
    progress, recipe = folder.start(args, new_recipe)        # the run resumed, or a new one
    run_folder.clear_if_fresh(folder, engine)                # --fresh: once training starts

Promise (`prepare` states each rule): a finished run is never trained over silently, nor
another engine's run; `--fresh` removes only what the engine wrote, once the new run is ready.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path
from typing import Any

from composer.cli import describe, engines, recipes
from composer.cli.engines.base import Checkpoint, CheckpointType, Engine, Progress, RunFolder
from composer.cli.errors import CliError, OutputError, PolicyError

# What a finished run writes beside its checkpoint and its policy, whatever the engine.
METRICS = "metrics.json"
CURVE = "learning_curve.png"
VIDEO = "video.mp4"  # a GIF beside it where ffmpeg is missing (composer.cli.video)
RESULTS = (METRICS, CURVE, VIDEO, Path(VIDEO).with_suffix(".gif").name)
CHOICES = "--resume continues it (to a larger --timesteps), --fresh replaces it, --out DIR "


def prepare(args: argparse.Namespace, engine: Engine[CheckpointType]) -> RunFolder[CheckpointType]:
    """The output folder of `composer train` with `engine` (--resume DIR, --out, or
    runs/TASK-ALGO, with '-ENGINE' for other engines than the default), checked against
    these rules. Raises CliError (a PolicyError for a checkpoint that cannot be resumed);
    writes nothing.

    - A folder that holds a finished run (a checkpoint marked completed, or results and no
      checkpoint) is never trained over silently: it says what is there and refuses, unless
      `--resume` (train it on, to a larger `--timesteps`) or `--fresh` (replace it) says what
      to do. A run that was stopped before it finished resumes without a flag.
    - `--fresh` removes only what the engine writes: its checkpoint's files, its policy, and
      the results every engine writes (metrics.json, learning_curve.png, the video), and only
      when the new run is ready to train (`clear_if_fresh`), so a run that cannot start (Ray
      unreachable, say) leaves the earlier one in place.
    - `--resume` needs a checkpoint, contradicts `--fresh`, and `--resume DIR` an `--out`
      elsewhere. A resumed run keeps its task and algorithm (others are refused) and its
      recipe, environments and seed (a note says so when others are given).
    - A run trains on only to more than its timesteps: a finished run needs a larger
      `--timesteps`; a stopped one may be given its own total even when its last update passed
      it (the same command then evaluates it and writes the results), but no smaller one.
    - A folder holding another engine's checkpoint or policy is refused, even with `--resume`
      or `--fresh`: the engine that wrote it resumes or replaces it.
    """
    if args.resume and args.fresh:
        raise CliError("--resume and --fresh contradict each other; give one of them")
    resume = args.resume if isinstance(args.resume, str) else None  # --resume alone: True
    if resume and args.out and Path(resume) != Path(args.out):
        raise CliError(f"--resume {resume} and --out {args.out} differ; give one of them")
    info = args.info
    suffix = "" if engine.name == engines.DEFAULT else f"-{engine.name}"
    default = Path("runs") / f"{info.name}-{args.algo or recipes.default_algo(info)}{suffix}"
    out = Path(resume or args.out or default)
    checkpoint = engine.checkpoint(out / "checkpoint")
    _refuse_other_engines(out, checkpoint)
    if args.resume and not checkpoint.exists():
        raise PolicyError(f"no checkpoint to resume in {out} (expected {checkpoint.state_path})")
    if args.fresh:
        return RunFolder(out, checkpoint, fresh=True, resumed=None)
    if checkpoint.exists():
        progress = checkpoint.progress()
        if progress.completed and not args.resume:
            raise CliError(
                f"{out} holds a finished run: {describe_run(progress)}; {CHOICES}trains elsewhere"
            )
        resumed = _resumed(out, progress, args, engine)
        return RunFolder(out, checkpoint, fresh=False, resumed=resumed)
    results = [name for name in (engine.policy, *RESULTS) if (out / name).exists()]
    if results:
        raise CliError(
            f"{out} holds results of an earlier run ({', '.join(results)}) and no checkpoint "
            "to resume; --fresh replaces them, --out DIR trains elsewhere"
        )
    return RunFolder(out, checkpoint, fresh=False, resumed=None)


def _refuse_other_engines(out: Path, checkpoint: Checkpoint) -> None:
    """Raise CliError when `out` holds a checkpoint or a policy of another engine."""
    ours = checkpoint.engine
    theirs = checkpoint.written_by()
    if theirs is not None and theirs != ours:
        found = f"a run of --engine {theirs} ({describe_run(checkpoint.progress())})"
    else:
        others = [e for e in engines.every() if e.name != ours and (out / e.policy).exists()]
        if not others:
            return
        theirs = others[0].name
        found = f"a policy of --engine {theirs} ({others[0].policy})"
    raise CliError(
        f"{out} holds {found}: --engine {ours} can neither resume nor replace it; "
        f"give --engine {theirs}, or --out DIR to train elsewhere"
    )


def _resumed(
    out: Path, progress: Progress, args: argparse.Namespace, engine: Engine[Any]
) -> tuple[Progress, recipes.Recipe]:
    """The checkpoint's progress and recipe, trained on to --timesteps if given. Raises
    PolicyError for another task or algorithm, CliError for a total it cannot train to."""
    task = args.info.name
    if progress.task != task:
        raise PolicyError(
            f"the checkpoint in {out} is of task {progress.task!r}, not {task!r}; "
            "choose another --out folder"
        )
    if args.algo and args.algo != progress.algo:
        raise PolicyError(
            f"the checkpoint in {out} was trained with {progress.algo}, not {args.algo}; "
            "choose another --out folder"
        )
    recipe = recipes.Recipe.from_table(progress.recipe)
    kept_values = [(name, getattr(recipe, name)) for name in engine.recipe_options]
    for name, kept in [*kept_values, ("seed", progress.seed)]:
        given = getattr(args, name, None)
        if given is not None and given != kept:
            print(f"note: resuming keeps the checkpoint's --{name.replace('_', '-')} {kept}")
    total = args.timesteps or recipe.timesteps
    if total <= progress.timesteps and (progress.completed or total != recipe.timesteps):
        raise CliError(
            f"the run in {out} has {progress.timesteps:,} steps already "
            f"({describe_run(progress)}); give --timesteps above that to train on"
        )
    return progress, recipe.replace(timesteps=total)


def describe_run(progress: Progress) -> str:
    """'Reach with PPO, 800,768 steps in 4m13s, last evaluation: return 61.57, success
    1.00'."""
    text = (
        f"{progress.task} with {progress.algo.upper()}, {progress.timesteps:,} steps in "
        f"{describe.duration(progress.wall_time)}"
    )
    if progress.evaluations:
        last = progress.evaluations[-1]
        text += f", last evaluation: return {last['mean_return']:.2f}"
        if last.get("success_rate") is not None:
            text += f", success {last['success_rate']:.2f}"
    return text


def clear_if_fresh(folder: RunFolder[Any], engine: Engine[Any]) -> None:
    """With --fresh, remove the earlier run of `engine` in `folder` (see `clear`), saying
    which files."""
    if folder.fresh:
        removed = clear(folder.out, folder.checkpoint, engine.policy)
        if removed:
            print(f"--fresh: removed the earlier run in {folder.out}: {', '.join(removed)}")


def clear(out: Path, checkpoint: Checkpoint, policy: str) -> list[str]:
    """Remove what `checkpoint`'s engine wrote in `out` (its checkpoint's files, its
    `policy` and the results); returns their names, folders ending in '/'. Raises
    OutputError when one cannot be removed."""
    found = [*checkpoint.files(), *(out / name for name in (policy, *RESULTS))]
    paths = [path for path in found if path.exists()]
    names = [f"{path.relative_to(out)}{'/' if path.is_dir() else ''}" for path in paths]
    try:
        for path in paths:
            if path.is_dir():
                shutil.rmtree(path)
            else:
                path.unlink()
        folder = checkpoint.folder
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    except OSError as e:
        raise OutputError(f"--fresh cannot remove the earlier run in {out}: {e}") from e
    return names
