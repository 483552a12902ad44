"""composer: entities, arenas and tasks composed into a Gymnasium environment on `mjcf`.

    import composer
    arena = composer.Arena()
    robot = composer.Entity.from_path('humanoid.xml')      # default observables enabled
    arena.add_free_entity(robot)
    env = composer.Environment(composer.NullTask(arena), time_limit=10.0)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Entities own MJCF models (`composer.entity`), an Arena is the root of a scene
(`composer.arena`), a Task says what to do (`composer.task`), and the Environment compiles
the scene once and steps it (`composer.environment`, which states the hook order and what is
promised). Observables, variations and initializers live in `composer.observation`,
`composer.variation` and `composer.initializers`; `composer.VectorEnvironment` steps many
environments of a task on MuJoCo's batch (`composer.vector`). A task's per-step methods
written once in batched form run in both, a single environment being a batch of one
(`composer.batched`, `composer.BatchOfOne`). Every error is a `composer.Error`.
"""

from composer import observation, variation, vector
from composer.arena import Arena
from composer.batch_of_one import BatchOfOne
from composer.batched import BatchedTask, BatchPhysics
from composer.entity import Entity, ModelEntity, Observables, observable
from composer.environment import Environment
from composer.errors import (
    BatchError,
    DivergenceWarning,
    EntityError,
    EpisodeError,
    Error,
    ObservableError,
    ObservableNotFoundError,
    PlacementError,
    TaskError,
    VariationError,
)
from composer.hooks import HOOK_NAMES
from composer.initializers import Initializer, PropPlacer
from composer.task import NullTask, Task
from composer.vector import VectorEnvironment

__all__ = [
    "HOOK_NAMES",
    "Arena",
    "BatchError",
    "BatchOfOne",
    "BatchPhysics",
    "BatchedTask",
    "DivergenceWarning",
    "Entity",
    "EntityError",
    "Environment",
    "EpisodeError",
    "Error",
    "Initializer",
    "ModelEntity",
    "NullTask",
    "ObservableError",
    "ObservableNotFoundError",
    "Observables",
    "PlacementError",
    "PropPlacer",
    "Task",
    "TaskError",
    "VariationError",
    "VectorEnvironment",
    "observable",
    "observation",
    "variation",
    "vector",
]
