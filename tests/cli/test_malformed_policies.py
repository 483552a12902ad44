"""Malformed and hostile policy files, read without --trust-policy: every one is refused
with a PolicyError (one line, exit status 2 on the command line) or loads and acts; none
raises anything else, spends memory its archive does not hold, or runs code. The files
are real policies with one part changed, made here."""

from __future__ import annotations

import io
import json
import tempfile
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import composer
from composer.cli import engines, rollout
from composer.cli.engines import untrusted
from composer.cli.errors import PolicyError
from tests.cli.helpers import assert_one_line_error
from tests.cli.helpers import composer as run_composer
from tests.cli.policies import ray_policy_folder, trained

DEEP = json.loads("[" * 800 + "]" * 800)
# Values put in place of a part of a policy's settings.
VALUES: list[Any] = [None, True, 0, -1, 1.5, 1e300, float("nan"), "x", [], {}, [1, "a"],
                     [[1]], {"a": 1}, [-3], [10**12], [2**31, 2**31], DEEP]  # fmt: skip
# The parts of stable-baselines3's `data` the plain reader reads, as key paths.
SB3_PARTS = [
    ("policy_class",), ("policy_class", "__module__"), ("observation_space",),
    ("observation_space", "_shape"), ("action_space", "_shape"), ("policy_kwargs",),
    ("policy_kwargs", "net_arch"), ("use_sde",), ("observation_normalization",),
    ("observation_normalization", "mean"), ("observation_normalization", "var"),
    ("observation_normalization", "epsilon"), ("observation_normalization", "clip"),
    ("pixel_encoder",), ("pixel_encoder", "conv"), ("pixel_encoder", "features"),
]  # fmt: skip


def _set(data: dict[str, Any], path: tuple[str, ...], value: Any) -> dict[str, Any]:
    """A copy of `data` with the part at `path` set to `value` (made where missing)."""
    data = json.loads(json.dumps(data))
    node = data
    for key in path[:-1]:
        if not isinstance(node.get(key), dict):
            node[key] = {}
        node = node[key]
    node[path[-1]] = value
    return data


def _rewrite(source: Path, target: Path, **members: bytes | None) -> Path:
    """`source`'s zip with `members` replaced (None: removed)."""
    with zipfile.ZipFile(source) as archive:
        contents = {name: archive.read(name) for name in archive.namelist()}
    contents.update(members)
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in contents.items():
            if data is not None:
                archive.writestr(name, data)
    return target


def _loads_or_refuses(path: Path, env) -> str:
    """'acts' when the policy at `path` loads and gives an action of the right shape and
    finite values, 'refused' when it raises composer.Error; anything else fails."""
    try:
        policy = engines.load_policy(path, env)
    except composer.Error:
        return "refused"
    observation, _ = env.reset(seed=0)
    action = rollout.model_policy(policy)(observation)
    assert np.shape(action) == env.action_space.shape
    assert np.all(np.isfinite(action))
    return "acts"


@pytest.fixture(scope="module")
def sb3_policy(tmp_path_factory):
    return trained(tmp_path_factory.mktemp("sb3"), "ppo", normalized=True)


def test_malformed_settings_of_a_stable_baselines3_policy_are_refused(sb3_policy, tmp_path):
    path, env = sb3_policy
    with zipfile.ZipFile(path) as archive:
        data = json.loads(archive.read("data"))
    outcomes = {}
    for part in SB3_PARTS:
        for index, value in enumerate(VALUES):
            changed = _set(data, part, value)
            target = _rewrite(path, tmp_path / "p.zip", data=json.dumps(changed).encode())
            outcomes[part, index] = _loads_or_refuses(target, env)
    assert list(outcomes.values()).count("refused") > 0.9 * len(outcomes)


_JSON = st.recursive(
    st.none() | st.booleans() | st.integers(-(2**70), 2**70)
    | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner,
                                                                max_size=4),
    max_leaves=12,
)  # fmt: skip


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(parts=st.lists(st.tuples(st.sampled_from(SB3_PARTS), _JSON), min_size=1, max_size=3))
def test_random_settings_of_a_stable_baselines3_policy_are_refused_or_act(sb3_policy, parts):
    """Random JSON in place of up to three parts of a real policy's settings: it loads and
    acts, or is refused with a PolicyError, nothing else."""
    path, env = sb3_policy
    with zipfile.ZipFile(path) as archive:
        data = json.loads(archive.read("data"))
    for part, value in parts:
        data = _set(data, part, value)
    with tempfile.TemporaryDirectory() as folder:
        target = _rewrite(path, Path(folder) / "p.zip", data=json.dumps(data).encode())
        _loads_or_refuses(target, env)


@pytest.mark.parametrize(
    "members",
    [
        {"data": b"not json"},
        {"data": b"[1, 2]"},
        {"data": ("[" * 800 + "]" * 800).encode()},
        {"data": ('{"a":' * 100_000 + "1" + "}" * 100_000).encode()},
        {"data": None},
        {"policy.pth": None},
        {"policy.pth": b"garbage"},
        {"policy.pth": "tensors"},
        {"policy.pth": "a list"},
        {"policy.pth": "a shape too large"},
        {"policy.pth": "a bomb inside"},
    ],
    ids=lambda members: ",".join(f"{k}={str(v)[:20]}" for k, v in members.items()),
)
def test_malformed_members_of_a_stable_baselines3_policy_are_refused(sb3_policy, tmp_path, members):
    import torch

    path, env = sb3_policy
    with zipfile.ZipFile(path) as archive:
        weights = torch.load(io.BytesIO(archive.read("policy.pth")), weights_only=True)
    made = {
        "tensors": {name: torch.zeros(3) for name in weights},
        "a list": [1, 2, 3],
        "a shape too large": {**weights, "action_net.weight": torch.zeros(4096, 4096)},
    }
    for name, value in members.items():
        if value in made:
            members[name] = _torch_bytes(made[value])
        elif value == "a bomb inside":
            members[name] = _deflated_torch_file(weights)
    target = _rewrite(path, tmp_path / "p.zip", **members)
    assert _loads_or_refuses(target, env) == "refused"


def _torch_bytes(value: Any) -> bytes:
    import torch

    buffer = io.BytesIO()
    torch.save(value, buffer)
    return buffer.getvalue()


def _deflated_torch_file(weights: dict[str, Any]) -> bytes:
    """The weights as torch saves them, with an entry of 64 MiB of zeros deflated into it
    (torch's reader allocates what an entry declares)."""
    plain = zipfile.ZipFile(io.BytesIO(_torch_bytes(weights)))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for info in plain.infolist():
            archive.writestr(info.filename, plain.read(info))
        archive.writestr(f"{plain.namelist()[0].split('/')[0]}/data/999", bytes(64 << 20))
    return out.getvalue()


# 64 layers of 4096 units: over a billion numbers (4 GiB filled) from a few bytes of settings.
HUGE_LAYERS = [4096] * 64


def test_settings_asking_for_a_network_larger_than_the_weights_are_refused(sb3_policy, tmp_path):
    """The settings are the stranger's: a network they ask for past twice the numbers its
    weights fill is refused as it is built, before its layers are filled."""
    path, env = sb3_policy
    with zipfile.ZipFile(path) as archive:
        data = json.loads(archive.read("data"))
    changed = _set(data, ("policy_kwargs", "net_arch"), HUGE_LAYERS)
    target = _rewrite(path, tmp_path / "p.zip", data=json.dumps(changed).encode())
    with pytest.raises(
        PolicyError,
        match=r"p\.zip: its settings make a network of more than "
        r"[\d,]+ numbers, far more than its weights fill",
    ):
        engines.load_policy(target, env)


def test_at_most_refuses_a_module_past_its_capacity_and_lets_one_within_it():
    torch = pytest.importorskip("torch", reason="needs the [train] extra")
    with untrusted.at_most(torch, 10 * 10 + 10, "small"):
        torch.nn.Linear(10, 10)
    with (
        pytest.raises(PolicyError, match="large: its settings make a network of more than 109"),
        untrusted.at_most(torch, 109, "large"),
    ):
        torch.nn.Linear(10, 10)
    torch.nn.Linear(4096, 4096)  # the hooks are gone after `with`, raised or not


def test_a_bomb_policy_zip_is_refused_on_the_command_line(sb3_policy, tmp_path):
    path, _ = sb3_policy
    target = _rewrite(path, tmp_path / "bomb.zip", **{"policy.pth": None})
    with (
        zipfile.ZipFile(target, "a", zipfile.ZIP_DEFLATED) as archive,
        archive.open("policy.pth", "w") as entry,
    ):
        for _ in range(64):
            entry.write(bytes(1 << 20))
    assert target.stat().st_size < 500_000
    for command in (["eval", "Reach", "bomb.zip"], ["run", "Reach", "--policy", "bomb.zip"]):
        result = run_composer(*command, cwd=tmp_path)
        assert_one_line_error(
            result, "bomb.zip: entry 'policy.pth'", "over the limit of 100 times",
            "--unpack-limit", "--unpack-ratio"
        )  # fmt: skip
    raised = run_composer("eval", "Reach", "bomb.zip", "--unpack-ratio", "1000000",
                          "--unpack-limit", "32M", cwd=tmp_path)  # fmt: skip
    assert_one_line_error(raised, "over the limit of 33,554,432 bytes unpacked in all")


def test_deep_json_in_a_policy_is_one_line_on_the_command_line(sb3_policy, tmp_path):
    path, _ = sb3_policy
    _rewrite(path, tmp_path / "deep.zip", data=("[" * 800 + "]" * 800).encode())
    assert_one_line_error(run_composer("eval", "Reach", "deep.zip", cwd=tmp_path), "deep.zip")


# -- Ray's policy folders --------------------------------------------------------------------

RAY_PARTS = [("format",), ("version",), ("algo",), ("model_config",),
             ("model_config", "fcnet_hiddens"), ("observation_shape",), ("action_low",),
             ("action_high",), ("observation_filter",), ("observation_filter", "mean"),
             ("observation_filter", "std"), ("observation_filter", "clip")]  # fmt: skip


@pytest.fixture(scope="module")
def ray_policy(tmp_path_factory):
    from composer.cli import catalog

    folder = ray_policy_folder(tmp_path_factory.mktemp("ray"), "ppo")
    return folder, catalog.make(catalog.find("CartpoleSwingup"))


def test_malformed_settings_of_a_ray_policy_are_refused(ray_policy, tmp_path):
    import shutil

    folder, env = ray_policy
    spec = json.loads((folder / "policy.json").read_text())
    outcomes = {}
    for part in RAY_PARTS:
        for index, value in enumerate(VALUES):
            target = tmp_path / f"policy-{len(outcomes)}"
            shutil.copytree(folder, target)
            (target / "policy.json").write_text(json.dumps(_set(spec, part, value)))
            outcomes[part, index] = _loads_or_refuses(target, env)
            shutil.rmtree(target)
    assert list(outcomes.values()).count("refused") > 0.9 * len(outcomes)


def test_a_ray_model_config_asking_for_a_network_larger_than_the_weights_is_refused(
    ray_policy, tmp_path
):
    import shutil

    folder, env = ray_policy
    target = tmp_path / "policy"
    shutil.copytree(folder, target)
    spec = json.loads((target / "policy.json").read_text())
    spec = _set(spec, ("model_config", "fcnet_hiddens"), HUGE_LAYERS)
    (target / "policy.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="far more than its weights fill"):
        engines.load_policy(target, env)


def _npz(arrays: dict[str, np.ndarray], compressed: bool = False) -> bytes:
    buffer = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buffer, **arrays)
    return buffer.getvalue()


@pytest.mark.parametrize("weights", ["garbage", "objects", "a zeros bomb", "a lying header",
                                     "wrong shapes", "missing"])  # fmt: skip
def test_malformed_weights_of_a_ray_policy_are_refused(ray_policy, tmp_path, weights):
    import shutil

    folder, env = ray_policy
    target = tmp_path / "policy"
    shutil.copytree(folder, target)
    path = target / "weights.npz"
    with np.load(path) as saved:
        arrays = {name: saved[name] for name in saved.files}
    first = next(iter(arrays))
    if weights == "garbage":
        path.write_bytes(b"PK\x03\x04garbage")
    elif weights == "objects":
        buffer = io.BytesIO()
        np.save(buffer, np.array([{"a": 1}], dtype=object), allow_pickle=True)
        with zipfile.ZipFile(path, "a") as archive:
            archive.writestr(first + "x.npy", buffer.getvalue())
    elif weights == "a zeros bomb":
        path.write_bytes(_npz({**arrays, first: np.zeros((64, 1 << 17))}, compressed=True))
    elif weights == "a lying header":
        buffer = io.BytesIO()
        np.lib.format.write_array_header_1_0(
            buffer, {"descr": "<f8", "fortran_order": False, "shape": (1 << 40,)}
        )
        with zipfile.ZipFile(path, "w") as archive:
            archive.writestr(first + ".npy", buffer.getvalue() + bytes(64))
    elif weights == "wrong shapes":
        path.write_bytes(_npz({name: np.zeros(3, np.float32) for name in arrays}))
    else:
        path.unlink()
    assert _loads_or_refuses(target, env) == "refused"
