"""Observables: the generic ones (`base`) and those of MJCF elements (`mjcf`).

    from composer.observation import observable
    qpos = observable.MJCFFeature('qpos', joints)
    clock = observable.Generic(lambda physics: physics.time())

See `base.Observable` for the options every observable has and how they are sampled.
"""

from composer.observation.observable import base, mjcf
from composer.observation.observable.base import (
    AGGREGATORS,
    Aggregator,
    BatchGeneric,
    FieldRows,
    GaussianNoise,
    Generic,
    MujocoCamera,
    MujocoFeature,
    Observable,
    reader_of,
    row_reader_of,
)
from composer.observation.observable.mjcf import MJCFCamera, MJCFFeature

__all__ = [
    "AGGREGATORS",
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
    "base",
    "mjcf",
    "reader_of",
    "row_reader_of",
]
