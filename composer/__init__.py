"""composer: entities, arenas and tasks composed into a Gymnasium environment on `mjcf`.

    import arenas, composer
    arena = arenas.Floor()                                 # or composer.Arena(): empty
    arena.add_free_entity(composer.Entity.from_path('humanoid.xml'))
    env = composer.Environment(composer.NullTask(arena), time_limit=10.0)

Every error is a `composer.Error`; dm_control's Composer code runs with `from dm_control
import composer` -> `import composer` (docs/dm_control_composer.md). `import composer` loads
what one environment needs, the CLI, Ray, SB3 and dm_env only when imported (docs/architecture.md).
"""

import importlib
from typing import TYPE_CHECKING

from composer import (
    arena,
    constants,
    define,
    entity,
    environment,
    initializer,
    observation,
    robot,
    task,
)
from composer.arena import Arena
from composer.batch.protocol import BatchedTask, BatchPhysics
from composer.batch.single import BatchOfOne
from composer.constants import SENSOR_SITES_GROUP
from composer.define import cached_property, observable
from composer.entity import (
    Entity,
    FreePropObservableMixin,
    ModelEntity,
    ModelWrapperEntity,
    Observables,
)
from composer.environment import Environment, ObservationPadding
from composer.errors import (
    BatchError,
    DivergenceWarning,
    EntityError,
    EpisodeError,
    EpisodeInitializationError,
    Error,
    InitializerError,
    ObservableError,
    ObservableNotFoundError,
    ObservableOptionError,
    OverrideError,
    PlacementError,
    PoseError,
    TaskError,
    UnknownAggregatorError,
    VariationError,
)
from composer.hooks import HOOK_NAMES
from composer.initializer import Initializer
from composer.robot import Robot
from composer.task import NullTask, Task

if TYPE_CHECKING:
    from composer import initializers, pixels, variation, vector
    from composer.initializers import PropPlacer
    from composer.pixels import PixelEnvironment
    from composer.vector import VectorEnvironment

# What an environment's user may never need, imported when first used: {name: (module,
# attribute of it, or None for the module itself)}.
_ON_DEMAND = {
    "initializers": ("composer.initializers", None),
    "PropPlacer": ("composer.initializers", "PropPlacer"),
    "pixels": ("composer.pixels", None),
    "PixelEnvironment": ("composer.pixels", "PixelEnvironment"),
    "variation": ("composer.variation", None),
    "vector": ("composer.vector", None),
    "VectorEnvironment": ("composer.vector", "VectorEnvironment"),
}

__all__ = [
    "HOOK_NAMES",
    "SENSOR_SITES_GROUP",
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
    "EpisodeInitializationError",
    "Error",
    "FreePropObservableMixin",
    "Initializer",
    "InitializerError",
    "ModelEntity",
    "ModelWrapperEntity",
    "NullTask",
    "ObservableError",
    "ObservableNotFoundError",
    "ObservableOptionError",
    "Observables",
    "ObservationPadding",
    "OverrideError",
    "PixelEnvironment",
    "PlacementError",
    "PoseError",
    "PropPlacer",
    "Robot",
    "Task",
    "TaskError",
    "UnknownAggregatorError",
    "VariationError",
    "VectorEnvironment",
    "arena",
    "cached_property",
    "constants",
    "define",
    "entity",
    "environment",
    "initializer",
    "initializers",
    "observable",
    "observation",
    "pixels",
    "robot",
    "task",
    "variation",
    "vector",
]


def __getattr__(name: str) -> object:
    """The names of `_ON_DEMAND`, importing their module when first asked for."""
    found = _ON_DEMAND.get(name)
    if found is None:
        raise AttributeError(f"module 'composer' has no attribute {name!r}")
    module = importlib.import_module(found[0])
    return module if found[1] is None else getattr(module, found[1])


def __dir__() -> list[str]:
    return sorted({*globals(), *_ON_DEMAND})
