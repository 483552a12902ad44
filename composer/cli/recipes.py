"""Training recipes: how `composer train` trains a task with no flags. Each task's recipes
live with the task, registered for its class (`register`: its first recipe the default).

    from composer.cli.recipes import Recipe, register
    register(MyTask, Recipe('ppo', timesteps=200_000, n_envs=8, net=(64, 64),
                            learning_rate=3e-4, batch_size=256, normalize=True))
    recipe = recipes.for_task(info, 'sac', engine='ray')   # else the generic one (GENERIC)
    recipe = recipes.for_task(catalog.with_pixels(info))   # its pixel recipe (`--pixels`)

A bad recipe raises RecipeError, registering nothing; `Recipe` says how engines read one.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import Any

from composer import registration
from composer.cli import catalog
from composer.cli.errors import RecipeError

ALGORITHMS = ("ppo", "sac")
# The fields only one algorithm reads.
_ONLY = {
    "ppo": ("n_steps", "n_epochs", "ent_coef"),
    "sac": (
        "buffer_size",
        "learning_starts",
        "train_freq",
        "gradient_steps",
        "initial_temperature",
    ),
}
# The fields only pixel recipes read.
_PIXELS_ONLY = ("pixels", "conv", "features")
VEC = ("dummy", "subproc", "batched")
# The task `composer train` trains when given none.
DEFAULT_TASK = "Reach"


@dataclasses.dataclass(frozen=True)
class Recipe:
    """How to train: algorithm, budget, parallel environments and hyperparameters.

    A recipe is written as stable-baselines3 reads it (per-environment rollout length,
    replay size ...); each engine translates it (`composer.cli.engines`). Where an engine
    was measured to do better with other values, `engine_changes` says which
    (`{'ray': {'n_envs': 32}}`). A task observed through its camera trains with its pixel
    recipes (`pixels=True`), the first of them its default, else GENERIC_PIXELS.
    """

    algo: str
    timesteps: int
    n_envs: int
    net: tuple[int, ...]
    learning_rate: float
    batch_size: int
    gamma: float = 0.99
    # How stable-baselines3 steps the n_envs environments: 'dummy' in this process (fastest
    # for cheap tasks), 'subproc' one process each (for costly physics), 'batched' all on
    # MuJoCo's thread pool (`composer.vector` through `composer.sb3`; it pays off when the
    # task declares batched rewards and observations: docs/performance_profile.md).
    vec: str = "dummy"
    # Observations and rewards scaled by running statistics (VecNormalize); the observation
    # statistics are saved inside the policy .zip, so `run` and `eval` apply them too. A
    # pixel recipe's frames are scaled by its policy: it normalizes rewards only.
    normalize: bool = False
    # PPO: steps per environment per update, epochs over them, entropy bonus.
    n_steps: int = 256
    n_epochs: int = 10
    ent_coef: float = 0.0
    # SAC: replay size, random steps first, environment steps and gradient steps per update.
    buffer_size: int = 300_000
    learning_starts: int = 5_000
    train_freq: int = 1
    gradient_steps: int = 1
    # SAC's entropy temperature at the start, tuned towards its target entropy after
    # (stable-baselines3 and RLlib start at 1.0, pytorch_sac at 0.1).
    initial_temperature: float = 1.0
    # Learns from frames (`--pixels`) with a small convolutional encoder under the `net`
    # heads (`composer.cli.engines.sb3.encoder`): (out channels, kernel, stride) per layer,
    # ReLU after each, then a linear layer of `features` units. Its environments are stepped
    # one by one ('dummy' or 'subproc': the batch has no camera observations).
    pixels: bool = False
    conv: tuple[tuple[int, int, int], ...] = ((16, 4, 4), (32, 3, 2), (32, 3, 1))
    features: int = 128
    # What an engine changes where it was measured to do better: {engine: {field: value}}.
    engine_changes: Mapping[str, Mapping[str, Any]] = dataclasses.field(
        default_factory=dict, hash=False
    )

    def replace(self, **changes: Any) -> Recipe:
        """A copy with `changes` (None values are ignored)."""
        return dataclasses.replace(self, **{k: v for k, v in changes.items() if v is not None})

    def for_engine(self, engine: str | None) -> Recipe:
        """This recipe as `engine` runs it: with its `engine_changes` (and no others)."""
        return self.replace(**(self.engine_changes.get(engine or "") or {}), engine_changes={})

    def table(self) -> dict[str, Any]:
        """The fields this recipe's algorithm uses, for printing and for metrics.json."""
        others = {f for algo, fields in _ONLY.items() if algo != self.algo for f in fields}
        others.add("engine_changes")
        if not self.pixels:
            others.update(_PIXELS_ONLY)
        return {k: v for k, v in dataclasses.asdict(self).items() if k not in others}

    @classmethod
    def from_table(cls, table: dict[str, Any]) -> Recipe:
        """The recipe whose `table()` (read back from JSON) is `table`."""
        conv = tuple(tuple(layer) for layer in table.get("conv", cls.conv))
        return cls(**{**table, "net": tuple(table["net"]), "conv": conv})


GENERIC = {
    "ppo": Recipe("ppo", 1_000_000, 8, (64, 64), 3e-4, 256, normalize=True),
    "sac": Recipe("sac", 100_000, 1, (256, 256), 3e-4, 256),
}
# CartpoleSwingup's measured pixel recipe with the generic budget. Tuning runs: a learning
# rate of 1e-3 returned 91 at 100k steps and 122 at 175k, 3e-4 returned 48 and 85.
GENERIC_PIXELS = {
    "ppo": Recipe("ppo", 1_000_000, 16, (64, 64), 1e-3, 256, normalize=True, n_steps=128,
                  n_epochs=4, pixels=True),
}  # fmt: skip

_RECIPES: dict[Callable[..., Any] | str, tuple[Recipe, ...]] = {}


def register(task: Callable[..., Any] | str, *recipes: Recipe) -> None:
    """Give `task` its recipes, the first its default: the class or factory registered task
    ids name (every id of it), or one Gymnasium id ('dm_control/walker-walk-v0': of tasks
    sharing a class, that one; it wins over its class's). Call it where the task is
    registered: the shipped tasks' are in `tasks/recipes.py`, and a module given to
    `composer --import` registers its own tasks' the same way. Registering a task again
    replaces its recipes; a task without a recipe for an algorithm trains with the
    algorithm's GENERIC one. Raises RecipeError, registering nothing, for a task that is
    neither, no recipe, a recipe of an unknown algorithm, two of one algorithm, an initial
    temperature not above 0, or engine changes of fields a recipe does not have."""
    if not (callable(task) or (isinstance(task, str) and "/" in task)):
        raise RecipeError(
            "recipes are registered for a task class or factory, or a Gymnasium id "
            f"'namespace/Name-vN', got {task!r}"
        )
    if not recipes:
        raise RecipeError(f"register({_name(task)}): give at least one Recipe")
    fields = {f.name for f in dataclasses.fields(Recipe)} - {"engine_changes"}
    for recipe in recipes:
        if not isinstance(recipe, Recipe):
            raise RecipeError(f"register({_name(task)}): expected Recipe objects, got {recipe!r}")
        if recipe.algo not in ALGORITHMS:
            raise RecipeError(
                f"register({_name(task)}): algo {recipe.algo!r} is not one of {list(ALGORITHMS)}"
            )
        for engine, changes in recipe.engine_changes.items():
            unknown = sorted(set(changes) - fields)
            if unknown:
                raise RecipeError(
                    f"register({_name(task)}): the {recipe.algo} recipe's changes for "
                    f"engine {engine!r} name fields a Recipe does not have: {unknown}"
                )
        if not recipe.initial_temperature > 0:
            raise RecipeError(
                f"register({_name(task)}): the {recipe.algo} recipe's initial_temperature "
                f"must be > 0, got {recipe.initial_temperature!r}"
            )
        if recipe.pixels and recipe.vec == "batched":
            raise RecipeError(
                f"register({_name(task)}): the {recipe.algo} pixel recipe cannot step its "
                "environments as one batch (vec='batched' has no frames); give vec='dummy' "
                "or 'subproc'"
            )
        if recipe.pixels and (not recipe.conv or recipe.features < 1):
            raise RecipeError(
                f"register({_name(task)}): the {recipe.algo} pixel recipe needs conv layers "
                f"and features >= 1, got conv={recipe.conv}, features={recipe.features}"
            )
    kinds = [(recipe.algo, recipe.pixels) for recipe in recipes]
    if len(set(kinds)) != len(kinds):
        algos = [f"{algo}{' pixels' if pixels else ''}" for algo, pixels in kinds]
        raise RecipeError(
            f"register({_name(task)}): one recipe per algorithm (and one per algorithm from "
            f"pixels), got {algos}"
        )
    _RECIPES[task] = tuple(recipes)


def registered(info: registration.TaskInfo) -> tuple[Recipe, ...]:
    """The recipes registered for `info`'s id, else for its task, state and pixel ones
    alike, its default first (none: empty). Raises RegistrationError when the task cannot
    be imported."""
    own = _RECIPES.get(info.env_id)
    if own is not None:
        return own
    return _RECIPES.get(registration.resolve_task(info.task), ())


def default_algo(info: registration.TaskInfo) -> str:
    """The algorithm of the task's default recipe for what `info` observes (its state, or
    frames: `catalog.observes_pixels`), PPO for a task without one."""
    own = _own(info)
    return own[0].algo if own else "ppo"


def for_task(
    info: registration.TaskInfo, algo: str | None = None, engine: str | None = None
) -> Recipe:
    """The task's recipe for `algo` (default: its default algorithm) and what `info`
    observes, else the algorithm's generic one (GENERIC_PIXELS from frames), as `engine`
    runs it (see `Recipe.for_engine`). Raises RecipeError for an algorithm that has no
    generic pixel recipe when the task has none of its own."""
    algo = algo or default_algo(info)
    own = {recipe.algo: recipe for recipe in _own(info)}
    generic = GENERIC_PIXELS if catalog.observes_pixels(info) else GENERIC
    if algo not in own and algo not in generic:
        raise RecipeError(
            f"{info.name} has no {algo} recipe from pixels, and there is no generic one: "
            f"train from pixels with {' or '.join(generic)}, or register a {algo} recipe "
            "with pixels=True for the task"
        )
    return own.get(algo, generic[algo]).for_engine(engine)


def _own(info: registration.TaskInfo) -> list[Recipe]:
    """The task's registered recipes for what `info` observes."""
    pixels = catalog.observes_pixels(info)
    return [recipe for recipe in registered(info) if recipe.pixels == pixels]


def _name(task: Callable[..., Any] | str) -> str:
    return task if isinstance(task, str) else getattr(task, "__qualname__", repr(task))
