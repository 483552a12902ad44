"""A checkpoint is saved atomically: a process killed at any moment of a save leaves the
previous save or the new one, whole; never the weights of one with the statistics, replay
buffer or progress of the other."""

from __future__ import annotations

import builtins
import io
import json
import os
import pickle
import shutil
import signal
import zipfile

import pytest
import torch

from composer.cli import catalog, recipes
from composer.cli.engines import base
from composer.cli.engines.sb3 import files

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="kills a forked process")

# What a save does to the disk: each call is a point where the process is killed.
_WRITES = {os: ("open", "replace", "rename", "fsync", "mkdir", "unlink", "rmdir")}


def _trainer(tmp_path, algo):
    """A stable-baselines3 trainer of `algo` on Reach (normalized observations for PPO, a
    replay buffer for SAC), as `composer train` makes one, checkpointing into tmp_path."""
    pytest.importorskip("stable_baselines3", reason="needs the [train] extra")
    from composer.cli.engines.sb3 import training

    info = catalog.find("Reach")
    recipe = recipes.for_task(info, algo, files.NAME).replace(
        timesteps=64, n_envs=1, vec="dummy", n_steps=64, batch_size=64, learning_starts=32
    )
    venv = training.vec_env(info, recipe, seed=0)
    model = training.new_model(recipe, venv, seed=0)
    model.learn(64)
    progress = base.Progress("Reach", info.env_id, algo, 0, recipe.table(), timesteps=64)
    checkpoint = files.Checkpoint(tmp_path / "checkpoint")
    return training.Trainer(model, progress, recipe, checkpoint, False, "run")


def _fingerprint(checkpoint: files.Checkpoint) -> tuple:
    """What a resumed run reads from the checkpoint: its progress, its weights, its
    observation statistics and the size of its replay buffer."""
    timesteps = checkpoint.progress().timesteps
    with zipfile.ZipFile(checkpoint.model_path) as archive:
        weights = torch.load(io.BytesIO(archive.read("policy.pth")), weights_only=True)
    first = float(next(iter(weights.values())).flatten()[0])
    statistics = None
    if checkpoint.normalization_path.is_file():
        with checkpoint.normalization_path.open("rb") as file:
            statistics = float(pickle.load(file).obs_rms.mean[0])
    buffered = None
    if checkpoint.buffer_path.is_file():
        with checkpoint.buffer_path.open("rb") as file:
            buffered = int(pickle.load(file).pos)
    return timesteps, first, statistics, buffered


def _change(trainer) -> None:
    """Make the next save differ from the last one in every file."""
    model = trainer.model
    with torch.no_grad():
        for parameter in model.policy.parameters():
            parameter.add_(1.0)
    normalize = model.get_vec_normalize_env()
    if normalize is not None:
        normalize.obs_rms.mean = normalize.obs_rms.mean + 1.0
    if hasattr(model, "replay_buffer"):
        model.replay_buffer.pos += 1
    trainer.progress.timesteps += 64


def _save_killed_at(trainer, point: int) -> bool:
    """Save in a forked process killed at its `point`-th write (see `_WRITES`); whether it
    was killed (False: the save ended before that point)."""
    child = os.fork()
    if child == 0:  # the child: count writes, die at the chosen one, else save and exit
        try:
            count = [0]

            def killing(function):
                def wrapped(*args, **kwargs):
                    if function is builtins.open and len(args) > 1 and "r" in str(args[1]):
                        return function(*args, **kwargs)
                    count[0] += 1
                    if count[0] == point:
                        os.kill(os.getpid(), signal.SIGKILL)
                    return function(*args, **kwargs)

                return wrapped

            for module, names in _WRITES.items():
                for name in names:
                    setattr(module, name, killing(getattr(module, name)))
            builtins.open = io.open = killing(builtins.open)
            trainer.save_checkpoint()
        except BaseException:
            os._exit(1)
        os._exit(0)
    _, status = os.waitpid(child, 0)
    assert os.WIFSIGNALED(status) or os.WEXITSTATUS(status) == 0, "the save failed"
    return os.WIFSIGNALED(status)


@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_a_save_killed_at_any_write_leaves_the_old_or_the_new_checkpoint(tmp_path, algo):
    trainer = _trainer(tmp_path, algo)
    checkpoint = trainer.checkpoint
    trainer.save_checkpoint()
    old = _fingerprint(checkpoint)
    kept = tmp_path / "kept"
    shutil.copytree(checkpoint.folder, kept)
    _change(trainer)
    new = _saved_elsewhere(trainer, files.Checkpoint(tmp_path / "elsewhere"))
    assert all(a != b for a, b in zip(old, new, strict=True) if a is not None)
    seen = set()
    point = 1
    while _save_killed_at(trainer, point):
        assert checkpoint.exists(), f"killed at write {point}: no complete checkpoint"
        found = _fingerprint(checkpoint)
        seen.add(found)
        assert found in (old, new), (point, found, old, new)
        shutil.rmtree(checkpoint.folder)
        shutil.copytree(kept, checkpoint.folder)
        point += 1
    print(f"{algo}: killed at each of {point - 1} writes")
    assert point > 10  # writes of four files, their folder, state.json and the clean-up
    assert seen == {old, new}  # killed before the save counts, and after
    extra = "vecnormalize.pkl" if algo == "ppo" else "replay_buffer.pkl"
    assert {p.name for p in checkpoint.current().iterdir()} == {"model.zip", extra}


def _saved_elsewhere(trainer, checkpoint: files.Checkpoint) -> tuple:
    """The fingerprint of `trainer`'s run saved whole into `checkpoint`."""
    saved_to, trainer.checkpoint = trainer.checkpoint, checkpoint
    try:
        trainer.save_checkpoint()
    finally:
        trainer.checkpoint = saved_to
    return _fingerprint(checkpoint)


def test_a_checkpoint_written_before_saves_had_folders_is_read_and_replaced(tmp_path):
    trainer = _trainer(tmp_path, "ppo")
    checkpoint = trainer.checkpoint
    trainer.save_checkpoint()
    # The layout of earlier releases: the files beside a state.json that names no save.
    current = checkpoint.current()
    for path in current.iterdir():
        path.rename(checkpoint.folder / path.name)
    current.rmdir()
    state = checkpoint.state()
    del state["saved"]
    checkpoint.state_path.write_text(json.dumps(state))
    assert checkpoint.exists() and checkpoint.model_path == checkpoint.folder / "model.zip"
    before = _fingerprint(checkpoint)
    trainer.save_checkpoint()
    assert _fingerprint(checkpoint) == before  # the same model, saved in the new layout
    names = {p.name for p in checkpoint.folder.iterdir()}
    assert names == {"state.json", checkpoint.current().name}
