"""Training on stable-baselines3: parallel environments, models, checkpoints, and the
engine's `Trainer`, which `composer train` drives through the engine (`trainer`).

    venv = training.vec_env(info, recipe, seed=0)          # K environments, VecMonitor'd
    model = training.new_model(recipe, venv, seed=0)
    with training.trainer(info, folder, args) as trainer:  # a new or resumed run's
        trainer.learn(session, stop)                       # model.learn, with the callback

This module imports stable-baselines3 and torch (the [train] extra); the engine imports it
only to train.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import signal
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import gymnasium
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.logger import Logger
from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
from stable_baselines3.common.running_mean_std import RunningMeanStd
from stable_baselines3.common.type_aliases import TrainFreq, TrainFrequencyUnit
from stable_baselines3.common.vec_env import (
    DummyVecEnv,
    SubprocVecEnv,
    VecEnv,
    VecMonitor,
    VecNormalize,
)

from composer import sb3
from composer.cli import catalog, describe, output, progress, recipes
from composer.cli.engines import base
from composer.cli.engines.sb3 import encoder
from composer.cli.engines.sb3.files import NAME, NORMALIZATION, Checkpoint, NormalizedPolicy
from composer.cli.engines.sb3.policy import ALGORITHMS
from composer.cli.errors import CliError, MissingExtraError, OutputError
from composer.registration import TaskInfo, make_environment

# -- environments and models -------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class EnvFactory:
    """A picklable maker of one training environment (for SubprocVecEnv workers too)."""

    task: str
    kwargs: dict[str, Any]
    worker: bool = False

    def __call__(self) -> gymnasium.Env:
        """Build the environment; a worker process leaves Ctrl-C to the main process."""
        if self.worker:
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        return make_environment(self.task, **self.kwargs)


def vec_env(
    info: TaskInfo, recipe: recipes.Recipe, seed: int, normalization: Path | None = None
) -> VecEnv:
    """`recipe.n_envs` environments of `info`'s task, stepped as `recipe.vec` says, with
    episode statistics (VecMonitor) and seeds seed, seed + 1, ...; normalized when the
    recipe says so (a pixel recipe's rewards only), with the statistics saved at
    `normalization` if given."""
    kwargs = catalog.environment_kwargs(info)
    if recipe.vec == "batched":
        venv: VecEnv = sb3.make_vec_env(info.task, recipe.n_envs, **kwargs)
    else:
        subprocesses = recipe.vec == "subproc" and recipe.n_envs > 1
        factories: list[Callable[[], gymnasium.Env]]
        factories = [EnvFactory(info.task, kwargs, subprocesses)] * recipe.n_envs
        venv = SubprocVecEnv(factories) if subprocesses else DummyVecEnv(factories)
    venv.seed(seed)
    venv = VecMonitor(venv)
    if not recipe.normalize:
        return venv
    if normalization is not None:
        return VecNormalize.load(str(normalization), venv)
    # Frames are scaled by the policy itself: a pixel recipe normalizes rewards only.
    return VecNormalize(venv, gamma=recipe.gamma, norm_obs=not recipe.pixels)


def keep_normalization(model: BaseAlgorithm) -> None:
    """Copy the training environments' observation statistics into the model (as
    NORMALIZATION, saved in its .zip) for the policies served from it; none when only
    rewards are normalized."""
    normalize = model.get_vec_normalize_env()
    if normalize is not None and normalize.norm_obs:
        statistics = normalize.obs_rms
        assert isinstance(statistics, RunningMeanStd), "observations are one vector"
        setattr(model, NORMALIZATION, {
            "mean": statistics.mean.tolist(),
            "var": statistics.var.tolist(),
            "epsilon": float(normalize.epsilon),
            "clip": float(normalize.clip_obs),
        })  # fmt: skip


def algo_kwargs(recipe: recipes.Recipe) -> dict[str, Any]:
    """The keyword arguments of the stable-baselines3 algorithm's constructor."""
    common = {
        "learning_rate": recipe.learning_rate,
        "batch_size": recipe.batch_size,
        "gamma": recipe.gamma,
        "policy_kwargs": (
            encoder.policy_kwargs(recipe) if recipe.pixels else {"net_arch": list(recipe.net)}
        ),
    }
    if recipe.algo == "ppo":
        return {**common, "n_steps": recipe.n_steps, "n_epochs": recipe.n_epochs,
                "ent_coef": recipe.ent_coef}  # fmt: skip
    return {
        **common,
        # A replay buffer larger than the run only costs memory.
        "buffer_size": min(recipe.buffer_size, recipe.timesteps),
        "learning_starts": recipe.learning_starts,
        "train_freq": recipe.train_freq,
        "gradient_steps": recipe.gradient_steps,
        # "auto_X": the temperature is learned, starting from X.
        "ent_coef": f"auto_{recipe.initial_temperature}",
    }


def new_model(
    recipe: recipes.Recipe, venv: VecEnv, seed: int, tensorboard: str | None = None
) -> BaseAlgorithm:
    """A fresh model of `recipe`'s algorithm on `venv`, on the CPU, logging to TensorBoard
    in the folder `tensorboard` if given; a pixel recipe's with its encoder (`encoder`),
    whose settings the model keeps as plain JSON for its policy file."""
    model = ALGORITHMS[recipe.algo](
        "CnnPolicy" if recipe.pixels else "MlpPolicy", venv, seed=seed, device="cpu",
        tensorboard_log=tensorboard, **algo_kwargs(recipe),
    )  # fmt: skip
    if recipe.pixels:
        setattr(model, encoder.SETTINGS_KEY, encoder.settings(recipe))
    return model


def require(args: argparse.Namespace) -> None:
    """Raise now, before training, if `--tensorboard DIR` cannot work (MissingExtraError
    without TensorBoard, OutputError when DIR cannot be written), or `--vec batched` is
    given for frames (CliError: the batch has no camera observations)."""
    if args.vec == "batched" and catalog.observes_pixels(args.info):
        raise CliError(
            f"{args.info.name} is observed through its camera, and --vec batched steps "
            "environments without frames: give --vec dummy or --vec subproc"
        )
    if args.tensorboard is None:
        return
    try:
        import torch.utils.tensorboard  # noqa: F401
    except ImportError as e:
        raise MissingExtraError(
            f"--tensorboard needs the tensorboard package ({e.name or e} is missing): "
            "pip install tensorboard, or pip install -e '.[train]'"
        ) from e
    output.directory(args.tensorboard)


def load_model(
    checkpoint: Checkpoint, algo: str, venv: VecEnv, tensorboard: str | None = None
) -> BaseAlgorithm:
    """The checkpointed model of `algo`, training on `venv`, with its replay buffer,
    logging to TensorBoard in the folder `tensorboard` if given."""
    model = ALGORITHMS[algo].load(
        checkpoint.model_path, env=venv, device="cpu", tensorboard_log=tensorboard
    )
    if isinstance(model, OffPolicyAlgorithm) and checkpoint.buffer_path.is_file():
        model.load_replay_buffer(checkpoint.buffer_path)
    return model


# -- the trainer -----------------------------------------------------------------------------


class Trainer(base.Trainer):
    """A stable-baselines3 model training on its environments (`trainer` opens one)."""

    def __init__(
        self,
        model: BaseAlgorithm,
        progress: base.Progress,
        recipe: recipes.Recipe,
        checkpoint: Checkpoint,
        resumed: bool,
        log_name: str,
    ) -> None:
        """Train `model` (`resumed` from `checkpoint` or new) on as `recipe` says;
        `log_name`: its TensorBoard run's name."""
        super().__init__(progress, recipe)
        self.model = model
        self.checkpoint = checkpoint
        self._resumed = resumed
        self._log_name = log_name

    @property
    def where(self) -> str:
        """'16 environments'."""
        return describe.count(self.recipe.n_envs, "environment")

    @property
    def timesteps(self) -> int:
        """The model's timesteps."""
        return int(self.model.num_timesteps)

    @property
    def collection(self) -> base.Collection:
        """PPO collects whole rollouts of `n_steps` per environment, an off-policy algorithm
        `train_freq` steps of every environment at a time; the callback runs at every step
        of the environments."""
        model, n_envs = self.model, self.model.n_envs
        environments = describe.count(n_envs, "environment")
        if isinstance(model, OffPolicyAlgorithm):
            train_freq = model.train_freq
            assert isinstance(train_freq, TrainFreq), "SB3 converts it when it builds the model"
            frequency = train_freq.frequency
            if train_freq.unit != TrainFrequencyUnit.STEP:
                return base.Collection(None, f"rounds of {frequency} episodes", n_envs)
            if frequency == 1:
                return base.Collection(n_envs, f"steps of its {environments}", n_envs)
            what = f"rounds of {frequency} steps of its {environments}"
            return base.Collection(n_envs * frequency, what, n_envs)
        n_steps = int(getattr(model, "n_steps", 1))
        what = f"rollouts of {environments} x {n_steps} steps"
        return base.Collection(n_envs * n_steps, what, n_envs)

    def learn(self, session: base.Session, stop: base.StopOnInterrupt) -> None:
        """`model.learn` up to the recipe's timesteps, with the progress bar on a terminal."""
        done, end = self.timesteps, self.end()
        evaluations = session.evaluations_until(end, done, self.collection.check_every)
        bar = progress.Bar.open(end, done, evaluations)
        try:
            self.model.learn(
                self.recipe.timesteps - self.model.num_timesteps,
                callback=_SessionCallback(self, session, stop, bar),
                reset_num_timesteps=not self._resumed,
                tb_log_name=self._log_name,
            )
        finally:
            if bar is not None:
                bar.close()

    def predictor(self) -> NormalizedPolicy:
        """The model with the training environments' observation statistics now."""
        keep_normalization(self.model)
        return NormalizedPolicy(self.model, getattr(self.model, NORMALIZATION, None))

    def save_checkpoint(self) -> None:
        """Save the model (and replay buffer, and normalization) with the progress (through
        `Checkpoint.save`, atomically). Raises OutputError."""
        model, checkpoint = self.model, self.checkpoint
        keep_normalization(model)
        normalize = model.get_vec_normalize_env()

        def write(folder: Path) -> None:
            folder.mkdir()
            model.save(folder / Checkpoint.MODEL)
            if isinstance(model, OffPolicyAlgorithm):
                model.save_replay_buffer(folder / Checkpoint.BUFFER)
            if normalize is not None:
                normalize.save(str(folder / Checkpoint.NORMALIZATION))

        try:
            checkpoint.save(self.progress.timesteps, write, self.progress.to_json())
        except OSError as e:
            raise OutputError(f"cannot save checkpoint in {checkpoint.folder}: {e}") from e

    def save_policy(self, path: Path) -> None:
        """The model's .zip, with its observation statistics (see `keep_normalization`)."""
        keep_normalization(self.model)
        base.replace(path, self.model.save)


@contextlib.contextmanager
def trainer(
    info: TaskInfo, folder: base.RunFolder[Checkpoint], args: argparse.Namespace
) -> Iterator[Trainer]:
    """Within `with`: the run in `folder` (resumed from its checkpoint, or new with the
    task's recipe and the command line's --timesteps, --n-envs and --vec) on its training
    environments, which are closed after."""
    progress, recipe = folder.start(
        args,
        lambda algo: recipes.for_task(info, algo, NAME).replace(
            timesteps=args.timesteps, n_envs=args.n_envs, vec=args.vec
        ),
    )
    checkpoint = folder.checkpoint
    saved = checkpoint.normalization_path if folder.resumes else None
    venv = vec_env(info, recipe, progress.seed, saved if saved and saved.is_file() else None)
    try:
        if folder.resumes:
            model = load_model(checkpoint, recipe.algo, venv, args.tensorboard)
            model.set_random_seed(progress.seed + model.num_timesteps)
        else:
            model = new_model(recipe, venv, progress.seed, args.tensorboard)
        if args.tensorboard is None:
            # stable-baselines3's own logger would make an empty folder per run in the
            # system's temporary folder (SB3-<date>), where nothing removes it.
            model.set_logger(Logger(folder=None, output_formats=[]))
        yield Trainer(model, progress, recipe, checkpoint, folder.resumes, folder.out.name)
    finally:
        venv.close()


class _SessionCallback(BaseCallback):
    """Runs the session during `model.learn`: records finished training episodes, advances
    the progress bar, and when the session says an evaluation is due evaluates, prints it,
    logs it for TensorBoard (`eval/...`, with --tensorboard) and saves a checkpoint
    (`files.Checkpoint`)."""

    def __init__(
        self,
        trainer: Trainer,
        session: base.Session,
        stop: base.StopOnInterrupt,
        bar: progress.Bar | None,
    ) -> None:
        super().__init__()
        self.trainer = trainer
        self.session = session
        self.stop = stop
        self.bar = bar

    def _on_step(self) -> bool:
        session = self.session
        timesteps = self.num_timesteps
        if self.bar is not None:
            self.bar.advance_to(timesteps)
        for info in self.locals.get("infos", ()):
            episode = info.get("episode")
            if episode is not None:
                session.progress.record_episode(
                    timesteps, float(episode["r"]), info.get("is_success")
                )
        if not self.stop.requested and session.due(timesteps):
            with progress.evaluating(self.bar):
                result = session.evaluate(self.trainer)
            progress.say(self.bar, describe.evaluation(result))
            for key in ("mean_return", "success_rate", "forward_speed"):
                if result.get(key) is not None:  # TensorBoard's, with --tensorboard
                    self.logger.record(f"eval/{key}", result[key])
            session.save(self.trainer)
        return not self.stop.requested
