"""Each engine needs only its own library: with stable-baselines3, torch or Ray not
installed, every CLI module imports (but those that exist to run the missing library),
and `composer list`, `run` and `eval` work, the latter on a policy of the engine that is
installed, with the same results as with everything installed. (`composer train` of each
engine without the other's library: tests/cli/test_train.py and test_train_ray.py.)"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from composer.cli import engines
from tests.cli.helpers import LIBRARIES, blocker, composer, composer_without, environment
from tests.cli.policies import ray_policy_folder, trained
from tests.cli.test_cli_architecture import cli_modules

# The modules that run stable-baselines3 (and torch), imported only to load its policies
# or to train with it (the pixel recipes' encoder is a torch module).
SB3_RUNNERS = {"engines.sb3.encoder", "engines.sb3.policy", "engines.sb3.training"}


@pytest.mark.parametrize(
    ("blocked", "failing"),
    [(("stable_baselines3",), SB3_RUNNERS), (("torch",), SB3_RUNNERS), (("ray",), set())],
)
def test_every_cli_module_imports_without_an_engines_library(tmp_path, blocked, failing):
    code = blocker(blocked) + (
        "import importlib, json\n"
        "outcome = {}\n"
        f"for name in {sorted(cli_modules())!r}:\n"
        "    try:\n"
        "        importlib.import_module('composer.cli.' + name)\n"
        "        outcome[name] = 'imported'\n"
        "    except ImportError as e:\n"
        "        outcome[name] = f'needs {e.name}'\n"
        "print(json.dumps(outcome))\n"
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=environment(),
                            capture_output=True, text=True, timeout=120, check=False)  # fmt: skip
    assert result.returncode == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert set(outcome) == set(cli_modules()) and len(outcome) > 25
    assert {name: how for name, how in outcome.items() if how != "imported"} == {
        name: f"needs {blocked[0]}" for name in failing
    }


def test_every_engine_is_known_without_its_library(tmp_path):
    """What the commands ask of every engine (its options, checkpoint and policy name,
    whether a folder holds its policy) needs no library."""
    code = blocker(LIBRARIES) + (
        "from pathlib import Path\n"
        "from composer.cli import engines\n"
        "for engine in engines.every():\n"
        "    print(engine.name, engine.policy, engine.checkpoint.engine, engine.options,\n"
        "          engine.find_policy(Path('nothing')))\n"
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=environment(),
                            capture_output=True, text=True, timeout=120, check=False)  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [
        "sb3 policy.zip sb3 ('n_envs', 'vec', 'tensorboard') None",
        "ray policy ray ('workers', 'envs_per_worker', 'address') None",
    ]
    assert engines.names() == ("sb3", "ray") and engines.DEFAULT == "sb3"


def _without(library: str, command: list[str], tmp_path) -> str:
    """The output of `command` with `library` not installed, checked to match the output
    with everything installed and to have imported no `library`."""
    result = composer_without((library,), *command, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    *lines, imported = result.stdout.splitlines()
    assert imported.startswith("imported: [") and repr(library) not in imported
    if command[0] != "list":  # `list` is checked by tests/cli/test_listing.py
        installed = composer(*command, cwd=tmp_path)
        assert installed.returncode == 0, installed.stderr
        assert lines == installed.stdout.splitlines()
    return "\n".join(lines)


def test_without_stable_baselines3_a_ray_policy_runs_and_evaluates(tmp_path):
    ray_policy_folder(tmp_path, "ppo")
    assert "CartpoleSwingup" in _without("stable_baselines3", ["list"], tmp_path)
    ran = _without("stable_baselines3", ["run", "CartpoleSwingup", "--policy", "policy"], tmp_path)
    assert "CartpoleSwingup, policy policy: return" in ran
    evaluated = _without("stable_baselines3", ["eval", "CartpoleSwingup", "policy", "--episodes",
                                               "2"], tmp_path)  # fmt: skip
    assert evaluated.startswith("CartpoleSwingup, policy policy: return")


def test_without_ray_a_stable_baselines3_policy_runs_and_evaluates(tmp_path):
    path, _ = trained(tmp_path, "ppo", normalized=True)
    assert "Reach" in _without("ray", ["list"], tmp_path)
    ran = _without("ray", ["run", "Reach", "--policy", path.name], tmp_path)
    assert f"Reach, policy {path.name}: return" in ran
    evaluated = _without("ray", ["eval", "Reach", path.name, "--episodes", "2"], tmp_path)
    assert evaluated.startswith(f"Reach, policy {path.name}: return")
