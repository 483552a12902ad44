"""Training recipes live with their tasks: the shipped ones are the measured runs', a
task's own module gives them (your `composer --import` module too), and an engine's
changes apply to that engine only."""

from __future__ import annotations

import json
import re

import pytest

import tasks
from composer import registration
from composer.cli import catalog, recipes
from composer.cli.errors import RecipeError
from composer.cli.recipes import GENERIC, Recipe
from tests.cli.helpers import REPO, composer
from tests.composer.scenes import SwingTask

TRAINING = REPO / "docs" / "training"
SWING = registration.TaskInfo("Swing", "composer/Swing-v0", "tests.composer.scenes:SwingTask",
                              "", {})  # fmt: skip


def plain_task() -> SwingTask:
    """A task factory no recipe is registered for."""
    return SwingTask()


@pytest.mark.parametrize("task", sorted(p.name for p in TRAINING.iterdir() if p.is_dir()))
def test_a_shipped_task_s_default_recipe_is_that_of_its_measured_run(task):
    measured = json.loads((TRAINING / task / "metrics.json").read_text())
    assert measured["task"] == task
    # NAME-pixels: the task's pixel recipe, measured with --pixels.
    name = task.removesuffix(catalog.PIXELS_SUFFIX)
    info = catalog.find(name) if name == task else catalog.with_pixels(catalog.find(name))
    assert recipes.default_algo(info) == measured["algo"]
    assert recipes.for_task(info) == Recipe.from_table(measured["recipe"])


def test_every_shipped_task_has_a_recipe_and_the_ray_engine_its_own_changes():
    infos = [info for info in registration.registered().values() if info.env_id in tasks.IDS]
    assert len(infos) == len(tasks.IDS) == 5
    for info in infos:
        sb3 = recipes.for_task(info, "ppo", "sb3")
        ray = recipes.for_task(info, "ppo", "ray")
        assert recipes.registered(info)[0].replace(engine_changes={}) == sb3
        if info.name == "CartpoleSwingup":  # measured: docs/ray.md
            assert ray == sb3.replace(n_envs=32, n_steps=128)
        else:
            assert ray == sb3
        # No task has a SAC recipe: the generic one.
        assert recipes.for_task(info, "sac") == GENERIC["sac"]


def test_a_task_without_recipes_trains_with_the_generic_ones():
    info = registration.TaskInfo("Plain", "composer/Plain-v0", "tests.cli.test_recipes:plain_task",
                                 "", {})  # fmt: skip
    assert recipes.registered(info) == ()
    assert recipes.default_algo(info) == "ppo"
    assert recipes.for_task(info) == GENERIC["ppo"]
    assert recipes.for_task(info, "sac", "ray") == GENERIC["sac"]


@pytest.mark.parametrize(
    ("task", "given", "message"),
    [
        ("not a task", (GENERIC["ppo"],), "a task class or factory, or a Gymnasium id"),
        (SwingTask, (), "give at least one Recipe"),
        (SwingTask, ({"algo": "ppo"},), "expected Recipe objects, got {'algo': 'ppo'}"),
        (SwingTask, (GENERIC["ppo"].replace(algo="a2c"),), "algo 'a2c' is not one of"),
        (SwingTask, (GENERIC["ppo"], GENERIC["ppo"]), "one recipe per algorithm"),
        (SwingTask, (GENERIC["sac"].replace(initial_temperature=0.0),),
         "the sac recipe's initial_temperature must be > 0, got 0.0"),
        (SwingTask, (GENERIC["ppo"].replace(engine_changes={"ray": {"envs": 4}}),),
         "the ppo recipe's changes for engine 'ray' name fields a Recipe does not have: "
         "['envs']"),
    ],
)  # fmt: skip
def test_a_recipe_that_cannot_be_registered_is_refused_and_nothing_changes(task, given, message):
    before = recipes.registered(SWING)
    with pytest.raises(RecipeError, match=re.escape(message)) as raised:
        recipes.register(task, *given)
    assert isinstance(raised.value, ValueError)
    assert recipes.registered(SWING) == before


def test_your_own_task_s_recipe_is_listed_and_trained_with(tmp_path):
    own = ("--import", "tests.cli.own_tasks")
    helped = composer(*own, "train", "--help", cwd=tmp_path)
    assert helped.returncode == 0, helped.stderr
    assert re.search(r"^  Swing +ppo +4,096 +2 +dummy +16x16 +0\.001 +64 +0\.99$", helped.stdout,
                     re.M)  # fmt: skip
    trained = composer(*own, "train", "Swing", "--timesteps", "64", "--no-video",
                       "--eval-episodes", "1", "--out", "run", cwd=tmp_path)  # fmt: skip
    assert trained.returncode == 0, trained.stderr
    assert "training Swing with PPO to 64 steps on 2 environments -> run" in trained.stdout
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert Recipe.from_table(metrics["recipe"]) == Recipe("ppo", 64, 2, (16, 16), 1e-3, 64,
                                                          n_steps=32, n_epochs=2)  # fmt: skip


def test_a_recipe_for_one_id_wins_over_its_task_class_s():
    swing = registration.TaskInfo("Swing2", "test/Swing-v2", "tests.composer.scenes:SwingTask",
                                  "", {})  # fmt: skip
    sac = GENERIC["sac"].replace(timesteps=1_000)
    recipes.register(SwingTask, GENERIC["ppo"].replace(timesteps=2_000))
    recipes.register("test/Swing-v2", sac)
    try:
        assert recipes.registered(swing) == (sac,)  # the id's own
        assert recipes.registered(SWING)[0].timesteps == 2_000  # the class's, for other ids
        assert recipes.default_algo(swing) == "sac"
    finally:
        recipes._RECIPES.pop("test/Swing-v2")
        recipes._RECIPES.pop(SwingTask)


@pytest.mark.parametrize("temperature", [1.0, 0.1])
def test_sac_starts_from_the_recipe_s_entropy_temperature(temperature):
    pytest.importorskip("stable_baselines3")
    import gymnasium as gym
    from stable_baselines3.common.vec_env import DummyVecEnv

    from composer.cli.engines.sb3 import training

    recipe = GENERIC["sac"].replace(initial_temperature=temperature, net=(8,))
    venv = DummyVecEnv(
        [lambda: gym.make("dm_control/cartpole-swingup-v0", flatten_observations=True)]
    )
    model = training.new_model(recipe, venv, seed=0)
    assert model.ent_coef_optimizer is not None  # learned, from the recipe's start
    assert float(model.log_ent_coef.detach().exp()) == pytest.approx(temperature)
