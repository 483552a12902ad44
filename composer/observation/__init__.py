"""Observables and the pipeline that samples them; see `observable`, `updater` (one
environment's pipeline), `schedule` (the schedule and samples of one environment or many)
and `entity_observables` (the observables of one entity, `composer.Observables`).

    from composer import observation
    obs = observation.MJCFFeature('qpos', joints, buffer_size=2)
    obs.corruptor = observation.GaussianNoise(0.01)

`observation.observable` holds them under dm_control's module paths (`observable.base`,
`observable.mjcf`).
"""

from composer.observation import observable
from composer.observation.channel import (
    DEFAULT_BUFFER_SIZE,
    DEFAULT_DELAY,
    DEFAULT_UPDATE_INTERVAL,
)
from composer.observation.observable import (
    AGGREGATORS,
    Aggregator,
    BatchGeneric,
    FieldRows,
    GaussianNoise,
    Generic,
    MJCFCamera,
    MJCFFeature,
    MujocoCamera,
    MujocoFeature,
    Observable,
    reader_of,
)
from composer.observation.updater import ObservationPadding, Updater

__all__ = [
    "AGGREGATORS",
    "DEFAULT_BUFFER_SIZE",
    "DEFAULT_DELAY",
    "DEFAULT_UPDATE_INTERVAL",
    "Aggregator",
    "BatchGeneric",
    "FieldRows",
    "GaussianNoise",
    "Generic",
    "MJCFCamera",
    "MJCFFeature",
    "MujocoCamera",
    "MujocoFeature",
    "Observable",
    "ObservationPadding",
    "Updater",
    "observable",
    "reader_of",
]
