"""The `composer` command: argument parsing, dispatch, and one-line errors.

    composer list                              # tasks with observation/action sizes
    composer show Reach --out reach.png        # the scene, and a rendered frame
    composer run Reach --episodes 3 --video reach.mp4
    composer train                             # the default task with its tuned recipe
    composer eval Reach runs/Reach-ppo

Promises: options match exactly (`--time` is not `--timesteps`); a usage mistake or a
`composer.Error` prints one line on stderr and exits with status 2; Ctrl-C exits with 130.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from typing import Any

import mjcf
from composer import errors, registration
from composer.cli import catalog, engines, recipes, rollout, video
from composer.cli.arguments import Parser, UsageError, byte_size, did_you_mean, positive_int, ratio

INTERRUPTED = 130
USAGE_ERROR = 2
# Each command's module, imported when the command is chosen, with a `run(args) -> exit
# status` (`args.info`: the TaskInfo of `args.task`, found first): so `list`, `show`, `run`
# and `view` never import stable-baselines3, torch or Ray unless given a trained policy. The
# training engines (`composer.cli.engines`) give `train` their options and `--engine` its
# choices.
COMMANDS = {
    "list": "composer.cli.listing",
    "show": "composer.cli.show",
    "run": "composer.cli.run",
    "view": "composer.cli.view",
    "train": "composer.cli.train",
    "eval": "composer.cli.evaluate",
}


def parser(imports: Sequence[str] = ()) -> argparse.ArgumentParser:
    """The argument parser of every command; `imports`: the modules given with --import,
    whose tasks' recipes `composer train --help` lists too."""
    top = Parser(
        prog="composer",
        description="List, show, run, view, train and evaluate composer's MuJoCo tasks.",
    )
    top.add_argument(
        "--import", dest="imports", action="append", default=[], metavar="MODULE",
        help="import MODULE first, to register your own tasks (repeatable)",
    )  # fmt: skip
    commands = top.add_subparsers(dest="command", metavar="COMMAND", required=True)

    _command(commands, "list", "list the registered tasks")

    show = _command(commands, "show", "print a task's scene; --out renders a frame")
    _task(show)
    show.add_argument("--out", help="render a frame into this PNG file (default: no frame)")
    show.add_argument("--seed", type=int, default=0, help="seed of the episode (default: 0)")

    run = _command(commands, "run", "roll out a policy, print returns, record a video")
    _task(run)
    run.add_argument(
        "--policy", default="random",
        help="'random' (default), or a folder or policy written by `composer train`",
    )  # fmt: skip
    _trust_policy(run)
    run.add_argument("--episodes", type=positive_int, default=1, help="episodes (default: 1)")
    formats = " or ".join(video.VIDEO_FORMATS)  # the ones `video.target` accepts
    run.add_argument("--video", help=f"write the episodes to this {formats} file")
    run.add_argument("--seed", type=int, default=0, help="seed of episode 1 (default: 0)")
    _pixels(run)

    view = _command(commands, "view", "watch a policy in MuJoCo's interactive viewer")
    _task(view)
    view.add_argument(
        "--policy", default="random",
        help="'random' (default), or a folder or policy written by `composer train`",
    )  # fmt: skip
    _trust_policy(view)
    view.add_argument("--episodes", type=positive_int, help="quit after this many episodes")
    view.add_argument("--seed", type=int, default=0, help="seed of episode 1 (default: 0)")

    _train_command(commands, imports)

    evaluate = _command(commands, "eval", "mean return and success of a policy")
    _task(evaluate)
    evaluate.add_argument("policy", help="a folder or policy written by `composer train`")
    _trust_policy(evaluate)
    evaluate.add_argument("--episodes", type=positive_int, default=10, help="default: 10")
    evaluate.add_argument(
        "--seed", type=int, default=rollout.EVAL_SEED,
        help=f"seed of episode 1 (default: {rollout.EVAL_SEED}, as in training's evaluations: "
        "with as many --episodes, eval repeats the last one)",
    )  # fmt: skip
    _pixels(evaluate)
    return top


def _train_command(commands: argparse._SubParsersAction, imports: Sequence[str]) -> None:
    """`composer train`: its options, then each engine's in a group of its own."""
    every = engines.every()
    with_extras = " or ".join(f"{engine.title} ([{engine.extra}] extra)" for engine in every)
    train = _command(
        commands, "train", f"train a policy with {with_extras}",
        epilog_source=lambda: recipe_table(imports),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )  # fmt: skip
    _task(train, nargs="?", default=recipes.DEFAULT_TASK)
    train.add_argument("--algo", choices=recipes.ALGORITHMS, help="default: the task's recipe")
    train.add_argument("--timesteps", type=positive_int, help="total, counting resumed ones")
    train.add_argument("--seed", type=int, help="seed (default: 0)")
    train.add_argument("--out", help="output folder (default: runs/TASK-ALGO)")
    train.add_argument(
        "--resume", nargs="?", const=True, metavar="DIR",
        help="continue the run in DIR (default: the output folder), a finished one too",
    )  # fmt: skip
    train.add_argument(
        "--fresh", action="store_true", help="replace an earlier run in the output folder"
    )
    train.add_argument("--eval-every", type=positive_int, help="timesteps (default: a tenth)")
    train.add_argument(
        "--eval-episodes", type=positive_int, default=10, help="per evaluation (default: 10)"
    )
    train.add_argument("--no-video", action="store_true", help="skip the trained policy's video")
    _pixels(train)
    summaries = [
        engine.summary + (" (default)" if engine.name == engines.DEFAULT else "")
        for engine in every
    ]
    train.add_argument(
        "--engine", choices=engines.names(), default=engines.DEFAULT,
        help=", or ".join(summaries),
    )  # fmt: skip
    for engine in every:
        engine.add_options(train.add_argument_group(f"--engine {engine.name} ({engine.title})"))


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line `argv` (default: sys.argv[1:]); returns the exit status."""
    try:
        args = parse(argv)
    except UsageError as e:
        print(f"{e.prog}: error: {_one_line(e)}", file=sys.stderr)
        return USAGE_ERROR
    except (errors.Error, mjcf.RenderError) as e:  # --help's recipe table: a task's import
        print(f"composer: error: {_one_line(e)}", file=sys.stderr)
        return USAGE_ERROR
    try:
        catalog.import_modules(args.imports)
        _limit_unpacking(args)
        if "task" in args:  # found before the command's module imports torch: fails fast
            args.info = catalog.find(args.task)
            if getattr(args, "pixels", False):
                args.info = catalog.with_pixels(args.info)
        command = importlib.import_module(COMMANDS[args.command])
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


def parse(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The parsed command line; raises UsageError for anything it does not know, naming
    the closest option of the command."""
    words = list(sys.argv[1:] if argv is None else argv)
    top = parser(_imports(words))
    known = [o for action in top._actions for o in action.option_strings]
    for index, word in enumerate(words):  # options before the command are the top's
        if not word.startswith("-"):
            if index == 0 or words[index - 1] != "--import":
                break
        elif word.partition("=")[0] not in known:
            top.error(f"unknown option {word}" + did_you_mean(word.partition("=")[0], known))
    args, unknown = top.parse_known_args(words)
    if unknown:
        name = getattr(args, "command", None)
        command = _subcommands(top).get(name, top) if name is not None else top
        known = [o for action in command._actions for o in action.option_strings]
        word = unknown[0]
        if word.startswith("-"):
            message = f"unknown option {word}" + did_you_mean(word.partition("=")[0], known)
        else:
            message = f"unexpected argument {word!r}"
        command.error(message)
    return args


def recipe_table(imports: Sequence[str] = ()) -> str:
    """The recipes of the registered tasks (those of `imports` too) as a text table, for
    `composer train --help`."""
    catalog.import_modules(imports)
    rows = [("task", "algo", "timesteps", "envs", "vec", "net", "lr", "batch", "gamma")]
    changes = []
    for name, info in catalog.tasks().items():
        try:
            own = recipes.registered(info)
        except registration.RegistrationError:  # `composer list` says why it is unavailable
            continue
        for r in own:
            task = f"{name} --pixels" if r.pixels else name
            net = ("cnn+" if r.pixels else "") + "x".join(map(str, r.net))
            rows.append((task, r.algo, f"{r.timesteps:,}", str(r.n_envs), r.vec, net,
                         f"{r.learning_rate:g}", str(r.batch_size), f"{r.gamma:g}"))  # fmt: skip
            if r.pixels:
                layers = ", ".join(f"{c} {k}x{k} stride {s}" for c, k, s in r.conv)
                changes.append(f"{task} {r.algo}: cnn = conv {layers}, {r.features} features")
            changes += [
                f"--engine {engine}: {name} {r.algo} with "
                + ", ".join(f"{field}={value}" for field, value in changed.items())
                for engine, changed in r.engine_changes.items()
            ]
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    lines = [
        "  ".join(f"{cell:<{w}}" for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    ]
    generic = ", ".join(f"{r.algo} {r.timesteps:,} steps" for r in recipes.GENERIC.values())
    return (
        f"recipes (a task's first row is its default; other tasks: {generic}):\n  "
        + "\n  ".join([*lines, *changes])
    )


def _imports(words: Sequence[str]) -> list[str]:
    """The modules given with --import before the command in `words`."""
    found = []
    for index, word in enumerate(words):
        if word == "--import" and index + 1 < len(words):
            found.append(words[index + 1])
        elif word.startswith("--import="):
            found.append(word.partition("=")[2])
        elif not word.startswith("-") and (index == 0 or words[index - 1] != "--import"):
            break
    return found


def _pixels(command: argparse.ArgumentParser) -> None:
    size = f"{catalog.PIXELS['width']}x{catalog.PIXELS['height']}"
    command.add_argument(
        "--pixels", action="store_true",
        help=f"observe the task through its camera: {size} frames, the latest "
        f"{catalog.PIXELS['frame_stack']} stacked (gym.make(id, pixels=True, ...)); a policy "
        "trained with --pixels needs it",
    )  # fmt: skip


def _trust_policy(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--trust-policy", action="store_true",
        help="load a policy file whole, with the pickled Python objects it may hold, which "
        "run code: only for files from a source you trust (default: weights and plain "
        "settings only; see SECURITY.md)",
    )  # fmt: skip
    limits = mjcf.archives
    command.add_argument(
        "--unpack-limit", type=byte_size, metavar="SIZE",
        help="bytes a policy file may unpack to without --trust-policy, e.g. 2G (default: "
        f"${limits.SIZE_VARIABLE}, else {limits.DEFAULT_SIZE >> 30}G)",
    )  # fmt: skip
    command.add_argument(
        "--unpack-ratio", type=ratio, metavar="N",
        help="times its compressed size each part of a policy file may unpack to without "
        f"--trust-policy (default: ${limits.RATIO_VARIABLE}, else {limits.DEFAULT_RATIO:g})",
    )  # fmt: skip


def _limit_unpacking(args: argparse.Namespace) -> None:
    """Make --unpack-limit and --unpack-ratio, where given, the limits of mjcf.archives
    for this process (over the environment's)."""
    size, times = getattr(args, "unpack_limit", None), getattr(args, "unpack_ratio", None)
    if size is not None or times is not None:
        try:
            limits = mjcf.archives.current_limits()
        except mjcf.UnpackLimitError as e:
            raise errors.Error(str(e)) from None
        mjcf.archives.LIMITS = limits._replace(
            size=limits.size if size is None else size,
            ratio=limits.ratio if times is None else times,
        )


def _subcommands(top: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in top._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _command(
    commands: argparse._SubParsersAction, name: str, summary: str, **options: Any
) -> argparse.ArgumentParser:
    return commands.add_parser(name, help=summary, description=summary, **options)


def _task(command: argparse.ArgumentParser, **options: Any) -> None:
    command.add_argument("task", help="task name, e.g. Reach (see `composer list`)", **options)


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__
