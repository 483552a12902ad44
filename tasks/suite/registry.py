"""The Control Suite's tasks by domain, their dm_control defaults, and their Gymnasium ids.

    entry = TASKS[('cartpole', 'swingup')]      # SuiteEntry: the task class and its keywords
    env = load('cartpole', 'swingup')           # a composer.Environment, as suite.load gives
    gym.make('dm_control/cartpole-swingup-v0')  # the same, registered by `import tasks`

`BENCHMARKING`, `EXTRA` and `ALL_TASKS` are dm_control's tuples of (domain, task) pairs,
sorted by domain as dm_control sorts them. Each id is registered with the task's time
limit (dm_control's default episode length) and keywords; `gym.make`'s keywords override
them (`time_limit`, `flatten_observations`, `control_timestep` ...).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import composer
from composer import registration
from tasks.suite.base import SuiteTask

NAMESPACE = "dm_control"


@dataclasses.dataclass(frozen=True)
class SuiteEntry:
    """One suite task: its domain and name, the class serving it and the keywords that make
    it that task, its default time limit (seconds), a line saying what it is, and
    dm_control's tags."""

    domain: str
    name: str
    task_class: type[SuiteTask]
    kwargs: dict[str, Any]
    time_limit: float
    description: str
    tags: tuple[str, ...] = ()

    @property
    def env_id(self) -> str:
        """The Gymnasium id, Shimmy's spelling: 'dm_control/DOMAIN-TASK-v0'."""
        return f"{NAMESPACE}/{self.domain}-{self.name}-v0"

    @property
    def import_path(self) -> str:
        """'module:Class' of the task class, as registration takes it."""
        return f"{self.task_class.__module__}:{self.task_class.__qualname__}"


TASKS: dict[tuple[str, str], SuiteEntry] = {}


def add(entry: SuiteEntry) -> None:
    """Add `entry` to TASKS. Raises composer.TaskError for a (domain, task) pair taken."""
    key = (entry.domain, entry.name)
    if key in TASKS:
        raise composer.TaskError(f"suite task {key} is defined twice")
    TASKS[key] = entry


def tagged(tag: str | None) -> tuple[tuple[str, str], ...]:
    """The (domain, task) pairs with `tag` (None: all), sorted by domain, each domain's
    tasks in the order they were added (dm_control's order)."""
    pairs = [key for key, entry in TASKS.items() if tag is None or tag in entry.tags]
    return tuple(sorted(pairs, key=lambda key: key[0]))


def register_all() -> tuple[str, ...]:
    """Register every task's Gymnasium id; returns the ids."""
    return tuple(
        registration.register(
            f"{entry.domain}-{entry.name}",
            entry.import_path,
            entry.description,
            namespace=NAMESPACE,
            time_limit=entry.time_limit,
            **entry.kwargs,
        )
        for entry in TASKS.values()
    )


def load(
    domain_name: str,
    task_name: str,
    task_kwargs: dict[str, Any] | None = None,
    environment_kwargs: dict[str, Any] | None = None,
) -> composer.Environment:
    """dm_control's `suite.load`: the task as a composer.Environment. `task_kwargs` may hold
    `time_limit` (seconds) and the task's keywords; `environment_kwargs` dm_control's
    `flat_observation` and `control_timestep`. Raises composer.TaskError for an unknown
    domain or task (naming those there are) or keyword."""
    entry = find(domain_name, task_name)
    kwargs = {**entry.kwargs, **(task_kwargs or {})}
    time_limit = kwargs.pop("time_limit", entry.time_limit)
    kwargs.pop("random", None)  # seeds go to reset(seed=...)
    environment = dict(environment_kwargs or {})
    flatten = bool(environment.pop("flat_observation", False))
    if "control_timestep" in environment:
        kwargs["control_timestep"] = environment.pop("control_timestep")
    if environment:
        raise composer.TaskError(
            f"environment_kwargs {sorted(environment)} are not supported: give "
            "flat_observation or control_timestep"
        )
    task = registration.task_factory(entry.task_class, kwargs, ("time_limit",))()
    return composer.Environment(task, time_limit=time_limit, flatten_observations=flatten)


def find(domain_name: str, task_name: str) -> SuiteEntry:
    """The entry of a suite task. Raises composer.TaskError naming the domains (or the
    domain's tasks) there are."""
    domains = sorted({domain for domain, _ in TASKS})
    if domain_name not in domains:
        raise composer.TaskError(
            f"the Control Suite has no domain {domain_name!r}; domains: {domains}"
        )
    names = [name for domain, name in TASKS if domain == domain_name]
    if task_name not in names:
        raise composer.TaskError(
            f"domain {domain_name!r} has no task {task_name!r}; its tasks: {names}"
        )
    return TASKS[(domain_name, task_name)]
