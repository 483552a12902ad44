"""Observables and the pipeline that samples them; see `observable` and `updater`.

from composer import observation
obs = observation.MJCFFeature('qpos', joints, buffer_size=2)
obs.corruptor = observation.GaussianNoise(0.01)
"""

from composer.observation.observable import (
    AGGREGATORS,
    GaussianNoise,
    Generic,
    MJCFCamera,
    MJCFFeature,
    Observable,
)
from composer.observation.updater import Updater

__all__ = [
    "AGGREGATORS",
    "GaussianNoise",
    "Generic",
    "MJCFCamera",
    "MJCFFeature",
    "Observable",
    "Updater",
]
