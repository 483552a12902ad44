"""`--pixels`: a task observed through its camera trains with its pixel recipe (a small CNN
on stacked 64x64 frames), and the policy it writes runs and evaluates on the same frames,
loaded without unpickling; the commands that cannot take frames say so."""

from __future__ import annotations

import json
import re
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from composer import registration
from composer.cli import catalog, engines, recipes, rollout
from composer.cli.engines.sb3 import files
from composer.cli.errors import RecipeError
from composer.cli.main import main
from composer.pixels import PixelEnvironment
from tests.cli.helpers import assert_one_line_error, composer
from tests.composer.scenes import SwingTask


def test_pixels_observe_the_task_as_gym_make_does_with_the_pixel_recipe():
    state = catalog.find("CartpoleSwingup")
    info = catalog.with_pixels(state)
    assert info.name == "CartpoleSwingup-pixels" and info.env_id == state.env_id
    assert catalog.command_line(info) == "CartpoleSwingup --pixels"
    assert catalog.observes_pixels(info) and not catalog.observes_pixels(state)
    env = catalog.make(info)
    try:
        assert isinstance(env, PixelEnvironment)
        assert env.observation_space.shape == (64, 64, 9)
        assert env.observation_space.dtype == np.uint8
        first, _ = env.reset(seed=3)
        # gym.make's keywords, the task's camera: the same frames.
        made = gym.make(state.env_id, pixels=True, width=64, height=64, frame_stack=3)
        np.testing.assert_array_equal(made.reset(seed=3)[0], first)
        made.close()
    finally:
        env.close()
    recipe = recipes.for_task(info)
    assert recipe.pixels and recipe == recipes.registered(state)[1]
    assert recipes.for_task(state) == recipes.registered(state)[0].for_engine(None)
    assert not recipes.for_task(state).pixels
    with pytest.raises(RecipeError, match="no sac recipe from pixels"):
        recipes.for_task(info, "sac")


@pytest.mark.parametrize(
    ("recipe", "message"),
    [
        (recipes.GENERIC_PIXELS["ppo"].replace(vec="batched"), "give vec='dummy' or 'subproc'"),
        (recipes.GENERIC_PIXELS["ppo"].replace(conv=()), "needs conv layers"),
    ],
)
def test_a_pixel_recipe_that_cannot_train_is_refused(recipe, message):
    with pytest.raises(RecipeError, match=re.escape(message)):
        recipes.register(SwingTask, recipe)


def test_a_state_and_a_pixel_recipe_of_one_algorithm_register_together():
    state, pixels = recipes.GENERIC["ppo"], recipes.GENERIC_PIXELS["ppo"].replace(n_envs=4)
    swing = registration.TaskInfo("Swing", "composer/Swing-v0",
                                          "tests.composer.scenes:SwingTask", "", {})  # fmt: skip
    try:
        recipes.register(SwingTask, state, pixels)
        assert recipes.for_task(swing) == state
        assert recipes.for_task(catalog.with_pixels(swing)) == pixels
        with pytest.raises(RecipeError, match="one per algorithm from pixels"):
            recipes.register(SwingTask, pixels, pixels)
        assert recipes.registered(swing) == (state, pixels)
    finally:
        recipes._RECIPES.pop(SwingTask, None)


def test_train_from_pixels_then_eval_and_run_the_policy(tmp_path, capsys, monkeypatch):
    pytest.importorskip("stable_baselines3", reason="needs the [train] extra")
    monkeypatch.chdir(tmp_path)  # in this process: the subprocesses' start-up is most of it
    assert main(["train", "CartpoleSwingup", "--pixels", "--timesteps", "256", "--n-envs", "2",
                 "--eval-every", "256", "--eval-episodes", "1", "--no-video"]) == 0  # fmt: skip
    trained = capsys.readouterr().out
    out = Path("runs") / "CartpoleSwingup-pixels-ppo"
    assert "training CartpoleSwingup-pixels with PPO to 256 steps on 2 environments" in trained
    assert f"composer run CartpoleSwingup --pixels --policy {out} " in trained
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["task"] == "CartpoleSwingup-pixels" and metrics["timesteps"] == 256
    recipe = recipes.Recipe.from_table(metrics["recipe"])
    shipped = recipes.for_task(catalog.with_pixels(catalog.find("CartpoleSwingup")))
    assert recipe == shipped.replace(timesteps=256, n_envs=2)

    # The policy file: read without unpickling, the recipe's encoder, the library's actions.
    from composer.cli.engines.sb3.encoder import PixelEncoder

    env = catalog.make(catalog.with_pixels(catalog.find("CartpoleSwingup")))
    try:
        ours = engines.load_policy(out, env)
        theirs = engines.load_policy(out, env, trusted=True)
        # Rewards were normalized (the checkpoint keeps their statistics), frames were not.
        checkpoint = files.Checkpoint(out / "checkpoint")
        assert recipe.normalize and checkpoint.normalization_path.is_file()
        assert ours.statistics is None and theirs.statistics is None
        encoder = ours.network.features_extractor
        assert isinstance(encoder, PixelEncoder)
        convs = [m for m in encoder.conv if hasattr(m, "kernel_size")]
        assert [(m.out_channels, m.kernel_size[0], m.stride[0]) for m in convs] == list(recipe.conv)
        assert encoder.features_dim == recipe.features
        frames = np.random.default_rng(0).integers(0, 256, (20, 64, 64, 9), dtype=np.uint8)
        for frame in frames:
            np.testing.assert_array_equal(
                rollout.model_policy(ours)(frame), rollout.model_policy(theirs)(frame)
            )
    finally:
        env.close()

    # eval repeats training's final evaluation on the same frames; run acts on them too.
    final = metrics["final"]
    assert main(["eval", "CartpoleSwingup", "--pixels", str(out), "--episodes", "1"]) == 0
    assert capsys.readouterr().out == (
        f"CartpoleSwingup-pixels, policy {out}: return {final['mean_return']:.2f} ± 0.00 "
        "over 1 episode\n"
    )
    assert main(["run", "CartpoleSwingup", "--pixels", "--policy", str(out)]) == 0
    assert f"CartpoleSwingup-pixels, policy {out}: return" in capsys.readouterr().out
    assert main(["eval", "CartpoleSwingup", str(out)]) == 2
    assert "observations of shape (9, 64, 64), but this task has (5,): it was trained from " \
        "pixels: give --pixels" in capsys.readouterr().err  # fmt: skip


def test_commands_that_cannot_take_frames_say_so(tmp_path):
    ray = composer("train", "CartpoleSwingup", "--pixels", "--engine", "ray", cwd=tmp_path)
    assert_one_line_error(ray, "--engine ray cannot train CartpoleSwingup-pixels yet")
    batched = composer("train", "CartpoleSwingup", "--pixels", "--vec", "batched", cwd=tmp_path)
    assert_one_line_error(batched, "--vec batched steps environments without frames")
    assert not (tmp_path / "runs").exists()
