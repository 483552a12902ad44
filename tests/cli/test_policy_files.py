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

from composer.cli import catalog, engines, rollout
from tests.cli.helpers import assert_one_line_error, composer
from tests.cli.policies import ray_policy_folder, trained


class CreatesFile:
    """Unpickling it creates `path`: what a stranger's pickle could do instead."""

    def __init__(self, path: Path) -> None:
        self.path = str(path)

    def __reduce__(self):
        return (open, (self.path, "w"))


def payload(marker: Path) -> str:
    """stable-baselines3's JSON form of a pickled value that creates `marker` when loaded."""
    return base64.b64encode(pickle.dumps(CreatesFile(marker))).decode()


@pytest.mark.parametrize(("algo", "normalized"), [("ppo", True), ("ppo", False), ("sac", False)])
def test_a_policy_read_without_pickles_acts_as_the_library_loads_it(tmp_path, algo, normalized):
    from stable_baselines3.common.base_class import BaseAlgorithm

    path, env = trained(tmp_path, algo, normalized)
    ours = engines.load_policy(path, env)
    theirs = engines.load_policy(path, env, trusted=True)
    assert isinstance(theirs.network, BaseAlgorithm)  # the library's loader: the whole model
    assert not isinstance(ours.network, BaseAlgorithm)  # its policy network alone
    assert (ours.statistics is not None) == (theirs.statistics is not None) == normalized
    observations = np.random.default_rng(0).normal(0, 2, (200, *env.observation_space.shape))
    act, act_as_they_do = rollout.model_policy(ours), rollout.model_policy(theirs)
    for observation in observations:
        np.testing.assert_array_equal(act(observation), act_as_they_do(observation))


def crafted(tmp_path: Path, member: str) -> tuple[Path, Path]:
    """A real policy.zip whose `member` ('data' or 'policy.pth') now creates a marker file
    when unpickled; the zip and the marker's path."""
    path, _ = trained(tmp_path, "ppo", normalized=False)
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


@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_a_ray_policy_read_without_pickles_acts_as_rllib_loads_it(tmp_path, algo):
    folder = ray_policy_folder(tmp_path, algo)
    env = catalog.make(catalog.find("CartpoleSwingup"))
    ours, theirs = engines.load_policy(folder, env), engines.load_policy(folder, env, True)
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
