"""dm_control's own Control Suite, run on our `mjcf.Physics`: the reference the suite's
tasks here are compared with (tests only; nothing of dm_control ships).

    module = suite_module('cartpole')                  # dm_control.suite.cartpole, rewritten
    env = reference('cartpole', 'swingup', seed=3)     # its control.Environment
    model = reference_model('cartpole', num_poles=2)   # the MjModel its XML compiles to
    assert_same_model(ours.physics.model, model)       # every numeric array equal
    compare_episode(ours, theirs, seed=3, steps=1000)
    compare_steps(ours, theirs, random_actions(theirs, seed=4, steps=50))  # from here on

The published wheel (`tests/dm_control_wheel.py`: fetched at test time, skipped when the
index is unreachable) is unpacked into a package of another name, `dm_suite_reference`, so
it never meets the `dm_control` package other tests import: its `rl`, `suite` and `utils`
folders, with `dm_control.X` imports renamed and `dm_control.mujoco` (which wraps MuJoCo
through ctypes and does not run on MuJoCo 4) replaced by `tests.tasks.suite.dm_mujoco`, a
few lines on our `mjcf.Physics`. The suite's own task code, its `control.Environment` step
loop, its reward functions (`utils.rewards`) and its randomizers run unchanged.
"""

from __future__ import annotations

import hashlib
import importlib
import re
import sys
import zipfile
from pathlib import Path
from types import ModuleType
from typing import Any

import mujoco
import numpy as np

import mjcf
from tests import dm_control_wheel

PACKAGE = "dm_suite_reference"
_FOLDERS = ("dm_control/rl/", "dm_control/suite/", "dm_control/utils/")
_SHIM = "tests.tasks.suite.dm_mujoco"
_REWRITES = (
    (re.compile(r"^(\s*)from dm_control import mujoco\b", re.M),
     r"\1from tests.tasks.suite import dm_mujoco as mujoco"),
    (re.compile(r"^(\s*)from dm_control\.mujoco\.wrapper\.mjbindings import (\w+)", re.M),
     rf"\1from {_SHIM} import mjbindings as _mjbindings; \2 = _mjbindings.\2"),
    (re.compile(r"^(\s*)from dm_control\.mujoco\.wrapper import (\w+)", re.M),
     rf"\1from {_SHIM} import \2"),
    (re.compile(r"^(\s*)from dm_control\.mujoco import (\w+)", re.M), rf"\1from {_SHIM} import \2"),
    (re.compile(r"\bdm_control\b"), PACKAGE),
)  # fmt: skip

# What differs in a composed model by construction only: the names (scoped "cartpole/...",
# which moves every name's address and the buffer's size), and the model's own checksum.
_NAMES = re.compile(
    r"^(names|names_map|paths|name_\w+adr|path_\w+adr|signature|nnames|nnames_map|npaths|nbuffer)$"
)


def _rewrite(source: str) -> str:
    for pattern, replacement in _REWRITES:
        source = pattern.sub(replacement, source)
    return source


def _tree() -> Path:
    """The folder holding the renamed package (on sys.path after this call)."""
    wheel = dm_control_wheel.wheel()
    digest = hashlib.sha1(Path(__file__).read_bytes()).hexdigest()[:12]
    target = wheel.parent / f"suite-oracle-{digest}"
    package = target / PACKAGE
    if not (package / "__init__.py").exists():
        staging = target.with_name(target.name + f".partial-{id(target)}")
        with zipfile.ZipFile(wheel) as archive:
            for name in archive.namelist():
                if not name.startswith(_FOLDERS):
                    continue
                relative = Path(PACKAGE, *Path(name).parts[1:])
                path = staging / relative
                path.parent.mkdir(parents=True, exist_ok=True)
                data = archive.read(name)
                if name == "dm_control/suite/__init__.py":
                    data = b""  # the domains are imported one at a time
                elif name.endswith(".py"):
                    data = _rewrite(data.decode("utf-8")).encode("utf-8")
                path.write_bytes(data)
        (staging / PACKAGE / "__init__.py").write_text("")
        staging.rename(target) if not target.exists() else None
    if str(target) not in sys.path:
        sys.path.insert(0, str(target))
    return target


def suite_module(domain: str) -> ModuleType:
    """dm_control's `suite.<domain>` module, running on our Physics."""
    _tree()
    return importlib.import_module(f"{PACKAGE}.suite.{domain}")


def reference(domain: str, task: str, seed: int, **task_kwargs: Any) -> Any:
    """dm_control's environment of `domain`/`task` (its `control.Environment`), its task
    made with `random=seed`."""
    return suite_module(domain).SUITE[task](random=seed, **task_kwargs)


def model_arrays(model: mujoco.MjModel) -> dict[str, Any]:
    """Every numeric array and size of `model` but the name tables, by attribute, and its
    `opt`, `vis` and `stat` structures' fields as 'opt.timestep' ..."""
    found: dict[str, Any] = {}
    for name in dir(model):
        if name.startswith("_") or _NAMES.match(name):
            continue
        value = getattr(model, name)
        if isinstance(value, np.ndarray) or (isinstance(value, int) and name.startswith("n")):
            found[name] = value
    for struct in ("opt", "stat"):
        for field in dir(getattr(model, struct)):
            if not field.startswith("_"):
                found[f"{struct}.{field}"] = getattr(getattr(model, struct), field)
    for group in ("global_", "quality", "headlight", "map", "scale", "rgba"):
        section = getattr(model.vis, group)
        for field in dir(section):
            if not field.startswith("_"):
                found[f"vis.{group}.{field}"] = getattr(section, field)
    return found


def assert_same_model(ours: mujoco.MjModel, theirs: mujoco.MjModel) -> None:
    """Every numeric array of both models equal, in the same order (names aside)."""
    mine, reference_arrays = model_arrays(ours), model_arrays(theirs)
    assert sorted(mine) == sorted(reference_arrays)
    differing = []
    for name, value in reference_arrays.items():
        other = mine[name]
        if callable(value):
            continue
        if not np.array_equal(np.asarray(other), np.asarray(value), equal_nan=True):
            differing.append(f"{name}: ours {np.asarray(other)!r} theirs {np.asarray(value)!r}")
    assert not differing, "model arrays differ:\n" + "\n".join(d[:400] for d in differing)


def reference_model(domain: str, **model_kwargs: Any) -> mujoco.MjModel:
    """The MjModel dm_control's XML of `domain` compiles to (`get_model_and_assets`)."""
    xml, assets = suite_module(domain).get_model_and_assets(**model_kwargs)
    return mjcf.Physics.from_xml_string(xml, assets=assets).model


def _flatten(observation: dict[str, np.ndarray]) -> np.ndarray:
    return np.concatenate([np.asarray(value).ravel() for value in observation.values()])


def compare_episode(ours: Any, theirs: Any, seed: int, steps: int, atol: float = 1e-9) -> int:
    """Run our environment `ours` (a composer.Environment, reset with `seed`) and
    dm_control's `theirs` (made with `random=seed`) with the same `steps` random actions
    (`random_actions` from RandomState(seed + 1)); every observation (keys, order, shapes
    and values), reward and discount must agree to `atol`, and both episodes must end at
    the same step. Returns the steps run."""
    observation, _ = ours.reset(seed=seed)
    timestep = theirs.reset()
    _assert_observations(observation, timestep.observation, 0, atol)
    return len(compare_steps(ours, theirs, random_actions(theirs, seed + 1, steps), atol))


def random_actions(theirs: Any, seed: int, steps: int) -> np.ndarray:
    """`steps` actions uniform within the bounds of dm_control's environment `theirs`, drawn
    from RandomState(seed): (steps, action size). Within [-1, 1] where an actuator is
    unbounded (lqr's): forces of up to 1e10 N would only blow the system up, which
    dm_control answers with a PhysicsError and ours with a truncation."""
    spec = theirs.action_spec()
    low = np.where(spec.minimum <= -mujoco.mjMAXVAL, -1.0, spec.minimum)
    high = np.where(spec.maximum >= mujoco.mjMAXVAL, 1.0, spec.maximum)
    return np.random.RandomState(seed).uniform(low, high, size=(steps, *spec.shape))


def compare_steps(ours: Any, theirs: Any, actions: np.ndarray, atol: float = 1e-9) -> np.ndarray:
    """Step both environments from the states they are in with each of `actions` until an
    episode ends, comparing as `compare_episode` says. Returns our rewards, one per step
    run."""
    rewards = []
    for t, action in enumerate(actions, start=1):
        observation, reward, terminated, truncated, info = ours.step(action)
        rewards.append(reward)
        timestep = theirs.step(action)
        _assert_observations(observation, timestep.observation, t, atol)
        assert abs(reward - timestep.reward) <= atol, f"step {t}: reward {reward} {timestep.reward}"
        assert abs(info["discount"] - timestep.discount) <= atol, f"step {t}: discount"
        assert (terminated or truncated) == timestep.last(), f"step {t}: episode end"
        if timestep.last():
            assert terminated == (timestep.discount == 0.0 and truncated is False)
            break
    return np.array(rewards)


def _assert_observations(ours: Any, theirs: dict[str, np.ndarray], t: int, atol: float) -> None:
    if isinstance(ours, dict):
        assert list(ours) == list(theirs) or sorted(ours) == sorted(theirs), (
            f"step {t}: keys {list(ours)} {list(theirs)}"
        )
        for key, value in theirs.items():
            assert np.shape(ours[key]) == np.shape(value), (
                f"step {t}: {key} has shape {np.shape(ours[key])}, dm_control's {np.shape(value)}"
            )
            np.testing.assert_allclose(
                ours[key], value, rtol=0, atol=atol, err_msg=f"step {t}: {key}"
            )
    else:
        np.testing.assert_allclose(ours, _flatten(theirs), rtol=0, atol=atol, err_msg=f"step {t}")
