"""The training engines of `composer train`, by name, each imported only when asked for;
and the trained policies they wrote, found and loaded by whichever engine wrote them.

    engine = engines.get('ray')          # imports composer.cli.engines.ray, not Ray itself
    engines.names()                      # ('sb3', 'ray'): --engine's choices, default first
    engines.every()                      # each engine (whose files are in a folder?)
    policy = engines.load_policy('runs/Reach-ppo', env)   # policy.predict(obs)

Promise: getting an engine, and reading the folders it writes, needs no library: an engine
imports its own (stable-baselines3, Ray) only inside functions or modules they import.
"""

from __future__ import annotations

import importlib
import os
from pathlib import Path
from typing import Any

import gymnasium

from composer.cli import rollout
from composer.cli.engines.base import DEFAULT_ENGINE, Engine
from composer.cli.errors import PolicyError

DEFAULT = DEFAULT_ENGINE
# Every engine by its --engine name: the package that defines it (its `ENGINE`: checkpoint,
# options, checks, trainer and policy loader), the default first. Adding an engine is
# adding its package and a line here; nothing else in the command line names an engine.
ENGINES = {
    "sb3": "composer.cli.engines.sb3",
    "ray": "composer.cli.engines.ray",
}


def names() -> tuple[str, ...]:
    """The engines' names, the default first."""
    return tuple(ENGINES)


def get(name: str) -> Engine[Any]:
    """The engine called `name` (one of `names()`), its package imported now."""
    engine = importlib.import_module(ENGINES[name]).ENGINE
    assert isinstance(engine, Engine) and engine.name == name, f"{ENGINES[name]}.ENGINE"
    return engine


def every() -> list[Engine[Any]]:
    """Every engine, the default first."""
    return [get(name) for name in ENGINES]


def load_policy(
    path: str | os.PathLike[str], env: gymnasium.Env, trusted: bool = False
) -> rollout.Predictor:
    """The policy `path` names (a policy, a folder written by `composer train`, or a
    checkpoint), loaded by the engine that wrote it and checked to fit `env`'s spaces
    (see `base.Engine.load_policy`: `trusted` lets it unpickle). Raises PolicyError when no
    engine's policy is there, and what the engine raises."""
    for engine in every():
        found = engine.find_policy(Path(path))
        if found is not None:
            return engine.load_policy(found, env, trusted)
    raise PolicyError(f"no policy at {path}: give a folder written by `composer train`, or a "
                      "policy in one")  # fmt: skip
