"""Record what every shipped task returns, and compare a later run with it bit for bit.

    python -m bench.trajectories record /tmp/before.pkl     # on the code before a change
    python -m bench.trajectories compare /tmp/before.pkl    # on the code after it

A performance change must not change a number: this steps every shipped task, every Control
Suite id (`dm_control/DOMAIN-TASK-v0`) and `bench.ant_v5`'s AntV5 through `gym.make`, with
dict and flattened observations and a few options, and a `VectorEnvironment` of each, from
fixed seeds with random actions (some outside the action space, so clipping is exercised),
through episode ends and resets; it keeps every observation, reward, termination,
truncation and info entry. `compare` runs
the same and reports the first difference of each run, exiting 1 if there is one. Arrays
are compared by their bytes, dtype and shape; numbers by type and value.
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import composer
import tasks
from bench.ant_v5 import AntV5

SUITE_IDS = tuple(env_id for env_id in gymnasium.registry if env_id.startswith("dm_control/"))
STEPS = 120
VECTOR_STEPS = 60
VECTOR_ENVS = 3
SEED = 7

# (label, gym id, keyword arguments): time limits short enough that episodes end.
SINGLE_RUNS: list[tuple[str, str, dict[str, Any]]] = [
    *[(f"{i}-flat", i, {"flatten_observations": True, "time_limit": 1.0}) for i in tasks.IDS],
    *[(f"{i}-dict", i, {"time_limit": 1.5}) for i in tasks.IDS],
    ("Reach-control-cost", "composer/Reach-v0", {"control_cost": 0.1, "time_limit": 1.0}),
    ("AntRun-terrain", "composer/AntRun-v0", {"arena": "terrain", "time_limit": 1.0}),
    ("AntRun-not-legacy", "AntRun", {"time_limit": 1.0, "legacy_step": False}),
    ("AntV5", "AntV5", {"time_limit": 1.0}),
    *[(f"{i}-dict", i, {"time_limit": 1.0}) for i in SUITE_IDS],
]


def _make(env_id: str, **kwargs: Any) -> gymnasium.Env:
    if env_id == "AntV5":
        return composer.Environment(AntV5(), **kwargs)
    if env_id == "AntRun":  # options gym.make does not pass on
        return composer.Environment(tasks.AntRun(), **kwargs)
    return gymnasium.make(env_id, **kwargs)


def _copy(value: Any) -> Any:
    """A deep, detached copy of what a step returned."""
    if isinstance(value, dict):
        return {key: _copy(item) for key, item in value.items()}
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, list | tuple):
        return type(value)(_copy(item) for item in value)
    return value


def single_run(env_id: str, options: dict[str, Any]) -> list[Any]:
    """Every value one environment returned over STEPS steps from reset(seed=SEED)."""
    env = _make(env_id, **options)
    rng = np.random.default_rng(SEED)
    space = env.action_space
    out: list[Any] = [_copy(env.reset(seed=SEED))]
    for _ in range(STEPS):
        action = rng.uniform(space.low * 1.5, space.high * 1.5).astype(space.dtype)
        result = env.step(action)
        out.append(_copy(result))
        if result[2] or result[3]:
            out.append(_copy(env.reset()))
    env.close()
    return out


def vector_run(env_id: str) -> list[Any]:
    """Every value a VectorEnvironment of VECTOR_ENVS returned over VECTOR_STEPS steps."""
    venv = gymnasium.make_vec(
        env_id, VECTOR_ENVS, vectorization_mode="vector_entry_point", time_limit=1.0,
        flatten_observations=True,
    )  # fmt: skip
    rng = np.random.default_rng(SEED)
    space = venv.action_space
    out: list[Any] = [_copy(venv.reset(seed=SEED))]
    for _ in range(VECTOR_STEPS):
        out.append(_copy(venv.step(rng.uniform(space.low * 1.5, space.high * 1.5))))
    venv.close()
    return out


def record() -> dict[str, list[Any]]:
    """{run label: the values it returned} for every run of this module."""
    runs = {label: single_run(env_id, options) for label, env_id, options in SINGLE_RUNS}
    for env_id in (*tasks.IDS, *SUITE_IDS):
        runs[f"{env_id}-vector"] = vector_run(env_id)
    return runs


def first_difference(a: Any, b: Any, where: str = "") -> str | None:
    """Where `a` and `b` first differ (type, shape, dtype or bytes), or None."""
    if type(a) is not type(b):
        return f"{where}: type {type(a).__name__} != {type(b).__name__}"
    if isinstance(a, dict):
        if list(a) != list(b):
            return f"{where}: keys {list(a)} != {list(b)}"
        for key in a:
            found = first_difference(a[key], b[key], f"{where}[{key!r}]")
            if found:
                return found
        return None
    if isinstance(a, list | tuple):
        if len(a) != len(b):
            return f"{where}: length {len(a)} != {len(b)}"
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            found = first_difference(x, y, f"{where}[{k}]")
            if found:
                return found
        return None
    if isinstance(a, np.ndarray):
        if a.dtype != b.dtype or a.shape != b.shape:
            return f"{where}: {a.dtype}{a.shape} != {b.dtype}{b.shape}"
        if a.dtype == object:
            return first_difference(a.tolist(), b.tolist(), where)
        return None if a.tobytes() == b.tobytes() else f"{where}: {a} != {b}"
    if isinstance(a, float) and a != a and b != b:
        return None
    return None if a == b else f"{where}: {a!r} != {b!r}"


def main(argv: list[str]) -> int:
    """`record PATH` or `compare PATH`; 1 if a compared run differs."""
    if len(argv) != 2 or argv[0] not in ("record", "compare"):
        print(__doc__)
        return 2
    command, path = argv
    runs = record()
    if command == "record":
        Path(path).write_bytes(pickle.dumps(runs))
        print(f"recorded {len(runs)} runs in {path}")
        return 0
    before = pickle.loads(Path(path).read_bytes())
    differ = 0
    for label in before:
        found = first_difference(before[label], runs.get(label), label)
        print(f"{'DIFFERS' if found else 'same':8} {label}" + (f": {found}" if found else ""))
        differ += bool(found)
    print(f"{len(before) - differ} of {len(before)} runs bit-identical")
    return int(differ > 0)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
