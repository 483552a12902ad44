"""Loading a trained policy reads its weights and plain settings only: the same actions as
the libraries' own loaders (which unpickle the whole file), and a crafted file's code does
not run unless the user passes --trust-policy."""

from __future__ import annotations

import base64
import json
import pickle
import zipfile
from pathlib import Path

import numpy as np
import pytest

from composer.cli import catalog, rollout
from tests.cli.helpers import assert_one_line_error, composer

training = pytest.importorskip("composer.cli.training", reason="needs the [train] extra")
from stable_baselines3 import PPO, SAC  # noqa: E402  (the [train] extra, checked above)
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize  # noqa: E402


class CreatesFile:
    """Unpickling it creates `path`: what a stranger's pickle could do instead."""

    def __init__(self, path: Path) -> None:
        self.path = str(path)

    def __reduce__(self):
        return (open, (self.path, "w"))


def payload(marker: Path) -> str:
    """stable-baselines3's JSON form of a pickled value that creates `marker` when loaded."""
    return base64.b64encode(pickle.dumps(CreatesFile(marker))).decode()


def trained(tmp_path: Path, algorithm: type, normalized: bool) -> tuple[Path, object]:
    """A stable-baselines3 model of `algorithm` trained briefly on Reach and saved as
    `composer train` saves it; the path and the environment."""
    info = catalog.find("Reach")
    venv = DummyVecEnv([lambda: catalog.make(info)] * 2)
    if normalized:
        venv = VecNormalize(venv)
    settings = {"n_steps": 64, "batch_size": 64} if algorithm is PPO else {"learning_starts": 32}
    model = algorithm("MlpPolicy", venv, policy_kwargs={"net_arch": [16, 16]}, seed=0,
                      device="cpu", **settings)  # fmt: skip
    model.learn(256)
    training.keep_normalization(model)
    path = tmp_path / f"{algorithm.__name__}.zip"
    model.save(path)
    return path, catalog.make(info)


@pytest.mark.parametrize(("algorithm", "normalized"), [(PPO, True), (PPO, False), (SAC, False)])
def test_a_policy_read_without_pickles_acts_as_the_library_loads_it(tmp_path, algorithm,
                                                                     normalized):  # fmt: skip
    path, env = trained(tmp_path, algorithm, normalized)
    ours = training.load_policy(path, env)
    theirs = training.load_policy(path, env, trusted=True)
    assert isinstance(theirs, algorithm) and not isinstance(ours, algorithm)
    assert hasattr(ours, rollout.NORMALIZATION_ATTRIBUTE) == normalized
    observations = np.random.default_rng(0).normal(0, 2, (200, *env.observation_space.shape))
    act, act_as_they_do = rollout.model_policy(ours), rollout.model_policy(theirs)
    for observation in observations:
        np.testing.assert_array_equal(act(observation), act_as_they_do(observation))


def crafted(tmp_path: Path, member: str) -> tuple[Path, Path]:
    """A real policy.zip whose `member` ('data' or 'policy.pth') now creates a marker file
    when unpickled; the zip and the marker's path."""
    path, _ = trained(tmp_path, PPO, normalized=False)
    marker = tmp_path / "code-ran"
    with zipfile.ZipFile(path) as archive:
        members = {name: archive.read(name) for name in archive.namelist()}
    if member == "data":
        data = json.loads(members["data"])
        data["policy_kwargs"] = {":type:": "<class 'dict'>", ":serialized:": payload(marker)}
        members["data"] = json.dumps(data).encode()
    else:
        members["policy.pth"] = pickle.dumps(CreatesFile(marker))
    crafted_path = tmp_path / "crafted.zip"
    with zipfile.ZipFile(crafted_path, "w") as archive:
        for name, contents in members.items():
            archive.writestr(name, contents)
    return crafted_path, marker


# stable-baselines3's own loader unpickles `data` (so the file's code runs when trusted)
# and reads policy.pth as torch does here, tensors only.
@pytest.mark.parametrize(("member", "runs_when_trusted"), [("data", True), ("policy.pth", False)])
def test_a_crafted_policy_zip_runs_no_code_unless_trusted(tmp_path, member, runs_when_trusted):
    path, marker = crafted(tmp_path, member)
    for command in (["eval", "Reach", path.name], ["run", "Reach", "--policy", path.name]):
        line = assert_one_line_error(composer(*command, cwd=tmp_path), "--trust-policy")
        assert f"{path.name} cannot be loaded without running code from it" in line
        assert not marker.exists()
    # What the refusal protects from: the library's loader runs the file's code.
    composer("eval", "Reach", path.name, "--episodes", "1", "--trust-policy", cwd=tmp_path)
    assert marker.exists() == runs_when_trusted


# -- Ray policies (the [ray] extra) ---------------------------------------------------------


def ray_policy_folder(tmp_path: Path, algo: str) -> Path:
    """A policy folder as `composer train --engine ray` writes it, of a new RLlib module of
    `algo` for CartpoleSwingup (random weights: what is compared is how they load)."""
    pytest.importorskip("ray.rllib", reason="needs the [ray] extra")
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.algorithms.sac import SACConfig

    from composer.cli import ray_files

    env = catalog.make(catalog.find("CartpoleSwingup"))
    config = (PPOConfig() if algo == "ppo" else SACConfig()).rl_module(
        model_config={"fcnet_hiddens": [16, 16], "fcnet_activation": "tanh"}
    )
    spec = config.get_default_rl_module_spec()
    spec.observation_space, spec.action_space = env.observation_space, env.action_space
    spec.model_config = config.model_config  # with what the algorithm adds (SAC's twin_q)
    spec.inference_only = True
    module = spec.build()
    folder = tmp_path / "policy"
    ray_files.write_module(module, folder)
    (folder / ray_files.POLICY_FILE).write_text(json.dumps({
        "format": ray_files.POLICY_FORMAT, "version": ray_files.POLICY_VERSION,
        "task": "CartpoleSwingup", "env_id": "composer/CartpoleSwingup-v0", "algo": algo,
        "model_config": dict(module.model_config),
        "observation_shape": list(env.observation_space.shape),
        "action_low": env.action_space.low.tolist(), "action_high": env.action_space.high.tolist(),
        "observation_filter": {"mean": [0.1] * 5, "std": [2.0] * 5, "clip": 10.0},
    }))  # fmt: skip
    return folder


@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_a_ray_policy_read_without_pickles_acts_as_rllib_loads_it(tmp_path, algo):
    folder = ray_policy_folder(tmp_path, algo)
    from composer.cli import ray_files

    env = catalog.make(catalog.find("CartpoleSwingup"))
    ours, theirs = ray_files.load_policy(folder, env), ray_files.load_policy(folder, env, True)
    for observation in np.random.default_rng(0).normal(0, 2, (200, 5)):
        np.testing.assert_array_equal(ours.predict(observation)[0], theirs.predict(observation)[0])


def test_a_crafted_ray_policy_runs_no_code_unless_trusted(tmp_path):
    folder = ray_policy_folder(tmp_path, "ppo")
    marker = tmp_path / "code-ran"
    (folder / "module" / "class_and_ctor_args.pkl").write_bytes(pickle.dumps(CreatesFile(marker)))
    ran = composer("eval", "CartpoleSwingup", "policy", "--episodes", "1", cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr  # weights.npz and policy.json: no pickle read
    assert not marker.exists()
    (folder / "weights.npz").unlink()  # as written before weights.npz: only RLlib's pickles
    line = assert_one_line_error(composer("eval", "CartpoleSwingup", "policy", cwd=tmp_path))
    assert "holds its network only as RLlib's pickles" in line and "--trust-policy" in line
    assert not marker.exists()
    composer("eval", "CartpoleSwingup", "policy", "--trust-policy", cwd=tmp_path)
    assert marker.exists()
