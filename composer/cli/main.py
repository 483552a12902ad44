"""The `composer` command: argument parsing, dispatch, and one-line errors.

    composer list                              # tasks with observation/action sizes
    composer show Reach --out reach.png        # the scene, and a rendered frame
    composer run Reach --episodes 3 --video reach.mp4
    composer train                             # the default task with its tuned recipe
    composer eval Reach runs/Reach-ppo

Each command is a module (`composer.cli.listing`, `show`, `run`, `train`, `evaluate`) with a
`run(args) -> exit status` (`args.info`: the TaskInfo of `args.task`, found first), imported
only when chosen: `list`, `show` and `run` never import stable-baselines3 or torch.

Every `composer.Error` (a mistake such as an unknown task, a missing optional dependency or
an unwritable output) is printed as one line on stderr with exit status 2; Ctrl-C exits
with 130. On a Linux machine without a display, commands that render re-run themselves
with MUJOCO_GL=egl, since MuJoCo picks its OpenGL backend once, when it is imported.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

import mjcf
from composer import errors
from composer.cli import catalog, recipes

INTERRUPTED = 130
USAGE_ERROR = 2


def parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    top = argparse.ArgumentParser(
        prog="composer",
        description="List, show, run, train and evaluate composer's MuJoCo tasks.",
    )
    top.add_argument(
        "--import", dest="imports", action="append", default=[], metavar="MODULE",
        help="import MODULE first, to register your own tasks (repeatable)",
    )  # fmt: skip
    commands = top.add_subparsers(dest="command", metavar="COMMAND", required=True)

    _command(commands, "list", "listing", "list the registered tasks")

    show = _command(commands, "show", "show", "print a task's scene and render a frame")
    _task(show)
    show.add_argument("--out", help="PNG file for the frame (default: TASK.png)")
    show.add_argument("--seed", type=int, default=0, help="seed of the episode (default: 0)")
    show.set_defaults(renders=lambda args: True)

    run = _command(commands, "run", "run", "roll out a policy, print returns, record a video")
    _task(run)
    run.add_argument(
        "--policy", default="random",
        help="'random' (default), or a folder or .zip written by `composer train`",
    )  # fmt: skip
    run.add_argument("--episodes", type=positive_int, default=1, help="episodes (default: 1)")
    run.add_argument("--video", help="write the episodes to this .mp4 (or .gif) file")
    run.add_argument("--seed", type=int, default=0, help="seed of episode 1 (default: 0)")
    run.set_defaults(renders=lambda args: args.video is not None)

    train = _command(
        commands, "train", "train",
        "train a policy with stable-baselines3 ([train] extra) or RLlib on Ray ([ray] extra)",
        epilog=recipe_table(), formatter_class=argparse.RawDescriptionHelpFormatter,
    )  # fmt: skip
    _task(train, nargs="?", default=recipes.DEFAULT_TASK)
    train.add_argument("--algo", choices=recipes.ALGORITHMS, help="default: the task's recipe")
    train.add_argument("--timesteps", type=positive_int, help="total, counting resumed ones")
    train.add_argument("--n-envs", type=positive_int, help="parallel environments")
    train.add_argument(
        "--vec", choices=recipes.VEC, help="step them in this process or one process each"
    )
    train.add_argument("--seed", type=int, help="seed (default: 0)")
    train.add_argument("--out", help="output folder (default: runs/TASK-ALGO)")
    train.add_argument("--resume", metavar="DIR", help="continue the checkpoint in DIR")
    train.add_argument("--eval-every", type=positive_int, help="timesteps (default: a tenth)")
    train.add_argument(
        "--eval-episodes", type=positive_int, default=10, help="per evaluation (default: 10)"
    )
    train.add_argument("--no-video", action="store_true", help="skip the trained policy's video")
    train.add_argument(
        "--engine", choices=("sb3", "ray"), default="sb3",
        help="stable-baselines3 on this machine (default), or RLlib on Ray ([ray] extra)",
    )  # fmt: skip
    train.add_argument(
        "--workers", type=positive_int, metavar="N", help="ray: env runners (default: CPUs)"
    )
    train.add_argument(
        "--envs-per-worker", type=positive_int, metavar="M", help="ray: environments each"
    )
    train.add_argument(
        "--address", metavar="HOST:PORT", help="ray: join this cluster (default: start locally)"
    )
    train.set_defaults(renders=lambda args: not args.no_video)

    evaluate = _command(commands, "eval", "evaluate", "mean return and success of a policy")
    _task(evaluate)
    evaluate.add_argument("policy", help="a folder or .zip written by `composer train`")
    evaluate.add_argument("--episodes", type=positive_int, default=10, help="default: 10")
    evaluate.add_argument("--seed", type=int, default=0, help="seed of episode 1 (default: 0)")
    return top


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line `argv` (default: sys.argv[1:]); returns the exit status."""
    args = parser().parse_args(argv)
    if argv is None and _needs_headless_gl(args):
        env = {**os.environ, "MUJOCO_GL": "egl"}
        os.execve(sys.executable, [sys.executable, "-m", "composer", *sys.argv[1:]], env)
    try:
        catalog.import_modules(args.imports)
        if "task" in args:  # found before the command's module imports torch: fails fast
            args.info = catalog.find(args.task)
        command = importlib.import_module(f"composer.cli.{args.module}")
        return command.run(args)
    except (errors.Error, mjcf.RenderError) as e:
        print(f"composer: error: {_one_line(e)}", file=sys.stderr)
        return USAGE_ERROR
    except KeyboardInterrupt:
        print("composer: interrupted", file=sys.stderr)
        return INTERRUPTED
    except BrokenPipeError:  # e.g. `composer list | head -1`
        sys.stderr.close()
        return 0


def positive_int(text: str) -> int:
    """An argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def recipe_table() -> str:
    """The recipes as a text table, for `composer train --help`."""
    rows = [("task", "algo", "timesteps", "envs", "vec", "net", "lr", "batch", "gamma")]
    for (task, algo), r in recipes.RECIPES.items():
        net = "x".join(map(str, r.net))
        rows.append((task, algo, f"{r.timesteps:,}", str(r.n_envs), r.vec, net,
                     f"{r.learning_rate:g}", str(r.batch_size), f"{r.gamma:g}"))  # fmt: skip
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    lines = [
        "  ".join(f"{cell:<{w}}" for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    ]
    generic = ", ".join(f"{r.algo} {r.timesteps:,} steps" for r in recipes.GENERIC.values())
    return (
        "recipes (a task's first row is its default; other tasks: "
        + generic
        + "):\n  "
        + "\n  ".join(lines)
    )


def _command(
    commands: argparse._SubParsersAction, name: str, module: str, summary: str, **options: object
) -> argparse.ArgumentParser:
    command = commands.add_parser(name, help=summary, description=summary, **options)
    command.set_defaults(module=module, renders=lambda args: False)
    return command


def _task(command: argparse.ArgumentParser, **options: object) -> None:
    command.add_argument("task", help="task name, e.g. Reach (see `composer list`)", **options)


def _needs_headless_gl(args: argparse.Namespace) -> bool:
    """Whether this command renders on a Linux machine with no display and no MUJOCO_GL."""
    if not sys.platform.startswith("linux") or os.environ.get("MUJOCO_GL"):
        return False
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return False
    return bool(args.renders(args))


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__
