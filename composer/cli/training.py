"""Training on stable-baselines3: parallel environments, models, checkpoints, a session
that evaluates, records progress and stops cleanly on Ctrl-C, and the engine's `Trainer`.

    venv = training.vec_env(info, recipe, seed=0)          # K environments, VecMonitor'd
    model = training.new_model(recipe, venv, seed=0)
    checkpoint = training.Checkpoint('runs/Reach-ppo/checkpoint')
    session = training.Session(progress, checkpoint, eval_env, eval_every=80_000,
                               eval_episodes=10)
    with training.StopOnInterrupt() as stop:
        bar = progress.Bar.open(recipe.timesteps, done=0)       # None off a terminal
        model.learn(recipe.timesteps, callback=session.callback(stop, bar))
    session.save(model)                                    # a checkpoint with the progress
    policy = training.load_policy('runs/Reach-ppo', env)   # for `run`, `eval`, `view`

`composer train` drives it through `trainer(info, folder, args)`, the stable-baselines3
`engine.Trainer`. `Session`, `StopOnInterrupt` and `report` serve the Ray engine too.

This module imports stable-baselines3 and torch, so the commands import it only when they
need it; without them importing it raises MissingExtraError with the install command.

A checkpoint is a folder: `model.zip`, `replay_buffer.pkl` for off-policy algorithms,
`vecnormalize.pkl` for normalized recipes, and `state.json` (the `Progress`), each replaced
atomically, `state.json` last (`composer.cli.engine`).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import os
import signal
import sys
import time
import zipfile
from collections.abc import Callable, Iterator
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any

import gymnasium

from composer.cli import catalog, engine, progress, ray_files, recipes, rollout
from composer.cli.engine import DEFAULT_ENGINE, Progress
from composer.cli.errors import TRAIN_INSTALL, MissingExtraError, OutputError, PolicyError
from composer.cli.ray_files import RayPolicy
from composer.registration import TaskInfo, make_environment

if TYPE_CHECKING:
    from composer.cli.run_folder import RunFolder

try:
    import stable_baselines3
    import torch
    from stable_baselines3.common.base_class import BaseAlgorithm
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
    from stable_baselines3.common.policies import BasePolicy
    from stable_baselines3.common.running_mean_std import RunningMeanStd
    from stable_baselines3.common.vec_env import (
        DummyVecEnv,
        SubprocVecEnv,
        VecEnv,
        VecMonitor,
        VecNormalize,
    )

    from composer import sb3
    from composer.cli import sb3_files
except ImportError as e:
    raise MissingExtraError(
        f"this command needs the [train] extra ({e.name or 'stable-baselines3'} is missing): "
        f"{TRAIN_INSTALL}"
    ) from e

ALGORITHMS: dict[str, type[BaseAlgorithm]] = {
    "ppo": stable_baselines3.PPO,
    "sac": stable_baselines3.SAC,
}
EVAL_SEED = rollout.EVAL_SEED
# Small networks gain nothing from intra-op threads, and on a busy CPU torch's spinning
# threads made each update 7 to 30 times slower (measured on 2 cores): use one.
TORCH_THREADS = 1
torch.set_num_threads(TORCH_THREADS)


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
    recipe says so, with the statistics saved at `normalization` if given."""
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
    return VecNormalize(venv, gamma=recipe.gamma)


def keep_normalization(model: BaseAlgorithm) -> None:
    """Copy the training environments' observation statistics into the model (as
    `observation_normalization`, saved in its .zip) for `rollout.model_policy`."""
    normalize = model.get_vec_normalize_env()
    if normalize is not None:
        statistics = normalize.obs_rms
        assert isinstance(statistics, RunningMeanStd), "observations are one vector"
        setattr(model, rollout.NORMALIZATION_ATTRIBUTE, {
            "mean": statistics.mean.tolist(),
            "var": statistics.var.tolist(),
            "epsilon": float(normalize.epsilon),
            "clip": float(normalize.clip_obs),
        })  # fmt: skip


def new_model(
    recipe: recipes.Recipe, venv: VecEnv, seed: int, tensorboard: str | None = None
) -> BaseAlgorithm:
    """A fresh model of `recipe`'s algorithm on `venv`, on the CPU, logging to TensorBoard
    in the folder `tensorboard` if given."""
    kwargs = recipe.algo_kwargs()
    if recipe.algo == "sac":  # a replay buffer larger than the run only costs memory
        kwargs["buffer_size"] = min(kwargs["buffer_size"], recipe.timesteps)
    return ALGORITHMS[recipe.algo](
        "MlpPolicy", venv, seed=seed, device="cpu", tensorboard_log=tensorboard, **kwargs
    )


def require_tensorboard() -> None:
    """Raise MissingExtraError now, before training, if TensorBoard logging cannot work."""
    try:
        import torch.utils.tensorboard  # noqa: F401
    except ImportError as e:
        raise MissingExtraError(
            f"--tensorboard needs the tensorboard package ({e.name or e} is missing): "
            "pip install tensorboard, or pip install -e '.[train]'"
        ) from e


def policy_file(path: str | os.PathLike[str]) -> Path:
    """The policy .zip `path` names: itself, or in a folder written by `composer train`
    its policy.zip, else its checkpoint. Raises PolicyError when there is none."""
    path = Path(path)
    candidates = [path] if path.suffix == ".zip" else [
        path / "policy.zip", path / "checkpoint" / "model.zip", path / "model.zip"
    ]  # fmt: skip
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    raise PolicyError(f"no policy at {path}: give a .zip or a folder written by `composer train`")


def algo_of(path: Path) -> str:
    """The algorithm ('ppo', 'sac') a stable-baselines3 .zip was saved by, from the module
    of its policy class: `stable_baselines3.sac.policies` for SAC, the shared actor-critic
    policies of `stable_baselines3.common.policies` for PPO."""
    try:
        with zipfile.ZipFile(path) as archive:
            module = json.loads(archive.read("data"))["policy_class"]["__module__"]
    except (OSError, zipfile.BadZipFile, KeyError, TypeError, ValueError) as e:
        raise PolicyError(f"{path} is not a stable-baselines3 policy file: {e}") from e
    if module == "stable_baselines3.common.policies":
        algo = "ppo"
    else:
        algo = module.removeprefix("stable_baselines3.").partition(".")[0]
    if algo not in ALGORITHMS:
        raise PolicyError(f"{path} holds a {module!r} policy, not one of {list(ALGORITHMS)}")
    return algo


def load_policy(
    path: str | os.PathLike[str], env: gymnasium.Env, trusted: bool = False
) -> BasePolicy | BaseAlgorithm | RayPolicy:
    """The policy saved at `path` (see `policy_file`), checked to fit `env`'s spaces, with
    `predict(observation, deterministic)`; one trained with `--engine ray` loads as a
    RayPolicy (`composer.cli.ray_files`). Only its weights and plain settings are read
    (`composer.cli.sb3_files`), unless `trusted`: then the library's own loader reads it
    whole, unpickling and so running code from the file. Raises PolicyError, and
    UntrustedPolicyError when the file can only be read whole."""
    ray_policy = ray_files.find_policy(path)
    if ray_policy is not None:
        return ray_files.load_policy(ray_policy, env, trusted)
    file = policy_file(path)
    algorithm = ALGORITHMS[algo_of(file)]
    if not trusted:
        return sb3_files.load_policy(file, algorithm, env)
    model = algorithm.load(file, device="cpu")
    engine.check_spaces(file, model, env)
    return model


# -- checkpoints and the trainer -----------------------------------------------------------


class Checkpoint(engine.Checkpoint):
    """A stable-baselines3 training checkpoint in a folder (see the module docstring)."""

    engine = DEFAULT_ENGINE
    policy = "policy.zip"

    def __init__(self, folder: str | os.PathLike[str]) -> None:
        """A checkpoint at `folder` (which need not exist yet)."""
        super().__init__(folder)
        self.model_path = self.folder / "model.zip"
        self.buffer_path = self.folder / "replay_buffer.pkl"
        self.normalization_path = self.folder / "vecnormalize.pkl"

    def save(self, model: BaseAlgorithm, progress: Progress) -> None:
        """Save the model (and replay buffer), then the progress; raises OutputError."""
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            keep_normalization(model)
            engine.replace(self.model_path, model.save)
            if isinstance(model, OffPolicyAlgorithm):
                engine.replace(self.buffer_path, model.save_replay_buffer)
            normalize = model.get_vec_normalize_env()
            if normalize is not None:
                engine.replace(self.normalization_path, lambda path: normalize.save(str(path)))
            self._save_state(progress.to_json())
        except OSError as e:
            raise OutputError(f"cannot save checkpoint in {self.folder}: {e}") from e

    def load(self, algo: str, venv: VecEnv, tensorboard: str | None = None) -> BaseAlgorithm:
        """The checkpointed model of `algo`, training on `venv`, with its replay buffer,
        logging to TensorBoard in the folder `tensorboard` if given."""
        model = ALGORITHMS[algo].load(
            self.model_path, env=venv, device="cpu", tensorboard_log=tensorboard
        )
        if isinstance(model, OffPolicyAlgorithm) and self.buffer_path.is_file():
            model.load_replay_buffer(self.buffer_path)
        return model

    def _complete(self) -> bool:
        return self.model_path.is_file()

    def _saved_files(self) -> list[Path]:
        saved = (self.model_path, self.buffer_path, self.normalization_path)
        return [p for path in saved for p in (path, engine.partial_path(path)) if p.is_file()]


class Trainer(engine.Trainer):
    """A stable-baselines3 model training on its environments (`trainer` opens one)."""

    def __init__(
        self,
        model: BaseAlgorithm,
        progress: Progress,
        recipe: recipes.Recipe,
        resumed: bool,
        log_name: str,
    ) -> None:
        """Train `model` (`resumed` from a checkpoint or new) on as `recipe` says;
        `log_name`: its TensorBoard run's name."""
        super().__init__(model, progress, recipe)
        self._resumed = resumed
        self._log_name = log_name

    @property
    def where(self) -> str:
        """'16 environments'."""
        return engine.plural(self.recipe.n_envs, "environment")

    def learn(self, session: Session, stop: StopOnInterrupt) -> None:
        """`model.learn` up to the recipe's timesteps, with the progress bar on a terminal."""
        bar = progress.Bar.open(self.recipe.timesteps, self.model.num_timesteps)
        try:
            self.model.learn(
                self.recipe.timesteps - self.model.num_timesteps,
                callback=session.callback(stop, bar),
                reset_num_timesteps=not self._resumed,
                tb_log_name=self._log_name,
            )
        finally:
            if bar is not None:
                bar.close()

    def save_policy(self, path: Path) -> None:
        """The model's .zip, with its observation statistics (see `keep_normalization`)."""
        keep_normalization(self.model)
        engine.replace(path, self.model.save)


@contextlib.contextmanager
def trainer(
    info: TaskInfo, folder: RunFolder[Checkpoint], args: argparse.Namespace
) -> Iterator[Trainer]:
    """Within `with`: the run in `folder` (resumed from its checkpoint, or new with the
    task's recipe and the command line's --timesteps, --n-envs and --vec) on its training
    environments, which are closed after."""
    progress, recipe = folder.start(
        args,
        lambda algo: recipes.for_task(info.name, algo).replace(
            timesteps=args.timesteps, n_envs=args.n_envs, vec=args.vec
        ),
    )
    checkpoint = folder.checkpoint
    saved = checkpoint.normalization_path
    venv = vec_env(
        info, recipe, progress.seed, saved if folder.resumes and saved.is_file() else None
    )
    try:
        if folder.resumes:
            model = checkpoint.load(recipe.algo, venv, args.tensorboard)
            model.set_random_seed(progress.seed + model.num_timesteps)
        else:
            model = new_model(recipe, venv, progress.seed, args.tensorboard)
        if args.tensorboard is None:
            # stable-baselines3's own logger would make an empty folder per run in the
            # system's temporary folder (SB3-<date>), where nothing removes it.
            model.set_logger(Logger(folder=None, output_formats=[]))
        yield Trainer(model, progress, recipe, folder.resumes, folder.out.name)
    finally:
        venv.close()


# -- a training session ------------------------------------------------------------------


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
    """Book-keeping of one training session, on either engine: evaluates every
    `eval_every` timesteps, saves a checkpoint after each evaluation, records finished
    training episodes."""

    def __init__(
        self,
        progress: Progress,
        checkpoint: engine.Checkpoint,
        eval_env: gymnasium.Env,
        eval_every: int,
        eval_episodes: int,
    ) -> None:
        """Continue `progress`; evaluate on `eval_env` (flattened observations)."""
        self.progress = progress
        self.checkpoint = checkpoint
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

    def evaluate(self, model: Any) -> dict[str, Any]:
        """Evaluate `model` (an engine's Trainer's, as it is now: see `rollout.model_policy`),
        record the result in the progress and return it. A result at the timesteps of the
        last one replaces it: PPO evaluates during its last rollout and updates the policy
        after, so the model after training is evaluated again."""
        episodes = rollout.run_episodes(
            self.eval_env, rollout.model_policy(model), self.eval_episodes, EVAL_SEED
        )
        result = {
            "timesteps": int(model.num_timesteps),
            "wall_time": round(self.elapsed(), 2),
            **rollout.summary(episodes),
        }
        evaluations = self.progress.evaluations
        if evaluations and evaluations[-1]["timesteps"] == result["timesteps"]:
            evaluations.pop()
        evaluations.append(result)
        return result

    def save(self, model: Any) -> None:
        """Save a checkpoint of `model` (the checkpoint's engine's) with the progress so far."""
        self.progress.timesteps = int(model.num_timesteps)
        self.progress.wall_time = round(self.elapsed(), 2)
        self.progress.cpu_time = round(
            self._cpu_time_before + time.process_time() - self._cpu_started, 2
        )
        self.checkpoint.save(model, self.progress)

    def callback(self, stop: StopOnInterrupt, bar: progress.Bar | None = None) -> BaseCallback:
        """The stable-baselines3 callback running this session, advancing `bar`."""
        return _SessionCallback(self, stop, bar)

    def due(self, timesteps: int) -> bool:
        """Whether an evaluation is due at `timesteps`; schedules the next one."""
        if timesteps < self._next_eval:
            return False
        while self._next_eval <= timesteps:
            self._next_eval += self.eval_every
        return True


class _SessionCallback(BaseCallback):
    def __init__(self, session: Session, stop: StopOnInterrupt, bar: progress.Bar | None) -> None:
        super().__init__()
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
            keep_normalization(self.model)
            result = session.evaluate(self.model)
            progress.say(self.bar, report(result))
            for key in ("mean_return", "success_rate", "forward_speed"):
                if result.get(key) is not None:  # TensorBoard's, with --tensorboard
                    self.logger.record(f"eval/{key}", result[key])
            session.save(self.model)
        return not self.stop.requested


def report(result: dict[str, Any]) -> str:
    """One line for an evaluation, short enough for an 80-column terminal under the
    progress bar: '   200,000 steps  1m32s  return 44.38 ± 14.73  success 0.50'."""
    text = (
        f"{result['timesteps']:>10,} steps {duration(result['wall_time']):>6}  "
        f"return {result['mean_return']:.2f} ± {result['std_return']:.2f}"
    )
    if result["success_rate"] is not None:
        text += f"  success {result['success_rate']:.2f}"
    if result.get("forward_speed") is not None:
        text += f"  {result['forward_speed']:.2f} m/s"
    return text


def duration(seconds: float) -> str:
    """'42s', '3m05s', '1h02m'."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"
