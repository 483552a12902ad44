"""Observables and the pipeline that samples them; see `observable` and `updater`.

from composer import observation
obs = observation.MJCFFeature('qpos', joints, buffer_size=2)
obs.corruptor = observation.GaussianNoise(0.01)
"""

from composer.observation.observable import (
    AGGREGATORS,
    BatchGeneric,
    GaussianNoise,
    Generic,
    MJCFCamera,
    MJCFFeature,
    Observable,
    reader_of,
)
from composer.observation.updater import Updater

__all__ = [
    "AGGREGATORS",
    "BatchGeneric",
    "GaussianNoise",
    "Generic",
    "MJCFCamera",
    "MJCFFeature",
    "Observable",
    "Updater",
    "reader_of",
]
