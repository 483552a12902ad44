"""The contract between `composer train`, `run`, `eval`, `view` and a training engine, and
what every engine shares: the run's `Progress`, its checkpoint folder, the `Session` that
evaluates and saves, and Ctrl-C. This module imports no engine's library.

    engine = engines.get('sb3')                      # an Engine (composer.cli.engines)
    checkpoint = engine.checkpoint('runs/Reach-ppo/checkpoint')   # a `Checkpoint`: atomic
    with engine.trainer(info, folder, args) as trainer, StopOnInterrupt() as stop:
        session = Session(trainer.progress, eval_env, eval_every=80_000, eval_episodes=10)
        trainer.learn(session, stop)     # evaluates and saves when `session.due(...)`
        session.save(trainer)            # a checkpoint with the progress so far
"""

from __future__ import annotations

import abc
import argparse
import dataclasses
import json
import os
import re
import secrets
import shutil
import signal
import sys
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from types import FrameType
from typing import Any, ClassVar, Generic, TypeVar

import gymnasium

from composer.cli import recipes, rollout
from composer.cli.errors import PolicyError
from composer.cli.recipes import Recipe
from composer.registration import TaskInfo

# The engine of a state.json that names none (stable-baselines3 wrote those before there
# was a choice), and so the default of `--engine`.
DEFAULT_ENGINE = "sb3"
# Points of the training curve kept in metrics.json (and the checkpoint).
CURVE_POINTS = 200
# Both engines train small networks: torch's intra-op threads gain them nothing, and on a
# busy CPU its spinning threads made each update 7 to 30 times slower (measured, 2 cores).
TORCH_THREADS = 1


@dataclasses.dataclass
class Progress:
    """What a training run has done: kept in checkpoints, written out as metrics.json."""

    task: str
    env_id: str
    algo: str
    seed: int
    recipe: dict[str, Any]
    engine: str = DEFAULT_ENGINE
    timesteps: int = 0
    wall_time: float = 0.0
    # CPU seconds of the training process, all its threads (not SubprocVecEnv workers' nor
    # Ray's env runners'): what the run costs apart from what else the machine was doing.
    cpu_time: float = 0.0
    completed: bool = False
    evaluations: list[dict[str, Any]] = dataclasses.field(default_factory=list)
    # Training episodes by stretches of CURVE_POINTS-th of the run: [timesteps at the last
    # episode's end, mean return, episodes, success rate (None if the task does not say)].
    train_curve: list[list[Any]] = dataclasses.field(default_factory=list)

    def record_episode(self, timesteps: int, episode_return: float, success: Any) -> None:
        """Add a finished training episode to `train_curve`."""
        width = max(1, int(self.recipe["timesteps"]) // CURVE_POINTS)
        rows = self.train_curve
        if not rows or rows[-1][0] // width != timesteps // width:
            rows.append([timesteps, 0.0, 0, None])
        row = rows[-1]
        row[0], row[2] = timesteps, row[2] + 1
        row[1] = round(row[1] + (episode_return - row[1]) / row[2], 4)
        if success is not None:
            rate = row[3] or 0.0
            row[3] = round(rate + (float(success) - rate) / row[2], 4)

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict of every field."""
        return dataclasses.asdict(self)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Progress:
        """The progress `to_json` wrote (other keys are ignored); raises TypeError when a
        field without a default is missing."""
        names = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in names})


def partial_path(path: Path) -> Path:
    """Where `replace` writes `path` first: '.model.partial.zip' for 'model.zip'."""
    return path.with_name(f".{path.stem}.partial{path.suffix}")


def replace(path: Path, write: Callable[[Path], Any]) -> None:
    """Write the file or folder `path` through `write(partial)` beside it, flush it to disk,
    then move it over `path` (a folder there is removed first) and flush the move, so `path`
    is never half written, even after a power cut."""
    partial = partial_path(path)
    _remove(partial)
    write(partial)
    _flush(partial)
    if path.is_dir():
        shutil.rmtree(path)
    os.replace(partial, path)
    _flush_folder(path.parent)


def _flush(path: Path) -> None:
    """fsync the file `path`, or every file and folder in the folder `path`."""
    if path.is_dir():
        for folder, _, names in os.walk(path):
            for name in names:
                _flush_file(Path(folder) / name)
            _flush_folder(Path(folder))
    else:
        _flush_file(path)


def _flush_file(path: Path) -> None:
    with path.open("rb") as file:
        os.fsync(file.fileno())


def _flush_folder(path: Path) -> None:
    """fsync the folder `path`, so that the names it holds survive a power cut (where the
    system can: Windows cannot open a folder)."""
    try:
        descriptor = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def _remove(path: Path) -> None:
    if path.is_dir():
        shutil.rmtree(path)
    elif path.exists():
        path.unlink()


# A save's subfolder in a checkpoint, '000000020480-3fa9c1' (timesteps, then a random tag),
# and one being written ('.000000020480-3fa9c1.partial').
_SAVED = re.compile(r"\d{12,}-[0-9a-f]{6}|\.\d{12,}-[0-9a-f]{6}\.partial")


class Checkpoint(abc.ABC):
    """An engine's training checkpoint in a folder, as the run folder's rules read it; the
    engine's trainer writes it through `save`. Subclasses name their engine and say when a
    save holds what they need.

    A checkpoint is a folder holding `state.json`, the run's `Progress` (which names the
    engine that wrote it: a state.json naming none was written by stable-baselines3, before
    there was a choice), and the engine's files of the last save in a subfolder that state.json
    names (`<timesteps>-<tag>/`). `Checkpoint.save` is atomic: the new subfolder is written and
    flushed to disk whole, then state.json is replaced and flushed, then older saves are removed;
    a reader, or a run resumed after a kill or a power cut at any moment, finds the previous
    save or the new one, never the weights of one with the statistics of the other. Every file
    an engine writes goes through `replace`: beside its target as `.NAME.partial`, flushed
    (fsync), then moved over it.
    """

    # The --engine that writes it.
    engine: ClassVar[str]

    def __init__(self, folder: str | os.PathLike[str]) -> None:
        """A checkpoint at `folder` (which need not exist yet)."""
        self.folder = Path(folder)
        self.state_path = self.folder / "state.json"

    def state(self) -> dict[str, Any]:
        """The contents of state.json; raises PolicyError if it cannot be read."""
        try:
            state = json.loads(self.state_path.read_text())
        except (OSError, ValueError) as e:
            raise PolicyError(f"cannot read checkpoint {self.state_path}: {e}") from e
        if not isinstance(state, dict):
            raise PolicyError(f"cannot read checkpoint {self.state_path}: not a JSON object")
        return state

    def written_by(self) -> str | None:
        """The engine whose state.json is in the folder; None when there is none. Raises
        PolicyError for one that cannot be read."""
        if not self.state_path.is_file():
            return None
        return str(self.state().get("engine", DEFAULT_ENGINE))

    def exists(self) -> bool:
        """Whether a complete checkpoint of this engine is there (raises PolicyError for a
        state.json that cannot be read)."""
        return self.written_by() == self.engine and self._complete()

    def progress(self) -> Progress:
        """The progress saved with the checkpoint; raises PolicyError if unreadable."""
        try:
            return Progress.from_json(self.state())
        except TypeError as e:
            raise PolicyError(f"cannot read checkpoint {self.state_path}: {e}") from e

    def files(self) -> list[Path]:
        """The files and folders of this engine's checkpoint that are there, state.json
        last: what --fresh removes."""
        state = [p for p in (self.state_path, partial_path(self.state_path)) if p.exists()]
        return [*self.engine_files(), *state]

    def current(self) -> Path:
        """The folder of the last complete save: the subfolder state.json names (or, for a
        stable-baselines3 checkpoint written before saves had subfolders, the checkpoint
        folder itself). Raises PolicyError for a state.json that cannot be read or names
        something else."""
        saved = self.state().get("saved")
        if saved is None:
            return self.folder
        if not isinstance(saved, str) or not _SAVED.fullmatch(saved) or saved.startswith("."):
            raise PolicyError(f"{self.state_path} names no save of this checkpoint: {saved!r}")
        return self.folder / saved

    def save(self, timesteps: int, write: Callable[[Path], Any], state: dict[str, Any]) -> None:
        """Save atomically (see the class docstring): `write(folder)` fills a new subfolder
        with the engine's files, then state.json (`state`, naming this engine and the
        subfolder) replaces the last one, then the older saves are removed. Raises OSError;
        the last complete save is then still the current one."""
        name = f"{int(timesteps):012d}-{secrets.token_hex(3)}"
        self.folder.mkdir(parents=True, exist_ok=True)
        replace(self.folder / name, write)
        text = json.dumps({**state, "engine": self.engine, "saved": name})
        replace(self.state_path, lambda path: path.write_text(text))
        for old in self.engine_files():
            if old.name != name:
                _remove(old)

    def engine_files(self) -> list[Path]:
        """The saves' subfolders that are there (complete and partial); an engine adds the
        files it wrote before saves had subfolders."""
        if not self.folder.is_dir():
            return []
        return sorted(p for p in self.folder.iterdir() if p.is_dir() and _SAVED.fullmatch(p.name))

    @abc.abstractmethod
    def _complete(self) -> bool:
        """Whether the files state.json points at are there."""


CheckpointType = TypeVar("CheckpointType", bound=Checkpoint)


@dataclasses.dataclass(frozen=True)
class RunFolder(Generic[CheckpointType]):
    """An output folder of `composer train` that `composer.cli.run_folder.prepare` found
    fit for the command: its checkpoint, whether the run there goes on (`resumed`: its
    progress and recipe), and whether --fresh asked to replace what is there."""

    out: Path
    checkpoint: CheckpointType
    fresh: bool
    resumed: tuple[Progress, Recipe] | None

    @property
    def resumes(self) -> bool:
        """Whether training goes on from the checkpoint."""
        return self.resumed is not None

    def start(
        self, args: argparse.Namespace, new_recipe: Callable[[str], Recipe]
    ) -> tuple[Progress, Recipe]:
        """The progress and recipe to train with: the checkpoint's, or a new run's with
        `new_recipe(algo)` (the engine's recipe with the command line's changes)."""
        if self.resumed is not None:
            progress, recipe = self.resumed
        else:
            info = args.info
            algo = args.algo or recipes.default_algo(info)
            recipe = new_recipe(algo)
            progress = Progress(info.name, info.env_id, algo, args.seed or 0, {},
                                engine=self.checkpoint.engine)  # fmt: skip
        progress.recipe = recipe.table()
        progress.completed = False
        return progress, recipe


@dataclasses.dataclass(frozen=True)
class Collection:
    """How an engine's algorithm collects steps: in batches of `batch` steps (None where
    the engine cannot say beforehand), called `what` in the announcement ('rollouts of 16
    environments x 128 steps'), checking for a due evaluation every `check_every` steps."""

    batch: int | None
    what: str
    check_every: int

    def end(self, done: int, total: int) -> int:
        """Where a session starting at `done` steps towards `total` stops: the first whole
        batch at or past `total` (`total` itself when the batch is not known)."""
        if done >= total or not self.batch:
            return max(done, total)
        return done + -(-(total - done) // self.batch) * self.batch


class Trainer(abc.ABC):
    """One engine training one run, as `composer.cli.train` drives it: the engine opens it
    (a context manager that builds the model, or restores it from the checkpoint), the
    command announces it, calls `learn`, saves and finishes. Subclasses say where they
    sample and implement the abstract methods."""

    # What the announcement names before the algorithm ('RLlib'), if anything.
    library: ClassVar[str] = ""

    def __init__(self, progress: Progress, recipe: Recipe) -> None:
        """Train on from `progress` as `recipe` says."""
        self.progress = progress
        self.recipe = recipe

    @property
    def algorithm(self) -> str:
        """The algorithm as the announcement names it: 'PPO', 'RLlib PPO'."""
        return " ".join(filter(None, (self.library, self.recipe.algo.upper())))

    @property
    @abc.abstractmethod
    def where(self) -> str:
        """Where it samples, for the announcement: '16 environments'."""

    @property
    @abc.abstractmethod
    def timesteps(self) -> int:
        """Environment steps trained so far in the run (resumed ones counted)."""

    @property
    @abc.abstractmethod
    def collection(self) -> Collection:
        """How its algorithm collects steps (where the run will end, and why)."""

    def end(self) -> int:
        """The steps this session will end at: the recipe's timesteps, rounded up to whole
        batches of the algorithm from where the run stands (`Collection.end`)."""
        return self.collection.end(self.timesteps, self.recipe.timesteps)

    @abc.abstractmethod
    def learn(self, session: Session, stop: StopOnInterrupt) -> None:
        """Train until `recipe.timesteps` or until `stop` is requested, evaluating and
        saving when `session` says; leaves the policy ready to evaluate."""

    @abc.abstractmethod
    def predictor(self) -> rollout.Predictor:
        """The policy as trained so far, for evaluations and the video."""

    @abc.abstractmethod
    def save_checkpoint(self) -> None:
        """Save the model with `progress` into the run's checkpoint (through
        `Checkpoint.save`, atomically); raises OutputError."""

    @abc.abstractmethod
    def save_policy(self, path: Path) -> None:
        """Write the trained policy to `path` (named by the engine's `policy`)."""

    def metrics(self) -> dict[str, Any]:
        """The engine's own keys of metrics.json (none by default)."""
        return {}


class Engine(abc.ABC, Generic[CheckpointType]):
    """A training engine, as the commands see it. A subclass names it, gives its checkpoint
    class and policy name, and implements the abstract methods; its library is imported
    only by them.

    An `Engine` gives its checkpoint, its options of `composer train`, the checks it makes
    before training (its libraries installed), its `Trainer`, and its policy loader; the
    commands see engines only through it. A `Trainer` trains one run; what it offers the
    session (its timesteps, its current policy, saving) is all the session needs.
    """

    # --engine's value, and what the help and the messages call it.
    name: ClassVar[str]
    title: ClassVar[str]
    # --engine's help for it: 'stable-baselines3 on this machine'.
    summary: ClassVar[str]
    # The optional dependencies it needs ('train': `pip install -e '.[train]'`).
    extra: ClassVar[str]
    checkpoint: type[CheckpointType]
    # The trained policy it writes in the output folder, beside `checkpoint/`.
    policy: ClassVar[str]
    # The destinations of the options `add_options` adds: refused with another engine.
    options: ClassVar[tuple[str, ...]] = ()
    # Those of them that set the recipe's field of the same name: a resumed run keeps its
    # recipe's instead (a note says so).
    recipe_options: ClassVar[tuple[str, ...]] = ()

    def add_options(self, group: argparse._ArgumentGroup) -> None:
        """Add its own options (`options`) to `composer train`'s parser: none by default."""

    def instead(self, given: Sequence[str]) -> str:
        """What to give this engine instead of another engine's options `given` (their
        destinations), as '; ...' to end the refusal; '' by default."""
        return ""

    @abc.abstractmethod
    def prepare(self, args: argparse.Namespace) -> None:
        """Check, before any work, what training with `args` needs of this engine: its
        libraries installed, its own outputs writable. Raises MissingExtraError, CliError."""

    @abc.abstractmethod
    def trainer(
        self, info: TaskInfo, folder: RunFolder[CheckpointType], args: argparse.Namespace
    ) -> AbstractContextManager[Trainer]:
        """Within `with`: the run in `folder` (resumed from its checkpoint, or new with the
        task's recipe as this engine runs it and the command line's changes), whose
        resources are released after. Raises CliError when it cannot start."""

    @abc.abstractmethod
    def find_policy(self, path: Path) -> Path | None:
        """The policy of this engine that `path` names (its policy, a folder written by
        `composer train`, or a checkpoint), or None when it names none of this engine's;
        needs no library."""

    @abc.abstractmethod
    def load_policy(self, found: Path, env: gymnasium.Env, trusted: bool) -> rollout.Predictor:
        """The policy `find_policy` found, checked to fit `env`'s spaces; read whole,
        unpickling and so running code from it, only when `trusted`. Raises PolicyError,
        UntrustedPolicyError (only pickles hold it), MissingExtraError (no library)."""


def check_spaces(source: object, policy: Any, env: gymnasium.Env) -> None:
    """Raise PolicyError unless `policy`'s observation and action spaces have the shapes of
    `env`'s (frames channels first or last alike: stable-baselines3 trains on them turned
    around); `source` names where the policy came from."""
    for label, theirs, ours in (
        ("observations", policy.observation_space, env.observation_space),
        ("actions", policy.action_space, env.action_space),
    ):
        if theirs.shape == ours.shape or _channels_first(ours.shape) == theirs.shape:
            continue
        hint = "was it trained on another task?"
        if label == "observations" and len(theirs.shape or ()) != len(ours.shape or ()):
            frames = len(theirs.shape or ()) == 3
            hint = "it was trained " + ("from pixels: give --pixels" if frames else
                                        "on the task's state: leave out --pixels")  # fmt: skip
        raise PolicyError(
            f"{source} was trained with {label} of shape {theirs.shape}, but this task "
            f"has {ours.shape}: {hint}"
        )


def _channels_first(shape: tuple[int, ...] | None) -> tuple[int, ...] | None:
    """A frame's shape (height, width, channels) as (channels, height, width)."""
    if shape is None or len(shape) != 3:
        return None
    return (shape[2], shape[0], shape[1])


# -- a training session --------------------------------------------------------------------


class StopOnInterrupt:
    """Within `with`: the first Ctrl-C asks training to stop after the current step (the
    session then saves a checkpoint); a second one interrupts at once."""

    requested = False

    def __enter__(self) -> StopOnInterrupt:
        self._previous = signal.signal(signal.SIGINT, self._handle)
        return self

    def __exit__(self, *exc_info: object) -> None:
        signal.signal(signal.SIGINT, self._previous)

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self.requested = True
        signal.signal(signal.SIGINT, self._previous)
        print("\nstopping: saving a checkpoint (Ctrl-C again to quit now)", file=sys.stderr)


class Session:
    """Book-keeping of one training session, on any engine: evaluates every `eval_every`
    timesteps (deterministic actions, episode i from seed `rollout.EVAL_SEED` + i), records
    the results and the time spent in the progress, and saves checkpoints."""

    def __init__(
        self, progress: Progress, eval_env: gymnasium.Env, eval_every: int, eval_episodes: int
    ) -> None:
        """Continue `progress`; evaluate on `eval_env` (flattened observations)."""
        self.progress = progress
        self.eval_env = eval_env
        self.eval_every = eval_every
        self.eval_episodes = eval_episodes
        self._wall_time_before = progress.wall_time
        self._cpu_time_before = progress.cpu_time
        self._started = time.monotonic()
        self._cpu_started = time.process_time()
        last = progress.evaluations[-1]["timesteps"] if progress.evaluations else 0
        self._next_eval = last + eval_every

    def elapsed(self) -> float:
        """Wall-clock seconds of training so far, over every session of the run."""
        return self._wall_time_before + time.monotonic() - self._started

    def evaluate(self, trainer: Trainer) -> dict[str, Any]:
        """Evaluate `trainer`'s policy as it is now, record the result in the progress and
        return it. A result at the timesteps of the last one replaces it: PPO evaluates
        during its last rollout and updates the policy after, so the policy after training
        is evaluated again."""
        policy = rollout.model_policy(trainer.predictor())
        episodes = rollout.run_episodes(
            self.eval_env, policy, self.eval_episodes, rollout.EVAL_SEED
        )
        result = {
            "timesteps": int(trainer.timesteps),
            "wall_time": round(self.elapsed(), 2),
            **rollout.summary(episodes),
        }
        evaluations = self.progress.evaluations
        if evaluations and evaluations[-1]["timesteps"] == result["timesteps"]:
            evaluations.pop()
        evaluations.append(result)
        return result

    def save(self, trainer: Trainer) -> None:
        """Save a checkpoint of `trainer`'s run with the progress and time so far."""
        self.progress.timesteps = int(trainer.timesteps)
        self.progress.wall_time = round(self.elapsed(), 2)
        self.progress.cpu_time = round(
            self._cpu_time_before + time.process_time() - self._cpu_started, 2
        )
        trainer.save_checkpoint()

    def evaluations_until(self, end: int, done: int, check_every: int) -> int:
        """How many evaluations `due` will ask for from `done` steps to `end`, asked every
        `check_every` steps; changes nothing."""
        evaluations, next_eval, steps = 0, self._next_eval, done
        while True:
            # The first check at or past the next evaluation: one at least.
            steps += max(1, -(-(next_eval - steps) // check_every)) * check_every
            if steps > end:
                return evaluations
            evaluations += 1
            while next_eval <= steps:
                next_eval += self.eval_every

    def due(self, timesteps: int) -> bool:
        """Whether an evaluation is due at `timesteps`; schedules the next one."""
        if timesteps < self._next_eval:
            return False
        while self._next_eval <= timesteps:
            self._next_eval += self.eval_every
        return True
