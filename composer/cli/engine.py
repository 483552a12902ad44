"""What a training engine gives `composer train`: its checkpoint and its trainer, and the
`Progress` both keep. Both engines (stable-baselines3 in `composer.cli.training`, RLlib on
Ray in `composer.cli.ray_training` and `ray_files`) implement these, and `composer.cli.train`
and `composer.cli.run_folder` see them only through them.

    checkpoint = training.Checkpoint('runs/Reach-ppo/checkpoint')   # an engine's subclass
    checkpoint.written_by()      # 'sb3', 'ray', or None: whose state.json is there
    checkpoint.exists()          # a complete checkpoint of this engine
    checkpoint.progress()        # the run's Progress
    checkpoint.files()           # what this engine wrote there (what --fresh removes)

A checkpoint is a folder holding the engine's own files and `state.json`: the run's
`Progress`, which names the engine that wrote it (a state.json naming none was written by
stable-baselines3, before there was a choice). `state.json` is written last, atomically, so
a folder with one holds a complete checkpoint even when training was killed while saving.
Every file an engine writes goes through `replace`: beside its target as `.NAME.partial`,
then moved over it.

This module imports neither stable-baselines3 nor Ray.
"""

from __future__ import annotations

import abc
import dataclasses
import json
import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from composer.cli.errors import PolicyError

if TYPE_CHECKING:
    import gymnasium

    from composer.cli.recipes import Recipe
    from composer.cli.training import Session, StopOnInterrupt

# The engine of a state.json that names none, and the default of `--engine`.
DEFAULT_ENGINE = "sb3"
# Points of the training curve kept in metrics.json (and the checkpoint).
CURVE_POINTS = 200


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
    """Write the file or folder `path` through `write(partial)` beside it, then move it over
    `path` (a folder there is removed first), so `path` is never half written."""
    partial = partial_path(path)
    _remove(partial)
    write(partial)
    if path.is_dir():
        shutil.rmtree(path)
    os.replace(partial, path)


def _remove(path: Path) -> None:
    if path.is_dir():
        shutil.rmtree(path)
    elif path.exists():
        path.unlink()


class Checkpoint(abc.ABC):
    """An engine's training checkpoint in a folder (see the module docstring): what
    `composer.cli.run_folder` needs of it. Subclasses name their engine and policy and
    implement the abstract methods."""

    # The --engine that writes it.
    engine: ClassVar[str]
    # The trained policy this engine writes in the output folder, beside `checkpoint/`.
    policy: ClassVar[str]

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
        return [*self._saved_files(), *state]

    @abc.abstractmethod
    def save(self, model: Any, progress: Progress) -> None:
        """Save `model`, then `progress` (through `_save_state`); raises OutputError."""

    @abc.abstractmethod
    def _complete(self) -> bool:
        """Whether the files state.json points at are there."""

    @abc.abstractmethod
    def _saved_files(self) -> list[Path]:
        """The engine's own files and folders that are there (written ones and partial)."""

    def _save_state(self, state: dict[str, Any]) -> None:
        """Write state.json naming this engine, atomically: the last step of `save`."""
        text = json.dumps({**state, "engine": self.engine})
        replace(self.state_path, lambda path: path.write_text(text))


class Trainer(abc.ABC):
    """One engine training one run, as `composer.cli.train` drives it: the engine opens it
    (a context manager that builds the model, or restores it from the checkpoint), the
    command announces it, calls `learn`, saves and finishes. Subclasses say where they
    sample and implement `learn` and `save_policy`."""

    # What the announcement names before the algorithm ('RLlib'), if anything.
    library: ClassVar[str] = ""

    def __init__(self, model: Any, progress: Progress, recipe: Recipe) -> None:
        """Train `model` (what `Session` evaluates and saves: `num_timesteps`,
        `predict(observation, deterministic)`) on from `progress` as `recipe` says."""
        self.model = model
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

    @abc.abstractmethod
    def learn(self, session: Session, stop: StopOnInterrupt) -> None:
        """Train until `recipe.timesteps` or until `stop` is requested, evaluating and
        saving when `session` says; leaves `model` ready to evaluate."""

    @abc.abstractmethod
    def save_policy(self, path: Path) -> None:
        """Write the trained policy to `path` (named by the checkpoint's `policy`)."""

    def metrics(self) -> dict[str, Any]:
        """The engine's own keys of metrics.json (none by default)."""
        return {}


def check_spaces(source: object, policy: Any, env: gymnasium.Env) -> None:
    """Raise PolicyError unless `policy`'s observation and action spaces have the shapes of
    `env`'s; `source` names where the policy came from."""
    for label, theirs, ours in (
        ("observations", policy.observation_space, env.observation_space),
        ("actions", policy.action_space, env.action_space),
    ):
        if theirs.shape != ours.shape:
            raise PolicyError(
                f"{source} was trained with {label} of shape {theirs.shape}, but this task "
                f"has {ours.shape}: was it trained on another task?"
            )


def plural(count: int, noun: str) -> str:
    """'1 environment', '16 environments'."""
    return f"{count} {noun}{'s' if count != 1 else ''}"
